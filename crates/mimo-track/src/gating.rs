//! Gating (docs/model.md §6.5) and χ² helpers for consistency checks (§6.6).

use crate::association::Hypothesis;
use serde::{Deserialize, Serialize};

/// The gate family: decides whether a measurement may be associated with a track.
pub trait Gater: Send + Sync {
    /// Does the pairing pass the gate?
    fn accepts(&self, h: &Hypothesis) -> bool;
    /// Probability that a correct measurement passes (P_G), for likelihood costs.
    fn gate_probability(&self) -> f64;
    /// The NIS threshold (used as the miss cost of the simple NIS-cost GNN).
    fn threshold(&self) -> f64;
    /// The largest NIS the gate accepts, when it accepts a pairing on its NIS alone (lets the
    /// tracker skip pairs whose NIS is sure to be above it, docs/model.md §6.5). The default,
    /// `None`, means the tracker computes every pairing.
    fn nis_limit(&self) -> Option<f64> {
        None
    }
}

/// Ellipsoidal χ² gate on the NIS: `νᵀ S⁻¹ ν ≤ γ_G`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChiSquareGate {
    /// γ_G.
    pub threshold: f64,
    /// P_G = P(χ²₃ ≤ γ_G).
    pub probability: f64,
}

impl ChiSquareGate {
    /// 3-D, 99 %: γ = 11.34.
    pub const P99: ChiSquareGate = ChiSquareGate { threshold: 11.345, probability: 0.99 };
    /// 3-D, 99.9 %: γ = 16.27.
    pub const P999: ChiSquareGate = ChiSquareGate { threshold: 16.266, probability: 0.999 };
}

impl Default for ChiSquareGate {
    fn default() -> Self {
        ChiSquareGate::P999
    }
}

impl Gater for ChiSquareGate {
    fn accepts(&self, h: &Hypothesis) -> bool {
        h.nis.is_finite() && h.nis <= self.threshold
    }

    fn gate_probability(&self) -> f64 {
        self.probability
    }

    fn threshold(&self) -> f64 {
        self.threshold
    }

    fn nis_limit(&self) -> Option<f64> {
        Some(self.threshold)
    }
}

/// Standard normal quantile (Acklam's rational approximation, relative error < 1.2e-9).
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] =
        [7.784_695_709_041_462e-3, 3.224_671_290_700_398e-1, 2.445_134_137_142_996, 3.754_408_661_907_416];
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    let pl = 0.02425;
    if p < pl {
        let q = (-2.0 * p.ln()).sqrt();
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    } else if p <= 1.0 - pl {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -normal_quantile(1.0 - p)
    }
}

/// χ²_k quantile by the Wilson–Hilferty cube approximation (within 0.5 % for k ≥ 3 away from
/// the extreme tails; exact enough for Monte Carlo confidence bands, where k is large).
pub fn chi2_quantile(k: f64, p: f64) -> f64 {
    let z = normal_quantile(p);
    let a = 2.0 / (9.0 * k);
    k * (1.0 - a + z * a.sqrt()).powi(3).max(0.0)
}

/// Two-sided `conf` band of the average of `n` independent χ²_k variables, e.g. the ANEES of
/// N Monte Carlo runs with state dimension k: `[χ²_{kN}((1−c)/2), χ²_{kN}((1+c)/2)] / N`.
pub fn chi2_mean_band(k: f64, n: f64, conf: f64) -> (f64, f64) {
    let lo = chi2_quantile(k * n, 0.5 * (1.0 - conf)) / n;
    let hi = chi2_quantile(k * n, 0.5 * (1.0 + conf)) / n;
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_match_physics_md() {
        // docs/model.md §6.6: n = 6, N = 50 → [5.08, 7.00]; n = 3 → [2.36, 3.72].
        let (lo, hi) = chi2_mean_band(6.0, 50.0, 0.95);
        assert!((lo - 5.08).abs() < 0.01 && (hi - 7.00).abs() < 0.01, "{lo} {hi}");
        let (lo, hi) = chi2_mean_band(3.0, 50.0, 0.95);
        assert!((lo - 2.36).abs() < 0.01 && (hi - 3.72).abs() < 0.01, "{lo} {hi}");
        assert!((normal_quantile(0.975) - 1.959_964).abs() < 1e-6);
        assert!((chi2_quantile(3.0, 0.99) - 11.345).abs() < 0.05);
    }
}
