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

    /// Fraction of `[now − window_s, now]` that `radar` spent on test-article dwells; older
    /// intervals are forgotten.
    pub fn share(&mut self, radar: RadarId, now: f64, window_s: f64) -> f64 {
        let Some(q) = self.busy.get_mut(&radar) else { return 0.0 };
        let from = now - window_s;
        while q.front().is_some_and(|&(_, end)| end <= from) {
            q.pop_front();
        }
        let used: f64 = q.iter().map(|&(a, b)| (b.min(now) - a.max(from)).max(0.0)).sum();
        used / window_s
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
}
