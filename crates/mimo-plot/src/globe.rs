//! The earth: Natural Earth 110 m coastlines (public domain, shipped in
//! `assets/coastlines-110m.txt`, made by `scripts/natural_earth_coastlines.py`) and latitude–
//! longitude graticules on the WGS-84 ellipsoid (docs/model.md §1.1), all in the plot frame.
//!
//! Nothing is fetched when the page is viewed: the coastlines are compiled into the crate and
//! converted to plot coordinates here, when the page is built.

use crate::frame::PlotFrame;
use mimo_core::geo::Geodetic;
use serde::Serialize;

/// The coastline file: one polyline per line, `lon lat …` in hundredths of a degree.
const COASTLINES: &str = include_str!("../assets/coastlines-110m.txt");

/// Coastlines are drawn this far above the ellipsoid (m), above the graticule.
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

/// The values `lo`, every multiple of `step` strictly between, and `hi`.
fn ticks(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let mut v = vec![lo];
    let mut k = (lo / step).floor() + 1.0;
    while k * step < hi - 1e-9 {
        v.push(k * step);
        k += 1.0;
    }
    v.push(hi);
    v
}

/// A latitude–longitude graticule on the ellipsoid (height 0) over `[lat0, lat1] × [lon0,
/// lon1]` (deg): parallels and meridians at the box edges and every `step_deg`, each a polyline
/// sampled every `sample_deg` (at most), so it follows the earth's curvature. The page draws the
/// earth with it instead of a filled mesh (docs/decisions/0014-run-viewer-few-traces.md).
pub fn graticule(frame: &PlotFrame, lat: (f64, f64), lon: (f64, f64), step_deg: f64, sample_deg: f64) -> Polylines {
    let mut out = Polylines::default();
    let mut n = 0;
    let samples = |a: f64, b: f64| {
        let k = ((b - a) / sample_deg).ceil().max(1.0) as usize;
        (0..=k).map(move |i| a + (b - a) * i as f64 / k as f64)
    };
    let mut line = |pts: Vec<(f64, f64)>| {
        out.starts.push(n);
        for (la, lo) in pts {
            out.p.extend(frame.to_plot(Geodetic::from_deg(la, lo, 0.0).to_ecef()));
            n += 1;
        }
    };
    for la in ticks(lat.0, lat.1, step_deg) {
        line(samples(lon.0, lon.1).map(|lo| (la, lo)).collect());
    }
    for lo in ticks(lon.0, lon.1, step_deg) {
        line(samples(lat.0, lat.1).map(|la| (la, lo)).collect());
    }
    out
}

/// The whole earth: parallels and meridians every 15°, sampled every 5°.
pub fn globe_graticule(frame: &PlotFrame) -> Polylines {
    graticule(frame, (-90.0, 90.0), (-180.0, 180.0), 15.0, 5.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::geo::ecef_to_geodetic;

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
            let h = ecef_to_geodetic(p).alt_m;
            assert!((h - COAST_LIFT_M).abs() < 2.0, "{h}");
        }
    }

    #[test]
    fn graticule_lines_lie_on_the_ellipsoid_at_their_latitude_or_longitude() {
        let f = PlotFrame::at(Geodetic::from_deg(36.0, -70.0, 0.0));
        let g = graticule(&f, (33.3, 38.7), (-73.1, -66.9), 1.0, 0.1);
        // Parallels at 33.3, 34 … 38, 38.7 (7) and meridians at −73.1, −73 … −67, −66.9 (9).
        assert_eq!(g.starts.len(), 7 + 9);
        let ends: Vec<usize> = g.starts.iter().skip(1).copied().chain([g.p.len() / 3]).collect();
        for (l, (&a, &b)) in g.starts.iter().zip(&ends).enumerate() {
            let geo: Vec<_> =
                (a..b).map(|k| ecef_to_geodetic(f.to_ecef([g.p[3 * k], g.p[3 * k + 1], g.p[3 * k + 2]]))).collect();
            assert!(geo.iter().all(|x| x.alt_m.abs() < 2.0));
            let (first, last) = (geo[0], geo[geo.len() - 1]);
            if l < 7 {
                assert!((first.lat_deg() - last.lat_deg()).abs() < 1e-4);
                assert!((first.lon_deg() + 73.1).abs() < 1e-4 && (last.lon_deg() + 66.9).abs() < 1e-4);
            } else {
                assert!((first.lon_deg() - last.lon_deg()).abs() < 1e-4);
                assert!((first.lat_deg() - 33.3).abs() < 1e-4 && (last.lat_deg() - 38.7).abs() < 1e-4);
            }
            // Samples at most 0.1° apart (about 11 km).
            assert!(geo.windows(2).all(|w| (w[1].to_ecef() - w[0].to_ecef()).length() < 11_200.0));
        }
        let globe = globe_graticule(&f);
        assert_eq!(globe.starts.len(), 13 + 25);
    }
}
