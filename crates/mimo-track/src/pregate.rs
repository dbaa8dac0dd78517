//! The pre-gate: track–measurement pairs that cannot pass the gate, recognised without the full
//! prediction and innovation (docs/model.md §6.5).
//!
//! For a positive-definite `S` and any component `k`, `νᵀ S⁻¹ ν ≥ ν_k² / S_kk` (the smallest
//! quadratic form with `ν_k` fixed is the marginal's). With `k` the range sum `R_B`:
//! `S_RR = gᵀ P⁻_pos g + R_RR` with `g = ∂R_B/∂p`, the sum of two unit vectors, `|g| ≤ 2`, so
//! `S_RR ≤ 4 λ_max(P⁻_pos) + R_RR ≤ 4 tr P⁻_pos + R_RR`. The channel loop uses a pair's NIS
//! twice: against the gate and against the initiation exclusion's NIS, and its range-sum
//! residual against the exclusion's resolution cell. A pair whose lower bound lies above both
//! NIS limits by [`NIS_MARGIN`] (far above any rounding of the NIS) and whose residual lies
//! outside the cell is skipped; every other pair is computed exactly as before, so the gated
//! table, the association and the tracks are the same, bit for bit. The prediction itself is
//! left to the channel's cache, which computes it only when a pair or an update needs it.

use crate::config::InitiationExclusion;
use crate::filter::{FilterPrediction, TrackFilter};
use crate::gating::Gater;
use crate::measurement::PreparedMeasurement;
use crate::tracker::Track;
use mimo_core::DVec3;

/// Factor between the NIS lower bound and the largest limit before a pair is skipped.
pub(crate) const NIS_MARGIN: f64 = 2.0;

/// Relative slack on the resolution cell's range-sum half-width.
const CELL_MARGIN: f64 = 1e-6;

/// The limits one channel checks a pair against.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PreGate {
    /// The largest NIS that matters (gate or exclusion); `None` disables the pre-gate.
    nis_max: Option<f64>,
    /// Half-width of the exclusion cell in range sum (m), with slack.
    cell_rb_m: f64,
}

/// What the pre-gate knows of a track's prediction before making it: the combined predicted
/// mean, an upper bound of every mode's (and the combination's) position trace, and a radius
/// that holds every mode's predicted position around the combined one (0 for one mode).
#[derive(Debug, Clone, Copy)]
pub(crate) struct GateBound {
    mean: [f64; 6],
    position_trace: f64,
    mode_radius_m: f64,
}

impl GateBound {
    /// The filter's own bound ([`TrackFilter::prediction_bound`], one mode), or for an IMM with
    /// constant-velocity modes its convex trace bound `T = C + 2S`
    /// ([`TrackFilter::position_trace_upper_convex`]): every mixed prior is a convex combination
    /// of the modes, so every predicted mode mean and the combined mean lie in the hull of the
    /// modes' predicted means, whose diameter is `√S ≤ √(T/2)`; every mode's trace is at most
    /// `C + S ≤ T`.
    fn of(filter: &dyn TrackFilter, track: &Track, dt: f64) -> Option<GateBound> {
        if let Some(b) = filter.prediction_bound(&track.state, dt) {
            return Some(GateBound { mean: b.mean, position_trace: b.position_trace, mode_radius_m: 0.0 });
        }
        let t = filter.position_trace_upper_convex(&track.state, dt)?;
        let mode_radius_m = (0.5 * t).sqrt() * (1.0 + CELL_MARGIN);
        Some(GateBound { mean: filter.predict_mean(&track.state, dt), position_trace: t, mode_radius_m })
    }
}

/// A track's bound at one time (the channel's measurements usually share one time).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct BoundCache {
    entry: Option<(f64, Option<GateBound>)>,
}

impl PreGate {
    /// The pre-gate of a tracker's gate and initiation exclusion.
    pub(crate) fn new(gater: &dyn Gater, excl: &InitiationExclusion) -> PreGate {
        let cell_rb_m = 2.0 * excl.range_cell_m * (1.0 + CELL_MARGIN) + CELL_MARGIN;
        // A NaN cell width (a bad configuration) disables the pre-gate rather than skip pairs.
        let nis_max = gater.nis_limit().map(|g| g.max(excl.nis)).filter(|x| x.is_finite() && !cell_rb_m.is_nan());
        PreGate { nis_max, cell_rb_m }
    }

    /// Whether the pair of `track` and `m` is sure to fail the gate, the exclusion NIS and the
    /// exclusion cell (then the channel may skip it).
    pub(crate) fn excludes(
        &self,
        filter: &dyn TrackFilter,
        track: &Track,
        m: &PreparedMeasurement,
        cache: &mut BoundCache,
    ) -> bool {
        let Some(nis_max) = self.nis_max else { return false };
        let bound = match cache.entry {
            Some((t_s, b)) if t_s == m.t_s => b,
            _ => {
                let b = GateBound::of(filter, track, m.t_s - track.t_s);
                cache.entry = Some((m.t_s, b));
                b
            }
        };
        let Some(b) = bound else { return false };
        let tr = b.position_trace;
        let s_rr_max = 4.0 * tr + m.r[0][0];
        let p = DVec3::new(b.mean[0], b.mean[1], b.mean[2]);
        let nu_rb = m.z[0] - m.model.h_pos(p)[0];
        if !(tr.is_finite() && tr >= 0.0 && s_rr_max > 0.0 && s_rr_max.is_finite() && nu_rb.is_finite()) {
            return false;
        }
        // Every mode's range-sum residual is at least this (`R_B` is 2-Lipschitz in position).
        let nu_lo = nu_rb.abs() - 2.0 * b.mode_radius_m;
        let outside_cell = nu_rb.abs() > self.cell_rb_m;
        outside_cell && nu_lo > 0.0 && nu_lo * nu_lo > NIS_MARGIN * nis_max * s_rr_max
    }
}

impl PreGate {
    /// Whether every pair of a track whose predictions lie in `ball` with `m` is sure to fail
    /// the gate, the exclusion NIS and the exclusion cell ([`crate::track_balls`]): the
    /// range-sum residual of any point of the ball is at least the centre's less twice the
    /// radius (`R_B` is 2-Lipschitz), and every mode's trace is at most the ball's bound.
    pub(crate) fn excludes_ball(&self, ball: &crate::track_balls::TrackBall, m: &PreparedMeasurement) -> bool {
        let Some(nis_max) = self.nis_max else { return false };
        let nu_lo = (m.z[0] - m.model.h_pos(ball.centre)[0]).abs() - 2.0 * ball.radius_m;
        let s_rr_max = 4.0 * ball.trace_max_m2 + m.r[0][0];
        nu_lo.is_finite()
            && s_rr_max.is_finite()
            && s_rr_max > 0.0
            && nu_lo > self.cell_rb_m
            && nu_lo * nu_lo > NIS_MARGIN * nis_max * s_rr_max
    }
}

impl PreGate {
    /// Whether the pair of a track predicted as `pred` and `m` is sure to fail the gate, the
    /// exclusion NIS and the exclusion cell, from the prediction itself: for a multiple-model
    /// filter, whose gate statistic is the smallest mode NIS (and which offers no bound before
    /// predicting), every mode's range-sum bound lies above both NIS limits by [`NIS_MARGIN`]
    /// and the combined prediction's residual lies outside the cell. Skipping such a pair saves
    /// its per-mode innovations; the gated table and the tracks are the same, bit for bit.
    pub(crate) fn excludes_prediction(&self, pred: &FilterPrediction, m: &PreparedMeasurement) -> bool {
        let Some(nis_max) = self.nis_max else { return false };
        let nu_rb = |x: &[f64; 6]| m.z[0] - m.model.h_pos(DVec3::new(x[0], x[1], x[2]))[0];
        let nu_c = nu_rb(&pred.combined.x);
        if !(nu_c.is_finite() && nu_c.abs() > self.cell_rb_m) {
            return false;
        }
        pred.modes.iter().all(|g| {
            let tr = g.p[0][0] + g.p[1][1] + g.p[2][2];
            let s_rr_max = 4.0 * tr + m.r[0][0];
            let nu = nu_rb(&g.x);
            tr.is_finite()
                && tr >= 0.0
                && s_rr_max > 0.0
                && s_rr_max.is_finite()
                && nu.is_finite()
                && nu * nu > NIS_MARGIN * nis_max * s_rr_max
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::components::Components;
    use crate::config::TrackerConfig;
    use crate::frame::Gaussian;
    use crate::linalg::identity;
    use crate::measurement::BistaticRuv;
    use mimo_core::ids::RadarId;

    fn track(filter: &dyn TrackFilter, x: [f64; 6], var_m2: f64) -> Track {
        let mut p: [[f64; 6]; 6] = identity();
        for (i, row) in p.iter_mut().enumerate() {
            row[i] = if i < 3 { var_m2 } else { 100.0 };
        }
        Track::confirmed_for_test(1, filter.init(Gaussian { x, p }), 0.0, 5)
    }

    fn meas(model: BistaticRuv, rb_m: f64, t_s: f64) -> PreparedMeasurement {
        PreparedMeasurement {
            meas_id: 1,
            t_s,
            tx: RadarId(0),
            rx: RadarId(0),
            rx_face: 0,
            z: [rb_m, 0.0, 0.0],
            r: [[100.0, 0.0, 0.0], [0.0, 1e-6, 0.0], [0.0, 0.0, 1e-6]],
            model,
            merged: false,
            snr_db: 20.0,
        }
    }

    /// Whether a pre-gate skips a pair (gate, filter, track, its prediction, measurement).
    type Skips = dyn Fn(&PreGate, &dyn TrackFilter, &Track, &FilterPrediction, &PreparedMeasurement) -> bool;

    /// A sweep of range-sum offsets through the gate's edge for a track on the face's boresight
    /// (z axis) at 50 km moving at 200 m/s along it, predicted 2 s: each pair's computed NIS and
    /// whether `skips` skipped it.
    fn sweep(kind: crate::config::TrackerKind, skips: &Skips) -> (f64, Vec<(f64, bool)>) {
        let config = TrackerConfig::for_kind(kind);
        let c = Components::from_config(&config);
        let filter = &*c.filter;
        let gate = PreGate::new(&*c.gater, &config.initiation_exclusion);
        let model = BistaticRuv::monostatic(DVec3::ZERO, identity());
        let t = track(filter, [0.0, 0.0, 50_000.0, 0.0, 0.0, 200.0], 400.0);
        let dt = 2.0;
        let pred = filter.predict(&t.state, dt);
        let rb_true = 2.0 * (50_000.0 + 200.0 * dt);
        let pairs = (-400..=400)
            .map(|k| {
                let m = meas(model, rb_true + 10.0 * k as f64, dt);
                let h = filter.hypothesis(&pred, m.observation()).expect("finite");
                (h.nis, skips(&gate, filter, &t, &pred, &m))
            })
            .collect();
        (config.gate.threshold, pairs)
    }

    /// Both kinds occur: the sweep crosses the gate.
    fn assert_both_kinds(pairs: &[(f64, bool)]) {
        let skipped = pairs.iter().filter(|p| p.1).count();
        let kept = pairs.len() - skipped;
        assert!(skipped > 100 && kept > 10, "skipped {skipped}, kept {kept}");
    }

    /// Every skipped pair has a NIS above `NIS_MARGIN` times the gate, no pair inside the gate is
    /// skipped, and both kinds occur.
    fn assert_skips_only_beyond_the_margin(gate_nis: f64, pairs: &[(f64, bool)]) {
        for &(nis, skipped) in pairs {
            if skipped {
                assert!(nis > NIS_MARGIN * gate_nis, "skipped a pair with NIS {nis}");
            }
            if nis <= gate_nis {
                assert!(!skipped);
            }
        }
        assert_both_kinds(pairs);
    }

    /// Every pair the pre-gate skips has a computed NIS above the gate, and a pair well inside
    /// the gate is never skipped.
    #[test]
    fn skips_only_pairs_whose_nis_is_above_the_gate() {
        let (gate_nis, pairs) = sweep(crate::config::TrackerKind::Default, &|g, f, t, _, m| {
            g.excludes(f, t, m, &mut BoundCache::default())
        });
        assert_skips_only_beyond_the_margin(gate_nis, &pairs);
    }

    /// The IMM's bound before its prediction (the mode hull): every pair it skips has a
    /// smallest-mode NIS above the gate, a measurement 200 km beyond the track is skipped, and
    /// the sweep through the gate's edge skips and keeps pairs.
    #[test]
    fn the_imm_bound_skips_only_pairs_whose_nis_is_above_the_gate() {
        let (gate_nis, pairs) =
            sweep(crate::config::TrackerKind::Imm, &|g, f, t, _, m| g.excludes(f, t, m, &mut BoundCache::default()));
        assert_skips_only_beyond_the_margin(gate_nis, &pairs);
        let config = TrackerConfig::for_kind(crate::config::TrackerKind::Imm);
        let c = Components::from_config(&config);
        let gate = PreGate::new(&*c.gater, &config.initiation_exclusion);
        let model = BistaticRuv::monostatic(DVec3::ZERO, identity());
        let t = track(&*c.filter, [0.0, 0.0, 50_000.0, 0.0, 0.0, 0.0], 400.0);
        assert!(gate.excludes(&*c.filter, &t, &meas(model, 300_000.0, 1.0), &mut BoundCache::default()));
    }

    /// The IMM's pre-gate from its prediction: every pair it skips has a smallest-mode NIS above
    /// the gate, and the sweep through the gate's edge skips and keeps pairs.
    #[test]
    fn the_imm_prediction_skips_only_pairs_whose_nis_is_above_the_gate() {
        let (gate_nis, pairs) = sweep(crate::config::TrackerKind::Imm, &|g, _, _, pred, m| {
            assert!(pred.modes.len() > 1);
            g.excludes_prediction(pred, m)
        });
        for &(nis, skipped) in &pairs {
            if skipped {
                assert!(nis > gate_nis, "skipped a pair with NIS {nis}");
            }
        }
        assert_both_kinds(&pairs);
    }
}
