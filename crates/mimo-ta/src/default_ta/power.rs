//! The test article's transmit-power budget (docs/model.md §7.6): each radar may spend on the test
//! article's own dwells at most `power_budget_w` on average over any `power_window_s` window
//! (background search is the radar's own load and is not charged). A ledger of each radar's
//! recent and requested transmit energy decides, per request, whether it fits:
//!
//! * a look at a confirmed track (maintenance) fits when the window's energy with it stays within
//!   the budget, `L + E ≤ C` with `C = P_B·W`;
//! * a confirmation look must also leave the maintenance its headroom and may fill only the share
//!   of the window its detection's evidence earns: `L + E + h·M ≤ g(e)·C`, where `M` is the
//!   maintenance energy of the window, `h` = [`MAINTENANCE_HEADROOM`] and
//!   `g(e) = min(1, e / e_full)` grows with the detection's strength `e` (nats above the
//!   threshold: a false alarm is `e` strong with probability `exp(−e)`), `e_full` =
//!   [`FULL_EVIDENCE_NATS`].
//!
//! A dwell counts from the moment it is requested (it starts at or after that moment) until its
//! start leaves the window, so the windowed average of the dwells table never exceeds the budget.

use mimo_core::ids::RadarId;
use std::collections::{BTreeMap, VecDeque};

/// Headroom `h` a confirmation leaves the maintenance of confirmed tracks: confirmations may
/// use only what the window's maintenance energy `M`, taken `1 + h` times, leaves.
pub const MAINTENANCE_HEADROOM: f64 = 0.5;

/// Evidence `e_full` (nats above the threshold) that lets a confirmation fill the whole window:
/// `ln 1000`, a detection that a false alarm reaches once in a thousand.
pub const FULL_EVIDENCE_NATS: f64 = 6.907_755_278_982_137;

/// A request's priority class.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LookClass {
    /// A look at a confirmed track.
    Maintenance,
    /// A confirmation look at a tentative track whose strongest detection stood `e` nats above
    /// the detection threshold (`|Σ|²/σ² − γ`).
    Confirmation {
        /// Evidence `e` (nats).
        evidence_nats: f64,
    },
}

/// The energy one radar has committed in the window (J).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Load {
    /// Every test-article dwell it transmits whose start lies in the window, and every requested
    /// one not yet reported.
    pub total_j: f64,
    /// The maintenance part of `total_j`.
    pub maintenance_j: f64,
}

/// Share `g(e)` of the window's capacity a confirmation of evidence `e` nats may fill.
pub fn evidence_share(evidence_nats: f64) -> f64 {
    if evidence_nats.is_finite() { (evidence_nats / FULL_EVIDENCE_NATS).clamp(0.0, 1.0) } else { 0.0 }
}

/// Evidence (nats) of a detection of observed sum-channel SNR `snr_db` (the measurement's
/// `|Σ|²/σ²`) at a radar with per-cell false-alarm probability `pfa`: `|Σ|²/σ² + ln P_FA`, how
/// far it stands above the square-law threshold `γ = −ln P_FA` (docs/model.md §4.3). A false
/// alarm's crossing power is `γ` plus an `Exp(1)` draw, so it is this strong with probability
/// `exp(−e)`; a negative value (a primitive formed below the threshold) is 0.
pub fn evidence_nats(snr_db: f64, pfa: f64) -> f64 {
    let e = 10f64.powf(snr_db / 10.0) + pfa.ln();
    if e.is_finite() { e.max(0.0) } else { 0.0 }
}

/// The admission rule (module docs): whether a request of `energy_j` of this class fits a radar
/// whose window holds `load`, under a budget of `capacity_j = P_B·W`.
pub fn admits(capacity_j: f64, load: Load, energy_j: f64, class: LookClass) -> bool {
    match class {
        LookClass::Maintenance => load.total_j + energy_j <= capacity_j,
        LookClass::Confirmation { evidence_nats } => {
            load.total_j + energy_j + MAINTENANCE_HEADROOM * load.maintenance_j
                <= evidence_share(evidence_nats) * capacity_j
        }
    }
}

#[derive(Debug, Clone, Copy)]
struct Spent {
    start_s: f64,
    energy_j: f64,
    maintenance: bool,
}

#[derive(Debug, Clone, Copy)]
struct Pending {
    tag: u64,
    radar: RadarId,
    energy_j: f64,
    maintenance: bool,
}

/// Each radar's test-article transmit energy: what its reported dwells spent (by start time) and
/// what is requested and not yet reported.
#[derive(Debug, Clone, Default)]
pub struct PowerLedger {
    spent: BTreeMap<RadarId, VecDeque<Spent>>,
    pending: Vec<Pending>,
}

/// Dwells starting this close to the window's edge still count (s): the start is recovered from
/// the report's end and duration, so rounding never lets an entry leave early.
const EDGE_SLACK_S: f64 = 1e-6;

impl PowerLedger {
    /// Note a request for track `tag` transmitted by `radar` with `energy_j`.
    pub fn request(&mut self, tag: u64, radar: RadarId, energy_j: f64, class: LookClass) {
        let maintenance = class == LookClass::Maintenance;
        self.pending.push(Pending { tag, radar, energy_j, maintenance });
    }

    /// Record a reported test-article dwell for track `tag` (its first tag): each transmitter's
    /// energy from its start `start_s`; the request it answers stops counting as pending.
    pub fn report(&mut self, tag: Option<u64>, start_s: f64, transmits: &[(RadarId, f64)]) {
        let mut maintenance = false;
        if let Some(tag) = tag
            && let Some(k) = self.pending.iter().position(|p| p.tag == tag)
        {
            maintenance = self.pending.remove(k).maintenance;
        }
        for &(radar, energy_j) in transmits {
            if energy_j > 0.0 && start_s.is_finite() {
                self.spent.entry(radar).or_default().push_back(Spent { start_s, energy_j, maintenance });
            }
        }
    }

    /// Forget dwells whose start left the window ending at `now`; whether any did.
    pub fn prune(&mut self, now: f64, window_s: f64) -> bool {
        let mut any = false;
        for q in self.spent.values_mut() {
            while q.front().is_some_and(|s| s.start_s < now - window_s - EDGE_SLACK_S) {
                q.pop_front();
                any = true;
            }
        }
        any
    }

    /// What `radar` has committed in the window ending at `now` (after [`Self::prune`]).
    pub fn load(&self, radar: RadarId) -> Load {
        let mut l = Load::default();
        let spent = self.spent.get(&radar).into_iter().flatten().map(|s| (s.energy_j, s.maintenance));
        let pending = self.pending.iter().filter(|p| p.radar == radar).map(|p| (p.energy_j, p.maintenance));
        for (e, m) in spent.chain(pending) {
            l.total_j += e;
            if m {
                l.maintenance_j += e;
            }
        }
        l
    }

    /// The earliest time after `now` at which some radar's oldest dwell leaves the window.
    pub fn next_release_s(&self, window_s: f64) -> Option<f64> {
        self.spent
            .values()
            .filter_map(|q| q.front().map(|s| s.start_s + window_s + 2.0 * EDGE_SLACK_S))
            .min_by(f64::total_cmp)
    }

    /// Forget everything (a new run).
    pub fn clear(&mut self) {
        self.spent.clear();
        self.pending.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R1: RadarId = RadarId(0);
    const R2: RadarId = RadarId(1);

    #[test]
    fn a_budget_for_one_track_look_gives_it_to_the_track() {
        // 0.8 W over 10 s: 8 J, one 8-pulse look of 1 J pulses.
        let cap = 0.8 * 10.0;
        let empty = Load::default();
        assert!(admits(cap, empty, 8.0, LookClass::Maintenance));
        // Even the strongest confirmation must leave room: it fits alone...
        let strong = LookClass::Confirmation { evidence_nats: 20.0 };
        assert!(admits(cap, empty, 8.0, strong));
        // ...but not once the track look is committed, which then still fits a re-look budget
        // of nothing more.
        let after_track = Load { total_j: 8.0, maintenance_j: 8.0 };
        assert!(!admits(cap, after_track, 1.0, strong));
        assert!(!admits(cap, after_track, 1.0, LookClass::Maintenance));
        // A confirmation already committed does not stop the track look's...
        let after_confirm = Load { total_j: 4.0, maintenance_j: 0.0 };
        assert!(admits(cap, after_confirm, 4.0, LookClass::Maintenance));
        // ...but a confirmation cannot take the track's reserved headroom: with 4 J of
        // maintenance in the window, a confirmation of 2 J needs 4 + 2 + 0.5·4 = 8 ≤ 8.
        let half = Load { total_j: 4.0, maintenance_j: 4.0 };
        assert!(admits(cap, half, 2.0, strong));
        assert!(!admits(cap, half, 2.5, strong));
        assert!(admits(cap, half, 4.0, LookClass::Maintenance));
    }

    #[test]
    fn weak_detections_get_a_smaller_share_than_strong_ones() {
        let cap = 100.0;
        let load = Load { total_j: 30.0, maintenance_j: 20.0 };
        // 30 + 10 + 10 = 50: needs g(e) ≥ 0.5, e ≥ 3.45 nats.
        let conf = |e| LookClass::Confirmation { evidence_nats: e };
        assert!(!admits(cap, load, 10.0, conf(3.4)));
        assert!(admits(cap, load, 10.0, conf(3.5)));
        assert!(!admits(cap, load, 10.0, conf(0.0)));
        assert!(!admits(cap, load, 10.0, conf(f64::NAN)));
        assert_eq!(evidence_share(FULL_EVIDENCE_NATS), 1.0);
        assert_eq!(evidence_share(100.0), 1.0);
        assert!((evidence_share(FULL_EVIDENCE_NATS / 4.0) - 0.25).abs() < 1e-12);
        // A false alarm just at the threshold (13.8 = 11.40 dB at 1e-6) carries no evidence;
        // 4.6 nats above it, a false alarm reached once in a hundred.
        let gamma = -(1e-6f64).ln();
        assert!(evidence_nats(10.0 * gamma.log10(), 1e-6).abs() < 1e-9);
        assert!((evidence_nats(10.0 * (gamma + 4.6).log10(), 1e-6) - 4.6).abs() < 1e-9);
        assert_eq!(evidence_nats(0.0, 1e-6), 0.0);
    }

    #[test]
    fn the_ledger_counts_pending_requests_and_the_window_by_start_time() {
        let mut l = PowerLedger::default();
        l.request(7, R1, 4.0, LookClass::Maintenance);
        l.request(9, R1, 2.0, LookClass::Confirmation { evidence_nats: 1.0 });
        assert_eq!(l.load(R1), Load { total_j: 6.0, maintenance_j: 4.0 });
        assert_eq!(l.load(R2), Load::default());
        // Track 7's dwell ran from 1.0 s, transmitted by R1 (4 J) and received by R2 (no energy).
        l.report(Some(7), 1.0, &[(R1, 4.0)]);
        assert_eq!(l.load(R1), Load { total_j: 6.0, maintenance_j: 4.0 });
        l.report(Some(9), 3.0, &[(R1, 2.0)]);
        assert_eq!(l.load(R1), Load { total_j: 6.0, maintenance_j: 4.0 });
        assert!(l.pending.is_empty());
        // Window of 10 s: the 1.0-s dwell counts until 11 s, the 3.0-s one until 13 s.
        assert!(!l.prune(10.999, 10.0));
        assert_eq!(l.load(R1).total_j, 6.0);
        let release = l.next_release_s(10.0).expect("release");
        assert!(release > 11.0 && release < 11.0 + 1e-5, "{release}");
        assert!(l.prune(11.01, 10.0));
        assert_eq!(l.load(R1), Load { total_j: 2.0, maintenance_j: 0.0 });
        l.prune(13.01, 10.0);
        assert_eq!(l.load(R1), Load::default());
        assert_eq!(l.next_release_s(10.0), None);
    }

    /// For the same window, a larger budget admits everything a smaller one does.
    #[test]
    fn a_larger_budget_admits_whatever_a_smaller_one_does() {
        let mut rng = mimo_core::rng::Stream::new(20261126, &[1]);
        for _ in 0..2000 {
            let m = rng.uniform() * 50.0;
            let load = Load { total_j: m + rng.uniform() * 50.0, maintenance_j: m };
            let e = f64::from(1 + (rng.uniform() * 16.0) as u32);
            let class = if rng.uniform() < 0.3 {
                LookClass::Maintenance
            } else {
                LookClass::Confirmation { evidence_nats: rng.exp1() * 4.0 }
            };
            let mut admitted = false;
            for cap in [0.0, 5.0, 10.0, 20.0, 40.0, 80.0, 160.0, 1e9] {
                let now = admits(cap, load, e, class);
                assert!(now || !admitted, "capacity {cap} refuses what a smaller one admits");
                admitted = now;
            }
            assert!(admitted, "an unlimited budget refuses nothing");
        }
    }

    /// Looks at confirmed tracks inside one window: a larger budget never spends less. Where the
    /// two budgets first decide differently the larger admits the look, and its load then exceeds
    /// the smaller capacity, which bounds everything the smaller one ever admits. (With
    /// confirmations, whose share of the window is smaller, the order of arrival can make a larger
    /// budget spend less on one sequence; docs/model.md §7.6.)
    #[test]
    fn a_larger_budget_never_spends_less_on_track_looks() {
        let mut rng = mimo_core::rng::Stream::new(20261126, &[2]);
        for _ in 0..400 {
            let reqs: Vec<f64> = (0..40).map(|_| f64::from(1 + (rng.uniform() * 16.0) as u32)).collect();
            let spend = |cap: f64| {
                let mut l = PowerLedger::default();
                for (k, &e) in reqs.iter().enumerate() {
                    if admits(cap, l.load(R1), e, LookClass::Maintenance) {
                        l.request(k as u64, R1, e, LookClass::Maintenance);
                    }
                }
                l.load(R1).total_j
            };
            let mut last = 0.0;
            for cap in [0.0, 5.0, 10.0, 20.0, 40.0, 80.0, 160.0, 1e9] {
                let s = spend(cap);
                assert!(s >= last && s <= cap, "capacity {cap}: {s} after {last}");
                last = s;
            }
        }
    }
}
