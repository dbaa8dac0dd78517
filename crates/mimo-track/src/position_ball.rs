//! Where a track's predicted position can be over the next seconds, in ECEF, for schedulers
//! (docs/model.md §6.5, §7.3).
//!
//! A scheduler that asks whether any other track lies near a point needs every track's predicted
//! position, and a raid has hundreds of tracks. The tracker's own ball ([`crate::track_balls`])
//! holds a track's predicted positions over a window of prediction intervals until its next
//! update; handed out in ECEF (a rigid motion of the tracking frame, whose rounding the slack
//! below covers), it lets the scheduler pass over far tracks without predicting them, and predict
//! only those whose ball reaches the point.

use crate::queries::TrackDue;
use crate::track_balls::TrackBall;
use crate::tracker::MultiTargetTracker;
use mimo_core::DVec3;

/// Slack added to the radius for the change of frame (m): far above its rounding.
const ECEF_SLACK_M: f64 = 1e-3;

/// A ball holding a track's predicted position ([`MultiTargetTracker::predict_position`]) at
/// every time of a window, while the track is not updated.
#[derive(Debug, Clone)]
pub struct PositionBall {
    /// Centre, ECEF (m).
    pub centre_ecef: DVec3,
    /// Radius (m).
    pub radius_m: f64,
    ball: TrackBall,
    /// Time of the track's state (s) and its update count when the ball was made.
    t_state_s: f64,
    n_updates: u32,
}

impl PositionBall {
    /// About the last time (s) at which the ball still holds its track's prediction, while the
    /// track is not updated: its state's time plus the window's last interval (the exact test is
    /// [`PositionBall::holds`]; this sum may round either way by an ulp).
    pub fn last_time_s(&self) -> f64 {
        self.t_state_s + self.ball.dt_hi_s()
    }

    /// Whether the ball holds the predicted position at `t_s` of the track whose scheduling state
    /// is `due` (the same track it was made for).
    pub fn holds(&self, due: &TrackDue, t_s: f64) -> bool {
        let dt_s = t_s - due.t_last_update_s;
        due.t_last_update_s.to_bits() == self.t_state_s.to_bits()
            && due.n_updates == self.n_updates
            && self.ball.covers_dt(dt_s)
    }
}

impl MultiTargetTracker {
    /// A ball holding track `id`'s predicted position from `t_s` to a few seconds later (while
    /// the track is not updated), or `None` when the filter offers no bound of its modes' means
    /// (then the caller predicts the position).
    pub fn position_ball(&self, id: u64, t_s: f64) -> Option<PositionBall> {
        let t = self.tracks.get(&id)?;
        let filter = &*self.c.filter;
        let ball = TrackBall::of(filter, t, t_s - t.t_s).or_else(|| TrackBall::of_position(filter, t, t_s - t.t_s))?;
        let centre_ecef = self.frame.to_ecef(ball.centre);
        let radius_m = ball.radius_m + ECEF_SLACK_M;
        (centre_ecef.is_finite() && radius_m.is_finite()).then_some(PositionBall {
            centre_ecef,
            radius_m,
            ball,
            t_state_s: t.t_s,
            n_updates: t.n_updates,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::FilterState;
    use crate::frame::Gaussian;
    use crate::linalg::{identity, scale};
    use crate::tracker::Track;
    use crate::{TrackerConfig, TrackerKind};
    use mimo_core::geo::Geodetic;

    /// On an IMM tracker with three-mode tracks whose modes disagree, the ball holds the
    /// predicted position at every time of its window, and stops holding once the track is
    /// updated or the window is left.
    /// Track 5's ball made at 11 s, checked to hold its predicted position at every time of
    /// 11–16 s at which it says it holds (at least 80 of 100), with the track's scheduling state.
    fn ball_held_over_its_window(tr: &MultiTargetTracker) -> (PositionBall, TrackDue) {
        let ball = tr.position_ball(5, 11.0).expect("a ball");
        let due = tr.track_due(5).expect("due");
        let mut held = 0;
        for k in 0..100 {
            let t_s = 11.0 + 0.05 * f64::from(k);
            let p = tr.predict_position(5, t_s).expect("position");
            if ball.holds(&due, t_s) {
                held += 1;
                assert!((p - ball.centre_ecef).length() <= ball.radius_m, "outside the ball at {t_s}");
            }
        }
        assert!(held >= 80, "{held} times held");
        (ball, due)
    }

    #[test]
    fn the_ball_holds_the_predicted_position() {
        let mut tr =
            MultiTargetTracker::new(TrackerConfig::for_kind(TrackerKind::Imm), Geodetic::from_deg(36.0, -70.0, 0.0));
        let modes: Vec<Gaussian> = (0..3)
            .map(|k| {
                let k = f64::from(k);
                Gaussian {
                    x: [8e4 + 300.0 * k, -2e4, 3e3, -250.0 + 40.0 * k, 30.0 * k, -5.0],
                    p: scale(&identity(), 1e4),
                }
            })
            .collect();
        let n_modes = tr.c.filter.init(modes[0]).modes.len();
        let state = FilterState { modes: modes[..n_modes].to_vec(), mu: vec![1.0 / n_modes as f64; n_modes] };
        tr.tracks.insert(5, Track::confirmed_for_test(5, state, 10.0, 4));
        let (ball, due) = ball_held_over_its_window(&tr);
        assert!(!ball.holds(&due, 10.9));
        let updated = TrackDue { n_updates: 5, ..due };
        assert!(!ball.holds(&updated, 11.0));
    }

    /// On the default tracker (one NCV mode, no bound of its covariance's trace) the ball is
    /// made from the mean alone and holds the predicted position over its window.
    #[test]
    fn the_default_trackers_ball_holds_the_predicted_position() {
        let mut tr = MultiTargetTracker::new(TrackerConfig::default(), Geodetic::from_deg(36.0, -70.0, 0.0));
        let g = Gaussian { x: [8e4, -2e4, 3e3, -250.0, 30.0, -5.0], p: scale(&identity(), 1e4) };
        tr.tracks.insert(5, Track::confirmed_for_test(5, tr.c.filter.init(g), 10.0, 4));
        let (ball, _) = ball_held_over_its_window(&tr);
        // The segment of 4 s at about 252 m/s, halved.
        assert!((ball.radius_m - 2.0 * 252.0).abs() < 5.0, "radius {}", ball.radius_m);
    }
}
