//! The plot frame: a fixed local ENU frame at the scenario centre (docs/model.md §1.2, the
//! trackers' frame of §6.1), in whole metres.
//!
//! Every position in the page is `enu = R (p_ecef − o)` rounded to the metre, with `o` the
//! scenario centre on the ellipsoid and `R` the ECEF → ENU rotation there. Small integers keep
//! the page compact and WebGL's 32-bit floats exact to the metre; the page gets `o` and `R` to
//! show ECEF and latitude/longitude/altitude again.

use glam::{DMat3, DVec3};
use mimo_core::geo::{EnuFrame, Geodetic};
use serde::Serialize;

/// The plot frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlotFrame {
    /// ECEF → ENU at the origin.
    pub enu: EnuFrame,
    /// The origin (on the ellipsoid).
    pub origin: Geodetic,
}

/// The frame as the page reads it.
#[derive(Debug, Clone, Serialize)]
pub struct FrameJson {
    /// Origin, ECEF (m).
    pub origin_ecef_m: [f64; 3],
    /// Origin latitude and longitude (deg).
    pub origin_lat_deg: f64,
    /// Origin longitude (deg).
    pub origin_lon_deg: f64,
    /// ECEF → ENU rotation, row-major.
    pub enu_from_ecef: [f64; 9],
}

impl PlotFrame {
    /// The ENU frame at a point on the ellipsoid.
    pub fn at(origin: Geodetic) -> PlotFrame {
        PlotFrame { enu: EnuFrame::at(origin), origin }
    }

    /// ECEF (m) → plot coordinates (ENU, whole metres).
    pub fn to_plot(&self, p_ecef: DVec3) -> [i64; 3] {
        let e = self.enu.to_enu(p_ecef);
        [e.x.round() as i64, e.y.round() as i64, e.z.round() as i64]
    }

    /// Plot coordinates → ECEF (m).
    pub fn to_ecef(&self, p: [i64; 3]) -> DVec3 {
        self.enu.to_ecef(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
    }

    /// A covariance (m²) ECEF → plot frame: `R P Rᵀ`.
    pub fn cov_to_plot(&self, p_ecef: DMat3) -> DMat3 {
        self.enu.enu_from_ecef * p_ecef * self.enu.enu_from_ecef.transpose()
    }

    /// A free vector ECEF → plot frame.
    pub fn vec_to_plot(&self, v_ecef: DVec3) -> DVec3 {
        self.enu.vec_to_enu(v_ecef)
    }

    /// What the page needs to undo the transform.
    pub fn json(&self) -> FrameJson {
        let r = self.enu.enu_from_ecef.transpose().to_cols_array(); // rows of R, flattened
        let o = self.enu.origin_ecef;
        FrameJson {
            origin_ecef_m: [o.x, o.y, o.z],
            origin_lat_deg: self.origin.lat_deg(),
            origin_lon_deg: self.origin.lon_deg(),
            enu_from_ecef: r,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plot_coordinates_round_trip_to_the_metre() {
        let f = PlotFrame::at(Geodetic::from_deg(36.0, -70.0, 0.0));
        for g in [Geodetic::from_deg(36.5, -71.2, 6000.0), Geodetic::from_deg(33.0, -66.0, 11300.0)] {
            let p = g.to_ecef();
            let back = f.to_ecef(f.to_plot(p));
            assert!((back - p).length() <= 0.5 * 3f64.sqrt() + 1e-6, "{}", (back - p).length());
        }
        // Up at the origin is +z.
        let up = f.to_plot(Geodetic::from_deg(36.0, -70.0, 1000.0).to_ecef());
        assert_eq!(up, [0, 0, 1000]);
        // The row-major matrix handed to the page is R itself.
        let j = f.json();
        let r = f.enu.enu_from_ecef;
        assert_eq!(j.enu_from_ecef[1], r.row(0).y);
        assert_eq!(j.enu_from_ecef[3], r.row(1).x);
    }
}
