//! The ML monopulse direction estimator (docs/model.md §2.5–§2.7): the ratio of the difference to
//! the sum channel over a set of cells, its Rayleigh ML bias correction, its variances and the
//! imaginary-part statistic `T` that flags merged returns.

use num_complex::Complex64;

/// `χ²₂(0.99)`: threshold of the imaginary-part statistic `T` (§2.7).
pub const MERGE_T_THRESHOLD: f64 = 9.21;
/// Above this predicted mean SNR (linear, 20 dB) the ML bias correction is skipped (§2.5).
pub const ML_CORRECTION_MAX_SNR: f64 = 100.0;

/// Result of the monopulse estimator on a set of cells (§2.5–§2.7).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Monopulse {
    /// ML ratio estimate in azimuth (bias-corrected when `c < 1`).
    pub eta_a: f64,
    /// ML ratio estimate in elevation (bias-corrected when `c < 1`).
    pub eta_e: f64,
    /// Imaginary part in azimuth, `Σ Im(Δa_k Σ_k*)/S`.
    pub eta_qa: f64,
    /// Imaginary part in elevation, `Σ Im(Δe_k Σ_k*)/S`.
    pub eta_qe: f64,
    /// Observed sum-channel SNR `S = Σ |Σ_k|²` (linear).
    pub s: f64,
    /// The bias factor used (1 when not applied).
    pub c: f64,
    /// Variance of `eta_a`.
    pub var_a: f64,
    /// Variance of `eta_e`.
    pub var_e: f64,
    /// Imaginary-part statistic `T` (χ²₂ for one target).
    pub t_stat: f64,
}

/// The ML bias factor `c = R̄/(1+R̄)` for a predicted mean SNR, or 1 when there is no prediction
/// or it exceeds 20 dB.
pub fn ml_bias_factor(predicted_snr: Option<f64>) -> f64 {
    match predicted_snr {
        Some(r) if r.is_finite() && r > 0.0 && r <= ML_CORRECTION_MAX_SNR => r / (1.0 + r),
        _ => 1.0,
    }
}

/// Monopulse ratio estimator over `(Σ_k, Δa_k, Δe_k)` samples with bias factor `c` (§2.5–§2.7).
pub fn monopulse(samples: &[(Complex64, Complex64, Complex64)], c: f64) -> Monopulse {
    let (mut s, mut ra, mut re, mut qa, mut qe) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for (sum, az, el) in samples {
        s += sum.norm_sqr();
        let pa = az * sum.conj();
        let pe = el * sum.conj();
        ra += pa.re;
        qa += pa.im;
        re += pe.re;
        qe += pe.im;
    }
    let s = s.max(f64::MIN_POSITIVE);
    let c = if c > 0.0 && c <= 1.0 { c } else { 1.0 };
    let eta_a = ra / s / c;
    let eta_e = re / s / c;
    let (eta_qa, eta_qe) = (qa / s, qe / s);
    // Conditional variances: the real part's about its mean and the imaginary part's (§2.6, §2.7).
    let vq_a = (1.0 + c * eta_a * eta_a) / (2.0 * s);
    let vq_e = (1.0 + c * eta_e * eta_e) / (2.0 * s);
    let t_stat = eta_qa * eta_qa / vq_a + eta_qe * eta_qe / vq_e;
    Monopulse { eta_a, eta_e, eta_qa, eta_qe, s, c, var_a: vq_a / (c * c), var_e: vq_e / (c * c), t_stat }
}
