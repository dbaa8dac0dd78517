//! Range cells and the point-target range response (docs/model.md §4.1).
//!
//! Everything works in the equivalent monostatic range `ρ = R_B/2`, which is plain range for a
//! monostatic pair. Cells sit at `ρ_k = k·δ_s` with the sample spacing `δ_s = ΔR = c/(2B)`; the
//! matched-filter amplitude response to a point target is the triangle
//! `p(Δρ) = max(0, 1 − |Δρ|/ΔR)`, so a target between two samples at fractional offset `δ` gives
//! amplitudes `1 − δ` and `δ` (straddle loss −2.7 dB on average, −6.0 dB at worst).

/// Equivalent monostatic range `ρ = R_B/2` of a bistatic range sum.
pub fn equivalent_range(r_b_m: f64) -> f64 {
    0.5 * r_b_m
}

/// Triangular matched-filter amplitude response at range offset `d_rho_m`.
pub fn triangle(d_rho_m: f64, range_cell_m: f64) -> f64 {
    (1.0 - d_rho_m.abs() / range_cell_m).max(0.0)
}

/// Range of cell `k` (m).
pub fn cell_range(k: i64, spacing_m: f64) -> f64 {
    k as f64 * spacing_m
}

/// The cells `[k_min, k_max]` whose centres lie in `[rho_min, rho_max]`; `None` when empty or not
/// finite.
pub fn cell_window(rho_min_m: f64, rho_max_m: f64, spacing_m: f64) -> Option<(i64, i64)> {
    if !(rho_min_m.is_finite() && rho_max_m.is_finite() && spacing_m > 0.0) {
        return None;
    }
    let lo = (rho_min_m.max(0.0) / spacing_m).ceil();
    let hi = (rho_max_m / spacing_m).floor();
    if hi < lo || hi > 1e15 {
        return None;
    }
    Some((lo as i64, hi as i64))
}

/// Mean straddle loss on the peak sample in dB, `E[−20 log10 max(δ, 1−δ)]` for `δ` uniform:
/// 2.66 dB (docs/model.md §4.1, §7.2).
pub fn straddle_loss_mean_db() -> f64 {
    // 2∫_{½}^{1} −20 log10 x dx, in closed form.
    let ln_half = 0.5f64.ln();
    -(20.0 / std::f64::consts::LN_10) * 2.0 * ((0.0 - 1.0) - (0.5 * ln_half - 0.5))
}

/// Worst-case straddle loss (target midway between samples): 6.02 dB.
pub fn straddle_loss_worst_db() -> f64 {
    -20.0 * 0.5f64.log10()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn straddle_losses() {
        assert!((straddle_loss_mean_db() - 2.66).abs() < 0.01, "{}", straddle_loss_mean_db());
        assert!((straddle_loss_worst_db() - 6.02).abs() < 0.01);
        // Numerical check of the mean.
        let n = 100_000;
        let m: f64 = (0..n)
            .map(|i| {
                let d = (i as f64 + 0.5) / n as f64;
                -20.0 * triangle(d, 1.0).max(triangle(1.0 - d, 1.0)).log10()
            })
            .sum::<f64>()
            / n as f64;
        assert!((m - straddle_loss_mean_db()).abs() < 1e-3);
    }

    #[test]
    fn windows() {
        assert_eq!(cell_window(100.0, 200.0, 30.0), Some((4, 6)));
        assert_eq!(cell_window(100.0, 101.0, 30.0), None);
        assert_eq!(cell_window(f64::NAN, 101.0, 30.0), None);
        assert_eq!(triangle(15.0, 30.0), 0.5);
        assert_eq!(triangle(-45.0, 30.0), 0.0);
        assert_eq!(equivalent_range(200.0), 100.0);
    }
}
