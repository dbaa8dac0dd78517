//! Polarimetric scattering (docs/model.md §3.5, option `fidelity.polarization`): the echo voltage
//! of a target on a Tx→Rx pair is `s = h_rᵀ R(β) S R(β)ᵀ h_t`, with `S` the target's 2×2 complex
//! Gaussian scattering matrix in its own H/V basis, `R(β)` the rotation of that basis about the
//! line of sight and `h_t`, `h_r` the unit Jones vectors of the radars' linear polarizations.
//!
//! `S` is drawn once per dwell, per Tx–Rx pair and per target from the same stream as the
//! Swerling draw it replaces. A monostatic pair is reciprocal (`s_HV = s_VH`); a bistatic pair
//! draws the two cross-polar terms independently.

use mimo_core::polarimetry::Polarimetry;
use mimo_core::rng::Stream;
use num_complex::Complex64;

/// A target's scattering matrix in its own basis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scattering {
    /// `s_HH`.
    pub hh: Complex64,
    /// `s_HV` (H received from V transmitted).
    pub hv: Complex64,
    /// `s_VH` (V received from H transmitted).
    pub vh: Complex64,
    /// `s_VV`.
    pub vv: Complex64,
}

/// The Jones vector of a linear polarization at `angle_deg` from H, seen in the target's basis
/// rotated by `rotation_deg`: `R(β)ᵀ h = [cos(α−β), sin(α−β)]`.
pub fn jones_in_target_basis(angle_deg: f64, rotation_deg: f64) -> [f64; 2] {
    let a = (angle_deg - rotation_deg).to_radians();
    [a.cos(), a.sin()]
}

/// Draw `S` with the statistics of `p` (`E|s_HH|² = hh_m2`, …); `monostatic` ties `s_VH` to `s_HV`.
pub fn draw_scattering(p: &Polarimetry, monostatic: bool, s: &mut Stream) -> Scattering {
    let cn = |s: &mut Stream| {
        let (re, im) = s.cn01();
        Complex64::new(re, im)
    };
    let (z1, z2, z3, z4) = (cn(s), cn(s), cn(s), cn(s));
    let rho = p.hh_vv_correlation;
    let hh = z1 * p.hh_m2.sqrt();
    let vv = (z1 * rho + z2 * (1.0 - rho * rho).max(0.0).sqrt()) * p.vv_m2.sqrt();
    let hv = z3 * p.hv_m2.sqrt();
    let vh = if monostatic { hv } else { z4 * p.hv_m2.sqrt() };
    Scattering { hh, hv, vh, vv }
}

/// The effective voltage `gᵀ S f` for receive and transmit Jones vectors `g`, `f` in the target's
/// basis (units √m², like `√σ̄ ζ`).
pub fn effective_voltage(sm: &Scattering, g: [f64; 2], f: [f64; 2]) -> Complex64 {
    sm.hh * (g[0] * f[0]) + sm.hv * (g[0] * f[1]) + sm.vh * (g[1] * f[0]) + sm.vv * (g[1] * f[1])
}

/// `E|gᵀ S f|²` (m²): the mean RCS the pair sees.
pub fn mean_rcs_m2(p: &Polarimetry, monostatic: bool, g: [f64; 2], f: [f64; 2]) -> f64 {
    let co = g[0] * g[0] * f[0] * f[0] * p.hh_m2
        + g[1] * g[1] * f[1] * f[1] * p.vv_m2
        + 2.0 * p.hh_vv_correlation * g[0] * f[0] * g[1] * f[1] * (p.hh_m2 * p.vv_m2).sqrt();
    let cross = if monostatic {
        let c = g[0] * f[1] + g[1] * f[0];
        c * c
    } else {
        g[0] * g[0] * f[1] * f[1] + g[1] * g[1] * f[0] * f[0]
    };
    (co + cross * p.hv_m2).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::rng::domain;

    fn sample(p: &Polarimetry, mono: bool, g: [f64; 2], f: [f64; 2], n: usize, key: u64) -> (f64, f64) {
        let mut s = Stream::new(11, &[domain::TEST, key]);
        let (mut m, mut m2) = (0.0, 0.0);
        for _ in 0..n {
            let x = effective_voltage(&draw_scattering(p, mono, &mut s), g, f).norm_sqr();
            m += x;
            m2 += x * x;
        }
        let mean = m / n as f64;
        (mean, ((m2 / n as f64 - mean * mean) / n as f64).sqrt())
    }

    /// The sample mean power matches the closed form for co-, cross- and slant polarizations,
    /// rotated or not, monostatic and bistatic (each within 4.5 standard errors).
    #[test]
    fn mean_power_matches_the_closed_form() {
        let p = Polarimetry { hh_m2: 2.0, vv_m2: 5.0, hv_m2: 0.4, hh_vv_correlation: 0.5, rotation_deg: 0.0 };
        let cases = [(0.0, 0.0, 0.0), (90.0, 90.0, 0.0), (0.0, 90.0, 0.0), (45.0, 45.0, 0.0), (30.0, 100.0, 25.0)];
        for (k, &(at, ar, beta)) in cases.iter().enumerate() {
            for mono in [true, false] {
                let f = jones_in_target_basis(at, beta);
                let g = jones_in_target_basis(ar, beta);
                let want = mean_rcs_m2(&p, mono, g, f);
                let (got, se) = sample(&p, mono, g, f, 60_000, k as u64 * 2 + u64::from(mono));
                assert!((got - want).abs() < 4.5 * se, "case {k} mono {mono}: {got} vs {want} ± {se}");
            }
        }
        // The named cases: HH sees hh, VV sees vv, H→V sees hv.
        let (h, v) = (jones_in_target_basis(0.0, 0.0), jones_in_target_basis(90.0, 0.0));
        assert!((mean_rcs_m2(&p, true, h, h) - 2.0).abs() < 1e-12);
        assert!((mean_rcs_m2(&p, true, v, v) - 5.0).abs() < 1e-12);
        assert!((mean_rcs_m2(&p, true, v, h) - 0.4).abs() < 1e-12);
    }

    /// A 90° rotation swaps the co-polar channels: an H radar sees `vv`.
    #[test]
    fn rotation_by_a_right_angle_swaps_hh_and_vv() {
        let p = Polarimetry { hh_m2: 1.0, vv_m2: 8.0, hv_m2: 0.1, hh_vv_correlation: 0.5, rotation_deg: 90.0 };
        let h = jones_in_target_basis(0.0, p.rotation_deg);
        assert!((mean_rcs_m2(&p, true, h, h) - 8.0).abs() < 1e-9);
    }

    /// `s_HH` and `s_VV` have the stated correlation coefficient; a monostatic pair is reciprocal.
    #[test]
    fn hh_vv_correlation_and_reciprocity() {
        let p = Polarimetry { hh_m2: 3.0, vv_m2: 1.0, hv_m2: 0.3, hh_vv_correlation: 0.5, rotation_deg: 0.0 };
        let mut s = Stream::new(12, &[domain::TEST, 99]);
        let n = 60_000;
        let (mut c, mut a, mut b) = (Complex64::new(0.0, 0.0), 0.0, 0.0);
        for _ in 0..n {
            let sm = draw_scattering(&p, true, &mut s);
            assert_eq!(sm.hv, sm.vh);
            c += sm.hh * sm.vv.conj();
            a += sm.hh.norm_sqr();
            b += sm.vv.norm_sqr();
        }
        let rho = c.norm() / (a * b).sqrt();
        // Standard error of a sample coherence near 0.5 with n = 60 000 is about (1−ρ²)/√n ≈ 0.003.
        assert!((rho - 0.5).abs() < 0.015, "rho {rho}");
        let mut s = Stream::new(12, &[domain::TEST, 100]);
        let sm = draw_scattering(&p, false, &mut s);
        assert_ne!(sm.hv, sm.vh);
    }
}
