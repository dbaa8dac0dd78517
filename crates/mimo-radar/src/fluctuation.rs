//! RCS fluctuation: Swerling draws of the unit-mean-power voltage `ζ` (docs/model.md §3.2).
//!
//! One draw per target, per Tx–Rx pair and per dwell (SW0/SW1/SW3 are constant within a dwell;
//! pairs of a MIMO dwell are independent: spatial RCS diversity). The caller keys the stream by
//! (dwell, tx, rx, target) so a draw never depends on what else is in the scene.

use mimo_core::params::Swerling;
use mimo_core::rng::Stream;
use num_complex::Complex64;

/// Draw the complex RCS voltage `ζ` with `E|ζ|² = 1` for a Swerling case.
///
/// * SW0: `e^{jφ}`;
/// * SW1: `ζ ~ CN(0, 1)` (σ exponential);
/// * SW3: `√(σ/σ̄) e^{jφ}` with `σ/σ̄ ~ Γ(2, ½)`, the sum of two unit exponentials halved.
pub fn draw_zeta(swerling: Swerling, s: &mut Stream) -> Complex64 {
    match swerling {
        Swerling::Sw0 => Complex64::from_polar(1.0, s.phase()),
        Swerling::Sw1 => {
            let (re, im) = s.cn01();
            Complex64::new(re, im)
        }
        Swerling::Sw3 => {
            let ratio = 0.5 * (s.exp1() + s.exp1());
            Complex64::from_polar(ratio.sqrt(), s.phase())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::rng::domain;

    #[test]
    fn unit_mean_power_and_right_shape() {
        let n = 100_000;
        for (sw, var_of_power) in [(Swerling::Sw0, 0.0), (Swerling::Sw1, 1.0), (Swerling::Sw3, 0.5)] {
            let mut s = Stream::new(5, &[domain::TEST, sw as u64]);
            let (mut m, mut m2) = (0.0, 0.0);
            for _ in 0..n {
                let p = draw_zeta(sw, &mut s).norm_sqr();
                m += p;
                m2 += p * p;
            }
            let nf = n as f64;
            let mean = m / nf;
            let var = m2 / nf - mean * mean;
            // Mean power 1 (std error sqrt(var/n)); power variance 0 / 1 / ½ (χ² with 2 or 4 dof).
            let se = (var_of_power / nf).sqrt().max(1e-12);
            assert!((mean - 1.0).abs() < 4.5 * se + 1e-12, "{sw:?} mean {mean}");
            assert!((var - var_of_power).abs() < 0.05 * var_of_power.max(0.01), "{sw:?} var {var}");
        }
    }
}
