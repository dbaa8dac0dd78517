//! The interacting multiple model estimator (docs/model.md §6.3): mixing, mode-matched
//! prediction and update, mode probabilities, moment-matched combination, after filterpy's
//! `IMMEstimator`; with its mean-only prediction, its deletion-certificate bound (§6.4) and the
//! stack path of the mixing that keeps a prediction free of allocation but its result.

use crate::association::Hypothesis;
use crate::filter::{FilterPrediction, FilterState, FilterUpdate, TrackFilter, moment_match, weighted_mean};
use crate::frame::Gaussian;
use crate::measurement::Observation;
use crate::motion::Predictor;
use crate::update::{Innovation, UpdateError, Updater};

/// Interacting multiple model estimator.
pub struct ImmFilter {
    /// Name for manifests.
    pub name: String,
    /// One predictor per mode.
    pub predictors: Vec<Box<dyn Predictor>>,
    /// Mean sojourn time of each mode (s): mode `i` is left over `T` seconds with probability
    /// `1 − exp(−T/τ_i)`, spread evenly over the other modes (docs/model.md §6.3).
    pub sojourn_s: Vec<f64>,
    /// Mode probabilities of a new track.
    pub initial_mu: Vec<f64>,
    /// The measurement update of each mode.
    pub updater: Box<dyn Updater>,
}

/// Modes an IMM prediction mixes on the stack; more take the general (allocating) path.
const MAX_STACK_MODES: usize = 4;

/// `c̄_j = Σ_i π_ij μ_i`.
fn cbar_of(pi: &[[f64; MAX_STACK_MODES]; MAX_STACK_MODES], mu: &[f64], j: usize) -> f64 {
    (0..mu.len()).map(|i| pi[i][j] * mu[i]).sum()
}

/// Mixing weights `μ_{i|j} = π_ij μ_i / c̄_j` (mode `j` alone when `c̄_j` vanishes).
fn mixing_weights(
    pi: &[[f64; MAX_STACK_MODES]; MAX_STACK_MODES],
    mu: &[f64],
    cbar_j: f64,
    j: usize,
) -> [f64; MAX_STACK_MODES] {
    let mut w = [0.0; MAX_STACK_MODES];
    for (i, wi) in w.iter_mut().enumerate().take(mu.len()) {
        *wi = if cbar_j > 1e-300 {
            pi[i][j] * mu[i] / cbar_j
        } else if i == j {
            1.0
        } else {
            0.0
        };
    }
    w
}

impl ImmFilter {
    /// [`TrackFilter::predict`] for any number of modes (the reference the stack path follows).
    fn predict_general(&self, state: &FilterState, dt: f64) -> FilterPrediction {
        let m = self.predictors.len();
        let pi = self.transition_matrix(dt);
        // c̄_j = Σ_i π_ij μ_i.
        let cbar: Vec<f64> = (0..m).map(|j| (0..m).map(|i| pi[i][j] * state.mu[i]).sum()).collect();
        let mut modes = Vec::with_capacity(m);
        for j in 0..m {
            // Mixing weights μ_{i|j} = π_ij μ_i / c̄_j.
            let w: Vec<f64> = if cbar[j] > 1e-300 {
                (0..m).map(|i| pi[i][j] * state.mu[i] / cbar[j]).collect()
            } else {
                (0..m).map(|i| if i == j { 1.0 } else { 0.0 }).collect()
            };
            let x0 = moment_match(&w, &state.modes);
            modes.push(self.predictors[j].predict(&x0, dt));
        }
        let combined = moment_match(&cbar, &modes);
        FilterPrediction { modes, cbar, combined }
    }

    /// `Π(T)` on the stack (at most [`MAX_STACK_MODES`] modes), the same values as
    /// [`ImmFilter::transition_matrix`].
    fn transition_stack(&self, dt: f64) -> [[f64; MAX_STACK_MODES]; MAX_STACK_MODES] {
        let m = self.predictors.len();
        let mut pi = [[0.0; MAX_STACK_MODES]; MAX_STACK_MODES];
        for (i, row) in pi.iter_mut().enumerate().take(m) {
            let leave = if m > 1 { 1.0 - (-dt.abs() / self.sojourn_s[i]).exp() } else { 0.0 };
            for (j, p) in row.iter_mut().enumerate().take(m) {
                *p = if i == j { 1.0 - leave } else { leave / (m - 1) as f64 };
            }
        }
        pi
    }

    /// Mode transition matrix `Π(T)`, row `i` = from mode `i`.
    pub fn transition_matrix(&self, dt: f64) -> Vec<Vec<f64>> {
        let m = self.sojourn_s.len();
        (0..m)
            .map(|i| {
                let leave = if m > 1 { 1.0 - (-dt.abs() / self.sojourn_s[i]).exp() } else { 0.0 };
                (0..m).map(|j| if i == j { 1.0 - leave } else { leave / (m - 1) as f64 }).collect()
            })
            .collect()
    }
}

impl TrackFilter for ImmFilter {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn n_modes(&self) -> usize {
        self.predictors.len()
    }

    fn init(&self, g: Gaussian) -> FilterState {
        let m = self.predictors.len();
        let s: f64 = self.initial_mu.iter().sum();
        let mu = if self.initial_mu.len() == m && s > 0.0 {
            self.initial_mu.iter().map(|x| x / s).collect()
        } else {
            vec![1.0 / m as f64; m]
        };
        FilterState { modes: vec![g; m], mu }
    }

    fn predict(&self, state: &FilterState, dt: f64) -> FilterPrediction {
        let m = self.predictors.len();
        if m > MAX_STACK_MODES {
            return self.predict_general(state, dt);
        }
        // The same arithmetic as `predict_general`, on the stack (no allocation but the result's).
        if state.mu.len() != m {
            return self.predict_general(state, dt);
        }
        let pi = self.transition_stack(dt);
        let cbar: Vec<f64> = (0..m).map(|j| cbar_of(&pi, &state.mu, j)).collect();
        let modes: Vec<Gaussian> = (0..m)
            .map(|j| {
                let w = mixing_weights(&pi, &state.mu, cbar[j], j);
                self.predictors[j].predict(&moment_match(&w[..m], &state.modes), dt)
            })
            .collect();
        let combined = moment_match(&cbar, &modes);
        FilterPrediction { modes, cbar, combined }
    }

    /// With constant-velocity modes whose position traces are convex: every mixed prior is a
    /// convex combination of the modes, so each mode's predicted position trace is at most
    /// `max_{i,j} tr_pos(F P_i Fᵀ + Q_j) + S(dt)` with `S(dt) = max_{i,k} |F(x_i − x_k)|²_pos`
    /// (the spread of the mixed means), and the combined trace adds at most `S(dt)` more (the
    /// spread of the predicted means). Each term is convex in `dt`, so their sum is.
    fn position_trace_upper_convex(&self, state: &FilterState, dt: f64) -> Option<f64> {
        let m = self.predictors.len();
        if state.modes.len() != m || m < 2 {
            return None;
        }
        let mut covariance = f64::NEG_INFINITY;
        for p in &self.predictors {
            if !p.constant_velocity() {
                return None;
            }
            for g in &state.modes {
                if !p.position_trace_convex(g) {
                    return None;
                }
                covariance = covariance.max(p.position_trace(g, dt)?);
            }
        }
        let mut spread = 0.0f64;
        for a in &state.modes {
            for b in &state.modes {
                let d2: f64 = (0..3).map(|k| ((a.x[k] - b.x[k]) + dt * (a.x[k + 3] - b.x[k + 3])).powi(2)).sum();
                spread = spread.max(d2);
            }
        }
        Some(covariance + 2.0 * spread)
    }

    fn predict_mean(&self, state: &FilterState, dt: f64) -> [f64; 6] {
        let m = self.predictors.len();
        if !(2..=MAX_STACK_MODES).contains(&m) || state.modes.len() != m || state.mu.len() != m {
            return self.predict(state, dt).combined.x;
        }
        // `predict`'s arithmetic for the means alone: the mixed means (`moment_match`'s mean
        // loop), each mode's predicted mean, and their combination with c̄ (the same loop).
        let pi = self.transition_stack(dt);
        let mut x = [0.0; 6];
        for j in 0..m {
            let cbar_j = cbar_of(&pi, &state.mu, j);
            let w = mixing_weights(&pi, &state.mu, cbar_j, j);
            let x0 = weighted_mean(&w[..m], &state.modes);
            let xj = self.predictors[j].predict_mean(&Gaussian { x: x0, p: [[0.0; 6]; 6] }, dt);
            for (a, b) in x.iter_mut().zip(&xj) {
                *a += cbar_j * b;
            }
        }
        x
    }

    fn update(&self, pred: &FilterPrediction, obs: Observation, iterations: u32) -> Result<FilterUpdate, UpdateError> {
        let m = pred.modes.len();
        let mut posts = Vec::with_capacity(m);
        let mut loglik = Vec::with_capacity(m);
        let mut jitter = false;
        let mut last_err = UpdateError::NonFinite;
        for g in &pred.modes {
            match self.updater.update(g, obs, iterations) {
                Ok(o) => {
                    jitter |= o.jitter;
                    posts.push(o.posterior);
                    loglik.push(o.innovation.log_likelihood());
                }
                Err(e) => {
                    last_err = e;
                    posts.push(*g);
                    loglik.push(f64::NEG_INFINITY);
                }
            }
        }
        let best = loglik.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if !best.is_finite() {
            return Err(last_err);
        }
        // μ_j ∝ Λ_j c̄_j, computed in the log domain; a tiny floor keeps every mode alive.
        let mut mu: Vec<f64> = (0..m).map(|j| pred.cbar[j] * (loglik[j] - best).exp()).collect();
        let s: f64 = mu.iter().sum();
        if !(s.is_finite() && s > 0.0) {
            return Err(UpdateError::NonFinite);
        }
        for x in mu.iter_mut() {
            *x = (*x / s).max(1e-12);
        }
        let s: f64 = mu.iter().sum();
        let mu: Vec<f64> = vscale_vec(&mu, 1.0 / s);
        let innovation = self.updater.innovation(&pred.combined, obs)?;
        Ok(FilterUpdate { state: FilterState { modes: posts, mu }, innovation, jitter })
    }

    fn innovation(&self, pred: &FilterPrediction, obs: Observation) -> Result<Innovation, UpdateError> {
        self.updater.innovation(&pred.combined, obs)
    }

    /// Gate on the union of the mode-matched gates (the smallest mode NIS), so that a
    /// manoeuvre the quiet mode cannot explain still reaches the manoeuvre mode; cost from the
    /// mixture likelihood `Λ = Σ_j c̄_j N(ν_j; 0, S_j)`, i.e. `nis + ln_det_2pi_s = −2 ln Λ`.
    fn hypothesis(&self, pred: &FilterPrediction, obs: Observation) -> Result<Hypothesis, UpdateError> {
        let mut min_nis = f64::INFINITY;
        let mut terms = Vec::with_capacity(pred.modes.len());
        let mut last_err = UpdateError::NonFinite;
        for (g, c) in pred.modes.iter().zip(&pred.cbar) {
            match self.updater.innovation(g, obs) {
                Ok(i) => {
                    min_nis = min_nis.min(i.nis);
                    if *c > 0.0 {
                        terms.push(c.ln() + i.log_likelihood());
                    }
                }
                Err(e) => last_err = e,
            }
        }
        let best = terms.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        if !min_nis.is_finite() || !best.is_finite() {
            return Err(last_err);
        }
        let log_lik = best + terms.iter().map(|t| (t - best).exp()).sum::<f64>().ln();
        Ok(Hypothesis { nis: min_nis, ln_det_2pi_s: -2.0 * log_lik - min_nis })
    }
}

fn vscale_vec(v: &[f64], s: f64) -> Vec<f64> {
    v.iter().map(|x| x * s).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{identity, trace};
    use crate::motion::{KalmanPredictor, Ncv};
    use crate::update::EkfUpdater;

    fn imm() -> ImmFilter {
        ImmFilter {
            name: "imm".into(),
            predictors: vec![
                Box::new(KalmanPredictor::new(Ncv::dwna(1.0))),
                Box::new(KalmanPredictor::new(Ncv::dwna(25.0))),
            ],
            sojourn_s: vec![60.0, 15.0],
            initial_mu: vec![0.9, 0.1],
            updater: Box::new(EkfUpdater::default()),
        }
    }

    #[test]
    fn transition_matrix_is_stochastic_and_time_dependent() {
        let f = imm();
        let p = f.transition_matrix(1.0);
        assert!((p[0][1] - (1.0 - (-1.0f64 / 60.0).exp())).abs() < 1e-15);
        assert!((p[1][0] - (1.0 - (-1.0f64 / 15.0).exp())).abs() < 1e-15);
        for row in &p {
            assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-15);
        }
        let p0 = f.transition_matrix(0.0);
        assert_eq!(p0, vec![vec![1.0, 0.0], vec![0.0, 1.0]]);
    }

    #[test]
    fn imm_prediction_mixes_like_filterpy() {
        // Two modes with different means: the mixed prior of mode j is the μ_{i|j}-weighted
        // moment match, and the combination uses c̄.
        let f = imm();
        let mut a = Gaussian { x: [0.0; 6], p: identity() };
        let mut b = a;
        a.x[0] = 0.0;
        b.x[0] = 10.0;
        let st = FilterState { modes: vec![a, b], mu: vec![0.7, 0.3] };
        let pr = f.predict(&st, 0.0);
        assert_eq!(pr.cbar, vec![0.7, 0.3]);
        assert_eq!(pr.modes[0].x[0], 0.0);
        assert_eq!(pr.modes[1].x[0], 10.0);
        assert!((pr.combined.x[0] - 3.0).abs() < 1e-12);
        // Spread of means enters the combined covariance: 1 + 0.7·9 + 0.3·49.
        assert!((pr.combined.p[0][0] - (1.0 + 0.7 * 9.0 + 0.3 * 49.0)).abs() < 1e-9);
        let pr = f.predict(&st, 10.0);
        let pi = f.transition_matrix(10.0);
        let c0 = pi[0][0] * 0.7 + pi[1][0] * 0.3;
        assert!((pr.cbar[0] - c0).abs() < 1e-15);
        let w00 = pi[0][0] * 0.7 / c0;
        // The mixed mean of mode 0 at t+10 s is (1 − w00)·10 (zero velocity).
        assert!((pr.modes[0].x[0] - (1.0 - w00) * 10.0).abs() < 1e-9);
    }

    #[test]
    fn stack_prediction_is_the_general_one_bit_for_bit() {
        let imm_of = |m: usize| {
            let mut f = imm();
            f.predictors.push(Box::new(KalmanPredictor::new(Ncv::dwna(80.0))));
            f.sojourn_s.push(5.0);
            f.predictors.truncate(m);
            f.sojourn_s.truncate(m);
            f
        };
        let modes: Vec<Gaussian> = (0..3)
            .map(|k| {
                let mut g = Gaussian { x: [0.0; 6], p: identity() };
                for (i, x) in g.x.iter_mut().enumerate() {
                    *x = (1.0 + k as f64) * (i as f64 * 0.37 - 1.1) * 123.456;
                    g.p[i][i] = 1.0 + 0.3 * (k * 6 + i) as f64;
                }
                g
            })
            .collect();
        for (m, mu) in [(2, vec![0.62, 0.38]), (3, vec![0.5, 0.3, 0.2]), (3, vec![1.0, 0.0, 0.0])] {
            let f = imm_of(m);
            let st = FilterState { modes: modes[..m].to_vec(), mu };
            for dt in [0.0, 0.25, 1.7, 40.0] {
                assert_eq!(f.predict(&st, dt), f.predict_general(&st, dt), "{m} modes, dt {dt}");
            }
        }
    }

    #[test]
    fn imm_mean_prediction_is_the_full_one_bit_for_bit() {
        let mut f = imm();
        f.predictors.push(Box::new(KalmanPredictor::new(Ncv::dwna(80.0))));
        f.sojourn_s.push(5.0);
        let modes: Vec<Gaussian> = (0..3)
            .map(|k| {
                let mut g = Gaussian { x: [0.0; 6], p: identity() };
                for (i, x) in g.x.iter_mut().enumerate() {
                    *x = (1.0 + k as f64) * (i as f64 * 0.37 - 1.1) * 123.456 + 6.4e6 * f64::from(i == 0);
                }
                g
            })
            .collect();
        for mu in [vec![0.5, 0.3, 0.2], vec![1.0, 0.0, 0.0], vec![0.01, 0.98, 0.01]] {
            let st = FilterState { modes: modes.clone(), mu };
            for dt in [0.0, 0.05, 0.25, 1.7, 40.0] {
                let full = f.predict(&st, dt).combined.x;
                let mean = f.predict_mean(&st, dt);
                assert!(
                    full.iter().zip(&mean).all(|(a, b)| a.to_bits() == b.to_bits()),
                    "dt {dt}: {full:?} vs {mean:?}"
                );
            }
        }
    }

    #[test]
    fn the_imm_trace_bound_holds_and_is_convex() {
        let f = imm();
        for k in 0..20 {
            let kf = k as f64;
            let mut a = Gaussian { x: [0.0; 6], p: identity() };
            let mut b = a;
            for i in 0..6 {
                a.x[i] = (i as f64 - 2.5) * 37.0 * (1.0 + kf);
                b.x[i] = a.x[i] + (kf - 9.5) * (1.0 + i as f64) * 11.0;
                a.p[i][i] = 10.0 + kf * i as f64;
                b.p[i][i] = 500.0 / (1.0 + kf) + i as f64;
            }
            a.p[0][3] = 3.0;
            a.p[3][0] = 3.0;
            let mu = 0.05 + 0.045 * kf;
            let st = FilterState { modes: vec![a, b], mu: vec![mu, 1.0 - mu] };
            let bound = |dt: f64| f.position_trace_upper_convex(&st, dt).expect("CV modes");
            let dts: Vec<f64> = (0..=40).map(|n| 0.25 * n as f64).collect();
            for &dt in &dts {
                let tr = trace(&f.predict(&st, dt).combined.pos_cov());
                assert!(bound(dt) >= tr * (1.0 - 1e-12), "k {k} dt {dt}: bound {} < trace {tr}", bound(dt));
            }
            // Convex: no point above the chord of its neighbours.
            for w in dts.windows(3) {
                assert!(bound(w[1]) <= 0.5 * (bound(w[0]) + bound(w[2])) * (1.0 + 1e-12));
            }
        }
    }
}
