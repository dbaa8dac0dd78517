//! The expiry queue of the deletion certificates (docs/model.md §6.4).
//!
//! A track's certificate ([`crate::deletion_quiet`]) covers the checks at times `t` with
//! `0 ≤ t − t_state ≤ max_dt`. The deletion pass after a dwell needs only the tracks a certificate
//! may not cover: those changed since their certificate was made (or never certified), those
//! whose span ends before the check, and those whose state is later than the check. The queue
//! keeps the certified tracks ordered by the end and by the start of their span, so that the
//! pass finds them without visiting every track: a raid's hundreds of quiet tracks cost nothing.
//! The queue only preselects; every track it names is checked exactly as before.

use crate::track_balls::IdMap;
use std::collections::BTreeSet;
use std::ops::Bound;

/// Slack on the end of a span (s): a track whose rounded end lies this far after the check is
/// surely covered (far above the rounding of `t_state + max_dt` and of `t − t_state`).
const END_MARGIN_S: f64 = 1e-6;

/// An integer with the order of [`f64::total_cmp`].
fn order_key(x: f64) -> i64 {
    let b = x.to_bits() as i64;
    b ^ ((((b >> 63) as u64) >> 1) as i64)
}

/// Certified tracks by the ends of their spans, and the tracks no certificate covers.
#[derive(Debug, Default)]
pub(crate) struct ExpiryQueue {
    /// Certified tracks by the end of their span (`t_state + max_dt`, rounded).
    ends: BTreeSet<(i64, u64)>,
    /// Certified tracks by the time of their state.
    starts: BTreeSet<(i64, u64)>,
    /// Each certified track's keys in `starts` and `ends`.
    keys: IdMap<(i64, i64)>,
    /// Tracks that need a check at every pass: changed since their certificate, never certified,
    /// or certified with nothing promised.
    open: BTreeSet<u64>,
}

impl ExpiryQueue {
    /// Track `id` changed (or is new): it is checked at every pass until it is certified again.
    pub(crate) fn open(&mut self, id: u64) {
        self.unlink(id);
        self.open.insert(id);
    }

    /// Whether track `id` is open.
    pub(crate) fn is_open(&self, id: u64) -> bool {
        self.open.contains(&id)
    }

    /// Track `id`, in a state of time `start_s`, is certified over `0 ≤ t − start_s ≤ max_dt_s`
    /// (`max_dt_s` may be +∞; a NaN, −∞ or negative span, or a non-finite start, promises nothing
    /// and leaves the track open).
    pub(crate) fn certify(&mut self, id: u64, start_s: f64, max_dt_s: f64) {
        self.unlink(id);
        if !(start_s.is_finite() && max_dt_s >= 0.0) {
            self.open.insert(id);
            return;
        }
        self.open.remove(&id);
        let keys = (order_key(start_s), order_key(start_s + max_dt_s));
        self.starts.insert((keys.0, id));
        self.ends.insert((keys.1, id));
        self.keys.insert(id, keys);
    }

    /// Drop a deleted track.
    pub(crate) fn forget(&mut self, id: u64) {
        self.unlink(id);
        self.open.remove(&id);
    }

    /// The tracks a certificate may not cover at a check at `t_s`: the open ones, those whose
    /// span ends before `t_s` (with [`END_MARGIN_S`]) and those whose state is later than `t_s`.
    /// Every other track queued is covered, whatever rounding.
    pub(crate) fn candidates(&self, t_s: f64) -> BTreeSet<u64> {
        let mut out = self.open.clone();
        let end_limit = order_key(t_s + END_MARGIN_S);
        out.extend(self.ends.range(..(end_limit, 0)).map(|&(_, id)| id));
        let start_after = (Bound::Excluded((order_key(t_s), u64::MAX)), Bound::Unbounded);
        out.extend(self.starts.range(start_after).map(|&(_, id)| id));
        out
    }

    fn unlink(&mut self, id: u64) {
        if let Some((s, e)) = self.keys.remove(&id) {
            self.starts.remove(&(s, id));
            self.ends.remove(&(e, id));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tracks a full scan checks: those whose span does not cover `t_s` (the certificate's
    /// test, `0 ≤ t_s − start ≤ max_dt`), and the uncertified ones.
    fn scan(spans: &[(u64, Option<(f64, f64)>)], t_s: f64) -> BTreeSet<u64> {
        spans
            .iter()
            .filter(|(_, s)| match s {
                Some((start, max_dt)) => {
                    let dt = t_s - start;
                    !(dt >= 0.0 && dt <= *max_dt)
                }
                None => true,
            })
            .map(|(id, _)| *id)
            .collect()
    }

    /// On a hand-made set of spans (ends before, at and after the check, a state later than it,
    /// an unlimited span, a span promising nothing, an uncertified track, a re-certified one and
    /// a forgotten one), the queue names every track the scan checks, and only a few others
    /// (those within the margin of their span's end).
    #[test]
    fn the_queue_names_what_the_scan_checks() {
        let mut q = ExpiryQueue::default();
        let mut spans: Vec<(u64, Option<(f64, f64)>)> = vec![
            (1, Some((10.0, 5.0))),
            (2, Some((10.0, 0.5))),
            (3, Some((12.0, 30.0))),
            (4, Some((9.0, f64::INFINITY))),
            (5, Some((11.0, f64::NEG_INFINITY))),
            (6, None),
            (7, Some((10.3, 2.0))),
            (8, Some((13.7, 1.0))),
        ];
        for (id, s) in &spans {
            match s {
                Some((start, max_dt)) => q.certify(*id, *start, *max_dt),
                None => q.open(*id),
            }
        }
        // Track 7 changes: open until certified again, then its new span counts.
        q.open(7);
        assert!(q.is_open(7));
        q.certify(7, 11.5, 1.0);
        spans[6] = (7, Some((11.5, 1.0)));
        // Track 9 is certified and then deleted.
        q.certify(9, 0.0, 1.0);
        q.forget(9);
        for k in 0..400 {
            let t_s = 8.0 + 0.025 * f64::from(k);
            let named = q.candidates(t_s);
            let checked = scan(&spans, t_s);
            assert!(checked.is_subset(&named), "t {t_s}: scan {checked:?}, queue {named:?}");
            assert!(!named.contains(&9));
            // Beyond the checked tracks, only spans ending within the margin of `t_s`.
            for id in named.difference(&checked) {
                let (start, max_dt) = spans.iter().find(|s| s.0 == *id).and_then(|s| s.1).expect("certified");
                assert!(start + max_dt < t_s + END_MARGIN_S, "t {t_s}: track {id} named needlessly");
            }
        }
        // At 12.0: 1 covered (10 + 5), 2 expired, 3 starts at 12.0 (covered), 4 unlimited,
        // 5 and 6 open, 7 covered (11.5 + 1), 8 later than the check.
        assert_eq!(q.candidates(12.0), BTreeSet::from([2, 5, 6, 8]));
    }

    /// The key orders like `total_cmp`, across signs, zeros and infinities.
    #[test]
    fn order_key_orders_like_total_cmp() {
        let xs = [f64::NEG_INFINITY, -1e300, -2.5, -0.0, 0.0, 1e-300, 3.0, 1e300, f64::INFINITY];
        for a in xs {
            for b in xs {
                assert_eq!(order_key(a).cmp(&order_key(b)), a.total_cmp(&b), "{a} vs {b}");
            }
        }
    }
}
