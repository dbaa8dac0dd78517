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
use crate::measurement::BistaticRuv;
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
    pub(crate) fn of(filter: &dyn TrackFilter, track: &Track, dt_s: f64) -> Option<TrackBall> {
        let (a, b) = (dt_s, dt_s + WINDOW_S);
        let trace_max_m2 = filter
            .position_trace_upper_convex(&track.state, a)?
            .max(filter.position_trace_upper_convex(&track.state, b)?);
        if !trace_max_m2.is_finite() {
            return None;
        }
        Self::of_means(track, a, b, trace_max_m2)
    }

    /// The ball of `track`'s predicted positions over `[dt_s, dt_s + WINDOW_S]` alone, for a
    /// filter whose one mode's mean moves at constant velocity
    /// ([`TrackFilter::mean_constant_velocity`]): no bound of the covariance (its trace bound is
    /// infinite, so no gate may use it).
    pub(crate) fn of_position(filter: &dyn TrackFilter, track: &Track, dt_s: f64) -> Option<TrackBall> {
        if !filter.mean_constant_velocity(&track.state) {
            return None;
        }
        Self::of_means(track, dt_s, dt_s + WINDOW_S, f64::INFINITY)
    }

    /// The ball around the modes' means moved at constant velocity to `a` and `b`.
    fn of_means(track: &Track, a: f64, b: f64, trace_max_m2: f64) -> Option<TrackBall> {
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
        let finite = centre.is_finite() && radius_m.is_finite() && !trace_max_m2.is_nan() && trace_max_m2 >= 0.0;
        let (t_s, n_updates) = (track.t_s, track.n_updates);
        finite.then_some(TrackBall { t_s, n_updates, dt_lo_s: a, dt_hi_s: b, centre, radius_m, trace_max_m2 })
    }

    /// Whether no point of the ball lies within sine-space distance `theta` of the beam
    /// `(beam_u, beam_v)` of the receive face `m` (its `(u, v)` as [`BistaticRuv::h_pos`] gives
    /// them): then no prediction the ball holds is in that beam. `false` means "unsure". A point
    /// of a ball of radius `ρ` whose centre lies at face distance `R ≥ 2ρ` is seen within
    /// `1.05 ρ/R` of the centre in sine space (an angle `asin(ρ/R)`, and a rotation keeps lengths).
    pub(crate) fn clear_of_beam(&self, m: &BistaticRuv, beam_u: f64, beam_v: f64, theta: f64) -> bool {
        let l = crate::linalg::mul_vec(&m.m, &(self.centre - m.rx).to_array());
        let range_m = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
        if !(range_m > 0.0 && range_m >= 2.0 * self.radius_m) {
            return false;
        }
        let (du, dv) = (l[0] / range_m - beam_u, l[1] / range_m - beam_v);
        let need = theta + 1.05 * self.radius_m / range_m;
        du * du + dv * dv > need * need
    }

    /// The last prediction interval the ball covers (s from its state).
    pub(crate) fn dt_hi_s(&self) -> f64 {
        self.dt_hi_s
    }

    /// Whether `dt_s` lies in the ball's window of prediction intervals.
    pub(crate) fn covers_dt(&self, dt_s: f64) -> bool {
        dt_s >= self.dt_lo_s && dt_s <= self.dt_hi_s
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

    /// The kept ball of `track` when it covers `dt_s` (none is made).
    pub(crate) fn kept(&self, track: &Track, dt_s: f64) -> Option<&TrackBall> {
        self.by_track.get(&track.id).filter(|b| b.covers(track, dt_s))
    }

    /// Drop a deleted track's ball.
    pub(crate) fn forget(&mut self, id: u64) {
        self.by_track.remove(&id);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::rng::Stream;

    /// A random rotation (tracking frame → face), row-major, from three random angles.
    fn rotation(s: &mut Stream) -> crate::linalg::Mat3 {
        let (a, b, c) = (6.3 * s.uniform(), 3.1 * s.uniform() - 1.55, 6.3 * s.uniform());
        let rz = |t: f64| [[t.cos(), -t.sin(), 0.0], [t.sin(), t.cos(), 0.0], [0.0, 0.0, 1.0]];
        let ry = |t: f64| [[t.cos(), 0.0, t.sin()], [0.0, 1.0, 0.0], [-t.sin(), 0.0, t.cos()]];
        crate::linalg::mul(&crate::linalg::mul(&rz(a), &ry(b)), &rz(c))
    }

    /// A ball clear of a beam holds no point in that beam, on random faces, beams and balls
    /// (each ball sampled inside, and on its surface), and balls are found clear often.
    #[test]
    fn no_point_of_a_ball_clear_of_a_beam_is_in_it() {
        let mut s = Stream::new(7, &[41]);
        let theta = 0.0252;
        let (mut clear, mut unsure) = (0, 0);
        for _ in 0..2000 {
            let m =
                BistaticRuv { tx: DVec3::new(1e3, -2e3, 5.0), rx: DVec3::new(-3e3, 4e3, 20.0), m: rotation(&mut s) };
            let (bu, bv) = (0.8 * s.uniform() - 0.4, 0.8 * s.uniform() - 0.4);
            // A ball a few beamwidths from the beam (seen from the face), some of it behind.
            let range_m = 5e3 + 2e5 * s.uniform();
            let (u, v) = (bu + 12.0 * theta * (s.uniform() - 0.5), bv + 12.0 * theta * (s.uniform() - 0.5));
            let w = (1.0 - u * u - v * v).max(0.0).sqrt() * if s.uniform() < 0.1 { -1.0 } else { 1.0 };
            let face = DVec3::new(u, v, w) * range_m;
            let mt = |r: usize| DVec3::new(m.m[r][0], m.m[r][1], m.m[r][2]);
            let centre = m.rx + mt(0) * face.x + mt(1) * face.y + mt(2) * face.z;
            let radius_m = 8e3 * s.uniform() * s.uniform();
            let ball = TrackBall {
                t_s: 0.0,
                n_updates: 0,
                dt_lo_s: 0.0,
                dt_hi_s: WINDOW_S,
                centre,
                radius_m,
                trace_max_m2: 0.0,
            };
            if !ball.clear_of_beam(&m, bu, bv, theta) {
                unsure += 1;
                continue;
            }
            clear += 1;
            for k in 0..50 {
                let d = DVec3::new(s.normal(), s.normal(), s.normal()).normalize();
                let p = centre + d * radius_m * if k % 2 == 0 { 1.0 } else { s.uniform() };
                let z = m.h_pos(p);
                let (du, dv) = (z[1] - bu, z[2] - bv);
                assert!(du * du + dv * dv > theta * theta, "a point of a clear ball is in the beam");
            }
        }
        assert!(clear > 300 && unsure > 300, "clear {clear}, unsure {unsure}");
    }
}
