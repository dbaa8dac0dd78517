//! The tracking frame (docs/model.md §1.2, §6.1).
//!
//! Tracks live in one fixed ENU frame at the scenario centre: ECEF rotated and translated, so that
//! "horizontal" means something for manoeuvre models and the covariance arithmetic never sees
//! ECEF's 6·10⁶ m offsets. Sites and faces are converted into it once per measurement; outputs
//! ([`StateEcef`], `TrackRow`) are rotated back to ECEF.

use crate::linalg::{Mat6, Vec6, all_finite};
use mimo_core::face::FaceFrame;
use mimo_core::geo::{EnuFrame, Geodetic};
use mimo_core::{DMat3, DVec3};

/// A Gaussian state estimate `x = [p; v]` (m, m/s) with covariance `p` in the tracking frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gaussian {
    /// Mean `[p; v]` (m, m/s).
    pub x: Vec6,
    /// Covariance.
    pub p: Mat6,
}

impl Gaussian {
    /// Position part.
    pub fn pos(&self) -> DVec3 {
        DVec3::new(self.x[0], self.x[1], self.x[2])
    }

    /// Velocity part.
    pub fn vel(&self) -> DVec3 {
        DVec3::new(self.x[3], self.x[4], self.x[5])
    }

    /// Position covariance block.
    pub fn pos_cov(&self) -> [[f64; 3]; 3] {
        std::array::from_fn(|i| std::array::from_fn(|j| self.p[i][j]))
    }

    /// Every entry of the mean and covariance is finite.
    pub fn is_finite(&self) -> bool {
        self.x.iter().all(|v| v.is_finite()) && all_finite(&self.p)
    }
}

/// A state estimate rotated to ECEF: position (m), velocity (m/s) and the 6×6 covariance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StateEcef {
    /// Position (m, ECEF).
    pub pos: DVec3,
    /// Velocity (m/s, ECEF).
    pub vel: DVec3,
    /// Covariance of `[pos; vel]` in ECEF.
    pub cov: Mat6,
}

/// A face (or any sensor axis set) expressed in the tracking frame: its origin and the rotation
/// tracking frame → face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFace {
    /// Face origin in the tracking frame (m).
    pub origin: DVec3,
    /// Rotation from the tracking frame into face coordinates.
    pub face_from_local: DMat3,
}

impl LocalFace {
    /// Direction cosines `(u, v, w)` and range of a tracking-frame point.
    pub fn ruvw(&self, p: DVec3) -> (f64, DVec3) {
        let l = self.face_from_local * (p - self.origin);
        let r = l.length();
        (r, l / r)
    }
}

/// The fixed ENU tracking frame at the scenario centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackFrame {
    /// Origin of the ENU frame.
    pub centre: Geodetic,
    /// The ENU frame at `centre`.
    pub enu: EnuFrame,
}

impl TrackFrame {
    /// The ENU frame at `centre` (scenario centre, any height; 0 m is customary).
    pub fn new(centre: Geodetic) -> TrackFrame {
        TrackFrame { centre, enu: EnuFrame::at(centre) }
    }

    /// ECEF point → tracking frame.
    pub fn to_local(&self, p_ecef: DVec3) -> DVec3 {
        self.enu.to_enu(p_ecef)
    }

    /// Tracking-frame point → ECEF.
    pub fn to_ecef(&self, p: DVec3) -> DVec3 {
        self.enu.to_ecef(p)
    }

    /// ECEF vector (velocity) → tracking frame.
    pub fn vec_to_local(&self, v_ecef: DVec3) -> DVec3 {
        self.enu.vec_to_enu(v_ecef)
    }

    /// Tracking-frame vector → ECEF.
    pub fn vec_to_ecef(&self, v: DVec3) -> DVec3 {
        self.enu.vec_to_ecef(v)
    }

    /// A face frame (ECEF) in the tracking frame.
    pub fn face_to_local(&self, f: &FaceFrame) -> LocalFace {
        LocalFace {
            origin: self.to_local(f.origin_ecef),
            face_from_local: f.face_from_ecef * self.enu.enu_from_ecef.transpose(),
        }
    }

    /// Rotate a tracking-frame 6×6 covariance to ECEF: `P_ecef = Aᵀ P A` with
    /// `A = blockdiag(R, R)`, `R` = ECEF → ENU.
    pub fn cov_to_ecef(&self, p: &Mat6) -> Mat6 {
        rotate_cov(p, &self.enu.enu_from_ecef.transpose())
    }

    /// Rotate an ECEF 6×6 covariance into the tracking frame.
    pub fn cov_to_local(&self, p: &Mat6) -> Mat6 {
        rotate_cov(p, &self.enu.enu_from_ecef)
    }

    /// A tracking-frame estimate in ECEF.
    pub fn state_to_ecef(&self, g: &Gaussian) -> StateEcef {
        StateEcef { pos: self.to_ecef(g.pos()), vel: self.vec_to_ecef(g.vel()), cov: self.cov_to_ecef(&g.p) }
    }

    /// An ECEF estimate in the tracking frame.
    pub fn state_from_ecef(&self, s: &StateEcef) -> Gaussian {
        let p = self.to_local(s.pos);
        let v = self.vec_to_local(s.vel);
        Gaussian { x: [p.x, p.y, p.z, v.x, v.y, v.z], p: self.cov_to_local(&s.cov) }
    }
}

/// `B P Bᵀ` with `B = blockdiag(M, M)`, symmetrized.
fn rotate_cov(p: &Mat6, m: &DMat3) -> Mat6 {
    let mm: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| m.col(j)[i]));
    let mut b = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            b[i][j] = mm[i][j];
            b[i + 3][j + 3] = mm[i][j];
        }
    }
    crate::linalg::sandwich(&b, p)
}

/// Convert a glam 3×3 matrix to a row-major array.
pub fn dmat3_rows(m: &DMat3) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m.col(j)[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ecef_round_trip_of_state_and_covariance() {
        let f = TrackFrame::new(Geodetic::from_deg(36.0, -70.0, 0.0));
        let mut p = [[0.0; 6]; 6];
        for (i, row) in p.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = if i == j { 10.0 + i as f64 } else { 0.3 * ((i + j) as f64).cos() };
            }
        }
        let g = Gaussian { x: [1000.0, -2000.0, 5000.0, 200.0, -30.0, 5.0], p };
        let e = f.state_to_ecef(&g);
        let back = f.state_from_ecef(&e);
        for i in 0..6 {
            assert!((back.x[i] - g.x[i]).abs() < 1e-6);
            for j in 0..6 {
                assert!((back.p[i][j] - g.p[i][j]).abs() < 1e-12);
            }
        }
        // Up in ENU is the ellipsoid normal at the centre.
        let up = f.vec_to_ecef(DVec3::Z);
        let n = DVec3::new(
            36f64.to_radians().cos() * (-70f64).to_radians().cos(),
            36f64.to_radians().cos() * (-70f64).to_radians().sin(),
            36f64.to_radians().sin(),
        );
        assert!((up - n).length() < 1e-12);
        // Traces are rotation invariant per block.
        let tr_p: f64 = (0..3).map(|i| e.cov[i][i]).sum();
        assert!((tr_p - (10.0 + 11.0 + 12.0)).abs() < 1e-9);
    }
}
