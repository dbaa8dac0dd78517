//! Sensor geometry: where the radars and their faces are at a given time.
//!
//! The tracker never owns ship motion. The caller (the simulator's test article, or the offline
//! replayer reading a scenario) implements [`SensorGeometry`]; ships may steam slowly, so every
//! query carries the time. [`StaticGeometry`] is a ready-made implementation for stationary ships
//! built from [`RadarParams`] (docs/model.md §1.3).

use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use std::collections::BTreeMap;

/// Positions of radar sites and array faces, in ECEF, at time `t_s` (s since scenario start).
///
/// Return `None` for a radar or face the geometry does not know; the tracker then skips the
/// measurement (and counts it in its statistics) instead of panicking.
pub trait SensorGeometry {
    /// Phase centre of radar `radar` (the transmitter position in bistatic geometry).
    fn site_ecef(&self, radar: RadarId, t_s: f64) -> Option<DVec3>;
    /// Face `face` (0-based) of radar `radar`: origin (array centre) and ECEF → face rotation.
    fn face(&self, radar: RadarId, face: u8, t_s: f64) -> Option<FaceFrame>;
}

/// One stationary ship: its site and its faces.
#[derive(Debug, Clone, PartialEq)]
pub struct ShipGeometry {
    /// Radar site (m, ECEF).
    pub site_ecef: DVec3,
    /// Array faces.
    pub faces: Vec<FaceFrame>,
}

/// Stationary ships: a [`SensorGeometry`] that ignores time.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StaticGeometry {
    /// Ships by radar id.
    pub ships: BTreeMap<RadarId, ShipGeometry>,
}

impl StaticGeometry {
    /// Empty geometry.
    pub fn new() -> StaticGeometry {
        StaticGeometry::default()
    }

    /// Add (or replace) a ship whose array centre is at `site` (height included), with heading
    /// `heading_rad` (clockwise from north) and faces at `params.face_azimuths_deg` relative to the
    /// bow, tilted up by `params.face_tilt_deg`.
    pub fn add_ship(&mut self, radar: RadarId, site: Geodetic, heading_rad: f64, params: &RadarParams) -> &mut Self {
        let tilt = params.face_tilt_deg.to_radians();
        let faces = params
            .face_azimuths_deg
            .iter()
            .map(|az| FaceFrame::new(site, heading_rad + az.to_radians(), tilt))
            .collect();
        self.ships.insert(radar, ShipGeometry { site_ecef: site.to_ecef(), faces });
        self
    }

    /// Add a ship with explicit faces.
    pub fn add_faces(&mut self, radar: RadarId, site_ecef: DVec3, faces: Vec<FaceFrame>) -> &mut Self {
        self.ships.insert(radar, ShipGeometry { site_ecef, faces });
        self
    }
}

impl SensorGeometry for StaticGeometry {
    fn site_ecef(&self, radar: RadarId, _t_s: f64) -> Option<DVec3> {
        self.ships.get(&radar).map(|s| s.site_ecef)
    }

    fn face(&self, radar: RadarId, face: u8, _t_s: f64) -> Option<FaceFrame> {
        self.ships.get(&radar)?.faces.get(face as usize).copied()
    }
}

/// The face of `radar` that sees ECEF point `p` closest to boresight (largest `w`), with that
/// `w`. Scans faces `0..n_faces` as reported by `geom`; `None` if no face is known.
pub fn best_face(geom: &dyn SensorGeometry, radar: RadarId, p_ecef: DVec3, t_s: f64, n_faces: u8) -> Option<(u8, f64)> {
    let mut best: Option<(u8, f64)> = None;
    for f in 0..n_faces {
        if let Some(ff) = geom.face(radar, f, t_s) {
            let w = ff.to_sine(p_ecef).w;
            if w.is_finite() && best.is_none_or(|(_, bw)| w > bw) {
                best = Some((f, w));
            }
        }
    }
    best
}
