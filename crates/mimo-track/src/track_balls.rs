//! Where a track can be over the next seconds: a ball that holds every mode's predicted position,
//! and a bound of every mode's position trace, valid over a window of prediction intervals and
//! kept until the track is updated (docs/model.md §6.5).
//!
//! Every receive channel gates every track, so without it a channel's cost grows with the tracks
//! and a run's with their square: each pair first needed the track's prediction (for an IMM, its
//! mixing and mean prediction) before the pre-gate could reject it. With constant-velocity modes
//! a mode's predicted mean is its mixed prior's `p + dt·v`, and the mixed priors are convex
//! combinations of the modes, so for every `dt` in `[a, b]` every predicted mode mean (and the
//! combined one) lies in the hull of the points `p_i + a·v_i` and `p_i + b·v_i`: the ball around
//! their centroid through the farthest holds them. The IMM's convex trace bound
//! ([`TrackFilter::position_trace_upper_convex`]) at `a` and `b` bounds every mode's trace over
//! the window. A channel then rejects a far track with two distances, and the rest are gated
//! exactly as before: the gated table, the association and the tracks are the same, bit for bit.

use crate::filter::TrackFilter;
use crate::tracker::Track;
use mimo_core::DVec3;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// Length of the window of prediction intervals a ball covers (s): long enough to serve the
/// dwells between two updates of a track, short enough that the ball stays a few km wide.
pub(crate) const WINDOW_S: f64 = 4.0;

/// Relative slack on the radius, far above its rounding.
const RADIUS_MARGIN: f64 = 1e-6;

/// A track's ball over prediction intervals `[dt_lo_s, dt_hi_s]` from its state, named by the
/// state's time and update count (a track's state changes only in an update, which sets both:
/// `crate::state_stamp`; the ball keeps no copy of the state, so that checking it stays cheap).
#[derive(Debug, Clone)]
pub(crate) struct TrackBall {
    t_s: f64,
    n_updates: u32,
    dt_lo_s: f64,
    dt_hi_s: f64,
    /// Centre (tracking frame, m).
    pub(crate) centre: DVec3,
    /// Radius holding every mode's predicted position (m).
    pub(crate) radius_m: f64,
    /// Upper bound of every mode's predicted position trace (m²).
    pub(crate) trace_max_m2: f64,
}

impl TrackBall {
    /// The ball of `track` over `[dt_s, dt_s + WINDOW_S]`, or `None` when the filter offers no
    /// constant-velocity bound (then the channel gates the track the usual way).
    fn of(filter: &dyn TrackFilter, track: &Track, dt_s: f64) -> Option<TrackBall> {
        let (a, b) = (dt_s, dt_s + WINDOW_S);
        let trace_max_m2 = filter
            .position_trace_upper_convex(&track.state, a)?
            .max(filter.position_trace_upper_convex(&track.state, b)?);
        let ends: Vec<DVec3> = track
            .state
            .modes
            .iter()
            .flat_map(|g| {
                let (p, v) = (DVec3::new(g.x[0], g.x[1], g.x[2]), DVec3::new(g.x[3], g.x[4], g.x[5]));
                [p + a * v, p + b * v]
            })
            .collect();
        let centre = ends.iter().fold(DVec3::ZERO, |s, e| s + *e) / ends.len() as f64;
        let far = ends.iter().map(|e| (*e - centre).length()).fold(0.0, f64::max);
        let radius_m = far * (1.0 + RADIUS_MARGIN) + RADIUS_MARGIN;
        let finite = centre.is_finite() && radius_m.is_finite() && trace_max_m2.is_finite() && trace_max_m2 >= 0.0;
        let (t_s, n_updates) = (track.t_s, track.n_updates);
        finite.then_some(TrackBall { t_s, n_updates, dt_lo_s: a, dt_hi_s: b, centre, radius_m, trace_max_m2 })
    }

    /// Whether the ball holds predictions of `track` over `dt_s`.
    pub(crate) fn covers(&self, track: &Track, dt_s: f64) -> bool {
        dt_s >= self.dt_lo_s
            && dt_s <= self.dt_hi_s
            && self.t_s.to_bits() == track.t_s.to_bits()
            && self.n_updates == track.n_updates
    }
}

/// A hasher for track ids (distinct integers, counted up): one multiply by the golden ratio.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct IdHasher(u64);

impl Hasher for IdHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0.rotate_left(8) ^ u64::from(*b)).wrapping_mul(0x9E37_79B9_7F4A_7C15);
        }
    }
    fn write_u64(&mut self, id: u64) {
        self.0 = (self.0 ^ id).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

/// A map by track id.
pub(crate) type IdMap<V> = HashMap<u64, V, BuildHasherDefault<IdHasher>>;

/// The balls of the tracker's tracks.
#[derive(Debug, Default)]
pub(crate) struct TrackBalls {
    by_track: IdMap<TrackBall>,
}

impl TrackBalls {
    /// A ball of `track` covering `dt_s`, made anew when the kept one does not.
    pub(crate) fn get(&mut self, filter: &dyn TrackFilter, track: &Track, dt_s: f64) -> Option<&TrackBall> {
        let fresh = self.by_track.get(&track.id).is_some_and(|b| b.covers(track, dt_s));
        if !fresh {
            match TrackBall::of(filter, track, dt_s) {
                Some(b) => {
                    self.by_track.insert(track.id, b);
                }
                None => {
                    self.by_track.remove(&track.id);
                }
            }
        }
        self.by_track.get(&track.id)
    }

    /// Drop a deleted track's ball.
    pub(crate) fn forget(&mut self, id: u64) {
        self.by_track.remove(&id);
    }
}
