//! Small fixed-size dense linear algebra on row-major arrays (`[[f64; C]; R]`).
//!
//! The filters only ever need 6×6 state, 3×3 innovation and 3×6 Jacobian matrices, so plain
//! arrays with const-generic helpers are both faster and simpler than a general matrix crate.
//! Symmetric positive-definite systems are solved with a Cholesky factor; no inverse is ever
//! formed.

// Index loops read like the textbook formulas in this module.
#![allow(clippy::needless_range_loop)]

/// A 6-vector (state).
pub type Vec6 = [f64; 6];
/// A 6×6 matrix (state covariance, transition).
pub type Mat6 = [[f64; 6]; 6];
/// A 3-vector (measurement).
pub type Vec3 = [f64; 3];
/// A 3×3 matrix (measurement and innovation covariance).
pub type Mat3 = [[f64; 3]; 3];
/// A 3×6 matrix (measurement Jacobian).
pub type Mat3x6 = [[f64; 6]; 3];

/// The R×R identity.
pub fn identity<const N: usize>() -> [[f64; N]; N] {
    let mut m = [[0.0; N]; N];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    m
}

/// A · B.
pub fn mul<const R: usize, const K: usize, const C: usize>(a: &[[f64; K]; R], b: &[[f64; C]; K]) -> [[f64; C]; R] {
    let mut out = [[0.0; C]; R];
    for (i, row) in out.iter_mut().enumerate() {
        for (k, bk) in b.iter().enumerate() {
            let aik = a[i][k];
            if aik != 0.0 {
                for (o, &bkj) in row.iter_mut().zip(bk) {
                    *o += aik * bkj;
                }
            }
        }
    }
    out
}

/// A · Bᵀ.
pub fn mul_t<const R: usize, const K: usize, const C: usize>(a: &[[f64; K]; R], b: &[[f64; K]; C]) -> [[f64; C]; R] {
    let mut out = [[0.0; C]; R];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, o) in row.iter_mut().enumerate() {
            *o = dot(&a[i], &b[j]);
        }
    }
    out
}

/// Aᵀ.
pub fn transpose<const R: usize, const C: usize>(a: &[[f64; C]; R]) -> [[f64; R]; C] {
    let mut out = [[0.0; R]; C];
    for (i, row) in a.iter().enumerate() {
        for (j, &x) in row.iter().enumerate() {
            out[j][i] = x;
        }
    }
    out
}

/// A · x.
pub fn mul_vec<const R: usize, const C: usize>(a: &[[f64; C]; R], x: &[f64; C]) -> [f64; R] {
    let mut out = [0.0; R];
    for (o, row) in out.iter_mut().zip(a) {
        *o = dot(row, x);
    }
    out
}

/// x · y.
pub fn dot<const N: usize>(x: &[f64; N], y: &[f64; N]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

/// A + B.
pub fn add<const R: usize, const C: usize>(a: &[[f64; C]; R], b: &[[f64; C]; R]) -> [[f64; C]; R] {
    let mut out = *a;
    for (o, br) in out.iter_mut().zip(b) {
        for (x, y) in o.iter_mut().zip(br) {
            *x += y;
        }
    }
    out
}

/// A − B.
pub fn sub<const R: usize, const C: usize>(a: &[[f64; C]; R], b: &[[f64; C]; R]) -> [[f64; C]; R] {
    let mut out = *a;
    for (o, br) in out.iter_mut().zip(b) {
        for (x, y) in o.iter_mut().zip(br) {
            *x -= y;
        }
    }
    out
}

/// s · A.
pub fn scale<const R: usize, const C: usize>(a: &[[f64; C]; R], s: f64) -> [[f64; C]; R] {
    let mut out = *a;
    for row in out.iter_mut() {
        for x in row.iter_mut() {
            *x *= s;
        }
    }
    out
}

/// x + y.
pub fn vadd<const N: usize>(x: &[f64; N], y: &[f64; N]) -> [f64; N] {
    std::array::from_fn(|i| x[i] + y[i])
}

/// x − y.
pub fn vsub<const N: usize>(x: &[f64; N], y: &[f64; N]) -> [f64; N] {
    std::array::from_fn(|i| x[i] - y[i])
}

/// s · x.
pub fn vscale<const N: usize>(x: &[f64; N], s: f64) -> [f64; N] {
    std::array::from_fn(|i| x[i] * s)
}

/// x xᵀ.
pub fn outer<const N: usize>(x: &[f64; N]) -> [[f64; N]; N] {
    std::array::from_fn(|i| std::array::from_fn(|j| x[i] * x[j]))
}

/// A · B · Aᵀ (B symmetric), symmetrized.
pub fn sandwich<const R: usize, const C: usize>(a: &[[f64; C]; R], b: &[[f64; C]; C]) -> [[f64; R]; R] {
    symmetrize(&mul_t(&mul(a, b), a))
}

/// ½ (A + Aᵀ).
pub fn symmetrize<const N: usize>(a: &[[f64; N]; N]) -> [[f64; N]; N] {
    let mut out = *a;
    for i in 0..N {
        for j in (i + 1)..N {
            let m = 0.5 * (a[i][j] + a[j][i]);
            out[i][j] = m;
            out[j][i] = m;
        }
    }
    out
}

/// [`symmetrize`] in place, bit for bit (each pair `(i, j)`, `(j, i)` is read before it is written
/// and touched by no other pair), without the copy.
pub fn symmetrize_in_place<const N: usize>(a: &mut [[f64; N]; N]) {
    for i in 0..N {
        for j in (i + 1)..N {
            let m = 0.5 * (a[i][j] + a[j][i]);
            a[i][j] = m;
            a[j][i] = m;
        }
    }
}

/// Largest absolute asymmetry max |A_ij − A_ji| relative to the largest |A_ij|.
pub fn relative_asymmetry<const N: usize>(a: &[[f64; N]; N]) -> f64 {
    let mut big = 0.0f64;
    let mut asym = 0.0f64;
    for i in 0..N {
        for j in 0..N {
            big = big.max(a[i][j].abs());
            asym = asym.max((a[i][j] - a[j][i]).abs());
        }
    }
    if big > 0.0 { asym / big } else { 0.0 }
}

/// Trace.
pub fn trace<const N: usize>(a: &[[f64; N]; N]) -> f64 {
    (0..N).map(|i| a[i][i]).sum()
}

/// Are all entries finite?
pub fn all_finite<const R: usize, const C: usize>(a: &[[f64; C]; R]) -> bool {
    a.iter().all(|r| r.iter().all(|x| x.is_finite()))
}

/// Lower Cholesky factor L of a symmetric positive-definite A (A = L Lᵀ), reading only the lower
/// triangle. `None` if A is not numerically positive definite or has non-finite entries.
pub fn cholesky<const N: usize>(a: &[[f64; N]; N]) -> Option<[[f64; N]; N]> {
    let mut l = [[0.0; N]; N];
    for j in 0..N {
        let mut d = a[j][j];
        for k in 0..j {
            d -= l[j][k] * l[j][k];
        }
        // Reject non-positive pivots and pivots lost in rounding relative to the diagonal.
        if !(d.is_finite() && d > a[j][j].abs() * 1e-15 && d > 0.0) {
            return None;
        }
        let djj = d.sqrt();
        l[j][j] = djj;
        for i in (j + 1)..N {
            let mut s = a[i][j];
            for k in 0..j {
                s -= l[i][k] * l[j][k];
            }
            l[i][j] = s / djj;
        }
    }
    Some(l)
}

/// Solve L y = b (L lower triangular).
pub fn forward_sub<const N: usize>(l: &[[f64; N]; N], b: &[f64; N]) -> [f64; N] {
    let mut y = [0.0; N];
    for i in 0..N {
        let mut s = b[i];
        for k in 0..i {
            s -= l[i][k] * y[k];
        }
        y[i] = s / l[i][i];
    }
    y
}

/// Solve Lᵀ x = y (L lower triangular).
pub fn backward_sub_t<const N: usize>(l: &[[f64; N]; N], y: &[f64; N]) -> [f64; N] {
    let mut x = [0.0; N];
    for i in (0..N).rev() {
        let mut s = y[i];
        for k in (i + 1)..N {
            s -= l[k][i] * x[k];
        }
        x[i] = s / l[i][i];
    }
    x
}

/// Solve A x = b given the Cholesky factor L of A.
pub fn chol_solve_vec<const N: usize>(l: &[[f64; N]; N], b: &[f64; N]) -> [f64; N] {
    backward_sub_t(l, &forward_sub(l, b))
}

/// Solve A X = B (B is N×M) given the Cholesky factor L of A, column by column.
pub fn chol_solve<const N: usize, const M: usize>(l: &[[f64; N]; N], b: &[[f64; M]; N]) -> [[f64; M]; N] {
    let mut x = [[0.0; M]; N];
    for c in 0..M {
        let col: [f64; N] = std::array::from_fn(|r| b[r][c]);
        let sol = chol_solve_vec(l, &col);
        for r in 0..N {
            x[r][c] = sol[r];
        }
    }
    x
}

/// ln det A from its Cholesky factor.
pub fn chol_log_det<const N: usize>(l: &[[f64; N]; N]) -> f64 {
    2.0 * (0..N).map(|i| l[i][i].ln()).sum::<f64>()
}

/// Squared Mahalanobis norm xᵀ A⁻¹ x = ‖L⁻¹ x‖² from the Cholesky factor of A.
pub fn chol_mahalanobis<const N: usize>(l: &[[f64; N]; N], x: &[f64; N]) -> f64 {
    let y = forward_sub(l, x);
    dot(&y, &y)
}

/// Make a symmetric matrix positive definite if it is not: symmetrize, then try Cholesky and
/// on failure add a relative jitter ε·diag(A) (plus a tiny absolute floor), ε growing 100× per
/// attempt from 1e-12. Returns the repaired matrix and whether jitter was needed, or `None` if
/// even large jitter fails (or entries are not finite).
pub fn ensure_pd<const N: usize>(a: &[[f64; N]; N]) -> Option<([[f64; N]; N], bool)> {
    let a = symmetrize(a);
    if !all_finite(&a) {
        return None;
    }
    if cholesky(&a).is_some() {
        return Some((a, false));
    }
    let max_diag = (0..N).map(|i| a[i][i].abs()).fold(0.0f64, f64::max);
    let floor = if max_diag > 0.0 { max_diag * 1e-18 } else { 1e-18 };
    let mut eps = 1e-12;
    for _ in 0..7 {
        let mut b = a;
        for (i, row) in b.iter_mut().enumerate() {
            row[i] += eps * a[i][i].abs() + floor;
        }
        if cholesky(&b).is_some() {
            return Some((b, true));
        }
        eps *= 100.0;
    }
    None
}

/// Eigenvalues of a symmetric 2×2 matrix, largest first.
pub fn sym2_eigenvalues(a: &[[f64; 2]; 2]) -> (f64, f64) {
    let m = 0.5 * (a[0][0] + a[1][1]);
    let d = 0.5 * (a[0][0] - a[1][1]);
    let off = 0.5 * (a[0][1] + a[1][0]);
    let r = (d * d + off * off).sqrt();
    (m + r, m - r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_solve_matches_known_system() {
        let a: Mat3 = [[4.0, 2.0, 0.6], [2.0, 5.0, 1.0], [0.6, 1.0, 3.0]];
        let l = cholesky(&a).expect("pd");
        let llt = mul_t(&l, &l);
        for i in 0..3 {
            for j in 0..3 {
                assert!((llt[i][j] - a[i][j]).abs() < 1e-14);
            }
        }
        let b = [1.0, -2.0, 0.5];
        let x = chol_solve_vec(&l, &b);
        let ax = mul_vec(&a, &x);
        for i in 0..3 {
            assert!((ax[i] - b[i]).abs() < 1e-13);
        }
        let det: f64 = 4.0 * (5.0 * 3.0 - 1.0) - 2.0 * (2.0 * 3.0 - 0.6) + 0.6 * (2.0 - 5.0 * 0.6);
        assert!((chol_log_det(&l) - det.ln()).abs() < 1e-13);
        assert!((chol_mahalanobis(&l, &b) - dot(&b, &x)).abs() < 1e-13);
    }

    #[test]
    fn cholesky_rejects_indefinite_and_nan() {
        assert!(cholesky(&[[1.0, 2.0], [2.0, 1.0]]).is_none());
        assert!(cholesky(&[[f64::NAN, 0.0], [0.0, 1.0]]).is_none());
        assert!(cholesky(&[[0.0, 0.0], [0.0, 1.0]]).is_none());
    }

    #[test]
    fn ensure_pd_repairs_semidefinite() {
        let a = [[1.0, 1.0], [1.0, 1.0]];
        let (b, jit) = ensure_pd(&a).expect("repairable");
        assert!(jit);
        assert!(cholesky(&b).is_some());
        assert!((b[0][0] - 1.0).abs() < 1e-6);
        assert!(ensure_pd(&[[f64::INFINITY, 0.0], [0.0, 1.0]]).is_none());
    }

    #[test]
    fn symmetrize_in_place_is_symmetrize_bit_for_bit() {
        let mut a = [[0.0; 4]; 4];
        for (k, x) in a.iter_mut().flatten().enumerate() {
            *x = [1.5, -0.0, 0.0, 1e308, -3.25, 7.0e-310, 2.0, -1e-3][k % 8] * (1.0 + k as f64);
        }
        let want = symmetrize(&a);
        symmetrize_in_place(&mut a);
        assert!(a.iter().flatten().zip(want.iter().flatten()).all(|(x, y)| x.to_bits() == y.to_bits()));
        assert!(a[0][3].is_infinite(), "an infinite entry stays infinite");
    }

    #[test]
    fn eigen2() {
        let (a, b) = sym2_eigenvalues(&[[2.0, 1.0], [1.0, 2.0]]);
        assert!((a - 3.0).abs() < 1e-14 && (b - 1.0).abs() < 1e-14);
    }
}
