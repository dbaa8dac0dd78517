//! Track deletion (docs/model.md §6.4).
//!
//! [`Deleter`] is the family trait; the tracker asks it about every live track after each dwell.
//! [`MissCountDeleter`] drops a confirmed track after `n_miss` consecutive missed looks,
//! [`CovarianceDeleter`] any track whose predicted position covariance has grown too large,
//! [`CoastDeleter`] a track that has not been updated for too long. [`AnyDeleter`] combines
//! several.

use crate::frame::Gaussian;
use crate::linalg::trace;
use mimo_core::records::TrackStatus;
use serde::{Deserialize, Serialize};

/// What a deleter sees of a track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackView<'a> {
    /// The track.
    pub track_id: u64,
    /// Its status.
    pub status: TrackStatus,
    /// Consecutive looks at the track without a detection (reset by any update).
    pub consecutive_misses: u32,
    /// Updates so far.
    pub n_updates: u32,
    /// Time of the last update (s).
    pub t_last_update_s: f64,
    /// Time of the check.
    pub t_s: f64,
    /// The (combined) prediction at `t_s`.
    pub predicted: &'a Gaussian,
}

impl<'a> TrackView<'a> {
    /// What a deleter sees of `track` at `t_s`, given its prediction there.
    pub fn of(track: &crate::tracker::Track, t_s: f64, predicted: &'a Gaussian) -> TrackView<'a> {
        TrackView {
            track_id: track.id,
            status: track.status,
            consecutive_misses: track.consecutive_misses,
            n_updates: track.n_updates,
            t_last_update_s: track.t_s,
            t_s,
            predicted,
        }
    }
}

/// Why a track ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DeleteReason {
    /// Too many consecutive missed looks.
    Misses,
    /// Position covariance above the limit.
    Covariance,
    /// No update for too long.
    Coast,
    /// A tentative track failed its M-of-N confirmation.
    Unconfirmed,
    /// A filter failure left no usable state.
    Divergence,
}

/// A promise of a deleter about a track whose status, misses and updates stay as they are:
/// [`Deleter::check`] keeps it at every check time `t_s` with `0 ≤ t_s − t_last_update_s ≤
/// max_dt_s` whose prediction is finite with a position-covariance trace of at most
/// `max_position_trace_m2`. The tracker uses it to skip checks that cannot fire.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuietSpan {
    /// Longest time since the last update (s) the promise covers.
    pub max_dt_s: f64,
    /// Largest trace of the predicted position covariance (m²) the promise covers.
    pub max_position_trace_m2: f64,
}

impl QuietSpan {
    /// No limit of either kind.
    pub const ALWAYS: QuietSpan = QuietSpan { max_dt_s: f64::INFINITY, max_position_trace_m2: f64::INFINITY };
}

/// The deletion family.
pub trait Deleter: Send + Sync {
    /// The reason to delete the track now, or `None` to keep it.
    fn check(&self, track: &TrackView<'_>) -> Option<DeleteReason>;
    /// The promise this deleter makes about a track of this status, consecutive misses and
    /// updates (see [`QuietSpan`]), or `None` for no promise (the default: every check runs).
    fn quiet_span(&self, _status: TrackStatus, _consecutive_misses: u32, _n_updates: u32) -> Option<QuietSpan> {
        None
    }
}

/// Delete a confirmed track after `n_miss` consecutive missed looks (re-dwells count).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MissCountDeleter {
    /// Consecutive misses that end a track.
    pub n_miss: u32,
}

impl Deleter for MissCountDeleter {
    fn check(&self, t: &TrackView<'_>) -> Option<DeleteReason> {
        (t.status == TrackStatus::Confirmed && t.consecutive_misses >= self.n_miss).then_some(DeleteReason::Misses)
    }

    fn quiet_span(&self, status: TrackStatus, consecutive_misses: u32, _n_updates: u32) -> Option<QuietSpan> {
        (status != TrackStatus::Confirmed || consecutive_misses < self.n_miss).then_some(QuietSpan::ALWAYS)
    }
}

/// Delete when `tr P_pos` of the prediction exceeds a limit (m²).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CovarianceDeleter {
    /// Largest predicted position-covariance trace (m²) before the track ends.
    pub max_position_trace_m2: f64,
}

impl Deleter for CovarianceDeleter {
    fn check(&self, t: &TrackView<'_>) -> Option<DeleteReason> {
        let tr = trace(&t.predicted.pos_cov());
        (!tr.is_finite() || tr > self.max_position_trace_m2).then_some(DeleteReason::Covariance)
    }

    fn quiet_span(&self, _status: TrackStatus, _consecutive_misses: u32, _n_updates: u32) -> Option<QuietSpan> {
        Some(QuietSpan { max_position_trace_m2: self.max_position_trace_m2, ..QuietSpan::ALWAYS })
    }
}

/// Delete a track not updated for longer than its status allows (s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CoastDeleter {
    /// Longest a tentative track may go without an update (s).
    pub tentative_max_s: f64,
    /// Longest a confirmed track may go without an update (s).
    pub confirmed_max_s: f64,
}

impl Deleter for CoastDeleter {
    fn check(&self, t: &TrackView<'_>) -> Option<DeleteReason> {
        let limit = match t.status {
            TrackStatus::Tentative => self.tentative_max_s,
            _ => self.confirmed_max_s,
        };
        (t.t_s - t.t_last_update_s > limit).then_some(DeleteReason::Coast)
    }

    fn quiet_span(&self, status: TrackStatus, _consecutive_misses: u32, _n_updates: u32) -> Option<QuietSpan> {
        let limit = match status {
            TrackStatus::Tentative => self.tentative_max_s,
            _ => self.confirmed_max_s,
        };
        Some(QuietSpan { max_dt_s: limit, ..QuietSpan::ALWAYS })
    }
}

/// The first reason any member gives.
#[derive(Default)]
pub struct AnyDeleter {
    /// The rules; the first that fires gives the reason.
    pub members: Vec<Box<dyn Deleter>>,
}

impl Deleter for AnyDeleter {
    fn check(&self, t: &TrackView<'_>) -> Option<DeleteReason> {
        self.members.iter().find_map(|d| d.check(t))
    }

    /// Every member's promise at once: the tightest limits, or none if a member makes none.
    fn quiet_span(&self, status: TrackStatus, consecutive_misses: u32, n_updates: u32) -> Option<QuietSpan> {
        self.members.iter().try_fold(QuietSpan::ALWAYS, |acc, d| {
            let s = d.quiet_span(status, consecutive_misses, n_updates)?;
            Some(QuietSpan {
                max_dt_s: acc.max_dt_s.min(s.max_dt_s),
                max_position_trace_m2: acc.max_position_trace_m2.min(s.max_position_trace_m2),
            })
        })
    }
}

/// Configuration of the standard deletion rules.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DeletionConfig {
    /// Consecutive missed looks that end a confirmed track. Default 3.
    pub n_miss: u32,
    /// Largest trace of the predicted position covariance (m²). Default 3·(3 km)² = 2.7e7.
    pub max_position_trace_m2: f64,
    /// Longest a tentative track may go without an update (s). Default 5.
    pub tentative_max_coast_s: f64,
    /// Longest a confirmed track may go without an update (s). Default 30.
    pub confirmed_max_coast_s: f64,
}

impl Default for DeletionConfig {
    fn default() -> Self {
        DeletionConfig {
            n_miss: 3,
            max_position_trace_m2: 3.0 * 3000.0 * 3000.0,
            tentative_max_coast_s: 5.0,
            confirmed_max_coast_s: 30.0,
        }
    }
}

impl DeletionConfig {
    /// The three standard rules combined.
    pub fn build(&self) -> AnyDeleter {
        AnyDeleter {
            members: vec![
                Box::new(MissCountDeleter { n_miss: self.n_miss }),
                Box::new(CovarianceDeleter { max_position_trace_m2: self.max_position_trace_m2 }),
                Box::new(CoastDeleter {
                    tentative_max_s: self.tentative_max_coast_s,
                    confirmed_max_s: self.confirmed_max_coast_s,
                }),
            ],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{identity, scale};

    #[test]
    fn rules_fire_on_hand_made_cases() {
        let g = Gaussian { x: [0.0; 6], p: identity() };
        let big = Gaussian { x: [0.0; 6], p: scale(&identity(), 1e8) };
        let d = DeletionConfig::default().build();
        let base = TrackView {
            track_id: 1,
            status: TrackStatus::Confirmed,
            consecutive_misses: 0,
            n_updates: 10,
            t_last_update_s: 10.0,
            t_s: 11.0,
            predicted: &g,
        };
        assert_eq!(d.check(&base), None);
        assert_eq!(d.check(&TrackView { consecutive_misses: 2, ..base }), None);
        assert_eq!(d.check(&TrackView { consecutive_misses: 3, ..base }), Some(DeleteReason::Misses));
        // Misses do not delete tentative tracks (M-of-N does).
        assert_eq!(d.check(&TrackView { consecutive_misses: 3, status: TrackStatus::Tentative, ..base }), None);
        assert_eq!(d.check(&TrackView { predicted: &big, ..base }), Some(DeleteReason::Covariance));
        assert_eq!(d.check(&TrackView { t_s: 41.0, ..base }), Some(DeleteReason::Coast));
        assert_eq!(
            d.check(&TrackView { t_s: 16.0, status: TrackStatus::Tentative, ..base }),
            Some(DeleteReason::Coast)
        );
    }
}
