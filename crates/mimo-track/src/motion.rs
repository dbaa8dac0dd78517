//! Motion models and the predictor (docs/model.md §6.1, §6.3).
//!
//! [`MotionModel`] is the family trait: a (possibly nonlinear) state transition with its Jacobian
//! and process noise. [`Ncv`] is the nearly-constant-velocity model with DWNA or CWNA noise
//! (filterpy `Q_discrete_white_noise` / `Q_continuous_white_noise`, Bar-Shalom 2001 p. 274);
//! [`HorizontalTurn`] is a known-rate coordinated turn in the ENU horizontal plane, usable as an
//! extra IMM mode. [`Predictor`] turns a model into the Kalman prediction step; [`KalmanPredictor`]
//! is the EKF one.

use crate::cv_sandwich::cv_predicted_covariance;
use crate::frame::Gaussian;
use crate::linalg::{Mat6, Vec6, add, mul_vec, sandwich};
use serde::{Deserialize, Serialize};

/// A discrete-time motion model over an interval `dt` (s). A negative `dt` (a measurement older
/// than the state, which happens when dwells of different radars overlap) must be handled: the
/// models here run the transition backwards and add the process noise of `|dt|`, which is
/// conservative.
pub trait MotionModel: Send + Sync {
    /// Short name for logs and manifests.
    fn name(&self) -> String;
    /// The propagated mean `f(x, dt)`.
    fn propagate(&self, x: &Vec6, dt: f64) -> Vec6;
    /// `∂f/∂x` at `x`.
    fn jacobian(&self, x: &Vec6, dt: f64) -> Mat6;
    /// Process-noise covariance over `dt`.
    fn process_noise(&self, x: &Vec6, dt: f64) -> Mat6;
    /// Whether the trace of the predicted position covariance is a convex function of `dt ≥ 0`
    /// for every prior with non-negative velocity variances (true of a linear constant-velocity
    /// model with convex process noise). Lets the tracker skip deletion checks that cannot fire
    /// (docs/model.md §6.4). The default, `false`, is always safe.
    fn position_trace_convex(&self) -> bool {
        false
    }
    /// Whether the mean moves at constant velocity, `p(dt) = p + dt·v`, `v(dt) = v` (the IMM's
    /// deletion certificate bounds the spread of its modes' means with it). Default `false`.
    fn constant_velocity(&self) -> bool {
        false
    }
    /// Whether `jacobian(x, dt)` is [`cv_transition`]`(dt)` for every `x` and `dt`: the prediction
    /// then forms `F P Fᵀ` from that structure ([`crate::cv_sandwich::cv_predicted_covariance`], bit for bit
    /// the dense product). Default `false`.
    fn cv_jacobian(&self) -> bool {
        false
    }
    /// `tr` of the position block of `F P Fᵀ + Q` (the prediction's covariance before
    /// symmetrizing), up to rounding. The default multiplies out the three position rows.
    fn position_trace(&self, x: &Vec6, p: &Mat6, dt: f64) -> f64 {
        let f = self.jacobian(x, dt);
        let q = self.process_noise(x, dt);
        let mut tr = 0.0;
        for i in 0..3 {
            let fp = crate::linalg::mul_vec(p, &f[i]);
            tr += crate::linalg::dot(&f[i], &fp) + q[i][i];
        }
        tr
    }
}

/// Discretization of the white-noise acceleration.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum ProcessNoise {
    /// Discrete white-noise acceleration with standard deviation `sigma_a_mps2` (m/s²):
    /// `Q = σ_a² [[T⁴/4, T³/2], [T³/2, T²]] ⊗ I₃`.
    Dwna {
        /// σ_a (m/s²).
        sigma_a_mps2: f64,
    },
    /// Continuous white-noise acceleration with power spectral density `q_m2ps3` (m²/s³):
    /// `Q = q̃ [[T³/3, T²/2], [T²/2, T]] ⊗ I₃`.
    Cwna {
        /// q̃ (m²/s³).
        q_m2ps3: f64,
    },
}

impl ProcessNoise {
    /// The per-axis position, position–velocity and velocity entries of `Q` over `dt` (uses `|dt|`).
    fn blocks(&self, dt: f64) -> (f64, f64, f64) {
        let t = dt.abs();
        match *self {
            ProcessNoise::Dwna { sigma_a_mps2: s } => {
                let s2 = s * s;
                (s2 * t.powi(4) / 4.0, s2 * t.powi(3) / 2.0, s2 * t * t)
            }
            ProcessNoise::Cwna { q_m2ps3: q } => (q * t.powi(3) / 3.0, q * t * t / 2.0, q * t),
        }
    }

    /// The 6×6 `Q` over `dt` (uses `|dt|`).
    pub fn q(&self, dt: f64) -> Mat6 {
        let (pp, pv, vv) = self.blocks(dt);
        let mut m = [[0.0; 6]; 6];
        for i in 0..3 {
            m[i][i] = pp;
            m[i][i + 3] = pv;
            m[i + 3][i] = pv;
            m[i + 3][i + 3] = vv;
        }
        m
    }
}

/// `F(dt)` of the constant-velocity model.
pub fn cv_transition(dt: f64) -> Mat6 {
    let mut f = crate::linalg::identity::<6>();
    for (i, row) in f.iter_mut().enumerate().take(3) {
        row[i + 3] = dt;
    }
    f
}

/// Nearly constant velocity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Ncv {
    /// Process noise.
    pub noise: ProcessNoise,
}

impl Ncv {
    /// NCV with DWNA noise of `sigma_a_mps2`.
    pub fn dwna(sigma_a_mps2: f64) -> Ncv {
        Ncv { noise: ProcessNoise::Dwna { sigma_a_mps2 } }
    }
}

impl MotionModel for Ncv {
    fn name(&self) -> String {
        match self.noise {
            ProcessNoise::Dwna { sigma_a_mps2 } => format!("ncv-dwna({sigma_a_mps2})"),
            ProcessNoise::Cwna { q_m2ps3 } => format!("ncv-cwna({q_m2ps3})"),
        }
    }

    fn propagate(&self, x: &Vec6, dt: f64) -> Vec6 {
        [x[0] + dt * x[3], x[1] + dt * x[4], x[2] + dt * x[5], x[3], x[4], x[5]]
    }

    fn jacobian(&self, _x: &Vec6, dt: f64) -> Mat6 {
        cv_transition(dt)
    }

    fn process_noise(&self, _x: &Vec6, dt: f64) -> Mat6 {
        self.noise.q(dt)
    }

    /// `tr P⁻_pos(dt) = tr P_pp + 2 dt tr P_pv + dt² tr P_vv + 3 Q_pp(dt)`: a quadratic with a
    /// non-negative leading term plus `σ² dt⁴/4` or `q̃ dt³/3`, convex for `dt ≥ 0`.
    /// `Σ_i (P_ii + dt (P_i,i+3 + P_i+3,i) + dt² P_i+3,i+3) + 3 Q_pp(dt)`, without `F`.
    fn position_trace(&self, _x: &Vec6, p: &Mat6, dt: f64) -> f64 {
        let mut tr = 3.0 * self.noise.blocks(dt).0;
        for i in 0..3 {
            tr += p[i][i] + dt * (p[i][i + 3] + p[i + 3][i]) + dt * dt * p[i + 3][i + 3];
        }
        tr
    }

    fn position_trace_convex(&self) -> bool {
        match self.noise {
            ProcessNoise::Dwna { sigma_a_mps2 } => sigma_a_mps2.is_finite(),
            ProcessNoise::Cwna { q_m2ps3 } => q_m2ps3.is_finite() && q_m2ps3 >= 0.0,
        }
    }

    fn constant_velocity(&self) -> bool {
        true
    }

    fn cv_jacobian(&self) -> bool {
        true
    }
}

/// Coordinated turn at a known, fixed rate `omega_radps` (positive = counter-clockwise seen from
/// above, i.e. a left turn in ENU) in the horizontal plane, constant velocity vertically, with
/// the given acceleration noise on all axes (docs/model.md §6.3 with ω not estimated; TCL
/// `FCoordTurn2D`). Linear in the state, so the Jacobian is the transition itself.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct HorizontalTurn {
    /// Turn rate ω (rad/s), positive counter-clockwise seen from above.
    pub omega_radps: f64,
    /// Process noise.
    pub noise: ProcessNoise,
}

impl HorizontalTurn {
    fn coefficients(&self, dt: f64) -> (f64, f64, f64, f64) {
        let wt = self.omega_radps * dt;
        let (s, c) = wt.sin_cos();
        if wt.abs() < 1e-4 {
            // Taylor series of sin(ωT)/ω and (1 − cos ωT)/ω.
            let w = self.omega_radps;
            (dt * (1.0 - wt * wt / 6.0), w * dt * dt / 2.0 * (1.0 - wt * wt / 12.0), s, c)
        } else {
            (s / self.omega_radps, (1.0 - c) / self.omega_radps, s, c)
        }
    }
}

impl MotionModel for HorizontalTurn {
    fn name(&self) -> String {
        format!("ct({:.4} rad/s)", self.omega_radps)
    }

    fn propagate(&self, x: &Vec6, dt: f64) -> Vec6 {
        mul_vec(&self.jacobian(x, dt), x)
    }

    fn jacobian(&self, _x: &Vec6, dt: f64) -> Mat6 {
        let (a, b, s, c) = self.coefficients(dt);
        let mut f = cv_transition(dt);
        f[0][3] = a;
        f[0][4] = -b;
        f[1][3] = b;
        f[1][4] = a;
        f[3][3] = c;
        f[3][4] = -s;
        f[4][3] = s;
        f[4][4] = c;
        f
    }

    fn process_noise(&self, _x: &Vec6, dt: f64) -> Mat6 {
        self.noise.q(dt)
    }
}

/// The prediction step of a filter family.
pub trait Predictor: Send + Sync {
    /// Predict `prior` over `dt` seconds.
    fn predict(&self, prior: &Gaussian, dt: f64) -> Gaussian;
    /// The mean of [`Predictor::predict`], bit for bit, without the covariance.
    fn predict_mean(&self, prior: &Gaussian, dt: f64) -> Vec6 {
        self.predict(prior, dt).x
    }
    /// Whether the trace of the predicted position covariance of `prior` is convex in `dt ≥ 0`
    /// (see [`MotionModel::position_trace_convex`]). The default, `false`, is always safe.
    fn position_trace_convex(&self, _prior: &Gaussian) -> bool {
        false
    }
    /// Whether the predicted mean moves at constant velocity ([`MotionModel::constant_velocity`]).
    /// The default, `false`, is always safe.
    fn constant_velocity(&self) -> bool {
        false
    }
    /// The trace of the position block of [`Predictor::predict`]'s covariance, computed without
    /// the full prediction (equal to it up to rounding), for the pre-gate (docs/model.md §6.5).
    /// The default, `None`, means "not offered": the pre-gate then never skips a pair.
    fn position_trace(&self, _prior: &Gaussian, _dt: f64) -> Option<f64> {
        None
    }
}

/// EKF prediction with a motion model: `x⁻ = f(x)`, `P⁻ = F P Fᵀ + Q` (symmetrized).
#[derive(Clone)]
pub struct KalmanPredictor<M: MotionModel> {
    /// The motion model.
    pub model: M,
}

impl<M: MotionModel> KalmanPredictor<M> {
    /// A Kalman predictor for `model`.
    pub fn new(model: M) -> Self {
        KalmanPredictor { model }
    }
}

/// EKF prediction with any motion model (used by every built-in predictor).
pub fn ekf_predict(model: &dyn MotionModel, prior: &Gaussian, dt: f64) -> Gaussian {
    if dt == 0.0 {
        return *prior;
    }
    let x = model.propagate(&prior.x, dt);
    let q = model.process_noise(&prior.x, dt);
    if model.cv_jacobian() {
        // The same covariance bit for bit from the structure of `F`.
        return Gaussian { x, p: cv_predicted_covariance(dt, &prior.p, &q) };
    }
    let p = add(&sandwich(&model.jacobian(&prior.x, dt), &prior.p), &q);
    Gaussian { x, p: crate::linalg::symmetrize(&p) }
}

impl<M: MotionModel> Predictor for KalmanPredictor<M> {
    fn predict(&self, prior: &Gaussian, dt: f64) -> Gaussian {
        ekf_predict(&self.model, prior, dt)
    }

    fn predict_mean(&self, prior: &Gaussian, dt: f64) -> Vec6 {
        // The mean step of `ekf_predict`.
        if dt == 0.0 { prior.x } else { self.model.propagate(&prior.x, dt) }
    }

    fn position_trace_convex(&self, prior: &Gaussian) -> bool {
        self.model.position_trace_convex() && (3..6).all(|i| prior.p[i][i] >= 0.0)
    }

    fn constant_velocity(&self) -> bool {
        self.model.constant_velocity()
    }

    fn position_trace(&self, prior: &Gaussian, dt: f64) -> Option<f64> {
        if dt == 0.0 {
            // `ekf_predict` returns the prior itself.
            return Some((0..3).map(|i| prior.p[i][i]).sum());
        }
        Some(self.model.position_trace(&prior.x, &prior.p, dt))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dwna_and_cwna_match_filterpy() {
        // filterpy Q_discrete_white_noise(dim=2, dt=2, var=9) = 9·[[4, 4], [4, 4]].
        let q = ProcessNoise::Dwna { sigma_a_mps2: 3.0 }.q(2.0);
        assert_eq!(q[0][0], 36.0);
        assert_eq!(q[0][3], 36.0);
        assert_eq!(q[3][3], 36.0);
        assert_eq!(q[0][1], 0.0);
        // Q_continuous_white_noise(dim=2, dt=2, spectral_density=3) = 3·[[8/3, 2], [2, 2]].
        let q = ProcessNoise::Cwna { q_m2ps3: 3.0 }.q(2.0);
        assert!((q[1][1] - 8.0).abs() < 1e-12);
        assert!((q[1][4] - 6.0).abs() < 1e-12);
        assert!((q[4][4] - 6.0).abs() < 1e-12);
    }

    /// The position trace without the prediction: NCV's closed form and the generic rows agree
    /// with the trace of the full prediction (a correlated prior, forwards and backwards).
    #[test]
    fn position_trace_matches_the_prediction() {
        let mut p = [[0.0; 6]; 6];
        for i in 0..3 {
            p[i][i] = 400.0 * (i + 1) as f64;
            p[i + 3][i + 3] = 90.0;
            p[i][i + 3] = -150.0;
            p[i + 3][i] = -150.0;
        }
        p[0][1] = 30.0;
        p[1][0] = 30.0;
        let prior = Gaussian { x: [1e4, -2e4, 5e3, 200.0, -50.0, 3.0], p };
        for model in [Ncv::dwna(15.0), Ncv { noise: ProcessNoise::Cwna { q_m2ps3: 4.0 } }] {
            let pred = KalmanPredictor::new(model);
            for dt in [-0.7, 0.0, 0.4, 2.5, 30.0] {
                let full = pred.predict(&prior, dt).p;
                let want: f64 = (0..3).map(|i| full[i][i]).sum();
                let closed = pred.position_trace(&prior, dt).expect("offered");
                let rows = ekf_rows_trace(&model, &prior, dt);
                assert!((closed - want).abs() <= 1e-12 * want, "dt {dt}: {closed} vs {want}");
                assert!((rows - want).abs() <= 1e-12 * want, "dt {dt}: {rows} vs {want}");
            }
        }
    }

    /// The default `MotionModel::position_trace` (multiplied-out rows), for comparison.
    fn ekf_rows_trace(model: &Ncv, prior: &Gaussian, dt: f64) -> f64 {
        struct Generic<'a>(&'a Ncv);
        impl MotionModel for Generic<'_> {
            fn name(&self) -> String {
                self.0.name()
            }
            fn propagate(&self, x: &Vec6, dt: f64) -> Vec6 {
                self.0.propagate(x, dt)
            }
            fn jacobian(&self, x: &Vec6, dt: f64) -> Mat6 {
                self.0.jacobian(x, dt)
            }
            fn process_noise(&self, x: &Vec6, dt: f64) -> Mat6 {
                self.0.process_noise(x, dt)
            }
        }
        Generic(model).position_trace(&prior.x, &prior.p, dt)
    }

    #[test]
    fn turn_model_turns_and_reduces_to_cv() {
        let ct = HorizontalTurn { omega_radps: 0.1, noise: ProcessNoise::Dwna { sigma_a_mps2: 1.0 } };
        let x = [0.0, 0.0, 1000.0, 100.0, 0.0, 0.0];
        // A quarter turn: velocity rotates by +90°, position ends at (R, R) with R = v/ω.
        let y = ct.propagate(&x, std::f64::consts::FRAC_PI_2 / 0.1);
        assert!((y[0] - 1000.0).abs() < 1e-9 && (y[1] - 1000.0).abs() < 1e-9);
        assert!(y[3].abs() < 1e-9 && (y[4] - 100.0).abs() < 1e-9);
        let small = HorizontalTurn { omega_radps: 1e-9, ..ct };
        let a = small.propagate(&x, 3.0);
        let b = Ncv::dwna(1.0).propagate(&x, 3.0);
        for i in 0..6 {
            assert!((a[i] - b[i]).abs() < 1e-6);
        }
    }
}
