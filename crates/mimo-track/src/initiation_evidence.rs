//! Evidence before a track is started (docs/model.md §6.4, §7.7).
//!
//! A square-law detector's noise-only cell has power `|Σ|² ~ Exp(1)`, so a false alarm's power
//! above the detection threshold `γ = −ln P_FA` is `γ` plus a fresh exponential: a detection of
//! power `s` is as unlikely under noise as a crossing of a threshold set for the false-alarm
//! probability `e^{−s}`. [`FalseTrackConfig::admits`] lets a search detection start a tentative
//! track (and so spend a confirmation dwell) only when its power would have crossed the threshold
//! of a stricter false-alarm probability `power_pfa`: whatever the radar's own `P_FA` (raised near
//! clutter edges, or by the stress axis), false alarms start tracks at about `power_pfa` per
//! cell, while a real target, whose SW1 power is exponential with mean `1 + SNR`, passes with
//! probability `exp(−(γ_ev − γ)/(1 + SNR))`. Weaker detections still update the tracks that gate
//! them.

use mimo_core::records::DwellKind;
use serde::{Deserialize, Serialize};

/// False-track management settings (docs/model.md §6.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FalseTrackConfig {
    /// A search detection starts a tentative track only when its observed power `s` (linear SNR of
    /// the measurement) satisfies `e^{−s} ≤ power_pfa`, i.e. `s ≥ −ln power_pfa`. Default 1 (off:
    /// every detection may start a track); the default test article uses 1e-8.
    pub power_pfa: f64,
    /// Largest number of tentative tracks at once; when a dwell's initiations exceed it, the
    /// tentative tracks with the weakest initiating detection (the likeliest false alarms) are
    /// dropped first. Default 0 (no limit); the default test article uses 400.
    pub max_tentative: usize,
}

impl Default for FalseTrackConfig {
    fn default() -> Self {
        FalseTrackConfig { power_pfa: 1.0, max_tentative: 0 }
    }
}

impl FalseTrackConfig {
    /// The smallest observed power (linear SNR) that may start a track.
    pub fn min_power(&self) -> f64 {
        -self.power_pfa.ln()
    }

    /// Whether a detection with observed SNR `snr_db` in a dwell of this kind carries enough
    /// evidence to start a track. The rule applies to search dwells, whose window holds some
    /// 15 000 cells per channel; an aimed dwell's window holds a hundred times fewer, so its
    /// false alarms are as much rarer, and a second return in a beam aimed at a track is a
    /// priori a target (a formation opening up), so it starts a track at the radar's threshold.
    pub fn admits(&self, kind: DwellKind, snr_db: f64) -> bool {
        self.power_pfa >= 1.0 || kind != DwellKind::Search || 10f64.powf(snr_db / 10.0) >= self.min_power()
    }
}

/// The tentative tracks to drop so that at most `max` remain: the lowest `score` first (ties:
/// the oldest id first). `tentative` holds `(id, score)`; `max = 0` keeps every one.
pub fn shed_weakest(tentative: &mut [(u64, f64)], max: usize) -> Vec<u64> {
    if max == 0 || tentative.len() <= max {
        return Vec::new();
    }
    tentative.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
    tentative[..tentative.len() - max].iter().map(|t| t.0).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_power_rule_matches_its_false_alarm_probability() {
        let c = FalseTrackConfig { power_pfa: 1e-8, ..FalseTrackConfig::default() };
        let s_min_db = 10.0 * (-(1e-8f64).ln()).log10();
        assert!((s_min_db - 12.653).abs() < 1e-3, "{s_min_db}");
        let search = DwellKind::Search;
        assert!(c.admits(search, s_min_db + 1e-9) && !c.admits(search, s_min_db - 1e-3));
        assert!(c.admits(DwellKind::Track, s_min_db - 1.0), "aimed dwells initiate at the radar's threshold");
        assert!(FalseTrackConfig::default().admits(search, -30.0));
    }

    #[test]
    fn the_weakest_and_then_the_oldest_are_shed() {
        let mut t = vec![(1, 20.0), (2, 15.0), (3, 30.0), (4, 15.0), (5, 18.0)];
        assert_eq!(shed_weakest(&mut t, 3), vec![2, 4]);
        assert!(shed_weakest(&mut t, 0).is_empty());
        assert!(shed_weakest(&mut t, 5).is_empty());
    }
}
