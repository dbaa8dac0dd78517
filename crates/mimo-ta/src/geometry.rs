//! The ships as a test article knows them, as the tracker's [`SensorGeometry`].
//!
//! Built from the `start` event's ships (docs/ta-protocol.md §2.1): each steams along its great
//! circle, so the site and faces at any time follow from the start position, heading and speed
//! (docs/model.md §1.3, §8.3), sampled and interpolated exactly as the engine does
//! ([`ShipFrames`]). No truth is involved.

use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use mimo_scenario::{Ship, ShipFrames};
use mimo_sim::messages::StartInfo;
use mimo_track::SensorGeometry;

/// The radars of a run, from its `start` event.
#[derive(Debug, Clone)]
pub struct ShipGeometry {
    ships: Vec<Ship>,
    frames: Vec<ShipFrames>,
    centre: Geodetic,
}

impl ShipGeometry {
    /// The geometry of the ships of a `start` event.
    pub fn from_start(start: &StartInfo) -> ShipGeometry {
        let ships: Vec<Ship> = start.ships.iter().map(|s| s.to_ship()).collect();
        ShipGeometry {
            frames: ships.iter().map(|s| ShipFrames::new(s, start.duration_s)).collect(),
            ships,
            centre: Geodetic::from_deg(start.centre.lat_deg, start.centre.lon_deg, start.centre.alt_m),
        }
    }

    /// Every radar id, in order.
    pub fn ids(&self) -> Vec<RadarId> {
        self.ships.iter().map(|s| s.id).collect()
    }

    /// A radar's parameters (`None` for a radar the run does not have).
    pub fn params(&self, r: RadarId) -> Option<&RadarParams> {
        self.ships.get(r.index()).map(|s| &s.radar)
    }

    /// A radar's faces at `t_s` (empty for a radar the run does not have).
    pub fn faces_at(&self, r: RadarId, t_s: f64) -> Vec<FaceFrame> {
        self.frames.get(r.index()).map(|f| f.faces_at(t_s)).unwrap_or_default()
    }

    /// The scenario centre (origin of the tracking frame).
    pub fn centre(&self) -> Geodetic {
        self.centre
    }
}

impl SensorGeometry for ShipGeometry {
    fn site_ecef(&self, radar: RadarId, t_s: f64) -> Option<DVec3> {
        self.frames.get(radar.index()).map(|f| f.site_at(t_s))
    }
    fn face(&self, radar: RadarId, face: u8, t_s: f64) -> Option<FaceFrame> {
        self.frames.get(radar.index())?.face_at(t_s, face as usize)
    }
}
