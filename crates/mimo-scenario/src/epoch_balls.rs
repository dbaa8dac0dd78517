//! Balls that certainly hold a target over a one-second epoch of its trajectory: a cheap,
//! conservative "where can it be" for the engine's quiet search dwells (docs/model.md §4.7),
//! which then skip the targets' exact positions when the beam is far from every ball.
//!
//! Between two samples the trajectory is the cubic Hermite interpolant of the sampled positions
//! and velocities ([`crate::Trajectories::position_at`]); written as a Bézier curve its control
//! points are `p₀`, `p₀ + m₀/3`, `p₁ − m₁/3`, `p₁` (`m = v · STEP_S`), and the curve lies in
//! their convex hull. A ball holding the control points of every segment an epoch's times can
//! fall in therefore holds the target at every such time.

use crate::flight::STEP_S;
use glam::DVec3;

/// Trajectory samples per epoch.
const STEPS_PER_EPOCH: usize = 20;
/// Segments added on each side of an epoch's own, so that a time whose segment index rounds
/// across the epoch's edge is still covered.
const EDGE_SEGMENTS: usize = 2;
/// Added to every radius: the rounding of the interpolant's evaluation (far below a millimetre
/// on ECEF coordinates) with room to spare (m).
const SLACK_M: f64 = 1.0;

/// A ball in ECEF: centre and radius (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ball {
    /// Centre (ECEF, m).
    pub center_ecef: DVec3,
    /// Radius (m).
    pub radius_m: f64,
}

/// Per epoch and target, a [`Ball`] holding the target at every time of the epoch.
#[derive(Debug, Clone, Default)]
pub struct EpochBalls {
    /// Last sample's time (s): outside `(0, t_last)` the trajectory is extrapolated, not bounded.
    t_last_s: f64,
    /// Targets per epoch.
    n_targets: usize,
    /// `balls[epoch * n_targets + target]`.
    balls: Vec<Ball>,
}

fn epoch_len_s() -> f64 {
    STEPS_PER_EPOCH as f64 * STEP_S
}

impl EpochBalls {
    /// The balls of trajectories sampled at `pos[target][k]`, `vel[target][k]` (time `k · STEP_S`).
    pub(crate) fn new(pos: &[Vec<DVec3>], vel: &[Vec<DVec3>]) -> EpochBalls {
        let n_nodes = pos.first().map_or(0, Vec::len);
        let t_last_s = n_nodes.saturating_sub(1) as f64 * STEP_S;
        let n_segments = n_nodes.saturating_sub(1);
        let n_epochs = n_segments.div_ceil(STEPS_PER_EPOCH);
        let balls = (0..n_epochs)
            .flat_map(|e| pos.iter().zip(vel).map(move |(p, v)| epoch_ball(p, v, e, n_segments)))
            .collect();
        EpochBalls { t_last_s, n_targets: pos.len(), balls }
    }

    /// Every target's ball at `t_s` (in target order), or `None` when `t_s` lies outside the
    /// sampled span (the trajectories are extrapolated there).
    pub fn balls_at(&self, t_s: f64) -> Option<&[Ball]> {
        if !(t_s > 0.0 && t_s < self.t_last_s) {
            return None;
        }
        let e = (t_s / epoch_len_s()).floor() as usize;
        self.balls.get(e * self.n_targets..(e + 1) * self.n_targets)
    }
}

/// The ball of epoch `e`: every Bézier control point of segments `[20e − 2, 20e + 21]`.
fn epoch_ball(pos: &[DVec3], vel: &[DVec3], e: usize, n_segments: usize) -> Ball {
    let first = (e * STEPS_PER_EPOCH).saturating_sub(EDGE_SEGMENTS);
    let last = ((e + 1) * STEPS_PER_EPOCH + EDGE_SEGMENTS).min(n_segments) - 1;
    let controls = (first..=last).flat_map(|k| {
        let (p0, p1) = (pos[k], pos[k + 1]);
        let (m0, m1) = (vel[k] * STEP_S, vel[k + 1] * STEP_S);
        [p0, p0 + m0 / 3.0, p1 - m1 / 3.0, p1]
    });
    let (lo, hi) = controls.clone().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), c| (lo.min(c), hi.max(c)));
    let center_ecef = 0.5 * (lo + hi);
    let radius_m = controls.map(|c| c.distance(center_ecef)).fold(0.0, f64::max) + SLACK_M;
    Ball { center_ecef, radius_m }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A target turning on a 2-km circle at 250 m/s, sampled exactly.
    fn circle(n: usize) -> (Vec<DVec3>, Vec<DVec3>) {
        let (r, w) = (2_000.0, 250.0 / 2_000.0);
        let at = |t: f64| DVec3::new(6.4e6 + r * (w * t).cos(), r * (w * t).sin(), 1.0e5);
        let vel = |t: f64| DVec3::new(-r * w * (w * t).sin(), r * w * (w * t).cos(), 0.0);
        let ts: Vec<f64> = (0..n).map(|k| k as f64 * STEP_S).collect();
        (ts.iter().map(|&t| at(t)).collect(), ts.iter().map(|&t| vel(t)).collect())
    }

    /// The Hermite interpolant of `Trajectories::position_at`, at `t_s`.
    fn hermite(pos: &[DVec3], vel: &[DVec3], t_s: f64) -> DVec3 {
        let k = ((t_s / STEP_S).floor() as usize).min(pos.len() - 2);
        let s = (t_s - k as f64 * STEP_S) / STEP_S;
        let (s2, s3) = (s * s, s * s * s);
        pos[k] * (2.0 * s3 - 3.0 * s2 + 1.0)
            + vel[k] * STEP_S * (s3 - 2.0 * s2 + s)
            + pos[k + 1] * (3.0 * s2 - 2.0 * s3)
            + vel[k + 1] * STEP_S * (s3 - s2)
    }

    #[test]
    fn every_interpolated_position_lies_in_its_epoch_ball() {
        let (pos, vel) = circle(1_001);
        let balls = EpochBalls::new(std::slice::from_ref(&pos), std::slice::from_ref(&vel));
        let mut worst_margin_m = f64::INFINITY;
        for j in 1..49_900 {
            let t = j as f64 * 0.001_000_3;
            let b = balls.balls_at(t).expect("inside the span")[0];
            let margin = b.radius_m - hermite(&pos, &vel, t).distance(b.center_ecef);
            worst_margin_m = worst_margin_m.min(margin);
            // An epoch's ball is about half its path (250 m) across, not the whole turn.
            assert!(b.radius_m < 200.0, "radius {} m at t = {t}", b.radius_m);
        }
        assert!(worst_margin_m > 0.0, "a position outside its ball by {} m", -worst_margin_m);
        assert_eq!(balls.balls_at(0.0), None);
        assert_eq!(balls.balls_at(50.0), None);
        assert!(balls.balls_at(49.999).is_some());
    }
}
