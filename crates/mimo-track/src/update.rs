//! The update step (docs/model.md §6.2).
//!
//! [`Updater`] is the family trait. [`EkfUpdater`] is the extended Kalman filter in its careful
//! form: the innovation covariance `S` is factored once (Cholesky), the gain is obtained by
//! solving `S Kᵀ = H P⁻` (never forming `S⁻¹`), the covariance update is the Joseph form, the
//! result is symmetrized and checked positive definite with a relative-jitter fallback. With
//! `iterations > 1` it is the iterated EKF (Gauss–Newton relinearization about the updated
//! mean), worth using for the first updates after initiation while `P` is large compared with
//! the measurement curvature.

use crate::frame::Gaussian;
use crate::linalg::{
    Mat3, Mat3x6, Vec3, add, all_finite, chol_log_det, chol_mahalanobis, chol_solve, cholesky, ensure_pd, identity,
    mul, mul_vec, sandwich, sub, transpose, vadd, vsub,
};
use crate::measurement::Observation;
use std::fmt;

/// Innovation statistics of a prediction against a measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Innovation {
    /// `ν = z − h(x⁻)`.
    pub nu: Vec3,
    /// `S = H P⁻ Hᵀ + R`.
    pub s: Mat3,
    /// Lower Cholesky factor of `S`.
    pub s_chol: Mat3,
    /// `H = ∂h/∂x` at `x⁻`.
    pub h: Mat3x6,
    /// Normalized innovation squared `νᵀ S⁻¹ ν = ‖L⁻¹ν‖²` (χ²₃ when consistent).
    pub nis: f64,
    /// `ln |2π S|`.
    pub ln_det_2pi_s: f64,
}

impl Innovation {
    /// `ln N(ν; 0, S)`.
    pub fn log_likelihood(&self) -> f64 {
        -0.5 * (self.nis + self.ln_det_2pi_s)
    }
}

/// Result of a successful update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UpdateOutcome {
    /// The updated estimate.
    pub posterior: Gaussian,
    /// The innovation at the prior (used for NIS, gating and IMM likelihoods).
    pub innovation: Innovation,
    /// Jitter had to be added to keep the posterior positive definite.
    pub jitter: bool,
    /// Linearizations used (1 = plain EKF).
    pub iterations: u32,
}

/// Why an update was refused. The track then keeps its prior.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UpdateError {
    /// `h`, `H` or the prior is not finite.
    NonFinite,
    /// `S` is not positive definite.
    InnovationNotPd,
    /// The posterior could not be made positive definite.
    PosteriorNotPd,
}

impl fmt::Display for UpdateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            UpdateError::NonFinite => "non-finite prediction or measurement function",
            UpdateError::InnovationNotPd => "innovation covariance not positive definite",
            UpdateError::PosteriorNotPd => "posterior covariance not positive definite",
        })
    }
}

impl std::error::Error for UpdateError {}

/// The update family.
pub trait Updater: Send + Sync {
    /// Innovation statistics of `pred` against the observation.
    fn innovation(&self, pred: &Gaussian, obs: Observation) -> Result<Innovation, UpdateError>;

    /// Update `pred` with the observation, relinearizing `iterations` times (at least once).
    fn update(&self, pred: &Gaussian, obs: Observation, iterations: u32) -> Result<UpdateOutcome, UpdateError>;
}

/// The (iterated) extended Kalman filter update, Joseph form.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct EkfUpdater {
    /// Stop iterating when the mean moves by less than this fraction of its prior standard
    /// deviation (per component). Default (0.0) means "run all iterations".
    pub iteration_tolerance: f64,
}

fn innovation_at(pred: &Gaussian, obs: Observation, x_lin: &[f64; 6]) -> Result<(Innovation, Vec3), UpdateError> {
    let Observation { model, z, r } = obs;
    let h = model.jacobian(x_lin);
    let hx = model.h(x_lin);
    if !all_finite(&h) || !hx.iter().all(|v| v.is_finite()) {
        return Err(UpdateError::NonFinite);
    }
    // Innovation about the linearization point: z − h(x_i) − H (x⁻ − x_i).
    let dx = vsub(&pred.x, x_lin);
    let nu = vsub(&vsub(z, &hx), &mul_vec(&h, &dx));
    let s = add(&sandwich(&h, &pred.p), r);
    let l = cholesky(&s).ok_or(UpdateError::InnovationNotPd)?;
    let nis = chol_mahalanobis(&l, &nu);
    let ln_det = chol_log_det(&l) + 3.0 * (2.0 * std::f64::consts::PI).ln();
    if !nis.is_finite() || !ln_det.is_finite() {
        return Err(UpdateError::NonFinite);
    }
    Ok((Innovation { nu, s, s_chol: l, h, nis, ln_det_2pi_s: ln_det }, hx))
}

impl Updater for EkfUpdater {
    fn innovation(&self, pred: &Gaussian, obs: Observation) -> Result<Innovation, UpdateError> {
        if !pred.is_finite() {
            return Err(UpdateError::NonFinite);
        }
        innovation_at(pred, obs, &pred.x).map(|(i, _)| i)
    }

    fn update(&self, pred: &Gaussian, obs: Observation, iterations: u32) -> Result<UpdateOutcome, UpdateError> {
        if !pred.is_finite() {
            return Err(UpdateError::NonFinite);
        }
        let n_iter = iterations.max(1);
        let (first, _) = innovation_at(pred, obs, &pred.x)?;
        let mut inn = first;
        let mut x_lin = pred.x;
        let mut gain;
        let mut used = 0;
        loop {
            // S Kᵀ = H P⁻  ⇒  Kᵀ = chol_solve(L, H P⁻).
            let hp = mul(&inn.h, &pred.p);
            let kt = chol_solve(&inn.s_chol, &hp);
            gain = transpose(&kt);
            let x_new = vadd(&pred.x, &mul_vec(&gain, &inn.nu));
            used += 1;
            let moved = (0..6)
                .map(|i| (x_new[i] - x_lin[i]).abs() / pred.p[i][i].max(0.0).sqrt().max(1e-300))
                .fold(0.0f64, f64::max);
            x_lin = x_new;
            if used >= n_iter || moved <= self.iteration_tolerance {
                break;
            }
            match innovation_at(pred, obs, &x_lin) {
                Ok((i, _)) => inn = i,
                Err(_) => break,
            }
        }
        if !x_lin.iter().all(|v| v.is_finite()) {
            return Err(UpdateError::NonFinite);
        }
        // Joseph form with the last linearization: (I − KH) P (I − KH)ᵀ + K R Kᵀ.
        let a = sub(&identity::<6>(), &mul(&gain, &inn.h));
        let p = add(&sandwich(&a, &pred.p), &sandwich(&gain, obs.r));
        let (p, jitter) = ensure_pd(&p).ok_or(UpdateError::PosteriorNotPd)?;
        Ok(UpdateOutcome { posterior: Gaussian { x: x_lin, p }, innovation: first, jitter, iterations: used })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measurement::PositionMeasurement;

    fn position<'a>(z: &'a Vec3, r: &'a Mat3) -> Observation<'a> {
        Observation { model: &PositionMeasurement, z, r }
    }

    #[test]
    fn linear_update_matches_textbook_kalman() {
        let mut p = [[0.0; 6]; 6];
        for i in 0..3 {
            p[i][i] = 100.0;
            p[i + 3][i + 3] = 25.0;
            p[i][i + 3] = 10.0;
            p[i + 3][i] = 10.0;
        }
        let prior = Gaussian { x: [0.0, 0.0, 0.0, 1.0, 2.0, 3.0], p };
        let r = [[4.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 4.0]];
        let z = [10.0, -5.0, 2.0];
        let out = EkfUpdater::default().update(&prior, position(&z, &r), 1).expect("ok");
        // Scalar per axis: k_p = 100/104, k_v = 10/104.
        let kp = 100.0 / 104.0;
        let kv = 10.0 / 104.0;
        assert!((out.posterior.x[0] - 10.0 * kp).abs() < 1e-12);
        assert!((out.posterior.x[3] - (1.0 + 10.0 * kv)).abs() < 1e-12);
        assert!((out.posterior.p[0][0] - 100.0 * 4.0 / 104.0).abs() < 1e-10);
        assert!((out.posterior.p[3][3] - (25.0 - 100.0 / 104.0)).abs() < 1e-10);
        let nis = (100.0 + 25.0 + 4.0) / 104.0;
        assert!((out.innovation.nis - nis).abs() < 1e-12);
        // Iterating a linear model changes nothing.
        let it = EkfUpdater::default().update(&prior, position(&z, &r), 3).expect("ok");
        for i in 0..6 {
            assert!((it.posterior.x[i] - out.posterior.x[i]).abs() < 1e-9);
        }
    }

    #[test]
    fn refuses_nan_prior() {
        let prior = Gaussian { x: [f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0], p: identity() };
        let r = identity::<3>();
        assert_eq!(EkfUpdater::default().update(&prior, position(&[0.0; 3], &r), 1), Err(UpdateError::NonFinite));
    }
}
