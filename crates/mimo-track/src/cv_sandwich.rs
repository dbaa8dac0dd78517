//! `F P Fᵀ` for the constant-velocity transition `F = [[I, dt I], [0, I]]`, bit for bit equal to
//! the dense [`crate::linalg::sandwich`] (docs/model.md §6.1;
//! docs/decisions/0047-exact-constant-velocity-predictions.md).
//!
//! The dense sandwich forms `M = F P` with [`crate::linalg::mul`] (which skips the zeros of `F`, so
//! `M` is `0 + P_ij + dt·P_i+3,j` or `0 + P_ij` exactly as written here), then each entry of
//! `M Fᵀ` as a dot product of six terms summed from the float `Sum`'s start value, four or five of
//! them `M_ik · 0`. When `M` is finite those are zeros (of either sign); adding a zero to a non-zero
//! running sum leaves it unchanged, and adding a non-zero term to a zero of either sign gives that
//! term exactly, so the running sum over only the non-zero terms equals the dense one at every step
//! up to the sign of a zero: a non-zero, finite sparse entry `M_ij + M_i,j+3·dt` (or `M_ij`) is the
//! dense entry bit for bit. A row with a zero or non-finite entry takes the dense dot products
//! (that covers a row of `M` that is not finite, where the dense `M_ik · 0` are NaN); `dt = 0`
//! takes the dense sandwich. Then the same `symmetrize`. (NaN results may differ in payload,
//! which Rust leaves unspecified.)

use crate::linalg::{Mat6, add, dot, mul, mul_t, symmetrize};
use crate::motion::cv_transition;

/// `0 < |x| ≤ f64::MAX` (false for zeros, infinities and NaN), without branches.
fn nonzero_finite(x: f64) -> bool {
    let a = x.abs();
    (a > 0.0) & (a <= f64::MAX)
}

/// `sandwich(&cv_transition(dt), p)`, bit for bit, with a quarter of the multiplications.
#[cfg(test)]
pub fn cv_sandwich(dt: f64, p: &Mat6) -> Mat6 {
    symmetrize(&cv_product(dt, p))
}

/// The predicted covariance `symmetrize(add(sandwich(F, P), Q))` of `ekf_predict` for
/// `F = cv_transition(dt)`, bit for bit. When `Q` is symmetric bit for bit (as
/// [`crate::motion::ProcessNoise::q`] builds it), `sandwich(F, P) + Q` is too, so the second
/// `symmetrize` maps each entry `x` to `0.5·(x + x)`: both passes fold into one over the upper
/// triangle.
pub fn cv_predicted_covariance(dt: f64, p: &Mat6, q: &Mat6) -> Mat6 {
    let t = cv_product(dt, p);
    let symmetric_q = (0..6).all(|i| (i + 1..6).all(|j| q[i][j].to_bits() == q[j][i].to_bits()));
    if !symmetric_q {
        return symmetrize(&add(&symmetrize(&t), q));
    }
    let mut out = [[0.0; 6]; 6];
    for i in 0..6 {
        out[i][i] = t[i][i] + q[i][i];
        for j in (i + 1)..6 {
            let x = 0.5 * (t[i][j] + t[j][i]) + q[i][j];
            let y = 0.5 * (x + x);
            out[i][j] = y;
            out[j][i] = y;
        }
    }
    out
}

/// `mul_t(mul(F, P), F)` for `F = cv_transition(dt)`, bit for bit (before `symmetrize`).
#[inline(always)]
fn cv_product(dt: f64, p: &Mat6) -> Mat6 {
    if dt == 0.0 {
        // `mul` skips the `dt` terms altogether.
        let f = cv_transition(dt);
        return mul_t(&mul(&f, p), &f);
    }
    // M = F P as `mul` accumulates it: from +0, `1·P_ij` (= P_ij), then `dt·P_i+3,j`.
    let mut m = [[0.0; 6]; 6];
    for j in 0..6 {
        for i in 0..3 {
            m[i][j] = (0.0 + p[i][j]) + dt * p[i + 3][j];
            m[i + 3][j] = 0.0 + p[i + 3][j];
        }
    }
    // M Fᵀ over the non-zero terms; a row with a zero or non-finite entry is redone densely. A
    // non-finite M_ik makes entry (i, k) non-finite, so a row of M that is not finite (where the
    // dense `M_ik · 0` terms are NaN) is always redone.
    let mut t = [[0.0; 6]; 6];
    for (trow, mrow) in t.iter_mut().zip(&m) {
        for j in 0..3 {
            trow[j] = mrow[j] + mrow[j + 3] * dt;
            trow[j + 3] = mrow[j + 3];
        }
    }
    // The product of a row is zero or not finite if an entry is (and sometimes, harmlessly, when
    // it underflows or overflows): a cheap test that never misses a row to redo.
    let f = cv_transition(dt);
    for (trow, mrow) in t.iter_mut().zip(&m) {
        if !nonzero_finite((trow[0] * trow[1]) * (trow[2] * trow[3]) * (trow[4] * trow[5])) {
            for (o, fj) in trow.iter_mut().zip(&f) {
                *o = dot(mrow, fj);
            }
        }
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::ProcessNoise;

    /// SplitMix64: a small deterministic generator for the property tests.
    struct Rng(u64);

    impl Rng {
        fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }

        fn below(&mut self, n: u64) -> u64 {
            self.next_u64() % n
        }

        fn unit(&mut self) -> f64 {
            (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
        }

        /// A value drawn from a mix of ordinary, degenerate and extreme floats.
        fn value(&mut self) -> f64 {
            let sign = if self.below(2) == 0 { 1.0 } else { -1.0 };
            match self.below(16) {
                0 => 0.0,
                1 => -0.0,
                2 => sign * f64::MAX * self.unit(),
                3 => sign * f64::MIN_POSITIVE * self.unit(),
                4 => sign * 1e300,
                5 => sign * 1e-300,
                6 => [f64::INFINITY, f64::NEG_INFINITY, f64::NAN][self.below(3) as usize],
                7 => sign * (self.below(5) as f64),
                _ => sign * (self.unit() * 40.0 - 20.0).exp2() * self.unit(),
            }
        }

        /// A random matrix, each entry kept (probability `dense`/4) or zeroed.
        fn matrix<const R: usize, const C: usize>(&mut self, dense: u64) -> [[f64; C]; R] {
            std::array::from_fn(|_| std::array::from_fn(|_| if self.below(4) < dense { self.value() } else { 0.0 }))
        }

        /// A random covariance-like symmetric matrix of ordinary magnitudes with some exact
        /// zeros and negative zeros.
        #[allow(clippy::needless_range_loop)] // the symmetric fill reads best with indices
        fn covariance<const N: usize>(&mut self) -> [[f64; N]; N] {
            let mut p = [[0.0; N]; N];
            for i in 0..N {
                for j in i..N {
                    let x = match self.below(6) {
                        0 => 0.0,
                        1 => -0.0,
                        _ => (self.unit() - 0.5) * (self.unit() * 30.0 - 10.0).exp2(),
                    };
                    p[i][j] = x;
                    p[j][i] = x;
                }
            }
            p
        }
    }

    /// Equal bit for bit, but any NaN equals any NaN (Rust does not specify the payload or sign of
    /// a NaN result).
    fn same_bits(a: &Mat6, b: &Mat6) -> bool {
        a.iter()
            .flatten()
            .zip(b.iter().flatten())
            .all(|(x, y)| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()))
    }

    /// The reference: the dense sandwich, `symmetrize(mul_t(mul(F, P), F))`.
    fn dense(dt: f64, p: &Mat6) -> Mat6 {
        let f = cv_transition(dt);
        symmetrize(&mul_t(&mul(&f, p), &f))
    }

    #[test]
    fn the_cv_sandwich_is_the_dense_one_bit_for_bit_on_random_and_degenerate_matrices() {
        let mut rng = Rng(0x5EED);
        let fixed = [0.0, -0.0, 1e-300, -1e-300, 5e-324, -0.7, 0.25, 1.0, 3.3, -40.0, 1e3, 1e200, -1e200];
        let special = [f64::INFINITY, f64::NEG_INFINITY, f64::NAN, f64::MAX, f64::MIN_POSITIVE];
        let mut fallbacks = 0;
        for n in 0..20_000 {
            // Covariances of ordinary magnitudes (with zeros and negative zeros) and, one in
            // four, sparse matrices of extreme, infinite and NaN entries.
            let p: Mat6 = if n % 4 == 0 { rng.matrix(1 + (n / 4 % 4) as u64) } else { rng.covariance() };
            let drawn = [rng.value(), (rng.unit() - 0.5) * 20.0, special[n % special.len()]];
            for dt in fixed.iter().chain(&drawn).copied() {
                let want = dense(dt, &p);
                fallbacks += want.iter().flatten().filter(|x| **x == 0.0 || !x.is_finite()).count();
                let got = cv_sandwich(dt, &p);
                assert!(same_bits(&got, &want), "dt {dt:e}, P {p:?}: {got:?} vs {want:?}");
            }
        }
        // The draws reach the zero and non-finite entries the fallbacks exist for.
        assert!(fallbacks > 100_000, "{fallbacks}");
    }

    #[test]
    fn cancelling_and_overflowing_entries_match_the_dense_sandwich() {
        // P_03 = −P_33·dt cancels M_03 and the covariance term of entry (0, 0) to an exact zero;
        // huge entries overflow M to infinity.
        let mut p = [[0.0; 6]; 6];
        p[0][0] = 4.0;
        p[3][3] = 2.0;
        p[0][3] = -1.0;
        p[3][0] = -1.0;
        for dt in [0.5, 2.0, -2.0] {
            assert!(same_bits(&cv_sandwich(dt, &p), &dense(dt, &p)), "dt {dt}");
        }
        assert_eq!(cv_sandwich(0.5, &p)[0][3], 0.0);
        p[4][4] = f64::MAX;
        p[1][1] = f64::MAX;
        let want = dense(3.0, &p);
        assert!(want[1][1].is_infinite());
        assert!(same_bits(&cv_sandwich(3.0, &p), &want));
    }

    #[test]
    fn the_fused_predicted_covariance_is_the_two_pass_one_bit_for_bit() {
        let mut rng = Rng(0xC0DE);
        for n in 0..20_000 {
            let p: Mat6 = if n % 4 == 0 { rng.matrix(1 + (n / 4 % 4) as u64) } else { rng.covariance() };
            let dt = match n % 5 {
                0 => rng.value(),
                1 => 0.0,
                _ => (rng.unit() - 0.5) * 20.0,
            };
            let q = match n % 3 {
                0 => ProcessNoise::Dwna { sigma_a_mps2: rng.unit() * 30.0 }.q(dt),
                1 => ProcessNoise::Cwna { q_m2ps3: rng.value().abs() }.q(dt),
                // Not symmetric: the two-pass path.
                _ => rng.matrix(2),
            };
            let want = symmetrize(&add(&dense(dt, &p), &q));
            let got = cv_predicted_covariance(dt, &p, &q);
            assert!(same_bits(&got, &want), "dt {dt:e}, P {p:?}, Q {q:?}: {got:?} vs {want:?}");
        }
    }
}
