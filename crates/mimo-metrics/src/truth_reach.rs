//! Where a target's interpolated truth can be during each second, and which targets a beam
//! surely misses (docs/design.md §6: usage by purpose).
//!
//! A look is classified by asking whether any target's truth at the look's mid-time lies in the
//! transmitter's footprint (and a receiver's range window): every target was interpolated for
//! every look, so a raid's score grew with the square of its targets. Truth is interpolated by
//! cubic Hermite steps between samples; a step from `a` to `b` (length `h`) stays within
//! `|b − a|/2 + (4/27)·h·(|v_a| + |v_b|)` of the chord's midpoint (the Hermite weights of the
//! positions are a convex pair and those of the velocities at most 4/27 in size). Each second of a
//! target's span gets a ball holding every step that reaches it; a look skips a target whose ball
//! lies outside the transmitter's beam cone and interpolates the others as before, so the
//! classification is the same, look for look.

use crate::purpose_rule::LookPart;
use crate::track_metrics::TruthSample;
use glam::DVec3;

/// Length of a bucket (s).
const BUCKET_S: f64 = 1.0;

/// Slack on the time span a bucket takes steps from (s): above the interpolation's time
/// tolerance.
const TIME_SLACK_S: f64 = 1e-6;

/// Largest size of a Hermite velocity weight on `[0, 1]` (`s(1 − s)²` at `s = 1/3`), with slack.
const VELOCITY_WEIGHT: f64 = 4.0 / 27.0 * (1.0 + 1e-9);

/// Relative and absolute slack on a radius (far above the rounding of ECEF coordinates).
const RADIUS_SLACK: (f64, f64) = (1e-9, 1e-3);

/// Balls holding one target's interpolated truth, one per second from its first sample.
#[derive(Debug, Clone, Default)]
pub(crate) struct TruthBalls {
    t0_s: f64,
    /// `(centre ECEF, radius m)` per bucket.
    balls: Vec<(DVec3, f64)>,
}

impl TruthBalls {
    /// The balls of a target's samples (sorted by time).
    pub(crate) fn of(samples: &[TruthSample]) -> TruthBalls {
        let (Some(first), Some(last)) = (samples.first(), samples.last()) else { return TruthBalls::default() };
        let span_s = last.t - first.t;
        if !(span_s.is_finite() && span_s >= 0.0) {
            return TruthBalls::default();
        }
        let n = (span_s / BUCKET_S).floor() as usize + 1;
        // Per bucket, the box around the balls of the steps reaching it.
        let mut boxes: Vec<Option<(DVec3, DVec3)>> = vec![None; n];
        let steps = samples.windows(2).map(|w| (w[0], w[1])).chain(std::iter::once((*first, *first)));
        for (a, b) in steps {
            let h = (b.t - a.t).max(0.0);
            let centre = (a.p + b.p) * 0.5;
            let r = (b.p - a.p).length() * 0.5 + VELOCITY_WEIGHT * h * (a.v.length() + b.v.length());
            let lo = ((a.t - first.t - TIME_SLACK_S) / BUCKET_S).floor().max(0.0) as usize;
            let hi = (((b.t - first.t + TIME_SLACK_S) / BUCKET_S).floor() as usize).min(n - 1);
            for slot in &mut boxes[lo.min(n - 1)..=hi] {
                let (bl, bh) = (centre - DVec3::splat(r), centre + DVec3::splat(r));
                *slot = Some(slot.map_or((bl, bh), |(l, h)| (l.min(bl), h.max(bh))));
            }
        }
        let balls = boxes
            .into_iter()
            .map(|b| match b {
                Some((l, h)) => {
                    let c = (l + h) * 0.5;
                    let r = (h - l).length() * 0.5;
                    (c, r * (1.0 + RADIUS_SLACK.0) + RADIUS_SLACK.1 + RADIUS_SLACK.0 * c.length())
                }
                None => (DVec3::ZERO, f64::INFINITY),
            })
            .collect();
        TruthBalls { t0_s: first.t, balls }
    }

    /// A ball holding the target's interpolated truth at `t_s`, if the time falls in its span.
    fn at(&self, t_s: f64) -> Option<(DVec3, f64)> {
        let k = ((t_s - self.t0_s) / BUCKET_S).floor();
        if k.is_nan() || k < 0.0 {
            return self.balls.first().copied().filter(|_| t_s >= self.t0_s - TIME_SLACK_S);
        }
        self.balls.get(k as usize).copied()
    }

    /// Whether the target's truth at `t_s`, when it has one, is surely outside the 3 dB footprint
    /// of `tx` (`LookPart::in_footprint` false). A footprint point's direction `(u, v, w)` lies
    /// within `a` (the larger half-beamwidth) of the beam's `(u_b, v_b)` and, with `w > 0`,
    /// `|w − w_b| ≤ a (2 r_b + a) / w_b`; a ball of radius `ρ` at distance `R ≥ 2ρ` spans
    /// directions within `1.05 ρ/R` of its centre's.
    pub(crate) fn surely_outside(&self, tx: &LookPart, t_s: f64) -> bool {
        let Some((c, r)) = self.at(t_s) else { return false };
        let rb2 = tx.beam_u * tx.beam_u + tx.beam_v * tx.beam_v;
        let wb = (1.0 - rb2).sqrt();
        let a = 0.5 * tx.theta_u.max(tx.theta_v);
        if !(wb > 0.0 && a >= 0.0 && r.is_finite()) {
            return false;
        }
        let cone = a * (1.0 + ((2.0 * rb2.sqrt() + a) / wb).powi(2)).sqrt();
        let l = tx.frame.face_from_ecef * (c - tx.frame.origin_ecef);
        let range_m = l.length();
        if !(range_m > 0.0 && range_m >= 2.0 * r) {
            return false;
        }
        let off = (l / range_m - DVec3::new(tx.beam_u, tx.beam_v, wb)).length();
        off > cone + 1.05 * r / range_m + 1e-9
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::track_metrics::truth_at;
    use mimo_core::face::FaceFrame;
    use mimo_core::geo::Geodetic;
    use mimo_core::rng::Stream;

    /// A manoeuvring target sampled every 0.7 s (a turn, a climb, a sample repeated): its
    /// interpolated truth at any time of its span lies in the ball of that time.
    #[test]
    fn the_ball_holds_the_interpolated_truth() {
        let face = FaceFrame::new(Geodetic::from_deg(36.0, -70.0, 20.0), 0.3, 0.26);
        let mut samples: Vec<TruthSample> = (0..60)
            .map(|k| {
                let t = 3.0 + 0.7 * f64::from(k);
                let (u, v) = (0.2 * (0.1 * t).sin(), 0.05 + 0.001 * t);
                let p = face.from_ruv(90_000.0 - 250.0 * t, u, v);
                let v = DVec3::new(250.0 * (0.3 * t).cos(), 250.0 * (0.3 * t).sin(), 10.0);
                TruthSample { t, p, v, alt: 0.0 }
            })
            .collect();
        samples.insert(20, samples[20]);
        let balls = TruthBalls::of(&samples);
        let mut cursor = 0;
        for k in 0..5000 {
            let t = 2.9 + 0.0087 * f64::from(k);
            let Some((p, _, _)) = truth_at(&samples, &mut cursor, t) else { continue };
            let (c, r) = balls.at(t).expect("a ball in the span");
            assert!((p - c).length() <= r, "t {t}: {} m from the centre, radius {r}", (p - c).length());
        }
        assert!(balls.at(100.0).is_none());
    }

    /// A target whose ball is surely outside a beam is never in its footprint: random beams and
    /// balls, each ball sampled inside and on its surface; many are found outside, many not.
    #[test]
    fn surely_outside_is_never_in_the_footprint() {
        let mut s = Stream::new(11, &[3]);
        let frame = FaceFrame::new(Geodetic::from_deg(36.0, -70.0, 20.0), 1.0, 0.26);
        let (mut outside, mut unsure) = (0, 0);
        for _ in 0..3000 {
            let (bu, bv) = (1.4 * s.uniform() - 0.7, 1.4 * s.uniform() - 0.7);
            let tx = LookPart { frame, theta_u: 0.0252, theta_v: 0.03, beam_u: bu, beam_v: bv, receives: true };
            let (u, v) = (bu + 0.3 * (s.uniform() - 0.5), bv + 0.3 * (s.uniform() - 0.5));
            if u * u + v * v >= 1.0 {
                continue;
            }
            let centre = frame.from_ruv(2e4 + 2e5 * s.uniform(), u, v);
            let radius_m = 3e3 * s.uniform() * s.uniform();
            let balls = TruthBalls { t0_s: 0.0, balls: vec![(centre, radius_m)] };
            if !balls.surely_outside(&tx, 0.5) {
                unsure += 1;
                continue;
            }
            outside += 1;
            for k in 0..40 {
                let d = DVec3::new(s.normal(), s.normal(), s.normal()).normalize();
                let p = centre + d * radius_m * if k % 2 == 0 { 1.0 } else { s.uniform() };
                assert!(!tx.in_footprint(p), "a point of a ball surely outside is in the footprint");
            }
        }
        assert!(outside > 500 && unsure > 100, "outside {outside}, unsure {unsure}");
    }
}
