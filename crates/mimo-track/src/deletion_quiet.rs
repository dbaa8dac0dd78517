//! Deletion checks that cannot fire, skipped (docs/model.md §6.4).
//!
//! The tracker asks its deleter about every live track after each dwell, and the covariance rule
//! needs the track predicted to the dwell's time. Most tracks are far from every limit, so each
//! track carries a certificate: the span of times since its last update over which no rule can
//! fire, found once per change of the track (update, status, misses) from the deleter's
//! [`QuietSpan`] and the predicted position covariance's trace at two or a few times. A check
//! inside the span is skipped; every other check runs exactly as before, so the tracks and their
//! deletions are the same, bit for bit.
//!
//! The covariance limit is certified by convexity: when the filter says the trace of the
//! predicted position covariance is convex in `dt ≥ 0` ([`TrackFilter::position_trace_convex`]),
//! its largest value on `[0, D]` is at an end, so both ends below the limit (with a margin far
//! above rounding) put the whole span below it; when the far end is above, a shorter span is
//! found by bisection. Without that promise nothing is skipped.

use crate::deletion::Deleter;
use crate::filter::TrackFilter;
use crate::linalg::trace;
use crate::quiet_expiry::ExpiryQueue;
use crate::state_stamp::StateStamp;
use crate::tracker::Track;
use mimo_core::records::TrackStatus;

/// Relative margin below the covariance limit that the span's ends must keep: far above the
/// rounding of a 6×6 prediction, far below anything the limit means.
const TRACE_MARGIN: f64 = 1e-6;

/// What a certificate was computed from: the track's state ([`StateStamp`]) and the fields the
/// deleter sees besides it.
#[derive(Debug, Clone)]
struct Basis {
    stamp: StateStamp,
    status: TrackStatus,
    consecutive_misses: u32,
}

impl Basis {
    fn of(t: &Track) -> Basis {
        Basis { stamp: StateStamp::of(t), status: t.status, consecutive_misses: t.consecutive_misses }
    }

    fn matches(&self, t: &Track) -> bool {
        self.status == t.status && self.consecutive_misses == t.consecutive_misses && self.stamp.matches(t)
    }
}

/// Per-track certificates: `dt` from the last update up to `max_dt_s` needs no check; and their
/// expiry queue, which names the tracks a certificate may not cover ([`ExpiryQueue`]).
#[derive(Debug, Default)]
pub(crate) struct QuietTracks {
    certs: crate::track_balls::IdMap<(Basis, f64)>,
    queue: ExpiryQueue,
}

impl QuietTracks {
    /// Whether checking `track` at `t_s` is sure to keep it (and may be skipped). Recomputes the
    /// track's certificate when the track changed since it was made.
    pub(crate) fn is_quiet(
        &mut self,
        filter: &dyn TrackFilter,
        deleter: &dyn Deleter,
        track: &Track,
        t_s: f64,
    ) -> bool {
        let max_dt_s = match self.certs.get(&track.id) {
            Some((b, max_dt_s)) if b.matches(track) => *max_dt_s,
            _ => {
                let max_dt_s = quiet_dt_s(filter, deleter, track);
                self.certs.insert(track.id, (Basis::of(track), max_dt_s));
                self.queue.certify(track.id, track.t_s, max_dt_s);
                max_dt_s
            }
        };
        if self.queue.is_open(track.id) {
            // Touched without a change the certificate sees: it still holds.
            self.queue.certify(track.id, track.t_s, max_dt_s);
        }
        let dt = t_s - track.t_s;
        dt >= 0.0 && dt <= max_dt_s
    }

    /// Track `id` is new or may have changed (state, status or misses): it is a candidate of
    /// every pass until [`Self::is_quiet`] certifies it again.
    pub(crate) fn touch(&mut self, id: u64) {
        self.queue.open(id);
    }

    /// The tracks whose check at `t_s` may not be skipped: every other track that was touched
    /// when it changed has a certificate covering `t_s` ([`ExpiryQueue::candidates`]).
    pub(crate) fn candidates(&self, t_s: f64) -> std::collections::BTreeSet<u64> {
        self.queue.candidates(t_s)
    }

    /// Drop a deleted track's certificate.
    pub(crate) fn forget(&mut self, id: u64) {
        self.certs.remove(&id);
        self.queue.forget(id);
    }
}

/// Halvings of the span searched for the covariance limit when it falls inside the span.
const BISECTIONS: u32 = 5;

/// The longest `dt` since the last update over which no rule can fire, or −∞ when nothing can
/// be promised. When the covariance limit is reached inside the deleter's span, the span is cut
/// to a time found below it by bisection (the times below the limit are an interval from 0, the
/// trace being convex and below the limit at 0).
fn quiet_dt_s(filter: &dyn TrackFilter, deleter: &dyn Deleter, t: &Track) -> f64 {
    const NEVER: f64 = f64::NEG_INFINITY;
    let Some(span) = deleter.quiet_span(t.status, t.consecutive_misses, t.n_updates) else { return NEVER };
    if !(span.max_dt_s.is_finite() && span.max_dt_s >= 0.0) {
        return NEVER;
    }
    // Either the trace itself is convex, or the filter offers a convex upper bound of it (the
    // IMM with constant-velocity modes); without either nothing is promised.
    let convex = filter.position_trace_convex(&t.state);
    if !convex && filter.position_trace_upper_convex(&t.state, 0.0).is_none() {
        return NEVER;
    }
    let limit = span.max_position_trace_m2 * (1.0 - TRACE_MARGIN);
    // The trace comes from the filter's prediction bound when it offers one (no full prediction;
    // equal to the prediction's up to rounding, far inside `TRACE_MARGIN`). Convexity is only
    // promised by the constant-velocity model, whose prediction of a finite prior is finite when
    // its mean and position trace are (every other entry is bounded by them and the prior).
    let prior_finite = t.state.is_finite();
    let below_upper = |dt: f64| match filter.position_trace_upper_convex(&t.state, dt) {
        // A finite prior with constant-velocity modes predicts finite means and covariances
        // whenever the means and this bound are finite.
        Some(b) => {
            prior_finite
                && b.is_finite()
                && b <= limit
                && filter.predict_mean(&t.state, dt).iter().all(|x| x.is_finite())
        }
        None => false,
    };
    let below = |dt: f64| {
        if !convex {
            below_upper(dt)
        } else {
            match filter.prediction_bound(&t.state, dt) {
                Some(b) => {
                    prior_finite
                        && b.mean.iter().all(|x| x.is_finite())
                        && b.position_trace.is_finite()
                        && b.position_trace <= limit
                }
                None => {
                    let g = filter.predict(&t.state, dt).combined;
                    g.is_finite() && trace(&g.pos_cov()) <= limit
                }
            }
        }
    };
    if !below(0.0) {
        return NEVER;
    }
    if below(span.max_dt_s) {
        return span.max_dt_s;
    }
    let (mut lo, mut hi) = (0.0, span.max_dt_s);
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (lo + hi);
        if below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::deletion::{DeleteReason, DeletionConfig, TrackView};
    use crate::filter::{FilterState, SingleModelFilter};
    use crate::frame::Gaussian;
    use crate::linalg::{identity, scale};
    use crate::motion::{KalmanPredictor, Ncv};
    use crate::update::EkfUpdater;

    fn track(p_scale: f64) -> Track {
        let g = Gaussian { x: [0.0, 0.0, 0.0, 200.0, 0.0, 0.0], p: scale(&identity(), p_scale) };
        Track::confirmed_for_test(7, FilterState::single(g), 100.0, 5)
    }

    /// The default constant-velocity EKF (the filter whose covariance trace is convex in dt).
    fn ekf() -> SingleModelFilter {
        SingleModelFilter {
            name: "ekf".into(),
            predictor: Box::new(KalmanPredictor::new(Ncv::dwna(5.0))),
            updater: Box::new(EkfUpdater::default()),
        }
    }

    /// Whatever `is_quiet` skips, the deleter keeps: checked at many times against the full rule.
    #[test]
    fn skipped_checks_never_delete() {
        let filter = ekf();
        let deleter = DeletionConfig::default().build();
        let mut quiet = QuietTracks::default();
        let (mut skipped, mut deleted) = (0, 0);
        for (id, p_scale) in [1.0, 1e4, 1e6, 8.9e6, 1e7].into_iter().enumerate() {
            // Each state is another track (a tracker never gives one id two states at one update).
            let t = Track { id: id as u64, ..track(p_scale) };
            for k in 0..400 {
                let t_s = 99.0 + 0.1 * k as f64;
                let g = filter.predict(&t.state, t_s - t.t_s).combined;
                let reason: Option<DeleteReason> = deleter.check(&TrackView::of(&t, t_s, &g));
                if quiet.is_quiet(&filter, &deleter, &t, t_s) {
                    skipped += 1;
                    assert_eq!(reason, None, "skipped a deletion at p_scale {p_scale}, t {t_s}");
                } else if reason.is_some() {
                    deleted += 1;
                }
            }
        }
        // Both kinds of outcome happen: the test sees skips and real deletions.
        assert!(skipped > 100 && deleted > 100, "{skipped} skipped, {deleted} deleted");
    }

    /// A track with misses due for deletion is never skipped.
    #[test]
    fn missed_tracks_are_checked() {
        let filter = ekf();
        let deleter = DeletionConfig::default().build();
        let mut quiet = QuietTracks::default();
        let mut t = track(1.0);
        assert!(quiet.is_quiet(&filter, &deleter, &t, 101.0));
        t.consecutive_misses = 3;
        assert!(!quiet.is_quiet(&filter, &deleter, &t, 101.0));
    }
}
