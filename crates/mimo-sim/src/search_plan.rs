//! A test article's search order: the background-search plan it sets for one radar or for
//! every radar, at start or later in the run (docs/ta-protocol.md §3, docs/model.md §7.4).
//!
//! A plan says which beams a radar searches (elevation bands, true-north azimuth sectors) and
//! how much of its idle time it gives them (a share of idle time and/or a shortest frame
//! period). A radar whose plan has no band, or share 0, does not search: with no test-article
//! dwell to run it idles — no dwell row, no energy, no dwell time.

use crate::search::{SearchBand, face_half_sector_deg};
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use serde::{Deserialize, Serialize};

/// An azimuth sector, clockwise from `from_deg` to `to_deg` (true north, degrees in [0, 360];
/// `from_deg` > `to_deg` runs through north; `{0, 360}` is the whole horizon).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AzSector {
    /// Where the sector starts (deg, clockwise from true north).
    pub from_deg: f64,
    /// Where it ends, clockwise from `from_deg` (deg, clockwise from true north).
    pub to_deg: f64,
}

impl AzSector {
    /// The sector's width (deg), in (0, 360].
    pub fn width_deg(&self) -> f64 {
        let w = (self.to_deg - self.from_deg).rem_euclid(360.0);
        if w == 0.0 { 360.0 } else { w }
    }

    /// Whether true-north azimuth `az_deg` (any branch) lies in the sector.
    pub fn contains(&self, az_deg: f64) -> bool {
        (az_deg - self.from_deg).rem_euclid(360.0) <= self.width_deg() + 1e-9
    }
}

fn full_share() -> f64 {
    1.0
}

/// A radar's background-search plan (docs/model.md §7.4).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SearchPlan {
    /// Elevation bands, swept as the default raster's are: each frame sweeps every band with
    /// `every_frames` = 1 and the next share of each slower band. Empty: no background search.
    pub bands: Vec<SearchBand>,
    /// True-north azimuth sectors searched (beams whose azimuth lies in none are dropped);
    /// empty: the whole horizon. Each must lie inside the radar's faces' search sectors.
    #[serde(default)]
    pub sectors: Vec<AzSector>,
    /// A new frame of the raster does not start before the previous frame started + this (s);
    /// `None`: no limit.
    #[serde(default)]
    pub frame_period_s: Option<f64>,
    /// Share of idle time given to search, in [0, 1]: after a search dwell of length d the
    /// radar waits d·(1 − share)/share before its next search beam. 1 (default): every idle
    /// moment, as the default raster; 0: no background search.
    #[serde(default = "full_share")]
    pub share: f64,
}

impl SearchPlan {
    /// A plan with no background search.
    pub fn none() -> SearchPlan {
        SearchPlan { bands: Vec::new(), sectors: Vec::new(), frame_period_s: None, share: 1.0 }
    }

    /// Whether the plan searches at all (some band and a share above 0).
    pub fn searches(&self) -> bool {
        !self.bands.is_empty() && self.share > 0.0
    }

    /// Check the numbers that need no radar; the error names the field under `plan.`.
    pub fn check(&self) -> Result<(), String> {
        for (i, b) in self.bands.iter().enumerate() {
            let f = |name: &str| format!("plan.bands[{i}].{name}");
            for (name, x) in [("el_min_deg", b.el_min_deg), ("el_max_deg", b.el_max_deg)] {
                if !(x.is_finite() && (-90.0..=90.0).contains(&x)) {
                    return Err(format!("{} = {x} is outside -90…90 deg", f(name)));
                }
            }
            if b.el_min_deg >= b.el_max_deg {
                return Err(format!(
                    "{} = {} is not below {} = {}",
                    f("el_min_deg"),
                    b.el_min_deg,
                    f("el_max_deg"),
                    b.el_max_deg
                ));
            }
            if b.n_pulses < 1 {
                return Err(format!("{} = 0: at least 1 pulse", f("n_pulses")));
            }
            if b.every_frames < 1 {
                return Err(format!("{} = 0: at least 1 (every frame)", f("every_frames")));
            }
        }
        for (i, s) in self.sectors.iter().enumerate() {
            for (name, x) in [("from_deg", s.from_deg), ("to_deg", s.to_deg)] {
                if !(x.is_finite() && (0.0..=360.0).contains(&x)) {
                    return Err(format!("plan.sectors[{i}].{name} = {x} is outside 0…360 deg"));
                }
            }
            if s.from_deg == s.to_deg {
                return Err(format!("plan.sectors[{i}] is empty: from_deg = to_deg = {}", s.from_deg));
            }
        }
        if let Some(p) = self.frame_period_s
            && !(p.is_finite() && p > 0.0)
        {
            return Err(format!("plan.frame_period_s = {p} is not a positive finite time (s)"));
        }
        if !(self.share.is_finite() && (0.0..=1.0).contains(&self.share)) {
            return Err(format!("plan.share = {} is outside [0, 1]", self.share));
        }
        Ok(())
    }

    /// Check that every sector lies inside the search sectors of the faces of a radar with
    /// `params` heading `heading_deg` (each face searches `min(180°/n_faces, 0.95 θ_max)` either
    /// side of its boresight, docs/model.md §7.4); the error names the first azimuth outside.
    pub fn check_sectors(&self, params: &RadarParams, heading_deg: f64) -> Result<(), String> {
        let half = face_half_sector_deg(params);
        let covered = |az: f64| {
            params.face_azimuths_deg.iter().any(|f| {
                let rel = (az - heading_deg - f + 540.0).rem_euclid(360.0) - 180.0;
                rel.abs() <= half + 1e-9
            })
        };
        for (i, s) in self.sectors.iter().enumerate() {
            let w = s.width_deg();
            let steps = (w / 0.25).ceil().max(1.0) as usize;
            for k in 0..=steps {
                let az = (s.from_deg + w * k as f64 / steps as f64).rem_euclid(360.0);
                if !covered(az) {
                    return Err(format!(
                        "plan.sectors[{i}] reaches azimuth {az:.2} deg, outside every face's search sector \
                         (±{half:.1} deg about each boresight)"
                    ));
                }
            }
        }
        Ok(())
    }
}

/// A test article's order: `plan` becomes the background search of `radar` (of every radar
/// when `radar` is `None`) from now on, starting at the first beam of its raster.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SearchOrder {
    /// The radar; `None` (or absent): every radar.
    #[serde(default)]
    pub radar: Option<RadarId>,
    /// The plan.
    pub plan: SearchPlan,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn band(lo: f64, hi: f64, n: u32, k: u32) -> SearchBand {
        SearchBand { el_min_deg: lo, el_max_deg: hi, n_pulses: n, every_frames: k }
    }

    fn plan(bands: Vec<SearchBand>) -> SearchPlan {
        SearchPlan { bands, ..SearchPlan::none() }
    }

    #[test]
    fn bad_plans_name_their_field() {
        let err = |p: SearchPlan| p.check().expect_err("refused");
        assert!(err(plan(vec![band(-95.0, 2.0, 1, 1)])).starts_with("plan.bands[0].el_min_deg"));
        assert!(err(plan(vec![band(0.0, 2.0, 1, 1), band(5.0, 3.0, 1, 1)])).starts_with("plan.bands[1].el_min_deg"));
        assert!(err(plan(vec![band(0.0, 2.0, 0, 1)])).starts_with("plan.bands[0].n_pulses"));
        assert!(err(plan(vec![band(0.0, 2.0, 1, 0)])).starts_with("plan.bands[0].every_frames"));
        assert!(err(SearchPlan { share: 1.5, ..plan(vec![]) }).starts_with("plan.share"));
        assert!(err(SearchPlan { share: f64::NAN, ..plan(vec![]) }).starts_with("plan.share"));
        assert!(err(SearchPlan { frame_period_s: Some(0.0), ..plan(vec![]) }).starts_with("plan.frame_period_s"));
        let s = AzSector { from_deg: 10.0, to_deg: 400.0 };
        assert!(err(SearchPlan { sectors: vec![s], ..plan(vec![]) }).starts_with("plan.sectors[0].to_deg"));
        assert!(plan(vec![band(0.0, 2.5, 2, 1), band(2.5, 12.0, 1, 3)]).check().is_ok());
        assert!(!SearchPlan { share: 0.0, ..plan(vec![band(0.0, 2.0, 1, 1)]) }.searches());
    }

    #[test]
    fn sectors_wrap_through_north_and_must_lie_inside_the_faces() {
        let s = AzSector { from_deg: 350.0, to_deg: 10.0 };
        assert_eq!(s.width_deg(), 20.0);
        assert!(s.contains(355.0) && s.contains(5.0) && s.contains(-5.0) && !s.contains(20.0) && !s.contains(340.0));
        assert!(AzSector { from_deg: 0.0, to_deg: 360.0 }.contains(181.0));
        // Two faces at bow ±45° on a ship heading north search 315±57° and 45±57°: 258°…102°.
        let p = RadarParams { face_azimuths_deg: vec![315.0, 45.0], ..RadarParams::default() };
        let inside = SearchPlan { sectors: vec![AzSector { from_deg: 270.0, to_deg: 90.0 }], ..SearchPlan::none() };
        assert!(inside.check_sectors(&p, 0.0).is_ok());
        let outside = SearchPlan { sectors: vec![AzSector { from_deg: 90.0, to_deg: 120.0 }], ..SearchPlan::none() };
        assert!(outside.check_sectors(&p, 0.0).expect_err("refused").contains("azimuth 102.25"));
        // Turned 90° to starboard, the same sector is inside.
        assert!(outside.check_sectors(&p, 90.0).is_ok());
    }
}
