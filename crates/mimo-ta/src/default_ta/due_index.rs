//! The live tracks ordered by when they may next be looked at (docs/model.md §7.1, §7.3).
//!
//! A track may be looked at from its due time (the tracker's `next_due_s`), or from the end of
//! its hold when the scheduler holds it as unresolved, whichever is later. A scheduling pass
//! needs the tracks due now, the earliest time one of the others falls due, and the confirmed
//! tracks due within the group look-ahead. Found by walking every track, each pass cost a raid's
//! hundreds of tracks, and a run their square; the index keeps the tracks ordered by that time,
//! updated only for the tracks a dwell changed or a pass held, so a pass visits the due tracks
//! alone. Every answer is the walk's: the same tracks, the same times.

use crate::default_ta::held_due;
use mimo_core::records::TrackStatus;
use mimo_track::MultiTargetTracker;
use std::collections::{BTreeMap, BTreeSet};
use std::ops::Bound;

/// An integer with the order of [`f64::total_cmp`] (which is `<`'s for numbers, once −0 is
/// made +0 by adding 0).
pub(super) fn order_key(x: f64) -> i64 {
    let b = (x + 0.0).to_bits() as i64;
    b ^ ((((b >> 63) as u64) >> 1) as i64)
}

/// Live tracks by the time from which they may be looked at.
#[derive(Debug, Default)]
pub struct DueIndex {
    by_time: BTreeSet<(i64, u64)>,
    /// The confirmed tracks of `by_time`.
    confirmed_by_time: BTreeSet<(i64, u64)>,
    /// Each track's time and whether it is confirmed.
    time_of: BTreeMap<u64, (f64, bool)>,
}

impl DueIndex {
    /// Forget every track.
    pub fn clear(&mut self) {
        self.by_time.clear();
        self.confirmed_by_time.clear();
        self.time_of.clear();
    }

    /// Track `id` may be looked at from `due_s`, and is confirmed or not (`None`: the track is
    /// gone).
    pub fn set(&mut self, id: u64, due_s: Option<(f64, bool)>) {
        if let Some((old, _)) = self.time_of.remove(&id) {
            self.by_time.remove(&(order_key(old), id));
            self.confirmed_by_time.remove(&(order_key(old), id));
        }
        if let Some((t, confirmed)) = due_s {
            self.time_of.insert(id, (t, confirmed));
            self.by_time.insert((order_key(t), id));
            if confirmed {
                self.confirmed_by_time.insert((order_key(t), id));
            }
        }
    }

    /// Track `id`'s entry from the tracker and the holds: its [`held_due`], or gone.
    pub fn refresh(&mut self, tracker: &MultiTargetTracker, hold_until: &BTreeMap<u64, f64>, id: u64) {
        let due =
            tracker.track_due(id).map(|d| (held_due(hold_until, id, d.next_due_s), d.status == TrackStatus::Confirmed));
        self.set(id, due);
    }

    /// The tracks with a time `≤ limit_s`, by id.
    pub fn due_by(&self, limit_s: f64) -> BTreeSet<u64> {
        self.up_to(&self.by_time, limit_s).into_iter().collect()
    }

    /// The confirmed tracks with a time `≤ limit_s`, by id.
    pub fn confirmed_due_by(&self, limit_s: f64) -> Vec<u64> {
        let mut ids = self.up_to(&self.confirmed_by_time, limit_s);
        ids.sort_unstable();
        ids
    }

    /// The tracks of `set` with a time `≤ limit_s`, in the set's order.
    fn up_to(&self, set: &BTreeSet<(i64, u64)>, limit_s: f64) -> Vec<u64> {
        set.range(..=(order_key(limit_s), u64::MAX))
            .filter(|&&(_, id)| self.time_of.get(&id).is_some_and(|&(t, _)| t <= limit_s))
            .map(|&(_, id)| id)
            .collect()
    }

    /// The earliest time `> limit_s` of a track `skip` does not name (NaN times ignored), if any.
    pub fn next_after(&self, limit_s: f64, skip: impl Fn(u64) -> bool) -> Option<f64> {
        let after = (Bound::Excluded((order_key(limit_s), u64::MAX)), Bound::Unbounded);
        self.by_time
            .range(after)
            .filter(|&&(_, id)| !skip(id))
            .filter_map(|&(_, id)| self.time_of.get(&id).map(|&(t, _)| t))
            .find(|t| !t.is_nan())
    }

    /// Every track's time and whether it is confirmed, by id (for the tests' comparison with
    /// the tracker).
    #[cfg(test)]
    pub fn times(&self) -> &BTreeMap<u64, (f64, bool)> {
        &self.time_of
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// On a hand-made set of times (ties, a NaN, ±0, +∞, a track moved and one removed), the
    /// index's answers are the walk's over every track.
    #[test]
    fn answers_are_the_walks() {
        let times: Vec<(u64, f64)> = vec![
            (1, 5.0),
            (2, 3.0),
            (3, 5.0),
            (4, f64::NAN),
            (5, -0.0),
            (6, f64::INFINITY),
            (7, 4.5),
            (8, 9.0),
            (9, 0.0),
        ];
        let mut index = DueIndex::default();
        for &(id, t) in &times {
            index.set(id, Some((t, id % 2 == 1)));
        }
        index.set(7, Some((6.5, false)));
        index.set(8, None);
        let live: Vec<(u64, f64)> =
            times.iter().filter(|(id, _)| *id != 8).map(|&(id, t)| if id == 7 { (id, 6.5) } else { (id, t) }).collect();
        for limit in [-1.0, -0.0, 0.0, 2.9, 3.0, 5.0, 6.0, 7.0, 1e300, f64::INFINITY] {
            let walk_due: BTreeSet<u64> = live.iter().filter(|(_, t)| *t <= limit).map(|p| p.0).collect();
            assert_eq!(index.due_by(limit), walk_due, "due by {limit}");
            // Odd ids are confirmed, but 7 no longer.
            let walk_confirmed: Vec<u64> = walk_due.iter().copied().filter(|id| id % 2 == 1 && *id != 7).collect();
            assert_eq!(index.confirmed_due_by(limit), walk_confirmed, "confirmed due by {limit}");
            for skipped in [None, Some(3), Some(7)] {
                let skip = |id: u64| Some(id) == skipped;
                let walk_next = live
                    .iter()
                    .filter(|(id, t)| (*t > limit || t.is_nan()) && !skip(*id))
                    .fold(f64::INFINITY, |m, (_, t)| m.min(*t));
                let next = index.next_after(limit, skip).unwrap_or(f64::INFINITY);
                assert_eq!(next.to_bits(), walk_next.to_bits(), "next after {limit}, skipping {skipped:?}");
            }
        }
        assert_eq!(index.due_by(5.0), BTreeSet::from([1, 2, 3, 5, 9]));
        assert_eq!(index.next_after(5.0, |_| false), Some(6.5));
    }
}
