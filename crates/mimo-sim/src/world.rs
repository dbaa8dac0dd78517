//! The simulated world of one scenario: ships (sites and faces over time) and target truth.

use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use mimo_scenario::{Scenario, ScenarioError, Trajectories};

/// A scenario with its trajectories built: everything the engine and the test article may ask
/// about geometry. Truth ([`World::targets_at`]) is for the engine only; a test article sees
/// ships and radars, never targets.
#[derive(Debug, Clone)]
pub struct World {
    pub scenario: Scenario,
    pub trajectories: Trajectories,
}

/// A target at one instant, as the radar model needs it.
#[derive(Debug, Clone)]
pub struct TargetNow<'w> {
    pub id: &'w str,
    pub index: u32,
    pub pos_ecef: DVec3,
    pub vel_ecef: DVec3,
    pub alt_m: f64,
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

impl mimo_track::SensorGeometry for World {
    fn site_ecef(&self, radar: RadarId, t_s: f64) -> Option<DVec3> {
        (radar.index() < self.n_radars()).then(|| self.site_at(radar, t_s))
    }
    fn face(&self, radar: RadarId, face: u8, t_s: f64) -> Option<FaceFrame> {
        if radar.index() >= self.n_radars() {
            return None;
        }
        self.faces_at(radar, t_s).get(face as usize).copied()
    }
}

/// What a test article may know of the world: the ships and their radars, never the targets.
#[derive(Debug, Clone, Copy)]
pub struct Radars<'w> {
    world: &'w World,
}

impl<'w> Radars<'w> {
    /// The radar view of a world.
    pub fn of(world: &'w World) -> Radars<'w> {
        Radars { world }
    }
    /// All radar ids.
    pub fn ids(&self) -> Vec<RadarId> {
        self.world.radar_ids()
    }
    /// A radar's parameters.
    pub fn params(&self, r: RadarId) -> &'w RadarParams {
        &self.world.scenario.ships[r.index()].radar
    }
    /// A radar's faces at `t_s`.
    pub fn faces_at(&self, r: RadarId, t_s: f64) -> Vec<FaceFrame> {
        self.world.faces_at(r, t_s)
    }
    /// A radar's array-centre position (ECEF) at `t_s`.
    pub fn site_at(&self, r: RadarId, t_s: f64) -> DVec3 {
        self.world.site_at(r, t_s)
    }
    /// The scenario centre (origin of a local tracking frame).
    pub fn centre(&self) -> mimo_core::geo::Geodetic {
        self.world.scenario.centre()
    }
}

impl mimo_track::SensorGeometry for Radars<'_> {
    fn site_ecef(&self, radar: RadarId, t_s: f64) -> Option<DVec3> {
        self.world.site_ecef(radar, t_s)
    }
    fn face(&self, radar: RadarId, face: u8, t_s: f64) -> Option<FaceFrame> {
        mimo_track::SensorGeometry::face(self.world, radar, face, t_s)
    }
}
