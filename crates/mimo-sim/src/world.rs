//! The simulated world of one scenario: ships (sites and faces over time) and target truth.
//! It is the engine's alone: a test article learns the ships from its `start` event and never
//! sees the targets.

use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use mimo_scenario::{Scenario, ScenarioError, Trajectories};

/// A scenario with its trajectories built.
#[derive(Debug, Clone)]
pub struct World {
    /// The validated scenario.
    pub scenario: Scenario,
    /// Every target's trajectory.
    pub trajectories: Trajectories,
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
        let trajectories = scenario.build_trajectories()?;
        Ok(World { scenario, trajectories })
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

    /// A radar's faces at time `t_s` (their origins are the array centre).
    pub fn faces_at(&self, r: RadarId, t_s: f64) -> Vec<FaceFrame> {
        self.scenario.ships[r.index()].faces_at(t_s)
    }

    /// A radar's array-centre position (ECEF) at `t_s`.
    pub fn site_at(&self, r: RadarId, t_s: f64) -> DVec3 {
        self.scenario.ships[r.index()].position_at(t_s).to_ecef()
    }

    /// Every target's truth at `t_s`.
    pub fn targets_at(&self, t_s: f64) -> Vec<TargetNow<'_>> {
        (0..self.scenario.targets.len())
            .map(|i| {
                let s = self.trajectories.state_at(i, t_s);
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
