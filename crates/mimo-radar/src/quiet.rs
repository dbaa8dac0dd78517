//! Quiet dwells: a monostatic dwell that no target reaches and whose §4.4 false-alarm draw is
//! zero produces nothing (docs/model.md §4.4, §4.7).
//!
//! Nearly every background-search dwell is such a dwell. [`is_quiet`] decides it without
//! building the dwell's looks, returns, channels or cells (no heap allocation): it applies the
//! same gates as the full model ([`crate::dwell::evaluate`]) in the same arithmetic — behind the
//! face, the pattern floor, the two-way pattern floor, the SNR floor — and then draws the
//! false-alarm count `K ~ Binomial(M, P_FA)` from the very stream the full model would use. When
//! it answers `true`, [`crate::dwell::evaluate`] would have returned no primitive and no voltage,
//! and the draws it would have made are the ones made here; when it is unsure (a target passes
//! the cheap gates, refraction or polarization (§3.5, whose pair RCS is not σ̄) is on, the dwell
//! is not a plain monostatic one) it answers `false`
//! and the caller evaluates the dwell in full, which then draws the same streams afresh. Either
//! way the recorded rows are the ones the full model gives, bit for bit.
//!
//! The horizon gate (§1.7) is not applied here (it needs geodetic heights): a target above both
//! floors but below the horizon makes the dwell "unsure", which is only slower.
//!
//! What the tests need of a radar that is the same for every dwell (its antenna, the clearance
//! of the ball test, the cells of its fixed search window) is a [`QuietRadar`], made once per
//! radar by the caller; [`beam_clear`] and [`is_quiet`] make one per call.

use crate::dwell::{Dwell, KEY_FALSE_ALARM, PATTERN_FLOOR, SNR_FLOOR, Target, stream};
use crate::equation::snr1;
use crate::pattern::Antenna;
use crate::range::cell_window;
use mimo_core::DVec3;
use mimo_core::params::{PatternModel, RadarParams};
use mimo_core::rng::ZeroBinomial;

/// A ball that certainly holds a target during a dwell (ECEF centre, radius in m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TargetBall {
    /// Centre (ECEF, m).
    pub center_ecef: DVec3,
    /// Radius (m).
    pub radius_m: f64,
}

/// Whether no target anywhere in `balls` can pass the pattern gate of the monostatic dwell `d`
/// (one transmitter, the Gaussian pattern of docs/model.md §2.2): then [`is_quiet`] gives the
/// same answer with the targets' exact positions as with no target at all, and the caller need
/// not compute the positions. `false` means "unsure" (another pattern model, a ball too close
/// to the radar or to the beam).
///
/// The bound: with `a = Δu/θ_u`, `b = Δv/θ_v`, `r² = a² + b²`, the Gaussian gains give the
/// two-way pattern `Σ² · max(Σ², Δa², Δe²) ≤ e^{−8 ln2 r²} · max(1, k_m² r²)`, and since
/// `r² ≤ e^{r² − 1}` this is at most `max(1, k_m²/e) · e^{−(8 ln2 − 1) r²}`, a decreasing
/// function of `r`. At `r ≥ r₀`, where that bound is half the pattern floor, every target is
/// dropped by the gate. A point of a ball of radius `ρ` whose centre lies at face-frame
/// distance `R ≥ 2ρ` is seen within an angle `asin(ρ/R)` of the centre, i.e. within a sine-space
/// distance (a chord of the unit sphere, projected) `≤ 1.04 ρ/R` of it; the face frame's matrix
/// is a rotation or a convex combination of two (the interpolated ship frames), so it does not
/// lengthen vectors.
pub fn beam_clear(d: &Dwell, balls: impl IntoIterator<Item = TargetBall>) -> bool {
    let [tx] = d.transmitters else { return false };
    QuietRadar::new(tx.params, d.fidelity.pattern).beam_clear(d, balls)
}

/// What [`beam_clear`] and [`is_quiet`] need of one radar that does not change from dwell to
/// dwell, computed once: its antenna, the ball test's sine-space clearance and the cells of its
/// fixed (search) range window. Each value comes from the expression the per-dwell code used,
/// so the answers and the random draws are the same bit for bit. A dwell whose transmitter has
/// other parameters (another `RadarParams` value), another pattern model or another window is
/// answered by computing them afresh.
#[derive(Debug, Clone, Copy)]
pub struct QuietRadar {
    /// Address of the `RadarParams` this was made from (identity only, never dereferenced).
    params_addr: usize,
    pattern: PatternModel,
    ant: Antenna,
    /// The ball test's clearance in sine space; `None` when it answers "unsure" whatever the balls.
    clear: Option<f64>,
    /// The fixed window `[ρ_min, ρ_max]` (m) of a search dwell and its cells.
    window_m: (f64, f64),
    cells: Option<(i64, i64)>,
    /// The false-alarm test of that window (`K ~ Binomial(cells, P_FA)` is zero).
    no_false_alarm: ZeroBinomial,
}

impl QuietRadar {
    /// The constant part of the quiet tests for a radar with `params` under `pattern`.
    pub fn new(params: &RadarParams, pattern: PatternModel) -> QuietRadar {
        let window_m = (params.min_range_m, params.instrumented_range_m);
        let cells = cell_window(window_m.0, window_m.1, params.range_cell_m());
        QuietRadar {
            params_addr: std::ptr::from_ref(params) as usize,
            pattern,
            ant: Antenna::new(params, pattern),
            clear: clearance(params, pattern),
            window_m,
            cells,
            no_false_alarm: ZeroBinomial::new(cells.map_or(0, cell_count), params.pfa),
        }
    }

    fn made_for(&self, params: &RadarParams, pattern: PatternModel) -> bool {
        std::ptr::from_ref(params) as usize == self.params_addr && pattern == self.pattern
    }

    /// [`beam_clear`] of dwell `d` (its transmitter made with this radar's parameters).
    pub fn beam_clear(&self, d: &Dwell, balls: impl IntoIterator<Item = TargetBall>) -> bool {
        let [tx] = d.transmitters else { return false };
        let clear = if self.made_for(tx.params, d.fidelity.pattern) {
            self.clear
        } else {
            clearance(tx.params, d.fidelity.pattern)
        };
        let Some(clear) = clear else { return false };
        balls.into_iter().all(|b| {
            let l = tx.frame.face_from_ecef * (b.center_ecef - tx.frame.origin_ecef);
            let range_m = l.length();
            if !(b.radius_m >= 0.0 && range_m >= 2.0 * b.radius_m && range_m > 0.0) {
                return false;
            }
            let (du, dv) = (l.x / range_m - tx.beam_u, l.y / range_m - tx.beam_v);
            let need = clear + 1.05 * b.radius_m / range_m;
            du * du + dv * dv > need * need
        })
    }

    /// [`is_quiet`] of dwell `d` (its transmitter made with this radar's parameters).
    pub fn is_quiet(&self, d: &Dwell, targets: &[Target]) -> bool {
        let ([tx], [rx]) = (d.transmitters, d.receivers) else { return false };
        let monostatic = tx.radar == rx.radar
            && std::ptr::eq(tx.params, rx.params)
            && tx.frame == rx.frame
            && tx.beam_u == rx.beam_u
            && tx.beam_v == rx.beam_v;
        if !monostatic || d.simulate_all_cells || d.fidelity.refraction || d.fidelity.polarization {
            return false;
        }
        let mine = self.made_for(tx.params, d.fidelity.pattern);
        let fresh;
        let ant = if mine {
            &self.ant
        } else {
            fresh = Antenna::new(tx.params, d.fidelity.pattern);
            &fresh
        };
        if targets.iter().any(|tg| may_return(d, ant, tg)) {
            return false;
        }
        // No return, no leakage (one transmitter): every cell of the window is a shortcut cell.
        let (lo, hi) = rx.window.limits(tx.frame.origin_ecef, rx.frame.origin_ecef);
        let same_window =
            mine && lo.to_bits() == self.window_m.0.to_bits() && hi.to_bits() == self.window_m.1.to_bits();
        let (cells, fresh_test);
        let no_false_alarm = if same_window {
            cells = self.cells;
            &self.no_false_alarm
        } else {
            cells = cell_window(lo, hi, rx.params.range_cell_m());
            fresh_test = ZeroBinomial::new(cells.map_or(0, cell_count), rx.params.pfa);
            &fresh_test
        };
        if cells.is_none() {
            return true;
        }
        let mut fa = stream(d, &[KEY_FALSE_ALARM, tx.radar.0 as u64, rx.radar.0 as u64]);
        // `fa.binomial(m, P_FA) == 0`, mostly without its two logarithms (same draw, same answer).
        fa.binomial_is_zero(no_false_alarm)
    }
}

/// The number of cells `[k_min, k_max]`.
fn cell_count((k_min, k_max): (i64, i64)) -> u64 {
    (k_max - k_min + 1).max(0) as u64
}

/// The ball test's sine-space distance beyond which the pattern gate drops a target (see
/// [`beam_clear`]); `None` for a pattern model other than the Gaussian or a degenerate antenna.
fn clearance(params: &RadarParams, pattern: PatternModel) -> Option<f64> {
    if pattern != PatternModel::Gaussian {
        return None;
    }
    let ant = Antenna::new(params, PatternModel::Gaussian);
    let k2 = ant.slope() * ant.slope();
    let r0_sq = (2.0 * (k2 / std::f64::consts::E).max(1.0) / PATTERN_FLOOR).ln() / (8.0 * std::f64::consts::LN_2 - 1.0);
    let theta = ant.theta_u().max(ant.theta_v());
    if !(r0_sq.is_finite() && theta.is_finite() && theta > 0.0) {
        return None;
    }
    // Sine-space distance beyond which the gate drops a target, with 1 % for rounding.
    Some(1.01 * r0_sq.sqrt() * theta)
}

/// Could target `tg` give a return in the monostatic dwell `d` (one transmitter, one receiver,
/// same face and beam)? `false` only when the full model's gates certainly drop it.
fn may_return(d: &Dwell, ant: &Antenna, tg: &Target) -> bool {
    let tx = &d.transmitters[0];
    let s = tx.frame.to_sine(tg.pos_ecef);
    // Behind the face (or at its centre): no look (crate::returns, `looks`).
    if !(s.w > 0.0 && s.range_m > 0.0) {
        return false;
    }
    let g = ant.gains(s.u - tx.beam_u, s.v - tx.beam_v);
    let p_max = (g.sum * g.sum).max(g.az * g.az).max(g.el * g.el);
    if p_max < PATTERN_FLOOR {
        return false;
    }
    // The two-way pattern of the monostatic channel: transmit Σ² times the receive maximum.
    let pattern = g.sum * g.sum * p_max;
    if pattern < PATTERN_FLOOR {
        return false;
    }
    if !(tg.rcs_m2 > 0.0 && tg.rcs_m2.is_finite()) {
        return false;
    }
    let w_b = (1.0 - tx.beam_u * tx.beam_u - tx.beam_v * tx.beam_v).max(0.0).sqrt();
    let peak = f64::from(tx.n_pulses) * snr1(tx.params, tx.params, w_b, w_b, tg.rcs_m2, s.range_m, s.range_m);
    !((peak * pattern).is_nan() || peak * pattern < SNR_FLOOR)
}

/// Whether the dwell certainly produces no primitive and no voltage: a plain monostatic dwell
/// (one radar transmitting and receiving on the same face and beam, the §4.4 shortcut on, no
/// refraction, no polarization) that no target reaches and whose false-alarm draw is zero. `false` means "evaluate
/// it" (see the module docs).
pub fn is_quiet(d: &Dwell, targets: &[Target]) -> bool {
    let [tx] = d.transmitters else { return false };
    QuietRadar::new(tx.params, d.fidelity.pattern).is_quiet(d, targets)
}
