//! What a track covariance must be, and the bounded repair of one that rounding left slightly
//! indefinite (docs/design.md §7 "Covariances",
//! docs/decisions/0302-near-positive-semi-definite-covariances.md).
//!
//! A covariance (the upper triangle of a symmetric 6×6, row-major, 21 values; symmetric by
//! construction) is
//!
//! * **valid** when its values are finite, its variances positive and it is positive
//!   semi-definite to rounding: the Cholesky factorisation of its correlation matrix, with
//!   [`CORRELATION_SLACK`] added to the diagonal, succeeds. Valid rows are used as they are, bit
//!   for bit;
//! * **repairable** when it is not valid but its smallest eigenvalue is no more negative than
//!   [`NEGATIVE_EIGENVALUE_BOUND`] times its largest: the residue of double-precision Kalman
//!   updates. It is replaced by the matrix with the same eigenvectors whose eigenvalues are
//!   raised to at least [`REPAIR_FLOOR`] times the largest ([`repair`]): the nearest matrix (in
//!   the Frobenius norm) whose eigenvalues keep that floor, so it is positive definite, its
//!   inverse (NEES) and ellipsoids are defined, and it is valid when read again;
//! * **refused** otherwise: a non-finite value, a variance that is not positive, or a smallest
//!   eigenvalue beyond the bound, named in the message with the largest.

/// Added to the diagonal of the correlation matrix before the Cholesky test of a valid matrix.
pub const CORRELATION_SLACK: f64 = 1e-9;

/// How negative the smallest eigenvalue of a covariance may be, relative to its largest, to be
/// repaired rather than refused (docs/decisions/0302): 10⁻⁴ covers the −1.2·10⁻⁵ a Stone Soup
/// EKF left on scenario 7 eight times over, and a repair within it moves no standard deviation by
/// more than √10⁻⁴ = 1 % of the largest.
pub const NEGATIVE_EIGENVALUE_BOUND: f64 = 1e-4;

/// The least eigenvalue of a repaired covariance, relative to its largest.
pub const REPAIR_FLOOR: f64 = 1e-9;

/// A covariance that passed: as it is, or repaired.
#[derive(Debug, Clone, PartialEq)]
pub enum Accepted {
    /// Valid: used as it is.
    Valid,
    /// Slightly indefinite: use `cov` instead.
    Repaired {
        /// The repaired covariance (upper triangle).
        cov: [f64; 21],
        /// The smallest eigenvalue of the matrix given.
        min_eigenvalue: f64,
        /// Its largest eigenvalue.
        max_eigenvalue: f64,
    },
}

/// Judge a packed covariance: valid, repairable (with its repair) or refused (`Err` says what is
/// wrong, naming the smallest eigenvalue when the matrix is beyond the bound).
pub fn check(c: &[f64; 21]) -> Result<Accepted, String> {
    if let Some(k) = c.iter().position(|x| !x.is_finite()) {
        return Err(format!("value {k} is {} (expected a finite number)", c[k]));
    }
    let m = crate::records::unpack_cov(c);
    if let Some(i) = (0..6).find(|&i| m[i][i] <= 0.0) {
        return Err(format!("variance {i} (diagonal) is {} (expected a positive number)", m[i][i]));
    }
    if correlation_cholesky_ok(&m) {
        return Ok(Accepted::Valid);
    }
    let (values, vectors) = symmetric_eigen(&m);
    let (min, max) = (values[5], values[0]);
    if min < -NEGATIVE_EIGENVALUE_BOUND * max {
        return Err(format!(
            "is not positive semi-definite: its smallest eigenvalue is {min:.6e} against a largest of {max:.6e} \
             ({:.3e} of it; down to -{NEGATIVE_EIGENVALUE_BOUND:e} of it is repaired as rounding)",
            min / max
        ));
    }
    Ok(Accepted::Repaired { cov: rebuild(&values, &vectors, max), min_eigenvalue: min, max_eigenvalue: max })
}

/// Whether a packed covariance can be one (valid, or repairable): `Err` says what is wrong.
pub fn covariance_ok(c: &[f64; 21]) -> Result<(), String> {
    check(c).map(|_| ())
}

/// The covariance to use for `c`: `c` itself when it is valid (or refused: the caller checked
/// it), its repair when it is slightly indefinite.
pub fn repair(c: &[f64; 21]) -> [f64; 21] {
    match check(c) {
        Ok(Accepted::Repaired { cov, .. }) => cov,
        _ => *c,
    }
}

/// Whether `c` is accepted only after a repair.
pub fn needs_repair(c: &[f64; 21]) -> bool {
    matches!(check(c), Ok(Accepted::Repaired { .. }))
}

/// The Cholesky test of a valid covariance: its correlation matrix plus [`CORRELATION_SLACK`] on
/// the diagonal factorises (variances already known positive).
fn correlation_cholesky_ok(m: &[[f64; 6]; 6]) -> bool {
    let sd: [f64; 6] = std::array::from_fn(|i| m[i][i].sqrt());
    let mut l = [[0.0f64; 6]; 6];
    for i in 0..6 {
        for j in 0..=i {
            let r = m[i][j] / (sd[i] * sd[j]) + if i == j { CORRELATION_SLACK } else { 0.0 };
            let s = r - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if s.is_nan() || s <= 0.0 {
                    return false;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    true
}

/// `V diag(max(λ, floor)) Vᵀ`, packed, with the floor raised tenfold until the result is valid
/// (rounding in the product can leave a direction of a tiny variance below the Cholesky test's
/// slack); never above [`NEGATIVE_EIGENVALUE_BOUND`] times the largest eigenvalue.
fn rebuild(values: &[f64; 6], vectors: &[[f64; 6]; 6], max: f64) -> [f64; 21] {
    let mut floor = REPAIR_FLOOR * max;
    loop {
        let lam: [f64; 6] = values.map(|v| v.max(floor));
        let m: [[f64; 6]; 6] = std::array::from_fn(|i| {
            std::array::from_fn(|j| (0..6).map(|k| vectors[k][i] * lam[k] * vectors[k][j]).sum())
        });
        // Exactly symmetric: the upper triangle is what is stored.
        let packed = crate::records::pack_cov(&m);
        let m = crate::records::unpack_cov(&packed);
        if correlation_cholesky_ok(&m) || floor >= NEGATIVE_EIGENVALUE_BOUND * max {
            return packed;
        }
        floor *= 10.0;
    }
}

/// Eigenvalues (descending) and eigenvectors (`vectors[k]` goes with `values[k]`) of a symmetric
/// 6×6 matrix, by cyclic Jacobi rotations (Golub & Van Loan, §8.5), exact to rounding.
pub fn symmetric_eigen(m: &[[f64; 6]; 6]) -> ([f64; 6], [[f64; 6]; 6]) {
    let mut a = *m;
    let mut v: [[f64; 6]; 6] = std::array::from_fn(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }));
    for _sweep in 0..100 {
        let off: f64 = (0..6).flat_map(|p| ((p + 1)..6).map(move |q| (p, q))).map(|(p, q)| a[p][q] * a[p][q]).sum();
        let diag: f64 = (0..6).map(|i| a[i][i] * a[i][i]).sum();
        if off == 0.0 || off <= 1e-32 * diag {
            break;
        }
        for p in 0..6 {
            for q in (p + 1)..6 {
                rotate(&mut a, &mut v, p, q);
            }
        }
    }
    let mut idx: [usize; 6] = std::array::from_fn(|i| i);
    idx.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    (idx.map(|i| a[i][i]), idx.map(|i| v[i]))
}

/// One Jacobi rotation zeroing `a[p][q]`; the rows of `v` are the eigenvectors being built.
#[allow(clippy::needless_range_loop)] // rows and columns p, q are rotated together
fn rotate(a: &mut [[f64; 6]; 6], v: &mut [[f64; 6]; 6], p: usize, q: usize) {
    if a[p][q] == 0.0 {
        return;
    }
    let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
    let t = if theta == 0.0 { 1.0 } else { theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt()) };
    let c = 1.0 / (t * t + 1.0).sqrt();
    let s = t * c;
    for k in 0..6 {
        let (akp, akq) = (a[k][p], a[k][q]);
        a[k][p] = c * akp - s * akq;
        a[k][q] = s * akp + c * akq;
    }
    for k in 0..6 {
        let (apk, aqk) = (a[p][k], a[q][k]);
        a[p][k] = c * apk - s * aqk;
        a[q][k] = s * apk + c * aqk;
    }
    for k in 0..6 {
        let (vpk, vqk) = (v[p][k], v[q][k]);
        v[p][k] = c * vpk - s * vqk;
        v[q][k] = s * vpk + c * vqk;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::{pack_cov, unpack_cov};

    /// `Q diag(λ) Qᵀ` for a fixed rotation Q mixing every axis (so no eigenvalue sits on the
    /// diagonal) and the given eigenvalues.
    fn with_eigenvalues(lam: [f64; 6]) -> [[f64; 6]; 6] {
        let mut q: [[f64; 6]; 6] = std::array::from_fn(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }));
        for (p, r, angle) in
            [(0, 1, 0.3), (1, 2, 0.7), (2, 3, -0.4), (3, 4, 1.1), (4, 5, 0.2), (0, 5, 0.9), (1, 4, -0.6)]
        {
            let (c, s) = (f64::cos(angle), f64::sin(angle));
            for row in q.iter_mut() {
                let (x, y) = (row[p], row[r]);
                row[p] = c * x - s * y;
                row[r] = s * x + c * y;
            }
        }
        std::array::from_fn(|i| std::array::from_fn(|j| (0..6).map(|k| q[i][k] * lam[k] * q[j][k]).sum()))
    }

    fn smallest_eigenvalue(c: &[f64; 21]) -> f64 {
        symmetric_eigen(&unpack_cov(c)).0[5]
    }

    #[test]
    fn eigenvalues_of_a_known_matrix() {
        let lam = [4311.0, 900.0, 25.0, 4.0, 1.0, 0.5];
        let (values, vectors) = symmetric_eigen(&with_eigenvalues(lam));
        for (v, l) in values.iter().zip(lam) {
            assert!((v - l).abs() < 1e-9 * 4311.0, "{values:?}");
        }
        // Orthonormal eigenvectors.
        for i in 0..6 {
            for j in 0..6 {
                let d: f64 = (0..6).map(|k| vectors[i][k] * vectors[j][k]).sum();
                assert!((d - if i == j { 1.0 } else { 0.0 }).abs() < 1e-12, "{i} {j} {d}");
            }
        }
    }

    /// The hand-made cases: −1e-6 of the largest is repaired (and the repair is valid,
    /// positive definite and close), −1e-2 is refused with the eigenvalue named.
    #[test]
    fn slightly_indefinite_is_repaired_and_far_is_refused() {
        let max = 4311.0;
        let near = pack_cov(&with_eigenvalues([max, 900.0, 25.0, 4.0, 1.0, -1e-6 * max]));
        let Ok(Accepted::Repaired { cov, min_eigenvalue, max_eigenvalue }) = check(&near) else {
            panic!("expected a repair: {:?}", check(&near));
        };
        assert!((min_eigenvalue / max_eigenvalue + 1e-6).abs() < 1e-9, "{min_eigenvalue} {max_eigenvalue}");
        assert_eq!(check(&cov), Ok(Accepted::Valid), "a repaired covariance is valid when read again");
        assert!(smallest_eigenvalue(&cov) > 0.0);
        let change = cov.iter().zip(near).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(change < 2e-6 * max, "moved by {change}");
        assert!(needs_repair(&near) && covariance_ok(&near).is_ok());
        let far = pack_cov(&with_eigenvalues([max, 900.0, 25.0, 4.0, 1.0, -1e-2 * max]));
        let e = covariance_ok(&far).expect_err("beyond the bound");
        assert!(e.contains("smallest eigenvalue is -4.311") && e.contains("-1.000e-2 of it"), "{e}");
        // Just inside and just outside the bound.
        let inside = pack_cov(&with_eigenvalues([max, 900.0, 25.0, 4.0, 1.0, -0.9 * NEGATIVE_EIGENVALUE_BOUND * max]));
        assert!(needs_repair(&inside));
        let outside = pack_cov(&with_eigenvalues([max, 900.0, 25.0, 4.0, 1.0, -1.1 * NEGATIVE_EIGENVALUE_BOUND * max]));
        assert!(covariance_ok(&outside).is_err());
    }

    #[test]
    fn valid_rows_are_kept_bit_for_bit() {
        let c = pack_cov(&with_eigenvalues([4311.0, 900.0, 25.0, 4.0, 1.0, 0.01]));
        assert_eq!(check(&c), Ok(Accepted::Valid));
        assert_eq!(repair(&c).map(f64::to_bits), c.map(f64::to_bits));
        // Rank-deficient (a perfectly correlated pair) is semi-definite: valid as it is.
        let mut m = [[0.0; 6]; 6];
        for (i, row) in m.iter_mut().enumerate() {
            row[i] = 1.0 + i as f64;
        }
        m[0][3] = 2.0;
        m[3][0] = 2.0;
        assert_eq!(check(&pack_cov(&m)), Ok(Accepted::Valid));
    }

    #[test]
    fn broken_values_are_refused_as_before() {
        let mut c = pack_cov(&with_eigenvalues([4.0, 3.0, 2.0, 1.0, 1.0, 1.0]));
        c[0] = f64::NAN;
        assert!(covariance_ok(&c).expect_err("nan").contains("finite"));
        c[0] = -1.0;
        assert!(covariance_ok(&c).expect_err("negative").contains("variance 0"));
        c[0] = 0.0;
        assert!(covariance_ok(&c).expect_err("zero").contains("variance 0"));
        // The fault matrix's correlation far above 1.
        let mut m = unpack_cov(&pack_cov(&with_eigenvalues([4.0, 3.0, 2.0, 1.0, 1.0, 1.0])));
        m[0][1] = 10.0 * (m[0][0] * m[1][1]).sqrt();
        m[1][0] = m[0][1];
        let e = covariance_ok(&pack_cov(&m)).expect_err("correlation above 1");
        assert!(e.contains("smallest eigenvalue is -"), "{e}");
    }

    /// Tiny eigenvalues beside a large one (ten decades): the repair is valid when read again.
    #[test]
    fn repairs_across_a_wide_dynamic_range() {
        let c = pack_cov(&with_eigenvalues([1e6, 1e4, 100.0, 1e-2, 1e-4, -5.0]));
        let Ok(Accepted::Repaired { cov, .. }) = check(&c) else { panic!("{:?}", check(&c)) };
        assert_eq!(check(&cov), Ok(Accepted::Valid));
    }
}
