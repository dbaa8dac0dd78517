//! Background search: each radar's own raster of beams, which fills every idle moment of its
//! timeline (DESIGN.md §5).
//!
//! The raster is a horizon fence: beams on a u–v lattice (spacing `spacing_beamwidths`·θ) of
//! each face, kept where the beam is inside the scan limit, its elevation lies in
//! `[el_min_deg, el_max_deg]` (local ENU at the ship) and its azimuth lies in the face's own
//! sector (half-width `min(180°/n_faces, 0.95 θ_max)` about the face boresight), so that faces
//! share the horizon without searching it twice. Beams are visited face by face, row by row.

use mimo_core::face::face_from_enu;
use mimo_core::params::RadarParams;
use serde::{Deserialize, Serialize};

/// Background-search settings (one set for all radars; recorded in the manifest).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SearchConfig {
    /// Pulses per search dwell.
    pub n_pulses: u32,
    /// Lowest beam elevation (deg).
    pub el_min_deg: f64,
    /// Highest beam elevation (deg).
    pub el_max_deg: f64,
    /// Beam spacing on the u–v lattice in beamwidths.
    pub spacing_beamwidths: f64,
}

impl Default for SearchConfig {
    fn default() -> Self {
        SearchConfig { n_pulses: 1, el_min_deg: 0.0, el_max_deg: 6.0, spacing_beamwidths: 0.9 }
    }
}

/// One search beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchBeam {
    pub face: u8,
    pub u: f64,
    pub v: f64,
}

/// Build a radar's search raster (ship heading `heading_deg`; faces from `params`).
pub fn raster(params: &RadarParams, heading_deg: f64, cfg: &SearchConfig) -> Vec<SearchBeam> {
    let n_faces = params.face_azimuths_deg.len().max(1);
    let half_sector = (180.0 / n_faces as f64).min(0.95 * params.max_scan_deg);
    let (du, dv) = (cfg.spacing_beamwidths * params.beamwidth_u(), cfg.spacing_beamwidths * params.beamwidth_v());
    let min_w = params.min_scan_w();
    let mut beams = Vec::new();
    for (fi, &az_f) in params.face_azimuths_deg.iter().enumerate() {
        let boresight_az = heading_deg + az_f;
        let enu_from_face = face_from_enu(boresight_az.to_radians(), params.face_tilt_deg.to_radians()).transpose();
        let nu = (1.0 / du).floor() as i64;
        let nv = (1.0 / dv).floor() as i64;
        // Row by row (v), stepping u; odd rows offset by half a step (a staggered lattice).
        for iv in -nv..=nv {
            let v = iv as f64 * dv;
            let offset = if iv.rem_euclid(2) == 1 { 0.5 * du } else { 0.0 };
            for iu in -nu..=nu {
                let u = iu as f64 * du + offset;
                let w2 = 1.0 - u * u - v * v;
                if w2 <= 0.0 || w2.sqrt() < min_w {
                    continue;
                }
                let d = enu_from_face * mimo_core::DVec3::new(u, v, w2.sqrt());
                let el = d.z.clamp(-1.0, 1.0).asin().to_degrees();
                if el < cfg.el_min_deg || el > cfg.el_max_deg {
                    continue;
                }
                let az = d.x.atan2(d.y).to_degrees();
                let rel = (az - boresight_az + 540.0).rem_euclid(360.0) - 180.0;
                if rel.abs() > half_sector {
                    continue;
                }
                beams.push(SearchBeam { face: fi as u8, u, v });
            }
        }
    }
    beams
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raster_covers_the_horizon_band_once() {
        let p = RadarParams::default();
        let cfg = SearchConfig::default();
        let beams = raster(&p, 30.0, &cfg);
        assert!(!beams.is_empty());
        // Every azimuth at 2° elevation is within half a lattice diagonal of some beam of the face
        // that owns it, measured in that face's u–v.
        let spacing = cfg.spacing_beamwidths * p.beamwidth_u();
        for az in (0..360).map(f64::from) {
            let el = 2.0f64.to_radians();
            let d_enu =
                mimo_core::DVec3::new(az.to_radians().sin() * el.cos(), az.to_radians().cos() * el.cos(), el.sin());
            let mut best = f64::INFINITY;
            for b in &beams {
                let m = face_from_enu(
                    (30.0 + p.face_azimuths_deg[b.face as usize]).to_radians(),
                    p.face_tilt_deg.to_radians(),
                );
                let d = m * d_enu;
                if d.z <= 0.0 {
                    continue;
                }
                best = best.min(((d.x - b.u).powi(2) + (d.y - b.v).powi(2)).sqrt());
            }
            assert!(best < spacing, "azimuth {az}: nearest beam {best} (spacing {spacing})");
        }
        // Four faces of similar size.
        let counts: Vec<usize> = (0..4).map(|f| beams.iter().filter(|b| b.face == f).count()).collect();
        assert!(counts.iter().all(|&c| c == counts[0]), "{counts:?}");
    }
}
