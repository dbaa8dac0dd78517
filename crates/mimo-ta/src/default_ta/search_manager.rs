//! The default test article's search manager (docs/model.md §7.4): how much background search
//! each radar runs, traded against how soon a new target is tracked.
//!
//! Two phases. **Acquiring** (from the start, and for `settle_s` after a track was confirmed or
//! a confirmed track was lost): every radar searches with share `share` of its idle time.
//! **Held** (at least one confirmed track, and none confirmed or lost for `settle_s`): share
//! `held_share`. The bands are the default two-band horizon fence with the pulses and upper-band
//! rate of the configuration. The phase is checked at every event the test article gets; an
//! order goes out only when the phase's plan differs from the one in force. With the defaults
//! no order is ever sent, and the radars run the engine's own raster: today's search.

use mimo_core::records::{TrackRow, TrackStatus};
use mimo_sim::messages::{Request, SearchBand, SearchOrder, SearchPlan};
use serde::{Deserialize, Serialize};
use std::collections::BTreeSet;

/// Settings of the search manager (`search_manager.*`). The defaults reproduce the engine's
/// own background search exactly (no order is sent).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SearchManagerConfig {
    /// Share of each radar's idle time given to search while acquiring, in [0, 1]: after a
    /// search dwell of length d the radar waits d·(1 − share)/share. Default 1 (every idle
    /// moment). The one knob that walks search energy from today's down to nothing.
    pub share: f64,
    /// Share once tracks are held, in [0, 1]. Default `None`: `share`.
    pub held_share: Option<f64>,
    /// Time without a new confirmed track or a lost one before tracks count as held (s).
    /// Default 20.
    pub settle_s: f64,
    /// Pulses per low-band (0–2.5°) search dwell. Default 2.
    pub low_band_pulses: u32,
    /// Pulses per upper-band (2.5–12°) search dwell. Default 1.
    pub upper_band_pulses: u32,
    /// The upper band is swept once every this many low-band frames; 0: never. Default 3.
    pub upper_band_every_frames: u32,
    /// Shortest time between two frame starts (s), in both phases. Default `None`: no limit.
    pub frame_period_s: Option<f64>,
}

impl Default for SearchManagerConfig {
    fn default() -> Self {
        SearchManagerConfig {
            share: 1.0,
            held_share: None,
            settle_s: 20.0,
            low_band_pulses: 2,
            upper_band_pulses: 1,
            upper_band_every_frames: 3,
            frame_period_s: None,
        }
    }
}

impl SearchManagerConfig {
    /// Whether the manager leaves search alone (the engine's raster, every idle moment): then
    /// it never sends an order, and every table is the one without a search manager.
    pub fn is_default(&self) -> bool {
        let d = SearchManagerConfig::default();
        self.share == 1.0
            && self.held_share.unwrap_or(self.share) == 1.0
            && self.low_band_pulses == d.low_band_pulses
            && self.upper_band_pulses == d.upper_band_pulses
            && self.upper_band_every_frames == d.upper_band_every_frames
            && self.frame_period_s.is_none()
    }

    /// Check the values; the error names the key and what was expected.
    pub fn validate(&self) -> Result<(), (String, String)> {
        let share = |k: &str, x: f64| {
            if x.is_finite() && (0.0..=1.0).contains(&x) {
                Ok(())
            } else {
                Err((format!("search_manager.{k}"), format!("a share in [0, 1], got {x}")))
            }
        };
        share("share", self.share)?;
        if let Some(h) = self.held_share {
            share("held_share", h)?;
        }
        if !(self.settle_s.is_finite() && self.settle_s >= 0.0) {
            return Err(("search_manager.settle_s".into(), format!("a time >= 0 s, got {}", self.settle_s)));
        }
        for (k, n) in [("low_band_pulses", self.low_band_pulses), ("upper_band_pulses", self.upper_band_pulses)] {
            if n < 1 {
                return Err((format!("search_manager.{k}"), "a whole number of pulses >= 1, got 0".into()));
            }
        }
        if let Some(p) = self.frame_period_s
            && !(p.is_finite() && p > 0.0)
        {
            return Err(("search_manager.frame_period_s".into(), format!("a positive finite time (s), got {p}")));
        }
        Ok(())
    }

    /// Every radar's plan at search share `share`.
    pub fn plan(&self, share: f64) -> SearchPlan {
        let mut bands =
            vec![SearchBand { el_min_deg: 0.0, el_max_deg: 2.5, n_pulses: self.low_band_pulses, every_frames: 1 }];
        if self.upper_band_every_frames > 0 {
            bands.push(SearchBand {
                el_min_deg: 2.5,
                el_max_deg: 12.0,
                n_pulses: self.upper_band_pulses,
                every_frames: self.upper_band_every_frames,
            });
        }
        SearchPlan { bands, sectors: Vec::new(), frame_period_s: self.frame_period_s, share }
    }
}

/// The manager's state in a run.
#[derive(Debug, Clone, Default)]
pub(crate) struct SearchManager {
    /// Whether it orders anything this run (a closed loop and settings other than the default).
    active: bool,
    /// The share ordered last (`None`: no order yet).
    ordered: Option<f64>,
    /// Confirmed tracks alive.
    confirmed: BTreeSet<u64>,
    /// When a track was last confirmed or a confirmed track lost (s).
    last_change_s: f64,
}

impl SearchManager {
    /// A new run starts: the acquiring plan (nothing with the default settings).
    pub fn start(&mut self, cfg: &SearchManagerConfig, closed_loop: bool) -> Vec<Request> {
        *self = SearchManager { active: closed_loop && !cfg.is_default(), ..SearchManager::default() };
        if !self.active {
            return Vec::new();
        }
        self.order(cfg, cfg.share)
    }

    /// Note the track rows of an event at `now_s`.
    pub fn note_rows(&mut self, rows: &[TrackRow], now_s: f64) {
        for r in rows {
            let changed = match r.status {
                TrackStatus::Confirmed => self.confirmed.insert(r.track_id),
                TrackStatus::Deleted => self.confirmed.remove(&r.track_id),
                TrackStatus::Tentative => false,
            };
            if changed {
                self.last_change_s = now_s;
            }
        }
    }

    /// The order for the phase at `now_s`, if it changed.
    pub fn update(&mut self, cfg: &SearchManagerConfig, now_s: f64) -> Vec<Request> {
        if !self.active {
            return Vec::new();
        }
        let held = !self.confirmed.is_empty() && now_s >= self.last_change_s + cfg.settle_s;
        let share = if held { cfg.held_share.unwrap_or(cfg.share) } else { cfg.share };
        if self.ordered == Some(share) { Vec::new() } else { self.order(cfg, share) }
    }

    fn order(&mut self, cfg: &SearchManagerConfig, share: f64) -> Vec<Request> {
        self.ordered = Some(share);
        vec![Request::Search(SearchOrder { radar: None, plan: cfg.plan(share) })]
    }

    /// The share ordered last (for tests).
    #[cfg(test)]
    pub fn share(&self) -> Option<f64> {
        self.ordered
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(id: u64, status: TrackStatus) -> TrackRow {
        let (x_m, y_m, z_m, vx_mps, vy_mps, vz_mps) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let cov = [0.0; 21];
        TrackRow {
            run: 0,
            t_s: 0.0,
            track_id: id,
            status,
            x_m,
            y_m,
            z_m,
            vx_mps,
            vy_mps,
            vz_mps,
            cov,
            n_updates: 1,
            last_meas_id: None,
        }
    }

    #[test]
    fn the_default_sends_nothing_and_bad_knobs_are_named() {
        let d = SearchManagerConfig::default();
        assert!(d.is_default() && d.validate().is_ok());
        let mut m = SearchManager::default();
        assert!(m.start(&d, true).is_empty());
        m.note_rows(&[row(1, TrackStatus::Confirmed)], 5.0);
        assert!(m.update(&d, 100.0).is_empty());
        // held_share 1 with share 1 is today's search too.
        assert!(SearchManagerConfig { held_share: Some(1.0), ..d.clone() }.is_default());
        let bad = |c: SearchManagerConfig| c.validate().expect_err("refused").0;
        assert_eq!(bad(SearchManagerConfig { share: 1.2, ..d.clone() }), "search_manager.share");
        assert_eq!(bad(SearchManagerConfig { held_share: Some(-0.1), ..d.clone() }), "search_manager.held_share");
        assert_eq!(bad(SearchManagerConfig { low_band_pulses: 0, ..d.clone() }), "search_manager.low_band_pulses");
        assert_eq!(
            bad(SearchManagerConfig { frame_period_s: Some(0.0), ..d.clone() }),
            "search_manager.frame_period_s"
        );
        assert_eq!(bad(SearchManagerConfig { settle_s: f64::NAN, ..d }), "search_manager.settle_s");
    }

    #[test]
    fn search_drops_to_the_held_share_once_tracks_settle_and_returns_on_a_loss() {
        let c = SearchManagerConfig { held_share: Some(0.1), settle_s: 20.0, ..SearchManagerConfig::default() };
        let mut m = SearchManager::default();
        let first = m.start(&c, true);
        let [Request::Search(o)] = first.as_slice() else { panic!("one order: {first:?}") };
        assert_eq!((o.radar, o.plan.share, o.plan.bands.len()), (None, 1.0, 2));
        assert_eq!(o.plan.bands[0].n_pulses, 2);
        // No track: acquiring however long it lasts.
        assert!(m.update(&c, 100.0).is_empty());
        m.note_rows(&[row(7, TrackStatus::Tentative)], 101.0);
        m.note_rows(&[row(7, TrackStatus::Confirmed)], 102.0);
        assert!(m.update(&c, 121.0).is_empty(), "not settled before 122 s");
        let held = m.update(&c, 122.5);
        assert!(matches!(held.as_slice(), [Request::Search(o)] if o.plan.share == 0.1));
        assert!(m.update(&c, 130.0).is_empty(), "ordered once");
        // An update of a held track changes nothing; losing it goes back to acquiring.
        m.note_rows(&[row(7, TrackStatus::Confirmed)], 140.0);
        assert!(m.update(&c, 140.0).is_empty());
        m.note_rows(&[row(7, TrackStatus::Deleted)], 150.0);
        assert!(matches!(m.update(&c, 150.0).as_slice(), [Request::Search(o)] if o.plan.share == 1.0));
        assert_eq!(m.share(), Some(1.0));
        // An open-loop replay orders nothing.
        assert!(SearchManager::default().start(&c, false).is_empty());
    }
}
