//! Each radar's timeline budget for the test article's dwells (docs/model.md §7.3): how much of
//! the last `budget_window_s` seconds a radar spent on track, confirmation and MIMO dwells
//! (transmitting or receiving), learned from the test article's own dwell reports.

use mimo_core::ids::RadarId;
use std::collections::{BTreeMap, VecDeque};

/// One radar's busy intervals, in the order recorded.
#[derive(Debug, Clone, Default)]
struct Busy {
    intervals: VecDeque<(f64, f64)>,
    /// Whether the intervals' ends never decrease (dwell reports arrive in order of their ends,
    /// so they do unless a caller records otherwise).
    ends_sorted: bool,
}

/// Busy intervals of the test article's dwells, per radar.
#[derive(Debug, Clone, Default)]
pub struct RadarBudget {
    busy: BTreeMap<RadarId, Busy>,
}

impl RadarBudget {
    /// Record that `radar` spent `[t_s, t_s + duration_s)` on a test-article dwell.
    pub fn record(&mut self, radar: RadarId, t_s: f64, duration_s: f64) {
        if t_s.is_finite() && duration_s.is_finite() && duration_s > 0.0 {
            let busy = self.busy.entry(radar).or_insert_with(|| Busy { ends_sorted: true, ..Busy::default() });
            let end = t_s + duration_s;
            busy.ends_sorted &= busy.intervals.back().is_none_or(|&(_, b)| b <= end);
            busy.intervals.push_back((t_s, end));
        }
    }

    /// Fraction of `[now − window_s, now]` that `radar` spent on test-article dwells. Nothing is
    /// forgotten here, so windows of different lengths can be asked in any order
    /// ([`RadarBudget::forget_before`] drops what no window reaches). The intervals that ended
    /// before the window add nothing (a zero, which leaves the sum as it is): when the ends are
    /// in order they are a prefix, skipped without a visit.
    pub fn share(&self, radar: RadarId, now: f64, window_s: f64) -> f64 {
        let Some(busy) = self.busy.get(&radar) else { return 0.0 };
        let from = now - window_s;
        let skip = if busy.ends_sorted { busy.intervals.partition_point(|&(_, b)| b <= from) } else { 0 };
        let used: f64 = busy.intervals.range(skip..).map(|&(a, b)| (b.min(now) - a.max(from)).max(0.0)).sum();
        used / window_s
    }

    /// Forget the busy intervals that ended at or before `t_s`.
    pub fn forget_before(&mut self, t_s: f64) {
        for busy in self.busy.values_mut() {
            let q = &mut busy.intervals;
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

    /// The share skipping the intervals that ended before the window is the full walk's, bit
    /// for bit (up to the sign of a zero), with ends in order and out of order.
    #[test]
    fn skipping_what_ended_before_the_window_changes_nothing() {
        let walk = |q: &[(f64, f64)], now: f64, w: f64| {
            let from = now - w;
            q.iter().map(|&(a, b)| (b.min(now) - a.max(from)).max(0.0)).sum::<f64>() / w
        };
        for shuffled in [false, true] {
            let mut b = RadarBudget::default();
            let r = RadarId(1);
            let mut q = Vec::new();
            for k in 0..400 {
                let t = 0.037 * f64::from(k) + if shuffled && k % 7 == 3 { -0.5 } else { 0.0 };
                let d = 0.004 + 0.001 * f64::from(k % 5);
                b.record(r, t, d);
                q.push((t, t + d));
            }
            assert_eq!(b.busy[&r].ends_sorted, !shuffled);
            for now in [0.5, 3.3, 7.77, 12.0, 15.2] {
                for w in [0.25, 2.0, 8.0] {
                    let (got, want) = (b.share(r, now, w), walk(&q, now, w));
                    assert!(got == want && (got != 0.0 || want == 0.0), "{got} against {want} at {now} s, {w} s");
                    assert!(got.to_bits() == want.to_bits() || got == 0.0, "bits differ at {now} s, {w} s");
                }
            }
        }
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
