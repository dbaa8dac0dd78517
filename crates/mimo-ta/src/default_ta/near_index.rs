//! The tracks that may lie near a point at a scheduling pass's instant (docs/model.md §7.2,
//! "Group looks", and the resolution-cell test of the unresolved hold).
//!
//! A pass asks, for each look, which other tracks may sit in its beam (group looks) or in its
//! resolution cell. Asking every track's position ball each time costs looks × tracks per pass,
//! and listing every ball once per pass costs tracks per pass: under a raid either dominates the
//! scheduling. The index keeps each track's ball (mimo-track's `PositionBall`, which holds the
//! track's predicted position over a few seconds while it is not updated) in a grid of
//! [`CELL_M`] cubes by its centre (ECEF), across passes. Before a pass's first query it renews
//! only the balls that may have gone stale: those of the tracks the last dwells changed (the
//! tracker lists them) and those whose window ends by the pass's instant. A query reads the
//! cubes within its distance plus [`WIDE_M`] and tests each ball there exactly; balls wider than
//! [`WIDE_M`] are listed apart and tested every time, tracks without a ball are always returned.
//!
//! A query returns a superset of the tracks whose predicted position lies within the distance:
//! callers apply their own exact test to what it returns, so their answers are the ones a walk
//! over every track gives, bit for bit.

use super::due_index::order_key;
use mimo_core::DVec3;
use mimo_track::position_ball::PositionBall;
use mimo_track::{MultiTargetTracker, TrackDue};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::hash::{BuildHasherDefault, Hasher};

/// Edge of the grid's cubes (m).
pub const CELL_M: f64 = 10_000.0;
/// Radius (m) above which a ball is kept out of the grid.
pub const WIDE_M: f64 = 5_000.0;
/// A ball whose window ends within this of a pass's instant (s) is checked again.
const EXPIRY_MARGIN_S: f64 = 1e-6;

/// Where a track sits in the index.
#[derive(Debug, Clone, Copy)]
enum Place {
    /// In the grid's cube `key`, its ball ending at `expiry` ([`order_key`]).
    Cube { key: [i64; 3], expiry: i64 },
    /// Wide ball, ending at `expiry`.
    Wide { expiry: i64 },
    /// No ball.
    Unbounded,
}

fn cube_of(p: DVec3) -> [i64; 3] {
    [p.x, p.y, p.z].map(|c| (c / CELL_M).floor() as i64)
}

/// A hasher for cube keys (three small integers): a multiply and a rotation per word, where the
/// standard SipHash cost more than the lookups it serves. Iteration order never reaches an
/// answer: queries sort what they return.
#[derive(Debug, Default, Clone, Copy)]
struct CubeHasher(u64);

impl Hasher for CubeHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x517c_c1b7_2722_0a95);
    }
    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

/// The tracks' balls, kept across passes, and their grid.
#[derive(Debug, Default)]
pub struct NearIndex {
    /// Each indexed track's ball.
    balls: BTreeMap<u64, PositionBall>,
    place: BTreeMap<u64, Place>,
    cubes: HashMap<[i64; 3], Vec<u64>, BuildHasherDefault<CubeHasher>>,
    wide: BTreeSet<u64>,
    unbounded: BTreeSet<u64>,
    /// `(end of window, id)` of every ball.
    expiry: BTreeSet<(i64, u64)>,
    /// Tracks changed since the last refresh.
    dirty: BTreeSet<u64>,
    /// The instant of the last refresh (`None`: nothing indexed yet).
    t_s: Option<f64>,
}

impl NearIndex {
    /// The tracks `ids` changed (started, updated, looked at, deleted): renew them at the next
    /// refresh.
    pub fn mark(&mut self, ids: &[u64]) {
        self.dirty.extend(ids.iter().copied());
    }

    /// Bring the index to the instant `t_s` of `tracker`: every live track indexed with a ball
    /// that holds at `t_s` (or none). The first refresh, and one going back in time, index every
    /// track.
    pub fn refresh(&mut self, tracker: &MultiTargetTracker, t_s: f64) {
        let ids: Vec<u64> = match self.t_s {
            Some(t0) if t_s >= t0 => {
                let until = order_key(t_s + EXPIRY_MARGIN_S);
                let expired = self.expiry.iter().take_while(|(k, _)| *k <= until).map(|(_, id)| *id);
                let mut ids: Vec<u64> = expired.chain(self.dirty.iter().copied()).collect();
                ids.sort_unstable();
                ids.dedup();
                ids
            }
            _ => {
                *self = NearIndex { balls: std::mem::take(&mut self.balls), ..NearIndex::default() };
                tracker.track_dues().map(|d| d.id).collect()
            }
        };
        for id in ids {
            self.renew(tracker, id, t_s);
        }
        self.dirty.clear();
        self.t_s = Some(t_s);
    }

    /// Take track `id` out of the grid and the lists.
    fn unplace(&mut self, id: u64) {
        match self.place.remove(&id) {
            Some(Place::Cube { key, expiry }) => {
                if let Some(v) = self.cubes.get_mut(&key) {
                    v.retain(|&x| x != id);
                    if v.is_empty() {
                        self.cubes.remove(&key);
                    }
                }
                self.expiry.remove(&(expiry, id));
            }
            Some(Place::Wide { expiry }) => {
                self.wide.remove(&id);
                self.expiry.remove(&(expiry, id));
            }
            Some(Place::Unbounded) => {
                self.unbounded.remove(&id);
            }
            None => {}
        }
    }

    /// Index track `id` anew at `t_s`: its kept ball if it still holds, else a new one; gone
    /// when the tracker no longer has it.
    fn renew(&mut self, tracker: &MultiTargetTracker, id: u64, t_s: f64) {
        self.unplace(id);
        let Some(due) = tracker.track_due(id) else {
            self.balls.remove(&id);
            return;
        };
        let place = match self.fresh_ball(tracker, &due, t_s) {
            Some((centre, radius_m, last_s)) => {
                let expiry = order_key(last_s);
                self.expiry.insert((expiry, id));
                if radius_m <= WIDE_M {
                    let key = cube_of(centre);
                    self.cubes.entry(key).or_default().push(id);
                    Place::Cube { key, expiry }
                } else {
                    self.wide.insert(id);
                    Place::Wide { expiry }
                }
            }
            None => {
                self.unbounded.insert(id);
                Place::Unbounded
            }
        };
        self.place.insert(id, place);
    }

    /// The kept ball of `due` if it holds at `t_s`, else a new one (kept), as (centre, radius,
    /// last time).
    fn fresh_ball(&mut self, tracker: &MultiTargetTracker, due: &TrackDue, t_s: f64) -> Option<(DVec3, f64, f64)> {
        if !self.balls.get(&due.id).is_some_and(|b| b.holds(due, t_s)) {
            match tracker.position_ball(due.id, t_s).filter(|b| b.holds(due, t_s)) {
                Some(b) => self.balls.insert(due.id, b),
                None => self.balls.remove(&due.id),
            };
        }
        self.balls.get(&due.id).map(|b| (b.centre_ecef, b.radius_m, b.last_time_s()))
    }

    /// The ball of `due` at `t_s` (centre, radius), if it has one; a ball made anew (the index
    /// not refreshed at `t_s`) is placed in the grid too.
    pub fn ball(&mut self, tracker: &MultiTargetTracker, due: &TrackDue, t_s: f64) -> Option<(DVec3, f64)> {
        // Refreshed at `t_s`, the index holds every track's ball (or its lack) at `t_s`.
        let current = self.t_s == Some(t_s) && self.place.contains_key(&due.id);
        if let Some(b) = self.balls.get(&due.id).filter(|b| current || b.holds(due, t_s)) {
            return Some((b.centre_ecef, b.radius_m));
        }
        if current {
            return None;
        }
        if self.t_s.is_some() {
            self.renew(tracker, due.id, t_s);
        } else {
            self.fresh_ball(tracker, due, t_s);
        }
        self.balls.get(&due.id).map(|b| (b.centre_ecef, b.radius_m))
    }

    /// The indexed tracks whose ball reaches within `dist_m` of `point` (`|centre − point| ≤
    /// dist_m + radius`) and those without a ball, by id.
    pub fn near(&self, point: DVec3, dist_m: f64) -> Vec<u64> {
        let within =
            |id: &u64| self.balls.get(id).is_none_or(|b| (b.centre_ecef - point).length() <= dist_m + b.radius_m);
        let mut out: Vec<u64> = Vec::new();
        // The cubes a narrow ball within reach can have its centre in, axis by axis.
        let reach_m = dist_m + WIDE_M;
        let lo = cube_of(point - DVec3::splat(reach_m));
        let hi = cube_of(point + DVec3::splat(reach_m));
        let span = |k: usize| (hi[k] - lo[k] + 1) as f64;
        if span(0) * span(1) * span(2) <= self.cubes.len() as f64 {
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        if let Some(v) = self.cubes.get(&[x, y, z]) {
                            out.extend(v.iter().copied().filter(within));
                        }
                    }
                }
            }
        } else {
            // Fewer cubes hold balls than the reach spans: visit those.
            let inside = |key: &[i64; 3]| (0..3).all(|k| lo[k] <= key[k] && key[k] <= hi[k]);
            for (_, v) in self.cubes.iter().filter(|(key, _)| inside(key)) {
                out.extend(v.iter().copied().filter(within));
            }
        }
        out.extend(self.wide.iter().copied().filter(within));
        out.extend(self.unbounded.iter().copied());
        out.sort_unstable();
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::default_ta::fixture::minute_of_scenario_7;

    /// After a minute of scenario 7, at the instant of the fixture, seconds later (balls expire)
    /// and back in time (the index is rebuilt): every track whose predicted position lies within
    /// the distance of a query is returned, nothing the tracker does not have is, and small
    /// queries leave tracks out.
    #[test]
    fn every_track_within_the_distance_is_returned() {
        let (ta, _geom) = minute_of_scenario_7();
        let tracker = ta.tracker().expect("started");
        let ids: Vec<u64> = tracker.track_dues().map(|d| d.id).collect();
        assert!(ids.len() >= 4, "{} tracks", ids.len());
        let mut index = NearIndex::default();
        let (mut queries, mut left_out) = (0, 0);
        for t_s in [60.4, 61.0, 63.5, 66.0, 75.0, 58.0] {
            index.refresh(tracker, t_s);
            let points: Vec<DVec3> = ids.iter().filter_map(|&id| tracker.predict_position(id, t_s)).collect();
            for &p in &points {
                for dist_m in [0.0, 300.0, 1_500.0, 20_000.0, 200_000.0] {
                    let near = index.near(p, dist_m);
                    assert!(near.windows(2).all(|w| w[0] < w[1]), "not sorted and distinct");
                    assert!(near.iter().all(|id| ids.contains(id)), "a track the tracker does not have");
                    for &id in &ids {
                        let q = tracker.predict_position(id, t_s).expect("position");
                        if (q - p).length() <= dist_m {
                            assert!(
                                near.contains(&id),
                                "track {id} at {} m of the point left out at {t_s} s",
                                (q - p).length()
                            );
                        }
                    }
                    queries += 1;
                    left_out += ids.len() - near.len();
                }
            }
        }
        assert!(queries > 100 && left_out > queries, "{queries} queries left {left_out} tracks out");
    }
}
