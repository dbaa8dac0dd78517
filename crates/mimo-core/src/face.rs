//! Array faces and sine space (docs/model.md §1.3–§1.5).
//!
//! A face frame has axes `(x̂_f, ŷ_f, n̂)`: `x̂_f` horizontal and pointing to the **left** when
//! looking out along boresight, `ŷ_f` "face-up", `n̂` the boresight. The direction cosines of a
//! point seen from the face are `(u, v, w) = face_from_ecef · (p − s) / ‖p − s‖`; the point is in
//! front of the face when `w > 0`.

use crate::geo::{Geodetic, enu_from_ecef};
use glam::{DMat3, DVec3};

/// Face axes written in ENU for boresight azimuth `az_rad` (clockwise from north) and elevation
/// tilt `tilt_rad`: returns the rotation ENU → face (rows x̂_f, ŷ_f, n̂).
pub fn face_from_enu(az_rad: f64, tilt_rad: f64) -> DMat3 {
    let (sa, ca) = az_rad.sin_cos();
    let (se, ce) = tilt_rad.sin_cos();
    let n = DVec3::new(sa * ce, ca * ce, se);
    let y = DVec3::new(-sa * se, -ca * se, ce);
    let x = y.cross(n);
    DMat3::from_cols(x, y, n).transpose()
}

/// A planar array face: its centre in ECEF and the rotation ECEF → face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceFrame {
    /// Face centre (the ship's array-centre position), ECEF (m).
    pub origin_ecef: DVec3,
    /// Rotation ECEF → face frame (rows x̂_f, ŷ_f, n̂).
    pub face_from_ecef: DMat3,
}

/// Sine-space coordinates of a point seen from a face.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SinePoint {
    /// Range from the face centre (m).
    pub range_m: f64,
    /// Direction cosine along the face's horizontal axis x̂_f (to the left looking out).
    pub u: f64,
    /// Direction cosine along the face-up axis ŷ_f.
    pub v: f64,
    /// Direction cosine along boresight (> 0 in front of the face).
    pub w: f64,
}

impl FaceFrame {
    /// The face of a ship at `site` (array-centre position) whose boresight is at azimuth
    /// `az_rad` (clockwise from north, ship heading already added) and tilted up by `tilt_rad`.
    pub fn new(site: Geodetic, az_rad: f64, tilt_rad: f64) -> FaceFrame {
        let m = face_from_enu(az_rad, tilt_rad) * enu_from_ecef(site.lat_rad, site.lon_rad);
        FaceFrame { origin_ecef: site.to_ecef(), face_from_ecef: m }
    }

    /// Direction cosines and range of an ECEF point (docs/model.md §1.4).
    pub fn to_sine(&self, p_ecef: DVec3) -> SinePoint {
        let l = self.face_from_ecef * (p_ecef - self.origin_ecef);
        let r = l.length();
        SinePoint { range_m: r, u: l.x / r, v: l.y / r, w: l.z / r }
    }

    /// ECEF point from range and direction cosines (in front of the face).
    pub fn from_ruv(&self, range_m: f64, u: f64, v: f64) -> DVec3 {
        let w = (1.0 - u * u - v * v).max(0.0).sqrt();
        self.origin_ecef + self.face_from_ecef.transpose() * (DVec3::new(u, v, w) * range_m)
    }

    /// The face-frame vector of an ECEF vector (no translation).
    pub fn vec_to_face(&self, v_ecef: DVec3) -> DVec3 {
        self.face_from_ecef * v_ecef
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_triad_is_right_handed_orthonormal() {
        for &az in &[0.0, 45.0, 135.0, 225.0, 315.0, 17.0] {
            for &tilt in &[0.0, 15.0, 30.0] {
                let m = face_from_enu(f64::to_radians(az), f64::to_radians(tilt));
                assert!((m.determinant() - 1.0).abs() < 1e-14);
                let mmt = m * m.transpose();
                assert!((mmt - DMat3::IDENTITY).to_cols_array().iter().all(|e| e.abs() < 1e-14));
                // x̂_f is horizontal and to the left of boresight.
                let rows = m.transpose();
                let x = rows.col(0);
                assert!(x.z.abs() < 1e-15);
                let n = rows.col(2);
                let left = DVec3::new(-n.y, n.x, 0.0); // boresight rotated +90° about up
                if tilt < 89.0 {
                    assert!(x.dot(left) > 0.0);
                }
            }
        }
    }

    #[test]
    fn boresight_gives_zero_uv_and_round_trips() {
        let site = Geodetic::from_deg(36.0, -70.0, 20.0);
        let f = FaceFrame::new(site, f64::to_radians(45.0), f64::to_radians(15.0));
        let p = f.from_ruv(100_000.0, 0.0, 0.0);
        let s = f.to_sine(p);
        assert!(s.u.abs() < 1e-12 && s.v.abs() < 1e-12 && (s.w - 1.0).abs() < 1e-12);
        assert!((s.range_m - 100_000.0).abs() < 1e-6);
        let q = f.from_ruv(150_000.0, 0.3, -0.2);
        let sq = f.to_sine(q);
        assert!((sq.u - 0.3).abs() < 1e-12 && (sq.v + 0.2).abs() < 1e-12);
        assert!(((sq.u * sq.u + sq.v * sq.v + sq.w * sq.w) - 1.0).abs() < 1e-12);
    }
}
