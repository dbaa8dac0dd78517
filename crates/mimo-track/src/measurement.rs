//! Measurement models (docs/model.md §5.4).
//!
//! A detection on receiver face `i` of a transmission from site `t` measures
//! `z = (R_B, u_r, v_r)`: the bistatic range sum and the direction cosines in the receiver face.
//! Monostatic is the special case `t = r` (then `R_B = 2R`). The tables store `ρ = R_B/2`
//! (`range_m`) with `var_range_m2 = σ_ρ²`; the tracker works in `R_B` with `σ_{R_B}² = 4σ_ρ²`.
//!
//! [`MeasurementModel`] is the family trait (a measurement function with an analytic Jacobian);
//! [`BistaticRuv`] is the radar's model, [`PositionMeasurement`] a plain Cartesian one for tests
//! and external cues. [`PreparedMeasurement`] is a validated `MeasurementRow` converted into the
//! tracking frame with its covariance.

use crate::frame::{TrackFrame, dmat3_rows};
use crate::geometry::SensorGeometry;
use crate::linalg::{Mat3, Mat3x6, Vec3, Vec6, sandwich};
use mimo_core::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::MeasurementRow;
use serde::{Deserialize, Serialize};
use std::fmt;

/// A 3-D measurement function `z = h(x)` of the 6-D state with its Jacobian.
pub trait MeasurementModel {
    /// Predicted measurement.
    fn h(&self, x: &Vec6) -> Vec3;
    /// `∂h/∂x` evaluated at `x`.
    fn jacobian(&self, x: &Vec6) -> Mat3x6;
}

/// Bistatic (or monostatic) range-sum and receiver sine-space measurement, all in the tracking
/// frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BistaticRuv {
    /// Transmitter phase centre.
    pub tx: DVec3,
    /// Receiver face origin.
    pub rx: DVec3,
    /// Rotation tracking frame → receiver face, row-major.
    pub m: Mat3,
}

fn rows_mul(m: &Mat3, v: DVec3) -> DVec3 {
    DVec3::new(
        m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
        m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
        m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z,
    )
}

fn rows_t_mul(m: &Mat3, v: DVec3) -> DVec3 {
    DVec3::new(
        m[0][0] * v.x + m[1][0] * v.y + m[2][0] * v.z,
        m[0][1] * v.x + m[1][1] * v.y + m[2][1] * v.z,
        m[0][2] * v.x + m[1][2] * v.y + m[2][2] * v.z,
    )
}

impl BistaticRuv {
    /// Monostatic model at a face.
    pub fn monostatic(origin: DVec3, m: Mat3) -> BistaticRuv {
        BistaticRuv { tx: origin, rx: origin, m }
    }

    /// Is this model monostatic (transmitter at the receiver)?
    pub fn is_monostatic(&self) -> bool {
        self.tx == self.rx
    }

    /// `h` of a position: `(R_B, u, v)`.
    pub fn h_pos(&self, p: DVec3) -> Vec3 {
        let rb = (p - self.tx).length() + (p - self.rx).length();
        let l = rows_mul(&self.m, p - self.rx);
        let r = l.length();
        [rb, l.x / r, l.y / r]
    }

    /// `∂h/∂p` (3×3) of a position (docs/model.md §5.4; TCL `rangeGradient`, `uvGradient`).
    pub fn jacobian_pos(&self, p: DVec3) -> Mat3 {
        let dt = p - self.tx;
        let dr = p - self.rx;
        let grad_rb = dt / dt.length() + dr / dr.length();
        let l = rows_mul(&self.m, dr);
        let (x, y, z) = (l.x, l.y, l.z);
        let r = l.length();
        let r3 = r * r * r;
        let du = DVec3::new(y * y + z * z, -x * y, -x * z) / r3;
        let dv = DVec3::new(-x * y, x * x + z * z, -y * z) / r3;
        // Row vector times M is Mᵀ times the column.
        let du = rows_t_mul(&self.m, du);
        let dv = rows_t_mul(&self.m, dv);
        [grad_rb.to_array(), du.to_array(), dv.to_array()]
    }

    /// Position from a measurement (docs/model.md §5.4, TCL `ruv2Cart`) and the Jacobian
    /// `∂p/∂(R_B, u, v)` (analytic, bistatic and monostatic). `None` when the measurement is not a
    /// valid point in front of the face (`u² + v² ≥ 1`, `R_B` not above the baseline, non-finite).
    pub fn ruv_to_cart(&self, z: &Vec3) -> Option<(DVec3, Mat3)> {
        let [rb, u, v] = *z;
        let w2 = 1.0 - u * u - v * v;
        if !(rb.is_finite() && u.is_finite() && v.is_finite() && w2 > 0.0) {
            return None;
        }
        let w = w2.sqrt();
        let d = DVec3::new(u, v, w);
        let lt = rows_mul(&self.m, self.tx - self.rx);
        let num = rb * rb - lt.length_squared();
        let den = 2.0 * (rb - d.dot(lt));
        if !(den > 0.0 && num > 0.0) {
            return None;
        }
        let rr = num / den;
        let p = self.rx + rows_t_mul(&self.m, d * rr);
        let dd_du = DVec3::new(1.0, 0.0, -u / w);
        let dd_dv = DVec3::new(0.0, 1.0, -v / w);
        let drr_drb = 2.0 * (rb - rr) / den;
        let drr_du = 2.0 * rr * dd_du.dot(lt) / den;
        let drr_dv = 2.0 * rr * dd_dv.dot(lt) / den;
        let c_rb = rows_t_mul(&self.m, d * drr_drb);
        let c_u = rows_t_mul(&self.m, d * drr_du + dd_du * rr);
        let c_v = rows_t_mul(&self.m, d * drr_dv + dd_dv * rr);
        let j = [[c_rb.x, c_u.x, c_v.x], [c_rb.y, c_u.y, c_v.y], [c_rb.z, c_u.z, c_v.z]];
        if !p.is_finite() || !j.iter().flatten().all(|x| x.is_finite()) {
            return None;
        }
        Some((p, j))
    }

    /// Position and its covariance `J R Jᵀ` from a measurement with covariance `r`.
    pub fn ruv_to_cart_cov(&self, z: &Vec3, r: &Mat3) -> Option<(DVec3, Mat3)> {
        let (p, j) = self.ruv_to_cart(z)?;
        Some((p, sandwich(&j, r)))
    }

    /// The model of channel `tx → rx` on face `rx_face` at time `t_s`, in the tracking frame
    /// (monostatic when `tx == rx`, using the face origin for both ends).
    pub fn from_geometry(
        frame: &TrackFrame,
        geom: &dyn SensorGeometry,
        tx: RadarId,
        rx: RadarId,
        rx_face: u8,
        t_s: f64,
    ) -> Result<BistaticRuv, MeasurementError> {
        let face = geom.face(rx, rx_face, t_s).ok_or(MeasurementError::UnknownFace(rx, rx_face))?;
        let lf = frame.face_to_local(&face);
        let txp = if tx == rx {
            lf.origin
        } else {
            frame.to_local(geom.site_ecef(tx, t_s).ok_or(MeasurementError::UnknownRadar(tx))?)
        };
        let m = BistaticRuv { tx: txp, rx: lf.origin, m: dmat3_rows(&lf.face_from_local) };
        if m.tx.is_finite() && m.rx.is_finite() && m.m.iter().flatten().all(|x| x.is_finite()) {
            Ok(m)
        } else {
            Err(MeasurementError::NonFinite("geometry"))
        }
    }

    /// Bistatic angle β at a target position (rad); 0 when monostatic.
    pub fn bistatic_angle(&self, p: DVec3) -> f64 {
        let a = (self.tx - p).normalize_or_zero();
        let b = (self.rx - p).normalize_or_zero();
        a.dot(b).clamp(-1.0, 1.0).acos()
    }
}

impl MeasurementModel for BistaticRuv {
    fn h(&self, x: &Vec6) -> Vec3 {
        self.h_pos(DVec3::new(x[0], x[1], x[2]))
    }

    fn jacobian(&self, x: &Vec6) -> Mat3x6 {
        let jp = self.jacobian_pos(DVec3::new(x[0], x[1], x[2]));
        let mut h = [[0.0; 6]; 3];
        for i in 0..3 {
            h[i][..3].copy_from_slice(&jp[i]);
        }
        h
    }
}

/// A linear position measurement `z = p` (tests, external cues).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PositionMeasurement;

impl MeasurementModel for PositionMeasurement {
    fn h(&self, x: &Vec6) -> Vec3 {
        [x[0], x[1], x[2]]
    }

    fn jacobian(&self, _x: &Vec6) -> Mat3x6 {
        let mut h = [[0.0; 6]; 3];
        for (i, row) in h.iter_mut().enumerate() {
            row[i] = 1.0;
        }
        h
    }
}

/// How measurement rows become filter measurements.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MeasurementConfig {
    /// Standard deviation added in quadrature to u and v of a `merged` measurement (sine space).
    /// Default θ/4 = 0.0252/4 (docs/model.md §2.7, "a fixed (θ/4)²").
    pub merged_angle_std: f64,
    /// Standard deviation added in quadrature to ρ of a `merged` measurement (m). Default ΔR/2 =
    /// 15 m: the range centroid of two unresolved returns is off by up to half a cell.
    pub merged_range_std_m: f64,
    /// Floor on σ_ρ (m) applied to every row, guarding the filter against zero variances.
    /// Default 1e-3 m (the radar applies its own, larger floors, docs/model.md §4.6).
    pub range_std_floor_m: f64,
    /// Floor on σ_u and σ_v. Default 1e-7.
    pub angle_std_floor: f64,
}

impl Default for MeasurementConfig {
    fn default() -> Self {
        MeasurementConfig {
            merged_angle_std: 0.0252 / 4.0,
            merged_range_std_m: 15.0,
            range_std_floor_m: 1e-3,
            angle_std_floor: 1e-7,
        }
    }
}

/// Why a measurement row was not used.
#[derive(Debug, Clone, PartialEq)]
pub enum MeasurementError {
    /// A value is NaN or infinite.
    NonFinite(&'static str),
    /// A variance is negative (or NaN).
    BadVariance(&'static str),
    /// `u² + v² ≥ 1`: not a direction in front of the face.
    OutsideSineSpace,
    /// The range is not positive.
    BadRange,
    /// The geometry does not know this radar.
    UnknownRadar(RadarId),
    /// The geometry does not know this face.
    UnknownFace(RadarId, u8),
}

impl fmt::Display for MeasurementError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeasurementError::NonFinite(n) => write!(f, "measurement field `{n}` is not finite"),
            MeasurementError::BadVariance(n) => write!(f, "measurement variance `{n}` is negative"),
            MeasurementError::OutsideSineSpace => write!(f, "measurement has u² + v² ≥ 1"),
            MeasurementError::BadRange => write!(f, "measurement range is not positive"),
            MeasurementError::UnknownRadar(r) => write!(f, "unknown radar {r}"),
            MeasurementError::UnknownFace(r, i) => write!(f, "unknown face {i} of radar {r}"),
        }
    }
}

impl std::error::Error for MeasurementError {}

/// A validated measurement in the tracking frame: `z = (R_B, u, v)`, its covariance and its
/// measurement function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreparedMeasurement {
    /// Measurement id.
    pub meas_id: u64,
    /// Measurement time (s).
    pub t_s: f64,
    /// Transmitter.
    pub tx: RadarId,
    /// Receiver.
    pub rx: RadarId,
    /// Receive face.
    pub rx_face: u8,
    /// `z = (R_B, u, v)`.
    pub z: Vec3,
    /// Measurement covariance (diagonal, merged inflation included).
    pub r: Mat3,
    /// The channel’s measurement model.
    pub model: BistaticRuv,
    /// The detection may hold several unresolved targets.
    pub merged: bool,
    /// Observed SNR (dB).
    pub snr_db: f64,
}

/// A measurement as an update sees it: `z` under `model`, with noise covariance `r`.
#[derive(Clone, Copy)]
pub struct Observation<'a> {
    /// The measurement function `h` and its Jacobian.
    pub model: &'a dyn MeasurementModel,
    /// The measurement `z`.
    pub z: &'a Vec3,
    /// Its noise covariance `R`.
    pub r: &'a Mat3,
}

impl PreparedMeasurement {
    /// The measurement with its model and covariance, for the filter.
    pub fn observation(&self) -> Observation<'_> {
        Observation { model: &self.model, z: &self.z, r: &self.r }
    }

    /// Validate a row and put it in the tracking frame. The geometry is queried at the row's time.
    pub fn from_row(
        row: &MeasurementRow,
        geom: &dyn SensorGeometry,
        frame: &TrackFrame,
        cfg: &MeasurementConfig,
    ) -> Result<PreparedMeasurement, MeasurementError> {
        for (name, v) in [("t_s", row.t_s), ("range_m", row.range_m), ("u", row.u), ("v", row.v)] {
            if !v.is_finite() {
                return Err(MeasurementError::NonFinite(name));
            }
        }
        for (name, v) in [("var_range_m2", row.var_range_m2), ("var_u", row.var_u), ("var_v", row.var_v)] {
            if !v.is_finite() {
                return Err(MeasurementError::NonFinite(name));
            }
            if v < 0.0 {
                return Err(MeasurementError::BadVariance(name));
            }
        }
        if row.range_m <= 0.0 {
            return Err(MeasurementError::BadRange);
        }
        if row.u * row.u + row.v * row.v >= 1.0 {
            return Err(MeasurementError::OutsideSineSpace);
        }
        let model = BistaticRuv::from_geometry(frame, geom, row.tx, row.rx, row.rx_face, row.t_s)?;
        let mut var_rho = row.var_range_m2.max(cfg.range_std_floor_m.powi(2));
        let mut var_u = row.var_u.max(cfg.angle_std_floor.powi(2));
        let mut var_v = row.var_v.max(cfg.angle_std_floor.powi(2));
        if row.merged {
            var_rho += cfg.merged_range_std_m.powi(2);
            var_u += cfg.merged_angle_std.powi(2);
            var_v += cfg.merged_angle_std.powi(2);
        }
        if !(var_rho > 0.0 && var_u > 0.0 && var_v > 0.0) {
            return Err(MeasurementError::BadVariance("var_range_m2"));
        }
        Ok(PreparedMeasurement {
            meas_id: row.meas_id,
            t_s: row.t_s,
            tx: row.tx,
            rx: row.rx,
            rx_face: row.rx_face,
            z: [2.0 * row.range_m, row.u, row.v],
            r: [[4.0 * var_rho, 0.0, 0.0], [0.0, var_u, 0.0], [0.0, 0.0, var_v]],
            model,
            merged: row.merged,
            snr_db: if row.snr_db.is_finite() { row.snr_db } else { 0.0 },
        })
    }

    /// Position and covariance implied by this measurement alone (one-point initiation).
    pub fn to_cartesian(&self) -> Option<(DVec3, Mat3)> {
        self.model.ruv_to_cart_cov(&self.z, &self.r)
    }
}

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    use super::*;
    use mimo_core::face::FaceFrame;
    use mimo_core::geo::Geodetic;

    fn geometry() -> (TrackFrame, FaceFrame, DVec3) {
        let frame = TrackFrame::new(Geodetic::from_deg(36.0, -70.0, 0.0));
        let rx_site = Geodetic::from_deg(36.05, -70.1, 20.0);
        let face = FaceFrame::new(rx_site, 40f64.to_radians(), 15f64.to_radians());
        let tx = Geodetic::from_deg(35.8, -69.9, 20.0).to_ecef();
        (frame, face, tx)
    }

    fn model(bistatic: bool) -> BistaticRuv {
        let (frame, face, tx) = geometry();
        let lf = frame.face_to_local(&face);
        let m = dmat3_rows(&lf.face_from_local);
        if bistatic {
            BistaticRuv { tx: frame.to_local(tx), rx: lf.origin, m }
        } else {
            BistaticRuv::monostatic(lf.origin, m)
        }
    }

    fn targets(m: &BistaticRuv) -> Vec<DVec3> {
        // Points in front of the face at various ranges and off-boresight angles.
        let mut out = Vec::new();
        for &(r, u, v) in &[(3_000.0, 0.0, 0.8), (50_000.0, 0.3, -0.2), (150_000.0, -0.6, 0.5), (300_000.0, 0.05, 0.02)]
        {
            let w = f64::sqrt(1.0 - u * u - v * v);
            out.push(m.rx + rows_t_mul(&m.m, DVec3::new(u, v, w) * r));
        }
        out
    }

    fn check_jacobian(m: &BistaticRuv) {
        for p in targets(m) {
            let j = m.jacobian(&[p.x, p.y, p.z, 10.0, 20.0, 30.0]);
            for row in 0..3 {
                let scale = j[row][..3].iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for col in 0..6 {
                    let h = if col < 3 { 1e-3 * (1.0 + p.length() * 1e-5) } else { 1.0 };
                    let mut xp = [p.x, p.y, p.z, 10.0, 20.0, 30.0];
                    let mut xm = xp;
                    xp[col] += h;
                    xm[col] -= h;
                    let fd = (m.h(&xp)[row] - m.h(&xm)[row]) / (2.0 * h);
                    let err = (fd - j[row][col]).abs() / scale;
                    assert!(err < 1e-6, "row {row} col {col}: analytic {} fd {fd} rel {err}", j[row][col]);
                }
            }
        }
    }

    #[test]
    fn jacobian_matches_finite_differences_monostatic() {
        check_jacobian(&model(false));
    }

    #[test]
    fn jacobian_matches_finite_differences_bistatic() {
        check_jacobian(&model(true));
    }

    #[test]
    fn ruv_to_cart_inverts_h_and_its_jacobian_matches_finite_differences() {
        for bistatic in [false, true] {
            let m = model(bistatic);
            for p in targets(&m) {
                if m.bistatic_angle(p) > 150f64.to_radians() {
                    continue;
                }
                let z = m.h_pos(p);
                let (q, j) = m.ruv_to_cart(&z).expect("valid");
                assert!((q - p).length() < 1e-6 * (1.0 + p.length() * 1e-3), "bistatic {bistatic}: {q} vs {p}");
                let steps = [1e-2, 1e-7, 1e-7];
                for col in 0..3 {
                    let mut zp = z;
                    let mut zm = z;
                    zp[col] += steps[col];
                    zm[col] -= steps[col];
                    let (pp, _) = m.ruv_to_cart(&zp).expect("valid");
                    let (pm, _) = m.ruv_to_cart(&zm).expect("valid");
                    let fd = (pp - pm) / (2.0 * steps[col]);
                    let an = DVec3::new(j[0][col], j[1][col], j[2][col]);
                    assert!((fd - an).length() < 1e-6 * an.length(), "bistatic {bistatic} col {col}: {an} vs {fd}");
                }
                // J is the inverse of ∂h/∂p.
                let hp = m.jacobian_pos(p);
                let prod = crate::linalg::mul(&hp, &j);
                for (a, row) in prod.iter().enumerate() {
                    for (b, x) in row.iter().enumerate() {
                        let e = if a == b { 1.0 } else { 0.0 };
                        assert!((x - e).abs() < 1e-6, "H·J[{a}][{b}] = {x}");
                    }
                }
            }
        }
    }

    #[test]
    fn monostatic_ruv_jacobian_matches_closed_form() {
        let m = model(false);
        let (r, u, v) = (80_000.0, 0.2, -0.1);
        let w = f64::sqrt(1.0 - u * u - v * v);
        let (_, j) = m.ruv_to_cart(&[2.0 * r, u, v]).expect("valid");
        // docs/model.md §5.4: columns ∂/∂(r, u, v) = Mᵀ [[u, r, 0], [v, 0, r], [w, −ru/w, −rv/w]];
        // our first column is ∂/∂R_B = ½ ∂/∂r.
        let cols = [DVec3::new(u, v, w) * 0.5, DVec3::new(r, 0.0, -r * u / w), DVec3::new(0.0, r, -r * v / w)];
        for (c, col) in cols.iter().enumerate() {
            let e = rows_t_mul(&m.m, *col);
            let a = DVec3::new(j[0][c], j[1][c], j[2][c]);
            assert!((e - a).length() < 1e-9 * e.length());
        }
    }

    #[test]
    fn rows_are_validated() {
        let (frame, face, tx) = geometry();
        let mut geom = crate::geometry::StaticGeometry::new();
        geom.add_faces(RadarId(0), face.origin_ecef, vec![face]);
        geom.add_faces(RadarId(1), tx, vec![]);
        let row = MeasurementRow {
            run: 0,
            meas_id: 7,
            dwell_id: 1,
            t_s: 1.0,
            rx: RadarId(0),
            tx: RadarId(1),
            rx_face: 0,
            range_m: 60_000.0,
            u: 0.1,
            v: 0.2,
            snr_db: 20.0,
            var_range_m2: 25.0,
            var_u: 1e-6,
            var_v: 1e-6,
            n_primitives: 2,
            merged: false,
            target_hint: None,
        };
        let cfg = MeasurementConfig::default();
        let pm = PreparedMeasurement::from_row(&row, &geom, &frame, &cfg).expect("valid");
        assert_eq!(pm.z[0], 120_000.0);
        assert_eq!(pm.r[0][0], 100.0);
        let merged = MeasurementRow { merged: true, ..row.clone() };
        let pmm = PreparedMeasurement::from_row(&merged, &geom, &frame, &cfg).expect("valid");
        assert!(pmm.r[1][1] > 1e-6 + 3e-5);
        for bad in [
            MeasurementRow { u: f64::NAN, ..row.clone() },
            MeasurementRow { var_u: -1.0, ..row.clone() },
            MeasurementRow { u: 0.9, v: 0.9, ..row.clone() },
            MeasurementRow { rx_face: 3, ..row.clone() },
            MeasurementRow { tx: RadarId(5), ..row.clone() },
            MeasurementRow { range_m: -5.0, ..row.clone() },
        ] {
            assert!(PreparedMeasurement::from_row(&bad, &geom, &frame, &cfg).is_err());
        }
    }
}
