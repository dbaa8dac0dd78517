//! WGS-84 geodetic ⇄ ECEF, local ENU axes, and horizon tests (docs/model.md §1.1, §1.2, §1.7).

use glam::{DMat3, DVec3};
use serde::{Deserialize, Serialize};

/// WGS-84 semi-major axis (m).
pub const WGS84_A_M: f64 = 6_378_137.0;
/// WGS-84 flattening.
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;
/// WGS-84 first eccentricity squared, f(2−f).
pub const WGS84_E2: f64 = WGS84_F * (2.0 - WGS84_F);
/// WGS-84 semi-minor axis (m).
pub const WGS84_B_M: f64 = WGS84_A_M * (1.0 - WGS84_F);
/// Mean earth radius used for the effective-earth horizon (m).
pub const EARTH_MEAN_RADIUS_M: f64 = 6_371_000.0;
/// Effective earth-radius factor for standard refraction.
pub const K_EFFECTIVE_EARTH: f64 = 4.0 / 3.0;

/// A geodetic position on WGS-84: latitude and longitude in radians, height above the
/// ellipsoid in metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Geodetic {
    /// Geodetic latitude (rad, north positive).
    pub lat_rad: f64,
    /// Longitude (rad, east positive).
    pub lon_rad: f64,
    /// Height above the WGS-84 ellipsoid (m).
    pub alt_m: f64,
}

impl Geodetic {
    /// From degrees and metres.
    pub fn from_deg(lat_deg: f64, lon_deg: f64, alt_m: f64) -> Geodetic {
        Geodetic { lat_rad: lat_deg.to_radians(), lon_rad: lon_deg.to_radians(), alt_m }
    }

    /// Latitude in degrees.
    pub fn lat_deg(&self) -> f64 {
        self.lat_rad.to_degrees()
    }

    /// Longitude in degrees.
    pub fn lon_deg(&self) -> f64 {
        self.lon_rad.to_degrees()
    }

    /// ECEF position (m).
    pub fn to_ecef(&self) -> DVec3 {
        geodetic_to_ecef(*self)
    }
}

/// Prime-vertical radius of curvature N(φ) (m).
pub fn prime_vertical_radius_m(lat_rad: f64) -> f64 {
    WGS84_A_M / (1.0 - WGS84_E2 * lat_rad.sin().powi(2)).sqrt()
}

/// Meridian radius of curvature M(φ) (m).
pub fn meridian_radius_m(lat_rad: f64) -> f64 {
    WGS84_A_M * (1.0 - WGS84_E2) / (1.0 - WGS84_E2 * lat_rad.sin().powi(2)).powf(1.5)
}

/// Geodetic → ECEF (docs/model.md §1.1).
pub fn geodetic_to_ecef(g: Geodetic) -> DVec3 {
    let n = prime_vertical_radius_m(g.lat_rad);
    let (sl, cl) = g.lat_rad.sin_cos();
    let (so, co) = g.lon_rad.sin_cos();
    DVec3::new((n + g.alt_m) * cl * co, (n + g.alt_m) * cl * so, (n * (1.0 - WGS84_E2) + g.alt_m) * sl)
}

/// ECEF → geodetic by fixed-point iteration (docs/model.md §1.1), with the polar form of the height
/// when the point is near the axis.
pub fn ecef_to_geodetic(p: DVec3) -> Geodetic {
    let lon = p.y.atan2(p.x);
    let rho = (p.x * p.x + p.y * p.y).sqrt();
    let mut lat = p.z.atan2(rho * (1.0 - WGS84_E2));
    for _ in 0..8 {
        let n = prime_vertical_radius_m(lat);
        let (s, c) = lat.sin_cos();
        let h = if c.abs() > 1e-3 { rho / c - n } else { p.z.abs() / s.abs() - n * (1.0 - WGS84_E2) };
        let new_lat = p.z.atan2(rho * (1.0 - WGS84_E2 * n / (n + h)));
        let done = (new_lat - lat).abs() < 1e-14;
        lat = new_lat;
        if done {
            break;
        }
    }
    let n = prime_vertical_radius_m(lat);
    let (s, c) = lat.sin_cos();
    let h = if c.abs() > 1e-3 { rho / c - n } else { p.z.abs() / s.abs() - n * (1.0 - WGS84_E2) };
    Geodetic { lat_rad: lat, lon_rad: lon, alt_m: h }
}

/// Rotation ECEF → ENU at a site (rows are east, north, up, docs/model.md §1.2).
pub fn enu_from_ecef(lat_rad: f64, lon_rad: f64) -> DMat3 {
    let (sl, cl) = lat_rad.sin_cos();
    let (so, co) = lon_rad.sin_cos();
    // glam matrices are column-major: build from rows by transposing.
    DMat3::from_cols(DVec3::new(-so, co, 0.0), DVec3::new(-sl * co, -sl * so, cl), DVec3::new(cl * co, cl * so, sl))
        .transpose()
}

/// A fixed local ENU frame at a site: ECEF rotated and translated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnuFrame {
    /// The site, origin of the frame, ECEF (m).
    pub origin_ecef: DVec3,
    /// Rotation ECEF → ENU (rows east, north, up at the site).
    pub enu_from_ecef: DMat3,
}

impl EnuFrame {
    /// The ENU frame at a geodetic point.
    pub fn at(g: Geodetic) -> EnuFrame {
        EnuFrame { origin_ecef: g.to_ecef(), enu_from_ecef: enu_from_ecef(g.lat_rad, g.lon_rad) }
    }

    /// ECEF position → ENU position.
    pub fn to_enu(&self, p_ecef: DVec3) -> DVec3 {
        self.enu_from_ecef * (p_ecef - self.origin_ecef)
    }

    /// ENU position → ECEF position.
    pub fn to_ecef(&self, p_enu: DVec3) -> DVec3 {
        self.origin_ecef + self.enu_from_ecef.transpose() * p_enu
    }

    /// Rotate a vector (velocity) ECEF → ENU.
    pub fn vec_to_enu(&self, v_ecef: DVec3) -> DVec3 {
        self.enu_from_ecef * v_ecef
    }

    /// Rotate a vector (velocity) ENU → ECEF.
    pub fn vec_to_ecef(&self, v_enu: DVec3) -> DVec3 {
        self.enu_from_ecef.transpose() * v_enu
    }
}

/// Geometric line-of-sight test (no refraction): does the segment from `s` to `p` (ECEF) pass
/// through the WGS-84 ellipsoid? (docs/model.md §1.7, TCL `lineOfSightHitsEarth`.)
pub fn line_of_sight_blocked(s: DVec3, p: DVec3) -> bool {
    let scale = DVec3::new(1.0, 1.0, WGS84_A_M / WGS84_B_M);
    let s = s * scale;
    let d = p * scale - s;
    let a = d.length_squared();
    if a == 0.0 {
        return false;
    }
    let b = 2.0 * s.dot(d);
    let c = s.length_squared() - WGS84_A_M * WGS84_A_M;
    let disc = b * b - 4.0 * a * c;
    if disc <= 0.0 {
        return false;
    }
    let sq = disc.sqrt();
    let t1 = (-b - sq) / (2.0 * a);
    let t2 = (-b + sq) / (2.0 * a);
    (t1 > 0.0 && t1 < 1.0) || (t2 > 0.0 && t2 < 1.0)
}

/// 4/3-earth visibility of a target at height `h_t_m` from an antenna at height `h_a_m`, given
/// both ECEF positions (docs/model.md §1.7).
pub fn visible_effective_earth(s: DVec3, h_a_m: f64, p: DVec3, h_t_m: f64) -> bool {
    let re = K_EFFECTIVE_EARTH * EARTH_MEAN_RADIUS_M;
    let cos_psi = (s.normalize().dot(p.normalize())).clamp(-1.0, 1.0);
    let psi = cos_psi.acos();
    let psi_e = EARTH_MEAN_RADIUS_M * psi / re;
    let ha = h_a_m.max(0.0);
    let ht = h_t_m.max(0.0);
    let limit = (re / (re + ha)).acos() + (re / (re + ht)).acos();
    psi_e <= limit
}

/// A lower bound (m) of the height above the WGS-84 ellipsoid of an ECEF point, [`ecef_to_geodetic`]'s
/// `alt_m`, without trigonometry; within 1 cm plus 10⁻⁵ of the height above the ellipsoid, and
/// −∞ at or inside the ellipsoid's surface along the point's ray.
///
/// The tangent plane at the ellipsoid point `Q` on the ray through `p` keeps the (convex)
/// ellipsoid on its far side, so the height is at least `p`'s distance to that plane,
/// `(|p| − |Q|)·cos θ` with `θ` the angle between the ray and the normal at `Q`, which is below
/// the largest geodetic–geocentric latitude difference (0.19°: `cos θ > 1 − 6·10⁻⁶`).
pub fn height_lower_bound_m(p: DVec3) -> f64 {
    let r = p.length();
    let (a2, b2) = (WGS84_A_M * WGS84_A_M, WGS84_B_M * WGS84_B_M);
    let q = b2 * (p.x * p.x + p.y * p.y) + a2 * p.z * p.z;
    if !(r > 0.0 && q > 0.0) {
        return f64::NEG_INFINITY;
    }
    // |Q| = a·b·|p| / √(b²(x² + y²) + a² z²).
    let d = r - WGS84_A_M * WGS84_B_M * r / q.sqrt();
    if d.is_nan() || d <= 0.0 {
        return f64::NEG_INFINITY;
    }
    d * (1.0 - 1e-5) - 0.01
}

/// Whether [`visible_effective_earth`] is surely true for an antenna at least `h_a_lo_m` and a
/// target at least `h_t_lo_m` above the ellipsoid (lower bounds such as [`height_lower_bound_m`]):
/// the horizon limit only grows with either height, so a look inside the limit at the lower
/// heights (by a margin far above rounding) is inside it at the true ones. `false` means "not
/// certain", never "not visible".
pub fn surely_visible_effective_earth(s: DVec3, h_a_lo_m: f64, p: DVec3, h_t_lo_m: f64) -> bool {
    let re = K_EFFECTIVE_EARTH * EARTH_MEAN_RADIUS_M;
    let cos_psi = (s.normalize().dot(p.normalize())).clamp(-1.0, 1.0);
    let psi_e = EARTH_MEAN_RADIUS_M * cos_psi.acos() / re;
    let ha = h_a_lo_m.max(0.0);
    let ht = h_t_lo_m.max(0.0);
    let limit = (re / (re + ha)).acos() + (re / (re + ht)).acos();
    psi_e <= limit - 1e-9
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn height_lower_bound_is_below_and_within_a_few_centimetres() {
        for k in 0..=180 {
            let lat = -89.5 + f64::from(k) * 179.0 / 180.0;
            for &lon in &[-170.0, -75.2, 0.0, 33.3, 120.0] {
                for &h in &[0.5, 20.0, 300.0, 6000.0, 12_000.0, 40_000.0] {
                    let p = Geodetic::from_deg(lat, lon, h).to_ecef();
                    let alt = ecef_to_geodetic(p).alt_m;
                    let lo = height_lower_bound_m(p);
                    assert!(lo <= alt, "lat {lat} h {h}: bound {lo} above {alt}");
                    assert!(lo >= alt - 0.011 - 1e-5 * alt - 1e-6 * h, "lat {lat} h {h}: bound {lo} far below {alt}");
                }
                let below = Geodetic::from_deg(lat, lon, -50.0).to_ecef();
                assert_eq!(height_lower_bound_m(below), f64::NEG_INFINITY);
            }
        }
    }

    #[test]
    fn surely_visible_implies_visible_and_is_mostly_decided() {
        // A mast at 25 m, targets from 100 m to 12 km out to 600 km around it, every bearing.
        let site = Geodetic::from_deg(36.0, -75.0, 25.0).to_ecef();
        let frame = EnuFrame::at(ecef_to_geodetic(site));
        let (mut sure, mut visible) = (0, 0);
        for i in 0..600 {
            let range_m = 1000.0 * f64::from(i);
            for j in 0..12 {
                let bearing = f64::from(j) * 0.52 + 0.1;
                for &h in &[100.0, 1500.0, 6000.0, 12_000.0] {
                    let flat = frame.to_ecef(DVec3::new(range_m * bearing.sin(), range_m * bearing.cos(), 0.0));
                    let g = ecef_to_geodetic(flat);
                    let p = Geodetic { alt_m: h, ..g }.to_ecef();
                    let (ha, ht) = (ecef_to_geodetic(site).alt_m, ecef_to_geodetic(p).alt_m);
                    let exact = visible_effective_earth(site, ha, p, ht);
                    let surely =
                        surely_visible_effective_earth(site, height_lower_bound_m(site), p, height_lower_bound_m(p));
                    assert!(!surely || exact, "range {range_m} h {h}: sure but not visible");
                    sure += usize::from(surely);
                    visible += usize::from(exact);
                }
            }
        }
        // Only looks within a few metres of height of the horizon are left undecided.
        assert!(visible > 10_000 && sure + 40 >= visible, "{sure} sure of {visible} visible");
    }

    #[test]
    fn geodetic_round_trip_below_a_millimetre() {
        for &lat in &[-89.9999, -60.0, -36.5, 0.0, 1e-9, 36.5, 45.0, 75.0, 89.99, 90.0] {
            for &lon in &[-179.0, -75.2, 0.0, 70.0, 180.0] {
                for &h in &[-100.0, 0.0, 20.0, 6000.0, 10_000.0, 20_000.0] {
                    let g = Geodetic::from_deg(lat, lon, h);
                    let p = g.to_ecef();
                    let back = ecef_to_geodetic(p);
                    let p2 = back.to_ecef();
                    assert!((p - p2).length() < 1e-3, "lat {lat} lon {lon} h {h}: {}", (p - p2).length());
                    assert!((back.alt_m - h).abs() < 1e-3, "lat {lat} h {h} got {}", back.alt_m);
                }
            }
        }
    }

    #[test]
    fn known_ecef_value() {
        // Equator, prime meridian, sea level is (a, 0, 0); the pole is (0, 0, b).
        let p = Geodetic::from_deg(0.0, 0.0, 0.0).to_ecef();
        assert!((p - DVec3::new(WGS84_A_M, 0.0, 0.0)).length() < 1e-9);
        let q = Geodetic::from_deg(90.0, 0.0, 0.0).to_ecef();
        assert!((q.z - WGS84_B_M).abs() < 1e-6 && q.x.abs() < 1e-6);
    }

    #[test]
    fn enu_rows_orthonormal_and_up_is_normal() {
        for &(lat, lon) in &[(36.5, -75.2), (0.0, 0.0), (-45.0, 120.0), (89.0, 10.0)] {
            let r = enu_from_ecef(f64::to_radians(lat), f64::to_radians(lon));
            let rrt = r * r.transpose();
            for i in 0..3 {
                for j in 0..3 {
                    let e = if i == j { 1.0 } else { 0.0 };
                    assert!((rrt.col(i)[j] - e).abs() < 1e-14);
                }
            }
            assert!((r.determinant() - 1.0).abs() < 1e-14);
            // A point straight up from the site is along +U.
            let g = Geodetic::from_deg(lat, lon, 0.0);
            let up = Geodetic::from_deg(lat, lon, 1000.0);
            let f = EnuFrame::at(g);
            let d = f.to_enu(up.to_ecef());
            assert!((d - DVec3::new(0.0, 0.0, 1000.0)).length() < 1e-6);
            assert!((f.to_ecef(d) - up.to_ecef()).length() < 1e-6);
        }
    }

    #[test]
    fn effective_earth_horizon_examples() {
        // docs/model.md §1.7: a 20 m mast sees a 10 km airliner to about 431 km, a 100 m target to 60 km.
        let site = Geodetic::from_deg(36.0, -70.0, 20.0);
        let s = site.to_ecef();
        let at = |dist_km: f64, h: f64| {
            let lat = 36.0 + dist_km * 1000.0 / EARTH_MEAN_RADIUS_M * 180.0 / std::f64::consts::PI;
            let g = Geodetic::from_deg(lat, -70.0, h);
            visible_effective_earth(s, 20.0, g.to_ecef(), h)
        };
        assert!(at(420.0, 10_000.0));
        assert!(!at(445.0, 10_000.0));
        assert!(at(57.0, 100.0));
        assert!(!at(63.0, 100.0));
    }

    #[test]
    fn geometric_line_of_sight() {
        let a = Geodetic::from_deg(0.0, 0.0, 20.0).to_ecef();
        let near = Geodetic::from_deg(0.0, 0.5, 10_000.0).to_ecef();
        let far = Geodetic::from_deg(0.0, 10.0, 10_000.0).to_ecef();
        assert!(!line_of_sight_blocked(a, near));
        assert!(line_of_sight_blocked(a, far));
    }
}
