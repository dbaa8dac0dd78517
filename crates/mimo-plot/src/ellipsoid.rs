//! Covariance ellipsoids: the principal axes of a 3×3 position covariance.
//!
//! The page draws a 1σ and a 3σ ellipsoid around a selected track state or measurement. The
//! ellipsoid `{x : xᵀ P⁻¹ x = k²}` has semi-axes `k √λᵢ eᵢ` with `(λᵢ, eᵢ)` the eigenpairs of
//! the symmetric `P`; they are computed here (cyclic Jacobi rotations, exact to rounding for a
//! 3×3 matrix) and embedded as three 1σ axis vectors, so the page only scales and draws them.

use glam::{DMat3, DVec3};

/// Eigen-decomposition of a symmetric 3×3 matrix: eigenvalues (descending) and unit
/// eigenvectors (the matching columns). Negative eigenvalues (a covariance that is not quite
/// positive semi-definite after rounding) are returned as they are.
#[allow(clippy::needless_range_loop)] // rows and columns p, q are rotated together
pub fn symmetric_eigen(m: DMat3) -> ([f64; 3], [DVec3; 3]) {
    let mut a = m.to_cols_array_2d(); // symmetric: a[i][j] = a[j][i] whichever is the column
    for i in 0..3 {
        for j in 0..i {
            let s = 0.5 * (a[i][j] + a[j][i]);
            a[i][j] = s;
            a[j][i] = s;
        }
    }
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]; // v[i] is the i-th eigenvector
    for _sweep in 0..50 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let scale = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        if off <= 1e-30 * scale || off == 0.0 {
            break;
        }
        for (p, q) in [(0usize, 1usize), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            // Rotation that zeroes a[p][q] (Golub & Van Loan, symmetric Schur).
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for k in 0..3 {
                let (akp, akq) = (a[k][p], a[k][q]);
                a[k][p] = c * akp - s * akq;
                a[k][q] = s * akp + c * akq;
            }
            for k in 0..3 {
                let (apk, aqk) = (a[p][k], a[q][k]);
                a[p][k] = c * apk - s * aqk;
                a[q][k] = s * apk + c * aqk;
            }
            for k in 0..3 {
                let (vkp, vkq) = (v[p][k], v[q][k]);
                v[p][k] = c * vkp - s * vkq;
                v[q][k] = s * vkp + c * vkq;
            }
        }
    }
    let mut idx = [0usize, 1, 2];
    idx.sort_by(|&i, &j| a[j][j].total_cmp(&a[i][i]));
    let vals = idx.map(|i| a[i][i]);
    let vecs = idx.map(|i| DVec3::from_array(v[i]).normalize());
    (vals, vecs)
}

/// The 1σ semi-axes `√λᵢ eᵢ` of a position covariance (m²), longest first. Negative
/// eigenvalues from rounding count as zero.
pub fn sigma_axes(cov: DMat3) -> [DVec3; 3] {
    let (vals, vecs) = symmetric_eigen(cov);
    [0, 1, 2].map(|i| vecs[i] * vals[i].max(0.0).sqrt())
}

/// The 3×3 position block (ECEF, m²) of a track row's packed 6×6 covariance.
pub fn position_block(cov21: &[f64; 21]) -> DMat3 {
    let m = mimo_core::records::unpack_cov(cov21);
    DMat3::from_cols_array_2d(&[[m[0][0], m[1][0], m[2][0]], [m[0][1], m[1][1], m[2][1]], [m[0][2], m[1][2], m[2][2]]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenpairs_of_a_rotated_diagonal_matrix() {
        let r = DMat3::from_rotation_z(0.7) * DMat3::from_rotation_x(-0.4);
        let d = DMat3::from_diagonal(DVec3::new(900.0, 25.0, 4.0));
        let m = r * d * r.transpose();
        let (vals, vecs) = symmetric_eigen(m);
        for (got, want) in vals.iter().zip([900.0, 25.0, 4.0]) {
            assert!((got - want).abs() < 1e-9 * 900.0, "{got} vs {want}");
        }
        for i in 0..3 {
            let mv = m * vecs[i];
            assert!((mv - vecs[i] * vals[i]).length() < 1e-9 * 900.0);
        }
        // The axes rebuild the matrix: Σ aᵢ aᵢᵀ = P.
        let ax = sigma_axes(m);
        let mut back = DMat3::ZERO;
        for a in ax {
            back += DMat3::from_cols(a * a.x, a * a.y, a * a.z);
        }
        assert!((back - m).to_cols_array().iter().all(|e| e.abs() < 1e-9 * 900.0));
    }

    #[test]
    fn degenerate_and_diagonal_inputs() {
        let (vals, _) = symmetric_eigen(DMat3::from_diagonal(DVec3::new(1.0, 3.0, 2.0)));
        assert_eq!(vals, [3.0, 2.0, 1.0]);
        let (vals, vecs) = symmetric_eigen(DMat3::IDENTITY * 5.0);
        assert_eq!(vals, [5.0; 3]);
        assert!(vecs.iter().all(|v| (v.length() - 1.0).abs() < 1e-12));
        let ax = sigma_axes(DMat3::ZERO);
        assert!(ax.iter().all(|a| a.length() == 0.0));
    }
}
