//! Background search: each radar's own raster of beams, which fills every idle moment of its
//! timeline (docs/design.md §5, docs/model.md §7.4).
//!
//! The raster is a horizon fence of elevation bands: beams on a u–v lattice (spacing
//! `spacing_beamwidths`·θ) of each face, kept where the beam is inside the scan limit, its
//! elevation lies in the band (local ENU at the ship) and its azimuth lies in the face's own
//! sector (half-width `min(180°/n_faces, 0.95 θ_max)` about the face boresight), so that faces
//! share the horizon without searching it twice. Beams are visited face by face, row by row.

use crate::search_plan::AzSector;
use mimo_core::face::face_from_enu;
use mimo_core::params::RadarParams;
use serde::{Deserialize, Serialize};

/// One elevation band of the search raster.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SearchBand {
    /// Lowest beam elevation (deg).
    pub el_min_deg: f64,
    /// Highest beam elevation (deg).
    pub el_max_deg: f64,
    /// Pulses per search dwell in this band.
    pub n_pulses: u32,
    /// The band is swept once every this many frames of the first band (1 = every frame).
    #[serde(default = "one_frame")]
    pub every_frames: u32,
}

fn one_frame() -> u32 {
    1
}

/// Background-search settings (one set for all radars; recorded in the manifest).
///
/// The default is a two-band horizon fence: a low band (0–2.5°, where every long-range target
/// appears first) searched every frame with 2 pulses, and an upper band (2.5–12°, for targets
/// lost at short range) with 1 pulse, one third of it per frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SearchConfig {
    /// The elevation bands, searched as described above.
    pub bands: Vec<SearchBand>,
    /// Beam spacing on the u–v lattice in beamwidths.
    pub spacing_beamwidths: f64,
}

impl Default for SearchConfig {
    fn default() -> Self {
        SearchConfig {
            bands: vec![
                SearchBand { el_min_deg: 0.0, el_max_deg: 2.5, n_pulses: 2, every_frames: 1 },
                SearchBand { el_min_deg: 2.5, el_max_deg: 12.0, n_pulses: 1, every_frames: 3 },
            ],
            spacing_beamwidths: 0.9,
        }
    }
}

impl SearchConfig {
    /// The default bands with the first (low) band using `n_low` pulses (for `--search-pulses`).
    pub fn scaled_pulses(mut self, n_low: u32) -> SearchConfig {
        if let Some(b) = self.bands.first_mut() {
            b.n_pulses = n_low;
        }
        self
    }
}

/// One search beam.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchBeam {
    /// Array face (0-based).
    pub face: u8,
    /// Beam direction in the face's sine space.
    pub u: f64,
    /// Beam direction in the face's sine space.
    pub v: f64,
    /// Pulses per dwell.
    pub n_pulses: u32,
}

/// Half-width of each face's own azimuth sector (deg): `min(180°/n_faces, 0.95 θ_max)`.
pub fn face_half_sector_deg(params: &RadarParams) -> f64 {
    let n_faces = params.face_azimuths_deg.len().max(1);
    (180.0 / n_faces as f64).min(0.95 * params.max_scan_deg)
}

/// Beams of one band (ship heading `heading_deg`; faces from `params`), face by face, row by row,
/// kept when their true-north azimuth lies in one of `sectors` (all when `sectors` is empty).
fn band_beams(
    params: &RadarParams,
    heading_deg: f64,
    band: &SearchBand,
    spacing: f64,
    sectors: &[AzSector],
) -> Vec<SearchBeam> {
    let half_sector = face_half_sector_deg(params);
    let (du, dv) = (spacing * params.beamwidth_u(), spacing * params.beamwidth_v());
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
                if el < band.el_min_deg || el >= band.el_max_deg {
                    continue;
                }
                let az = d.x.atan2(d.y).to_degrees();
                let rel = (az - boresight_az + 540.0).rem_euclid(360.0) - 180.0;
                if rel.abs() > half_sector {
                    continue;
                }
                if !sectors.is_empty() && !sectors.iter().any(|s| s.contains(az)) {
                    continue;
                }
                beams.push(SearchBeam { face: fi as u8, u, v, n_pulses: band.n_pulses.clamp(1, params.max_pulses) });
            }
        }
    }
    beams
}

/// A radar's search sequence, visited cyclically: each frame sweeps every band whose
/// `every_frames` is 1 and the next share of each slower band.
pub fn raster(params: &RadarParams, heading_deg: f64, cfg: &SearchConfig) -> Vec<SearchBeam> {
    raster_of(params, heading_deg, &cfg.bands, cfg.spacing_beamwidths, &[]).beams
}

/// A search sequence and where its frames start.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Raster {
    /// The beams, visited cyclically.
    pub beams: Vec<SearchBeam>,
    /// Index in `beams` of the first beam of each frame, increasing (empty frames left out).
    pub frame_starts: Vec<usize>,
}

/// The raster of `bands` with lattice spacing `spacing` (beamwidths), restricted to the
/// true-north azimuth `sectors` (none: the whole horizon); see [`raster`].
pub fn raster_of(
    params: &RadarParams,
    heading_deg: f64,
    bands: &[SearchBand],
    spacing: f64,
    sectors: &[AzSector],
) -> Raster {
    let bands: Vec<(Vec<SearchBeam>, u32)> =
        bands.iter().map(|b| (band_beams(params, heading_deg, b, spacing, sectors), b.every_frames.max(1))).collect();
    let cycle = bands.iter().map(|(_, k)| *k).fold(1u32, lcm);
    let mut out = Raster::default();
    for frame in 0..cycle {
        let first = out.beams.len();
        for (beams, k) in &bands {
            let share = frame % k;
            out.beams.extend(beams.iter().enumerate().filter(|(i, _)| (*i as u32) % k == share).map(|(_, b)| *b));
        }
        if out.beams.len() > first {
            out.frame_starts.push(first);
        }
    }
    out
}

fn lcm(a: u32, b: u32) -> u32 {
    fn gcd(a: u32, b: u32) -> u32 {
        if b == 0 { a } else { gcd(b, a % b) }
    }
    a / gcd(a, b) * b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raster_covers_the_horizon_band_once() {
        let p = RadarParams::default();
        let cfg = SearchConfig::default();
        let beams = raster(&p, 30.0, &cfg);
        // Low band every frame, upper band a third per frame: a cycle of three frames holds the
        // low band three times and the upper band once.
        let low = band_beams(&p, 30.0, &cfg.bands[0], cfg.spacing_beamwidths, &[]);
        let high = band_beams(&p, 30.0, &cfg.bands[1], cfg.spacing_beamwidths, &[]);
        assert_eq!(beams.len(), 3 * low.len() + high.len());
        assert!(!beams.is_empty());
        // Every azimuth at 2° elevation is within half a lattice diagonal of some beam of the face
        // that owns it, measured in that face's u–v.
        let spacing = cfg.spacing_beamwidths * p.beamwidth_u();
        for az in (0..360).map(f64::from) {
            let el = 2.0f64.to_radians();
            let d_enu =
                mimo_core::DVec3::new(az.to_radians().sin() * el.cos(), az.to_radians().cos() * el.cos(), el.sin());
            let mut best = f64::INFINITY;
            for b in &low {
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
        let counts: Vec<usize> = (0..4).map(|f| low.iter().filter(|b| b.face == f).count()).collect();
        assert!(counts.iter().all(|&c| c == counts[0]), "{counts:?}");
    }
}
