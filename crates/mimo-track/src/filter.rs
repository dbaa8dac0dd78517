//! Filters: a predictor and an updater composed into a per-track recursive estimator.
//!
//! Every filter keeps a [`FilterState`], a Gaussian mixture over motion modes with mode
//! probabilities `μ` (one mode with `μ = [1]` for a plain EKF), so the tracker treats the EKF and
//! the IMM alike. [`TrackFilter`] is the family trait; [`SingleModelFilter`] and [`ImmFilter`] are
//! the implementations ([`ImmFilter`] in `imm.rs`). The IMM follows filterpy's `IMMEstimator` (mixing, mode-matched
//! filtering, mode-probability update, moment-matched combination) with the time-dependent mode
//! transition matrix of docs/model.md §6.3.

use crate::association::Hypothesis;
use crate::frame::Gaussian;
use crate::linalg::{symmetrize_in_place, vsub};
use crate::measurement::Observation;
use crate::motion::Predictor;
use crate::update::{Innovation, UpdateError, Updater};

/// A mixture of mode-conditioned Gaussians with mode probabilities.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterState {
    /// Mode-conditioned estimates (one for a single-model filter).
    pub modes: Vec<Gaussian>,
    /// Mode probabilities, summing to one.
    pub mu: Vec<f64>,
}

impl FilterState {
    /// A single-mode state.
    pub fn single(g: Gaussian) -> FilterState {
        FilterState { modes: vec![g], mu: vec![1.0] }
    }

    /// The moment-matched combination `Σ μ_j N(x_j, P_j)`.
    pub fn combined(&self) -> Gaussian {
        moment_match(&self.mu, &self.modes)
    }

    /// Every mode is finite.
    pub fn is_finite(&self) -> bool {
        self.modes.iter().all(Gaussian::is_finite) && self.mu.iter().all(|m| m.is_finite())
    }
}

/// `x = Σ w_j x_j`, accumulated in `j` order.
pub(crate) fn weighted_mean(w: &[f64], g: &[Gaussian]) -> [f64; 6] {
    let mut x = [0.0; 6];
    for (wj, gj) in w.iter().zip(g) {
        for (xi, gi) in x.iter_mut().zip(&gj.x) {
            *xi += wj * gi;
        }
    }
    x
}

/// `x = Σ w_j x_j`, `P = Σ w_j (P_j + (x_j − x)(x_j − x)ᵀ)` (weights summing to 1).
pub fn moment_match(w: &[f64], g: &[Gaussian]) -> Gaussian {
    if g.len() == 1 {
        return g[0];
    }
    let x = weighted_mean(w, g);
    // `P += w_j (P_j + d dᵀ)` entry by entry: the same operations in the same order as
    // `add(&p, &scale(&add(&P_j, &outer(&d)), w_j))`, without the four 6×6 temporaries.
    let mut p = [[0.0; 6]; 6];
    for (&wj, gj) in w.iter().zip(g) {
        let d = vsub(&gj.x, &x);
        for ((prow, pjrow), &dr) in p.iter_mut().zip(&gj.p).zip(&d) {
            for ((pe, &pje), &dc) in prow.iter_mut().zip(pjrow).zip(&d) {
                *pe += (pje + dr * dc) * wj;
            }
        }
    }
    symmetrize_in_place(&mut p);
    Gaussian { x, p }
}

/// A prediction of a [`FilterState`]: mode-conditioned predictions, predicted mode
/// probabilities `c̄`, and their combination.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterPrediction {
    /// Mode-conditioned predictions.
    pub modes: Vec<Gaussian>,
    /// Predicted mode probabilities c̄.
    pub cbar: Vec<f64>,
    /// The moment-matched combination.
    pub combined: Gaussian,
}

/// Result of a filter update.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterUpdate {
    /// The updated state.
    pub state: FilterState,
    /// Innovation of the combined prediction (NIS for consistency checks).
    pub innovation: Innovation,
    /// Some mode needed jitter to stay positive definite.
    pub jitter: bool,
}

/// The predicted mean and a bound of the predicted position covariance, without the full
/// prediction (see [`TrackFilter::prediction_bound`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictionBound {
    /// The combined predicted mean (`predict(..).combined.x`, bit for bit).
    pub mean: [f64; 6],
    /// `tr P⁻_pos` of the combined prediction (up to rounding), an upper bound of its largest
    /// eigenvalue.
    pub position_trace: f64,
}

/// A recursive estimator for one track.
pub trait TrackFilter: Send + Sync {
    /// Name for manifests ("ekf-ncv", "imm-cv2").
    fn name(&self) -> String;
    /// Number of motion modes.
    fn n_modes(&self) -> usize;
    /// The filter state of a new track with estimate `g`.
    fn init(&self, g: Gaussian) -> FilterState;
    /// Predict over `dt` seconds (pure: the state is not changed).
    fn predict(&self, state: &FilterState, dt: f64) -> FilterPrediction;
    /// The combined mean of [`TrackFilter::predict`], bit for bit, without the covariances.
    fn predict_mean(&self, state: &FilterState, dt: f64) -> [f64; 6] {
        self.predict(state, dt).combined.x
    }
    /// Whether the trace of the combined predicted position covariance is convex in `dt ≥ 0` for
    /// this state (lets the tracker skip deletion checks that cannot fire, docs/model.md §6.4).
    /// The default, `false`, is always safe.
    fn position_trace_convex(&self, _state: &FilterState) -> bool {
        false
    }
    /// Whether the combined predicted mean of this state moves at constant velocity from the
    /// state's single mode, `p(dt) = p + dt·v`: schedulers then bound where the track can be
    /// over a window from the mean alone (docs/model.md §7.2). The default, `false`, is always
    /// safe.
    fn mean_constant_velocity(&self, _state: &FilterState) -> bool {
        false
    }
    /// An upper bound on the trace of the combined predicted position covariance at `dt`
    /// (m²), convex in `dt ≥ 0` for this state, for deletion certificates when
    /// [`TrackFilter::position_trace_convex`] cannot promise the trace itself (docs/model.md
    /// §6.4). The default, `None`, offers none.
    fn position_trace_upper_convex(&self, _state: &FilterState, _dt: f64) -> Option<f64> {
        None
    }
    /// Update a prediction with a measurement.
    fn update(&self, pred: &FilterPrediction, obs: Observation, iterations: u32) -> Result<FilterUpdate, UpdateError>;
    /// Innovation of the combined prediction.
    fn innovation(&self, pred: &FilterPrediction, obs: Observation) -> Result<Innovation, UpdateError>;

    /// What the pre-gate needs of [`TrackFilter::predict`] (docs/model.md §6.5): the combined
    /// predicted mean, bit for bit, and the trace of the predicted position covariance, when
    /// [`TrackFilter::hypothesis`] is the combined prediction's innovation. The default, `None`,
    /// means the tracker computes every pairing in full.
    fn prediction_bound(&self, _state: &FilterState, _dt: f64) -> Option<PredictionBound> {
        None
    }

    /// Gating and association statistics of a measurement (see [`Hypothesis`]). The default is
    /// the combined prediction's innovation.
    fn hypothesis(&self, pred: &FilterPrediction, obs: Observation) -> Result<Hypothesis, UpdateError> {
        self.innovation(pred, obs).map(|i| Hypothesis { nis: i.nis, ln_det_2pi_s: i.ln_det_2pi_s })
    }
}

/// One motion model, one updater: the EKF of the default tracker.
pub struct SingleModelFilter {
    /// Name for manifests.
    pub name: String,
    /// The motion model’s predictor.
    pub predictor: Box<dyn Predictor>,
    /// The measurement update.
    pub updater: Box<dyn Updater>,
}

impl TrackFilter for SingleModelFilter {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn n_modes(&self) -> usize {
        1
    }

    fn init(&self, g: Gaussian) -> FilterState {
        FilterState::single(g)
    }

    fn predict(&self, state: &FilterState, dt: f64) -> FilterPrediction {
        let g = self.predictor.predict(&state.combined(), dt);
        FilterPrediction { modes: vec![g], cbar: vec![1.0], combined: g }
    }

    fn predict_mean(&self, state: &FilterState, dt: f64) -> [f64; 6] {
        self.predictor.predict_mean(&state.combined(), dt)
    }

    fn position_trace_convex(&self, state: &FilterState) -> bool {
        self.predictor.position_trace_convex(&state.combined())
    }

    fn mean_constant_velocity(&self, state: &FilterState) -> bool {
        state.modes.len() == 1 && self.predictor.constant_velocity()
    }

    fn prediction_bound(&self, state: &FilterState, dt: f64) -> Option<PredictionBound> {
        // `combined()` of one mode is that mode: no copy.
        let combined;
        let g = match state.modes.as_slice() {
            [g] => g,
            _ => {
                combined = state.combined();
                &combined
            }
        };
        let position_trace = self.predictor.position_trace(g, dt)?;
        Some(PredictionBound { mean: self.predictor.predict_mean(g, dt), position_trace })
    }

    fn update(&self, pred: &FilterPrediction, obs: Observation, iterations: u32) -> Result<FilterUpdate, UpdateError> {
        let out = self.updater.update(&pred.combined, obs, iterations)?;
        Ok(FilterUpdate { state: FilterState::single(out.posterior), innovation: out.innovation, jitter: out.jitter })
    }

    fn innovation(&self, pred: &FilterPrediction, obs: Observation) -> Result<Innovation, UpdateError> {
        self.updater.innovation(&pred.combined, obs)
    }
}

pub use crate::imm::ImmFilter;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::{add, outer, scale, symmetrize};

    /// The matrix form `moment_match` had before it accumulated in place.
    fn moment_match_by_matrices(w: &[f64], g: &[Gaussian]) -> Gaussian {
        if g.len() == 1 {
            return g[0];
        }
        let x = weighted_mean(w, g);
        let mut p = [[0.0; 6]; 6];
        for (wj, gj) in w.iter().zip(g) {
            let d = vsub(&gj.x, &x);
            p = add(&p, &scale(&add(&gj.p, &outer(&d)), *wj));
        }
        Gaussian { x, p: symmetrize(&p) }
    }

    #[test]
    fn moment_match_in_place_is_the_matrix_form_bit_for_bit() {
        let mut seed = 0x1234_5678_9ABC_DEF0u64;
        let mut draw = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            let u = (seed >> 11) as f64 / (1u64 << 53) as f64;
            match seed >> 60 {
                0 => 0.0,
                1 => -0.0,
                2 => 1e300 * (u - 0.5),
                _ => (u - 0.5) * 2f64.powi(((seed >> 40) % 40) as i32 - 20),
            }
        };
        for n in 0..5_000 {
            let m = 2 + n % 3;
            let g: Vec<Gaussian> = (0..m)
                .map(|_| Gaussian {
                    x: std::array::from_fn(|_| draw() * 1e4),
                    p: std::array::from_fn(|_| std::array::from_fn(|_| draw())),
                })
                .collect();
            let raw: Vec<f64> = (0..m).map(|_| draw().abs()).collect();
            let s: f64 = raw.iter().sum();
            let w: Vec<f64> =
                if s > 0.0 && s.is_finite() { raw.iter().map(|x| x / s).collect() } else { vec![1.0 / m as f64; m] };
            let (got, want) = (moment_match(&w, &g), moment_match_by_matrices(&w, &g));
            let bits =
                |a: &Gaussian| -> Vec<u64> { a.x.iter().chain(a.p.iter().flatten()).map(|v| v.to_bits()).collect() };
            assert_eq!(bits(&got), bits(&want), "weights {w:?}, modes {g:?}");
        }
    }
}
