//! Radar timelines: what each radar is doing now, the reservations ahead of it, and where its
//! background search raster stands (docs/design.md §5).

use crate::search::SearchBeam;
use mimo_core::time::SimTime;

/// One radar's timeline.
pub(crate) struct Timeline {
    /// The radar is busy until then.
    pub busy_until: SimTime,
    /// Future reservations `(start, end, group)`, sorted by start.
    pub reservations: Vec<(SimTime, SimTime, u64)>,
    /// The radar's search raster, visited cyclically.
    pub raster: Vec<SearchBeam>,
    /// Next beam of the raster.
    pub cursor: usize,
}

impl Timeline {
    /// A free radar with its raster.
    pub fn new(raster: Vec<SearchBeam>) -> Timeline {
        Timeline { busy_until: SimTime::ZERO, reservations: Vec::new(), raster, cursor: 0 }
    }

    /// Start of the next reservation, if any.
    pub fn next_reservation(&self) -> Option<SimTime> {
        self.reservations.first().map(|x| x.0)
    }

    /// Reserve `[start, end)` for group `gid`, keeping the list sorted by start.
    pub fn reserve(&mut self, start: SimTime, end: SimTime, gid: u64) {
        let pos = self.reservations.partition_point(|x| x.0 <= start);
        self.reservations.insert(pos, (start, end, gid));
    }

    /// The group starts now and keeps the radar busy until `end`.
    pub fn begin(&mut self, gid: u64, end: SimTime) {
        self.reservations.retain(|x| x.2 != gid);
        self.busy_until = end;
    }
}

/// The earliest start at or after `earliest` when every timeline in `radars` is free for
/// `dur_ns` nanoseconds: first come, first served, never moving an earlier reservation.
pub(crate) fn earliest_common_slot(
    timelines: &[Timeline],
    radars: &[usize],
    earliest: SimTime,
    dur_ns: i64,
) -> SimTime {
    let mut t = earliest;
    for &r in radars {
        t = t.max(timelines[r].busy_until);
    }
    // Move past overlapping reservations until every participant is free for [t, t+dur).
    loop {
        let mut moved = false;
        for &r in radars {
            for &(s, e, _) in &timelines[r].reservations {
                if s.0 < t.0 + dur_ns && t < e {
                    t = e;
                    moved = true;
                }
            }
        }
        if !moved {
            return t;
        }
    }
}
