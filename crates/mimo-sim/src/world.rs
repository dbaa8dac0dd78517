//! The simulated world of one scenario: ships (sites and faces over time) and target truth.
//! It is the engine's alone: a test article learns the ships from its `start` event and never
//! sees the targets.

use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use mimo_scenario::{Scenario, ScenarioError, ShipFrames, Trajectories};

/// A scenario with its trajectories built ([`World::new`]), or only its ships
/// ([`World::ships_only`], for a replay, which never asks where the targets are).
#[derive(Debug, Clone)]
pub struct World {
    /// The validated scenario.
    pub scenario: Scenario,
    /// Every target's trajectory (`None` in a ships-only world).
    trajectories: Option<Trajectories>,
    /// Every ship's faces over the run, sampled and interpolated.
    frames: Vec<ShipFrames>,
}

/// A target at one instant, as the radar model needs it.
#[derive(Debug, Clone)]
pub struct TargetNow<'w> {
    /// Target id (`F-1`, `A`, …).
    pub id: &'w str,
    /// Index of the target in the scenario.
    pub index: u32,
    /// Position (ECEF, m).
    pub pos_ecef: DVec3,
    /// Velocity (ECEF, m/s).
    pub vel_ecef: DVec3,
    /// Height above the ellipsoid (m).
    pub alt_m: f64,
    /// Mean RCS (m²).
    pub rcs_m2: f64,
}

impl World {
    /// Build the trajectories of a validated scenario.
    pub fn new(scenario: Scenario) -> Result<World, ScenarioError> {
        let trajectories = Some(scenario.build_trajectories()?);
        let frames = scenario.ships.iter().map(|s| ShipFrames::new(s, scenario.duration_s)).collect();
        Ok(World { scenario, trajectories, frames })
    }

    /// The ships alone, with no target trajectories: what a replay (`mimo track`) needs, since
    /// a test article never sees the targets. Building the trajectories (the flight integration
    /// of every target over the run) was a tenth of a replay's instructions. Asking such a world
    /// where a target is panics: it is a programming error, not bad input.
    pub fn ships_only(scenario: Scenario) -> World {
        let frames = scenario.ships.iter().map(|s| ShipFrames::new(s, scenario.duration_s)).collect();
        World { scenario, trajectories: None, frames }
    }

    /// Every target's trajectory.
    ///
    /// # Panics
    /// On a [`World::ships_only`] world.
    pub fn trajectories(&self) -> &Trajectories {
        self.trajectories.as_ref().expect("a ships-only world (World::ships_only) has no target trajectories")
    }

    /// Number of radars (ships).
    pub fn n_radars(&self) -> usize {
        self.scenario.ships.len()
    }

    /// All radar ids.
    pub fn radar_ids(&self) -> Vec<RadarId> {
        self.scenario.ships.iter().map(|s| s.id).collect()
    }

    /// A radar's parameters.
    pub fn params(&self, r: RadarId) -> &RadarParams {
        &self.scenario.ships[r.index()].radar
    }

    /// A radar's faces at time `t_s` (their origins are the array centre), from
    /// [`ShipFrames`].
    pub fn faces_at(&self, r: RadarId, t_s: f64) -> Vec<FaceFrame> {
        self.frames[r.index()].faces_at(t_s)
    }

    /// One face of a radar at `t_s` (`None` for a face it does not have).
    pub fn face_at(&self, r: RadarId, face: u8, t_s: f64) -> Option<FaceFrame> {
        self.frames[r.index()].face_at(t_s, face as usize)
    }

    /// A radar's array-centre position (ECEF) at `t_s`.
    pub fn site_at(&self, r: RadarId, t_s: f64) -> DVec3 {
        self.frames[r.index()].site_at(t_s)
    }

    /// Every target's position and mean RCS at `t_s`, as the radar model takes them, into `out`
    /// (cleared first; no geodetic conversion).
    pub fn radar_targets_into<'w>(&'w self, t_s: f64, out: &mut Vec<mimo_radar::Target<'w>>) {
        out.clear();
        let trajectories = self.trajectories();
        out.extend((0..self.scenario.targets.len()).map(|i| self.radar_target(trajectories, i, t_s)));
    }

    /// Target `i` at `t_s` as the radar model takes it.
    fn radar_target<'w>(&'w self, trajectories: &Trajectories, i: usize, t_s: f64) -> mimo_radar::Target<'w> {
        let t = &self.scenario.targets[i];
        mimo_radar::Target {
            id: t.id.as_str(),
            index: i as u32,
            pos_ecef: trajectories.position_at(i, t_s),
            rcs_m2: trajectories.rcs_m2(i),
            pol: t.polarimetry,
        }
    }

    /// The targets a dwell may reach at `t_s` (every target whose epoch ball some transmit beam
    /// may reach, [`mimo_radar::reach::DwellReach`]), in scenario order, into `out`; every target
    /// when `reach` is `None` or no balls cover `t_s`. The radar model gives the same dwell with
    /// these as with every target (docs/model.md §4.7), and a dwell's cost then follows the
    /// targets near its beams.
    pub fn radar_targets_reached_into<'w>(
        &'w self,
        t_s: f64,
        reach: Option<&mimo_radar::reach::DwellReach>,
        out: &mut Vec<mimo_radar::Target<'w>>,
    ) {
        let balls = self.target_balls_at(t_s).filter(|b| b.len() == self.scenario.targets.len());
        let (Some(reach), Some(balls)) = (reach, balls) else {
            return self.radar_targets_into(t_s, out);
        };
        out.clear();
        let trajectories = self.trajectories();
        for (i, b) in balls.iter().enumerate() {
            let ball = mimo_radar::quiet::TargetBall { center_ecef: b.center_ecef, radius_m: b.radius_m };
            if reach.may_reach(ball) {
                out.push(self.radar_target(trajectories, i, t_s));
            }
        }
    }

    /// For every target, a ball that holds it at `t_s` (and the rest of its one-second epoch:
    /// [`mimo_scenario::epoch_balls`]); `None` when `t_s` lies outside the sampled trajectories.
    pub fn target_balls_at(&self, t_s: f64) -> Option<&[mimo_scenario::epoch_balls::Ball]> {
        self.trajectories().balls_at(t_s)
    }

    /// Every target's truth at `t_s`.
    pub fn targets_at(&self, t_s: f64) -> Vec<TargetNow<'_>> {
        (0..self.scenario.targets.len())
            .map(|i| {
                let s = self.trajectories().state_at(i, t_s);
                TargetNow {
                    id: self.scenario.targets[i].id.as_str(),
                    index: i as u32,
                    pos_ecef: s.pos_ecef,
                    vel_ecef: s.vel_ecef,
                    alt_m: s.geodetic.alt_m,
                    rcs_m2: s.rcs_m2,
                }
            })
            .collect()
    }
}
