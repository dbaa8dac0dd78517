//! Beam-point geometry, scan loss, horizon and bistatic measurement geometry
//! (docs/model.md §1.4–§1.8, §5.1, §5.4).
//!
//! All positions are ECEF metres. A receiver's measurement is `(R_B, u, v)`: the bistatic range sum
//! and the direction cosines of the target in the receiver face; the tables store `ρ = R_B/2`
//! ([`crate::range::equivalent_range`]). The monostatic case is simply `tx == rx face origin`.

use mimo_core::face::{FaceFrame, SinePoint};
use mimo_core::geo::{
    EARTH_MEAN_RADIUS_M, K_EFFECTIVE_EARTH, ecef_to_geodetic, enu_from_ecef, visible_effective_earth,
};
use mimo_core::params::RadarParams;
use mimo_core::{DMat3, DVec3};

/// Largest bistatic angle for which a Tx–Rx pair is used (docs/model.md §5.1, an engineering default).
pub const MAX_BISTATIC_ANGLE_DEG: f64 = 150.0;

/// Where a beam aimed at a point points, on the face that sees the point best (docs/model.md §1.5).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeamPoint {
    /// Index of the chosen face in the slice given to [`beam_point`].
    pub face: u8,
    /// Steering direction cosines in that face.
    pub u: f64,
    /// Steering direction cosine v in that face.
    pub v: f64,
    /// Direction cosine along boresight, `w_b = cos θ_s` (≥ cos θ_max).
    pub w: f64,
    /// Range from the face centre to the aim point (m).
    pub range_m: f64,
}

/// The face (index into `faces`) giving the largest `w` for the point `p`, with the point's sine
/// coordinates in that face. `None` only for an empty slice or a degenerate point (at a face
/// centre).
pub fn best_face(faces: &[FaceFrame], p: DVec3) -> Option<(usize, SinePoint)> {
    let mut best: Option<(usize, SinePoint)> = None;
    for (i, f) in faces.iter().enumerate() {
        let s = f.to_sine(p);
        if !s.w.is_finite() {
            continue;
        }
        if best.is_none_or(|(_, b)| s.w > b.w) {
            best = Some((i, s));
        }
    }
    best
}

/// Steer a beam at `aim` (docs/model.md §1.5): the face with the largest `w_b`, allowed only if
/// `w_b ≥ cos θ_max`. `None` when no face can steer there.
pub fn beam_point(faces: &[FaceFrame], params: &RadarParams, aim: DVec3) -> Option<BeamPoint> {
    let (i, s) = best_face(faces, aim)?;
    if !within_scan_limit(params, s.w) {
        return None;
    }
    Some(BeamPoint { face: u8::try_from(i).ok()?, u: s.u, v: s.v, w: s.w, range_m: s.range_m })
}

/// Is a steering direction with boresight cosine `w` inside the scan limit `w ≥ cos θ_max`?
pub fn within_scan_limit(params: &RadarParams, w: f64) -> bool {
    w.is_finite() && w >= params.min_scan_w() - 1e-12
}

/// One-way scan-loss factor `w_b^α_s` (docs/model.md §1.6); 0 behind the face.
pub fn scan_loss_factor(params: &RadarParams, w: f64) -> f64 {
    if w > 0.0 { w.powf(params.scan_loss_exponent) } else { 0.0 }
}

/// One-way peak gain with scan loss, `G = G0·w_b^α_s` (linear).
pub fn scan_gain(params: &RadarParams, w: f64) -> f64 {
    params.peak_gain() * scan_loss_factor(params, w)
}

/// Height above the WGS-84 ellipsoid of an ECEF point (m).
pub fn height_m(p: DVec3) -> f64 {
    ecef_to_geodetic(p).alt_m
}

/// 4/3-earth visibility between an antenna at `site` and a target at `p` (docs/model.md §1.7); the
/// heights are computed from the ECEF positions. Use [`visible_with_heights`] when they are known.
pub fn visible(site: DVec3, p: DVec3) -> bool {
    visible_effective_earth(site, height_m(site), p, height_m(p))
}

/// 4/3-earth visibility with known heights above the ellipsoid.
pub fn visible_with_heights(site: DVec3, h_site_m: f64, p: DVec3, h_p_m: f64) -> bool {
    visible_effective_earth(site, h_site_m, p, h_p_m)
}

/// Apparent (refracted, 4/3-earth) unit direction from `site` to `p`, ECEF (docs/model.md §1.8). The
/// azimuth is kept, the elevation is replaced by the effective-earth apparent elevation.
pub fn refracted_direction(site: DVec3, p: DVec3) -> DVec3 {
    let g = ecef_to_geodetic(site);
    let h_a = g.alt_m;
    let h_t = height_m(p);
    let enu = enu_from_ecef(g.lat_rad, g.lon_rad);
    let d = enu * (p - site);
    let re = K_EFFECTIVE_EARTH * EARTH_MEAN_RADIUS_M;
    let psi = site.normalize().dot(p.normalize()).clamp(-1.0, 1.0).acos();
    let psi_e = EARTH_MEAN_RADIUS_M * psi / re;
    let x = (re + h_t) * psi_e.sin();
    let z = (re + h_t) * psi_e.cos() - (re + h_a);
    let e_app = z.atan2(x);
    let horiz = (d.x * d.x + d.y * d.y).sqrt();
    if horiz <= 0.0 {
        return (p - site).normalize();
    }
    let (se, ce) = e_app.sin_cos();
    let dir_enu = DVec3::new(d.x / horiz * ce, d.y / horiz * ce, se);
    enu.transpose() * dir_enu
}

/// Bistatic geometry of one target (docs/model.md §5.1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bistatic {
    /// Transmitter–target range (m).
    pub r_t_m: f64,
    /// Target–receiver range (m).
    pub r_r_m: f64,
    /// Bistatic range sum `R_B = R_t + R_r` (m).
    pub r_b_m: f64,
    /// Bistatic angle at the target (rad); 0 when monostatic.
    pub beta_rad: f64,
}

impl Bistatic {
    /// Equivalent monostatic range `ρ = R_B/2` (m).
    pub fn rho_m(&self) -> f64 {
        0.5 * self.r_b_m
    }
    /// Is the pair usable (`β ≤ 150°`)?
    pub fn usable(&self) -> bool {
        self.beta_rad.is_finite() && self.beta_rad <= MAX_BISTATIC_ANGLE_DEG.to_radians()
    }
}

/// Ranges and bistatic angle for transmitter `t`, receiver `r` and target `p`.
pub fn bistatic(t: DVec3, r: DVec3, p: DVec3) -> Bistatic {
    let a = t - p;
    let b = r - p;
    let (la, lb) = (a.length(), b.length());
    let beta = if la > 0.0 && lb > 0.0 { (a.dot(b) / (la * lb)).clamp(-1.0, 1.0).acos() } else { 0.0 };
    Bistatic { r_t_m: la, r_r_m: lb, r_b_m: la + lb, beta_rad: beta }
}

/// The measurement function `h(p) = (R_B, u_r, v_r)` of docs/model.md §5.4 for a transmitter at
/// `tx` (ECEF) and a receiver face `rx`.
pub fn measure(p: DVec3, tx: DVec3, rx: &FaceFrame) -> [f64; 3] {
    let s = rx.to_sine(p);
    [(p - tx).length() + s.range_m, s.u, s.v]
}

/// Rows of the measurement Jacobian `∂h/∂p` (docs/model.md §5.4, TCL `rangeGradient`, `uvGradient`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeasJacobian {
    /// `∂R_B/∂p`.
    pub d_rb: DVec3,
    /// `∂u/∂p`.
    pub d_u: DVec3,
    /// `∂v/∂p`.
    pub d_v: DVec3,
}

impl MeasJacobian {
    /// `∂ρ/∂p` for the tables' `ρ = R_B/2`.
    pub fn d_rho(&self) -> DVec3 {
        0.5 * self.d_rb
    }
    /// As a matrix whose rows are `∂(R_B, u, v)/∂p`.
    pub fn matrix(&self) -> DMat3 {
        DMat3::from_cols(self.d_rb, self.d_u, self.d_v).transpose()
    }
}

/// The Jacobian of [`measure`] with respect to the target position.
pub fn measurement_jacobian(p: DVec3, tx: DVec3, rx: &FaceFrame) -> MeasJacobian {
    let dt = p - tx;
    let dr = p - rx.origin_ecef;
    let lt = dt.length();
    let lr = dr.length();
    let mut d_rb = dr / lr;
    if lt > 0.0 {
        d_rb += dt / lt;
    }
    let m = rx.face_from_ecef;
    let l = m * dr;
    let (x, y, z) = (l.x, l.y, l.z);
    let r3 = lr * lr * lr;
    // Row vector a·M is Mᵀ·a as a column.
    let mt = m.transpose();
    let d_u = mt * DVec3::new(y * y + z * z, -x * y, -x * z) / r3;
    let d_v = mt * DVec3::new(-x * y, x * x + z * z, -y * z) / r3;
    MeasJacobian { d_rb, d_u, d_v }
}

/// Bistatic `(R_B, u, v)` → ECEF (docs/model.md §5.4, TCL `ruv2Cart`). `None` when the measurement is
/// geometrically impossible (`R_B` shorter than the baseline, `u² + v² > 1`, or a non-positive
/// receiver range).
pub fn bistatic_ruv_to_ecef(r_b: f64, u: f64, v: f64, tx: DVec3, rx: &FaceFrame) -> Option<DVec3> {
    let uv2 = u * u + v * v;
    if !(r_b.is_finite() && u.is_finite() && v.is_finite()) || uv2 > 1.0 {
        return None;
    }
    let d = DVec3::new(u, v, (1.0 - uv2).sqrt());
    let lt = rx.face_from_ecef * (tx - rx.origin_ecef);
    let den = 2.0 * (r_b - d.dot(lt));
    let num = r_b * r_b - lt.length_squared();
    if den <= 0.0 || num < 0.0 {
        return None;
    }
    let r_r = num / den;
    Some(rx.origin_ecef + rx.face_from_ecef.transpose() * (d * r_r))
}

/// Jacobian of [`bistatic_ruv_to_ecef`], `∂p/∂(R_B, u, v)` (columns), as the inverse of the
/// measurement Jacobian at the converted point. Map a measurement covariance `R` to ECEF with
/// `J R Jᵀ`. `None` where the conversion fails or the geometry is singular.
pub fn ruv_to_ecef_jacobian(r_b: f64, u: f64, v: f64, tx: DVec3, rx: &FaceFrame) -> Option<DMat3> {
    let p = bistatic_ruv_to_ecef(r_b, u, v, tx, rx)?;
    let h = measurement_jacobian(p, tx, rx).matrix();
    let det = h.determinant();
    if !det.is_finite() || det.abs() < 1e-300 {
        return None;
    }
    Some(h.inverse())
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::geo::Geodetic;

    fn faces(site: Geodetic) -> Vec<FaceFrame> {
        [45.0f64, 135.0, 225.0, 315.0]
            .iter()
            .map(|a| FaceFrame::new(site, a.to_radians(), 15f64.to_radians()))
            .collect()
    }

    fn rel_err(a: f64, b: f64, scale: f64) -> f64 {
        (a - b).abs() / scale
    }

    #[test]
    fn face_choice_and_scan_limit() {
        let site = Geodetic::from_deg(36.0, -70.0, 20.0);
        let fs = faces(site);
        let p = RadarParams::default();
        // A point straight along face 2's boresight.
        let aim = fs[2].from_ruv(100e3, 0.0, 0.0);
        let b = beam_point(&fs, &p, aim).expect("steerable");
        assert_eq!(b.face, 2);
        assert!(b.u.abs() < 1e-12 && b.v.abs() < 1e-12 && (b.w - 1.0).abs() < 1e-12);
        // Straight up is 75° from every boresight (tilt 15°, faces symmetric): w = sin 15° < 0.5.
        let up = Geodetic::from_deg(36.0, -70.0, 50e3).to_ecef();
        assert!(beam_point(&fs, &p, up).is_none());
        // Scan loss: 4.5 dB one way at 60°.
        let l = -10.0 * scan_loss_factor(&p, 0.5).log10();
        assert!((l - 4.515).abs() < 1e-3, "{l}");
    }

    #[test]
    fn horizon_uses_four_thirds_earth() {
        let site = Geodetic::from_deg(36.0, -70.0, 20.0).to_ecef();
        let at = |km: f64, h: f64| {
            let lat = 36.0 + (km * 1e3 / EARTH_MEAN_RADIUS_M).to_degrees();
            Geodetic::from_deg(lat, -70.0, h).to_ecef()
        };
        assert!(visible(site, at(420.0, 10e3)));
        assert!(!visible(site, at(445.0, 10e3)));
    }

    #[test]
    fn refraction_raises_low_targets() {
        let sg = Geodetic::from_deg(36.0, -70.0, 20.0);
        let site = sg.to_ecef();
        let lat = 36.0 + (200e3 / EARTH_MEAN_RADIUS_M).to_degrees();
        let p = Geodetic::from_deg(lat, -70.0, 3000.0).to_ecef();
        let enu = enu_from_ecef(sg.lat_rad, sg.lon_rad);
        let geo = enu * (p - site).normalize();
        let app = enu * refracted_direction(site, p);
        let e_geo = geo.z.asin();
        let e_app = app.z.asin();
        // Apparent elevation is higher by a few mrad at low elevation.
        assert!(e_app > e_geo && e_app - e_geo < 0.01, "{e_geo} {e_app}");
        assert!((app.length() - 1.0).abs() < 1e-12);
    }

    fn geometry() -> (FaceFrame, DVec3, Vec<DVec3>) {
        let rx_site = Geodetic::from_deg(36.0, -70.0, 20.0);
        let rx = FaceFrame::new(rx_site, 30f64.to_radians(), 15f64.to_radians());
        let tx = Geodetic::from_deg(36.2, -69.8, 20.0).to_ecef();
        let pts = vec![
            rx.from_ruv(120e3, 0.1, 0.05),
            rx.from_ruv(60e3, -0.4, 0.2),
            rx.from_ruv(250e3, 0.3, -0.1),
            rx.from_ruv(30e3, 0.0, 0.5),
        ];
        (rx, tx, pts)
    }

    #[test]
    fn bistatic_round_trip() {
        let (rx, tx, pts) = geometry();
        for &p in &pts {
            let b = bistatic(tx, rx.origin_ecef, p);
            assert!(b.usable());
            let [r_b, u, v] = measure(p, tx, &rx);
            assert!((r_b - b.r_b_m).abs() < 1e-6);
            let q = bistatic_ruv_to_ecef(r_b, u, v, tx, &rx).expect("converts");
            assert!((q - p).length() < 1e-5, "{}", (q - p).length());
            // Monostatic: tx at the receiver.
            let [r_b, u, v] = measure(p, rx.origin_ecef, &rx);
            let q = bistatic_ruv_to_ecef(r_b, u, v, rx.origin_ecef, &rx).expect("converts");
            assert!((q - p).length() < 1e-5);
        }
        // Shorter than the baseline: impossible.
        let base = (tx - rx.origin_ecef).length();
        assert!(bistatic_ruv_to_ecef(0.9 * base, 0.0, 0.0, tx, &rx).is_none());
    }

    #[test]
    fn jacobians_match_central_differences() {
        let (rx, tx, pts) = geometry();
        for &p in &pts {
            for txp in [tx, rx.origin_ecef] {
                let j = measurement_jacobian(p, txp, &rx);
                let h = 1.0; // m; the functions are smooth on the scale of km.
                for axis in 0..3 {
                    let mut e = DVec3::ZERO;
                    e[axis] = h;
                    let hp = measure(p + e, txp, &rx);
                    let hm = measure(p - e, txp, &rx);
                    let num: Vec<f64> = (0..3).map(|k| (hp[k] - hm[k]) / (2.0 * h)).collect();
                    let ana = [j.d_rb[axis], j.d_u[axis], j.d_v[axis]];
                    // Relative to each row's norm (single components can be near zero).
                    let scales = [j.d_rb.length(), j.d_u.length(), j.d_v.length()];
                    for k in 0..3 {
                        let e = rel_err(num[k], ana[k], scales[k]);
                        assert!(e < 1e-6, "row {k} axis {axis}: {} vs {} ({e})", num[k], ana[k]);
                    }
                }
                // Inverse map Jacobian against differences of ruv→ECEF.
                let z = measure(p, txp, &rx);
                let jinv = ruv_to_ecef_jacobian(z[0], z[1], z[2], txp, &rx).expect("regular");
                let steps = [1.0, 1e-6, 1e-6];
                for k in 0..3 {
                    let mut zp = z;
                    let mut zm = z;
                    zp[k] += steps[k];
                    zm[k] -= steps[k];
                    let pp = bistatic_ruv_to_ecef(zp[0], zp[1], zp[2], txp, &rx).expect("ok");
                    let pm = bistatic_ruv_to_ecef(zm[0], zm[1], zm[2], txp, &rx).expect("ok");
                    let num = (pp - pm) / (2.0 * steps[k]);
                    let ana = jinv.col(k);
                    let e = (num - ana).length() / ana.length();
                    assert!(e < 1e-6, "column {k}: {num} vs {ana} ({e})");
                }
            }
        }
    }

    #[test]
    fn bistatic_angle_limit() {
        let t = DVec3::new(0.0, 0.0, 0.0);
        let r = DVec3::new(100e3, 0.0, 0.0);
        // Target on the baseline: forward scatter, β = 180°.
        let b = bistatic(t, r, DVec3::new(50e3, 0.0, 0.0));
        assert!((b.beta_rad - std::f64::consts::PI).abs() < 1e-12 && !b.usable());
        // Target far broadside: small β.
        let b = bistatic(t, r, DVec3::new(50e3, 500e3, 0.0));
        assert!(b.usable() && b.beta_rad < 0.2);
        let m = bistatic(t, t, DVec3::new(1e3, 2e3, 3e3));
        assert_eq!(m.beta_rad, 0.0);
        assert!((m.rho_m() - m.r_t_m).abs() < 1e-9);
    }
}
