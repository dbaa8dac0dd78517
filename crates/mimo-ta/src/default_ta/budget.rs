//! Each radar's timeline budget for the test article's dwells (docs/model.md §7.3): how much of
//! the last `budget_window_s` seconds a radar spent on track, confirmation and MIMO dwells
//! (transmitting or receiving), learned from the test article's own dwell reports.

use mimo_core::ids::RadarId;
use std::collections::{BTreeMap, VecDeque};

/// Busy intervals of the test article's dwells, per radar.
#[derive(Debug, Clone, Default)]
pub struct RadarBudget {
    busy: BTreeMap<RadarId, VecDeque<(f64, f64)>>,
}

impl RadarBudget {
    /// Record that `radar` spent `[t_s, t_s + duration_s)` on a test-article dwell.
    pub fn record(&mut self, radar: RadarId, t_s: f64, duration_s: f64) {
        if t_s.is_finite() && duration_s.is_finite() && duration_s > 0.0 {
            self.busy.entry(radar).or_default().push_back((t_s, t_s + duration_s));
        }
    }

    /// Fraction of `[now − window_s, now]` that `radar` spent on test-article dwells. Nothing is
    /// forgotten here, so windows of different lengths can be asked in any order
    /// ([`RadarBudget::forget_before`] drops what no window reaches).
    pub fn share(&self, radar: RadarId, now: f64, window_s: f64) -> f64 {
        let Some(q) = self.busy.get(&radar) else { return 0.0 };
        let from = now - window_s;
        let used: f64 = q.iter().map(|&(a, b)| (b.min(now) - a.max(from)).max(0.0)).sum();
        used / window_s
    }

    /// Forget the busy intervals that ended at or before `t_s`.
    pub fn forget_before(&mut self, t_s: f64) {
        for q in self.busy.values_mut() {
            while q.front().is_some_and(|&(_, end)| end <= t_s) {
                q.pop_front();
            }
        }
    }

    /// Forget everything (a new run).
    pub fn clear(&mut self) {
        self.busy.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn share_counts_only_the_window() {
        let mut b = RadarBudget::default();
        let r = RadarId(0);
        b.record(r, 0.0, 1.0);
        b.record(r, 8.0, 1.0);
        b.record(r, 9.5, 0.5);
        // Window [5, 10]: 1.0 + 0.5 of 5 s.
        assert!((b.share(r, 10.0, 5.0) - 0.3).abs() < 1e-12);
        assert_eq!(b.share(RadarId(1), 10.0, 5.0), 0.0);
        // Window [8.5, 10.5]: 0.5 + 0.5 of 2 s.
        assert!((b.share(r, 10.5, 2.0) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn a_short_window_asked_first_leaves_a_long_one_whole() {
        let mut b = RadarBudget::default();
        let r = RadarId(2);
        b.record(r, 1.0, 2.0);
        b.record(r, 6.0, 1.0);
        // [2, 10]: 1 + 1 of 8 s; [7, 10]: nothing.
        assert_eq!(b.share(r, 10.0, 3.0), 0.0);
        assert!((b.share(r, 10.0, 8.0) - 0.25).abs() < 1e-12);
        // Forgetting before the long window's start keeps its share.
        b.forget_before(2.0);
        assert!((b.share(r, 10.0, 8.0) - 0.25).abs() < 1e-12);
        b.forget_before(7.0);
        assert_eq!(b.share(r, 10.0, 8.0), 0.0);
    }
}
