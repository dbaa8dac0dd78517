//! The earth: Natural Earth 110 m coastlines (public domain, shipped in
//! `assets/coastlines-110m.txt`, made by `scripts/natural_earth_coastlines.py`) and two
//! surface meshes on the WGS-84 ellipsoid (docs/model.md §1.1), all in the plot frame.
//!
//! Nothing is fetched when the page is viewed: the coastlines are compiled into the crate and
//! converted to plot coordinates here, when the page is built.

use crate::frame::PlotFrame;
use mimo_core::geo::Geodetic;
use serde::Serialize;

/// The coastline file: one polyline per line, `lon lat …` in hundredths of a degree.
const COASTLINES: &str = include_str!("../assets/coastlines-110m.txt");

/// Coastlines are drawn this far above the ellipsoid (m), so the surface mesh never hides them.
const COAST_LIFT_M: f64 = 300.0;

/// The coastlines as lon/lat polylines (deg).
pub fn coastlines_deg() -> Vec<Vec<(f64, f64)>> {
    COASTLINES
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> =
                l.split_ascii_whitespace().filter_map(|s| s.parse::<i64>().ok()).map(|x| x as f64 / 100.0).collect();
            v.chunks_exact(2).map(|c| (c[0], c[1])).collect()
        })
        .collect()
}

/// A polyline set: flat `x, y, z` triples (plot frame, m), polylines separated in `starts`.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Polylines {
    /// Flattened plot coordinates.
    pub p: Vec<i64>,
    /// Index (in points) where each polyline starts.
    pub starts: Vec<usize>,
}

/// A triangle mesh in the plot frame.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Mesh {
    /// Flattened vertex coordinates (m).
    pub p: Vec<i64>,
    /// Flattened vertex indices of the triangles.
    pub tri: Vec<u32>,
}

/// The coastlines in the plot frame.
pub fn coastlines(frame: &PlotFrame) -> Polylines {
    let mut out = Polylines::default();
    let mut n = 0;
    for line in coastlines_deg() {
        out.starts.push(n);
        for (lon, lat) in line {
            out.p.extend(frame.to_plot(Geodetic::from_deg(lat, lon, COAST_LIFT_M).to_ecef()));
            n += 1;
        }
    }
    out
}

/// A latitude–longitude grid mesh on the ellipsoid (height 0) over `[lat0, lat1] × [lon0,
/// lon1]` (deg) with `n_lat × n_lon` cells.
pub fn surface_mesh(frame: &PlotFrame, lat: (f64, f64), lon: (f64, f64), n_lat: usize, n_lon: usize) -> Mesh {
    let mut m = Mesh::default();
    for i in 0..=n_lat {
        let la = lat.0 + (lat.1 - lat.0) * i as f64 / n_lat as f64;
        for j in 0..=n_lon {
            let lo = lon.0 + (lon.1 - lon.0) * j as f64 / n_lon as f64;
            m.p.extend(frame.to_plot(Geodetic::from_deg(la, lo, 0.0).to_ecef()));
        }
    }
    let w = (n_lon + 1) as u32;
    for i in 0..n_lat as u32 {
        for j in 0..n_lon as u32 {
            let a = i * w + j;
            m.tri.extend([a, a + 1, a + w + 1, a, a + w + 1, a + w]);
        }
    }
    m
}

/// The whole earth, 5° cells (chords sag at most about 6 km below the surface).
pub fn globe_mesh(frame: &PlotFrame) -> Mesh {
    surface_mesh(frame, (-90.0, 90.0), (-180.0, 180.0), 36, 72)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coastlines_are_natural_earth_110m_outlines() {
        let lines = coastlines_deg();
        assert!(lines.len() > 100, "{}", lines.len());
        let pts: usize = lines.iter().map(Vec::len).sum();
        assert!((4000..8000).contains(&pts), "{pts}");
        assert!(lines.iter().flatten().all(|&(lo, la)| (-180.0..=180.0).contains(&lo) && (-90.0..=90.0).contains(&la)));
        // Cape Hatteras (35.2°N, 75.5°W) lies on the 110 m coast within about half a degree.
        let near = lines.iter().flatten().any(|&(lo, la)| (lo + 75.5).abs() < 0.6 && (la - 35.2).abs() < 0.6);
        assert!(near);
    }

    #[test]
    fn coastline_points_sit_on_the_ellipsoid() {
        let f = PlotFrame::at(Geodetic::from_deg(36.0, -70.0, 0.0));
        let c = coastlines(&f);
        assert_eq!(c.starts.len(), coastlines_deg().len());
        for k in (0..c.p.len() / 3).step_by(97) {
            let p = f.to_ecef([c.p[3 * k], c.p[3 * k + 1], c.p[3 * k + 2]]);
            let h = mimo_core::geo::ecef_to_geodetic(p).alt_m;
            assert!((h - COAST_LIFT_M).abs() < 2.0, "{h}");
        }
        let g = globe_mesh(&f);
        assert_eq!(g.p.len(), 3 * 37 * 73);
        assert_eq!(g.tri.len(), 3 * 2 * 36 * 72);
        assert!(g.tri.iter().all(|&i| (i as usize) < g.p.len() / 3));
    }
}
