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
    /// How a test article's search plan spaces the beams out; `None`: every idle moment (the
    /// default raster, and a plan with share 1 and no frame period).
    pub shape: Option<Box<SearchShape>>,
}

/// The pacing of a radar's search under a test article's plan (docs/model.md §7.4).
#[derive(Debug, Clone)]
pub(crate) struct SearchShape {
    /// Share of idle time given to search, in (0, 1].
    pub share: f64,
    /// Shortest time between two frame starts (ns).
    pub frame_period_ns: Option<i64>,
    /// Raster index of each frame's first beam, increasing.
    pub frame_starts: Vec<usize>,
    /// No search beam starts before then (the share's wait after the last one).
    pub next_search_at: SimTime,
    /// When the current frame's first beam started.
    pub last_frame_start: Option<SimTime>,
    /// The time of the `Decide` already scheduled for the end of a wait, if any.
    pub decide_at: Option<SimTime>,
}

impl SearchShape {
    /// When the beam at `cursor` may start at the earliest: after the share's wait and, for a
    /// frame's first beam, one frame period after the previous frame started.
    pub fn earliest_start(&self, cursor: usize) -> SimTime {
        let mut t = self.next_search_at;
        if let (Some(p), Some(last)) = (self.frame_period_ns, self.last_frame_start)
            && self.frame_starts.binary_search(&cursor).is_ok()
        {
            t = t.max(SimTime(last.0.saturating_add(p)));
        }
        t
    }

    /// A search beam at raster index `cursor` runs over `[start, end)`.
    pub fn ran(&mut self, cursor: usize, start: SimTime, end: SimTime) {
        if self.frame_starts.binary_search(&cursor).is_ok() {
            self.last_frame_start = Some(start);
        }
        if self.share < 1.0 {
            let d_ns = (end.0 - start.0) as f64;
            self.next_search_at =
                SimTime(end.0.saturating_add((d_ns * (1.0 - self.share) / self.share).round() as i64));
        }
    }
}

impl Timeline {
    /// A free radar with its raster.
    pub fn new(raster: Vec<SearchBeam>) -> Timeline {
        Timeline { busy_until: SimTime::ZERO, reservations: Vec::new(), raster, cursor: 0, shape: None }
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
