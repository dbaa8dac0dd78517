//! Ship motion, array faces and radar coverage.

use crate::model::Ship;
use glam::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::geo::{Geodetic, ecef_to_geodetic, enu_from_ecef, visible_effective_earth};

impl Ship {
    /// Array-centre position at t = 0.
    pub fn start_position(&self) -> Geodetic {
        Geodetic::from_deg(self.lat_deg, self.lon_deg, self.array_height_m)
    }

    /// The great circle the ship steams along: start point (ECEF), unit rotation axis through
    /// the earth's centre, and angular rate (rad/s).
    fn great_circle(&self) -> (Geodetic, DVec3, DVec3, f64) {
        let g = self.start_position();
        let p0 = g.to_ecef();
        let psi = self.heading_deg.to_radians();
        let dir = enu_from_ecef(g.lat_rad, g.lon_rad).transpose() * DVec3::new(psi.sin(), psi.cos(), 0.0);
        let axis = p0.cross(dir).normalize();
        (g, p0, axis, self.speed_mps / p0.length())
    }

    /// Position and heading (deg) at `t_s`, computed together.
    fn pose_at(&self, t_s: f64) -> (Geodetic, f64) {
        if self.speed_mps == 0.0 {
            return (self.start_position(), self.heading_deg);
        }
        let (g, p0, axis, omega) = self.great_circle();
        let (s, c) = (omega * t_s).sin_cos();
        let p = p0 * c + axis.cross(p0) * s;
        let mut here = ecef_to_geodetic(p);
        here.alt_m = g.alt_m;
        let enu = enu_from_ecef(here.lat_rad, here.lon_rad) * axis.cross(p);
        let h = enu.x.atan2(enu.y).to_degrees();
        // Stay on the start heading's branch (no jump at ±180°).
        (here, h + 360.0 * ((self.heading_deg - h) / 360.0).round())
    }

    /// Array-centre position at `t_s` (s since scenario start). A moving ship follows the
    /// great circle through its start point in the direction of its start heading at constant
    /// speed, and keeps its array height above the ellipsoid.
    pub fn position_at(&self, t_s: f64) -> Geodetic {
        self.pose_at(t_s).0
    }

    /// Heading at `t_s`, clockwise from north (deg). Constant for a stationary ship; a moving
    /// ship's heading drifts as on any great circle (0.07° per 10 km at 36°N heading east).
    pub fn heading_at(&self, t_s: f64) -> f64 {
        self.pose_at(t_s).1
    }

    /// ECEF velocity of the array centre at `t_s` (m/s).
    pub fn velocity_at(&self, t_s: f64) -> DVec3 {
        if self.speed_mps == 0.0 {
            return DVec3::ZERO;
        }
        let (here, heading) = self.pose_at(t_s);
        let psi = heading.to_radians();
        enu_from_ecef(here.lat_rad, here.lon_rad).transpose() * DVec3::new(psi.sin(), psi.cos(), 0.0) * self.speed_mps
    }

    /// The array faces at `t_s`: boresight azimuth = heading + face azimuth, tilt from the
    /// radar parameters, in the order of `radar.face_azimuths_deg` (the face index used in the
    /// dwell table).
    pub fn faces_at(&self, t_s: f64) -> Vec<FaceFrame> {
        let (site, heading) = self.pose_at(t_s);
        self.faces_for(site, heading)
    }

    fn faces_for(&self, site: Geodetic, heading_deg: f64) -> Vec<FaceFrame> {
        let tilt = self.radar.face_tilt_deg.to_radians();
        self.radar
            .face_azimuths_deg
            .iter()
            .map(|az| FaceFrame::new(site, (heading_deg + az).to_radians(), tilt))
            .collect()
    }

    /// The face that sees an ECEF point at the smallest scan angle, and its w = cos(scan
    /// angle), if that is within the scan limit (w ≥ cos `max_scan_deg`). Ignores range and
    /// horizon.
    pub fn best_face(&self, t_s: f64, p_ecef: DVec3) -> Option<(usize, f64)> {
        let (site, heading) = self.pose_at(t_s);
        self.best_of(&self.faces_for(site, heading), p_ecef)
    }

    fn best_of(&self, faces: &[FaceFrame], p_ecef: DVec3) -> Option<(usize, f64)> {
        let min_w = self.radar.min_scan_w();
        faces
            .iter()
            .enumerate()
            .map(|(i, f)| (i, f.to_sine(p_ecef).w))
            .filter(|&(_, w)| w >= min_w)
            .max_by(|a, b| a.1.total_cmp(&b.1))
    }

    /// Could this radar see a target at ECEF `p_ecef`, `alt_m` above the ellipsoid, at `t_s`?
    /// True when the target is between the radar's minimum and instrumented range, above the
    /// 4/3-earth horizon (docs/model.md §1.7) and inside some face's scan limit (§1.5). This is
    /// the per-radar part of docs/design.md §6's "scorable".
    pub fn sees(&self, t_s: f64, p_ecef: DVec3, alt_m: f64) -> bool {
        let (site, heading) = self.pose_at(t_s);
        let s = site.to_ecef();
        let r = (p_ecef - s).length();
        if r > self.radar.instrumented_range_m || r < self.radar.min_range_m {
            return false;
        }
        if !visible_effective_earth(s, site.alt_m, p_ecef, alt_m) {
            return false;
        }
        self.best_of(&self.faces_for(site, heading), p_ecef).is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::ids::RadarId;
    use mimo_core::params::RadarParams;

    fn ship(speed: f64, heading: f64) -> Ship {
        Ship {
            id: RadarId(0),
            lat_deg: 36.0,
            lon_deg: -70.0,
            array_height_m: 20.0,
            heading_deg: heading,
            speed_mps: speed,
            radar: RadarParams::default(),
        }
    }

    #[test]
    fn steaming_ship_keeps_speed_height_and_heading() {
        for &heading in &[0.0, 45.0, 90.0, 200.0, 359.0] {
            let s = ship(9.0, heading);
            let p0 = s.position_at(0.0);
            assert!((p0.lat_deg() - 36.0).abs() < 1e-12);
            let mut prev = p0.to_ecef();
            for i in 1..=100 {
                let t = i as f64 * 10.0;
                let g = s.position_at(t);
                assert!((g.alt_m - 20.0).abs() < 1e-6);
                let p = g.to_ecef();
                let v = (p - prev).length() / 10.0;
                assert!((v - 9.0).abs() < 9.0 * 1e-4, "speed {v}");
                // Velocity agrees with the position's finite difference.
                let fd = (s.position_at(t + 0.5).to_ecef() - s.position_at(t - 0.5).to_ecef()) / 1.0;
                assert!((fd - s.velocity_at(t)).length() < 0.01);
                prev = p;
            }
            let drift = s.heading_at(1000.0) - heading;
            assert!(drift.abs() < 0.1, "heading drift {drift}");
        }
        let still = ship(0.0, 30.0);
        assert_eq!(still.position_at(500.0), still.position_at(0.0));
        assert_eq!(still.heading_at(500.0), 30.0);
    }

    #[test]
    fn faces_follow_heading() {
        let s = ship(0.0, 30.0);
        let faces = s.faces_at(0.0);
        assert_eq!(faces.len(), 4);
        // A target due 075° (30 + 45) at low elevation is on the first face's boresight in u.
        let site = s.start_position();
        let enu_to_ecef = enu_from_ecef(site.lat_rad, site.lon_rad).transpose();
        let az = 75f64.to_radians();
        let el = 15f64.to_radians();
        let d = DVec3::new(az.sin() * el.cos(), az.cos() * el.cos(), el.sin());
        let p = site.to_ecef() + enu_to_ecef * d * 50_000.0;
        let sp = faces[0].to_sine(p);
        assert!(sp.u.abs() < 1e-9 && sp.v.abs() < 1e-9, "{sp:?}");
        assert_eq!(s.best_face(0.0, p).map(|f| f.0), Some(0));
        assert!(s.sees(0.0, p, ecef_to_geodetic(p).alt_m));
    }
}
