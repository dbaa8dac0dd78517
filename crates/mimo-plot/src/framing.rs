//! Framing: for each step of time, a box of the plot frame that holds every ship and every
//! target alive during the step, so that the page's region view frames what is in view at t
//! (not the box of the whole run). The page keeps its current box while the step's box lies
//! inside it, so the scene is not rescaled at every slider step (docs/decisions/0016-run-viewer-thinning-and-framing.md).
//!
//! Paths are drawn as chords between samples, so the box of a path's samples within the step
//! and its interpolated positions at the step's ends holds the path over the whole step.

use crate::decimate::{interp, points};
use crate::frame::PlotFrame;
use crate::objects::{RadarView, TruthPath};
use glam::DVec3;
use mimo_core::geo::ecef_to_geodetic;
use serde::Serialize;

/// Horizontal margin around the objects, as a fraction of the box's half-width.
pub const MARGIN: f64 = 0.15;
/// Smallest horizontal half-width of a box (m).
pub const MIN_HALF_M: f64 = 15_000.0;
/// Room above the highest object (m).
pub const HEADROOM_M: i64 = 2000;

/// Boxes per time step: step k covers `[t0_s + k step_s, t0_s + (k + 1) step_s]`.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Framing {
    /// Start of the first step (s).
    pub t0_s: f64,
    /// Step (s).
    pub step_s: f64,
    /// Lower corner per step (plot frame, m).
    pub lo: Vec<[i64; 3]>,
    /// Upper corner per step (plot frame, m).
    pub hi: Vec<[i64; 3]>,
}

/// Height (plot z, m) of the ellipsoid's surface under the plot point (x, y).
pub fn surface_z_m(frame: &PlotFrame, x_m: f64, y_m: f64) -> f64 {
    let g = ecef_to_geodetic(frame.enu.to_ecef(DVec3::new(x_m, y_m, 0.0)));
    let on_surface = mimo_core::geo::Geodetic::from_deg(g.lat_deg(), g.lon_deg(), 0.0).to_ecef();
    frame.enu.to_enu(on_surface).z
}

/// Grow `lo..hi` by the points of a path over `[a, b]` (nothing if the path is not alive then).
fn add_path(t_s: &[f64], p_m: &[[f64; 3]], a: f64, b: f64, lo: &mut [f64; 3], hi: &mut [f64; 3]) {
    let (Some(&first), Some(&last)) = (t_s.first(), t_s.last()) else { return };
    let (a, b) = (a.max(first), b.min(last));
    if a > b {
        return;
    }
    let inner = t_s.iter().zip(p_m).filter(|(t, _)| **t > a && **t < b).map(|(_, p)| *p);
    for q in [interp(t_s, p_m, a), interp(t_s, p_m, b)].into_iter().flatten().chain(inner) {
        for k in 0..3 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
}

/// The boxes of `[t0, t1]` in steps of `step_s`: each holds every ship and truth position of
/// its step, with a horizontal margin, square in plan, from the earth's surface under it to
/// above the highest object.
pub fn framing(frame: &PlotFrame, radars: &[RadarView], truth: &[TruthPath], t0: f64, t1: f64, step_s: f64) -> Framing {
    let paths: Vec<(&[f64], Vec<[f64; 3]>)> = radars
        .iter()
        .map(|r| (r.t.as_slice(), points(&r.p)))
        .chain(truth.iter().map(|p| (p.t.as_slice(), points(&p.p))))
        .collect();
    let n = ((t1 - t0) / step_s).ceil().max(1.0) as usize;
    let mut out = Framing { t0_s: t0, step_s, lo: Vec::with_capacity(n), hi: Vec::with_capacity(n) };
    for k in 0..n {
        let (a, b) = (t0 + k as f64 * step_s, (t0 + (k + 1) as f64 * step_s).min(t1));
        let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
        for (t, p) in &paths {
            add_path(t, p, a, b, &mut lo, &mut hi);
        }
        if lo[0] > hi[0] {
            (lo, hi) = ([0.0; 3], [0.0; 3]);
        }
        let half = ((hi[0] - lo[0]).max(hi[1] - lo[1]) / 2.0 * (1.0 + MARGIN)).max(MIN_HALF_M).ceil();
        let (cx, cy) = (((lo[0] + hi[0]) / 2.0).round(), ((lo[1] + hi[1]) / 2.0).round());
        let (x0, x1, y0, y1) = (cx - half, cx + half, cy - half, cy + half);
        // The surface is lowest at a corner: the frame's origin is the scenario centre, and the
        // surface falls away from it in every direction.
        let floor = [(x0, y0), (x0, y1), (x1, y0), (x1, y1), (cx, cy)]
            .iter()
            .map(|&(x, y)| surface_z_m(frame, x, y))
            .fold(lo[2], f64::min);
        out.lo.push([x0 as i64, y0 as i64, floor.floor() as i64 - 500]);
        out.hi.push([x1 as i64, y1 as i64, hi[2].max(1000.0).ceil() as i64 + HEADROOM_M]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::geo::Geodetic;

    fn path(id: &str, t: &[f64], p: impl Fn(f64) -> [f64; 3]) -> TruthPath {
        TruthPath {
            id: id.into(),
            t: t.to_vec(),
            p: t.iter().flat_map(|&t| p(t).map(|x| x.round() as i64)).collect(),
            v: vec![0; 3 * t.len()],
        }
    }

    #[test]
    fn each_box_holds_every_ship_and_target_of_its_step_and_is_smaller_than_the_run() {
        let frame = PlotFrame::at(Geodetic::from_deg(35.0, 20.0, 0.0));
        let t: Vec<f64> = (0..=600).map(f64::from).collect();
        let ship = path("R1", &t, |t| [5.0 * t, 0.0, 20.0]);
        let radars = vec![RadarView { id: ship.id.clone(), t: ship.t.clone(), p: ship.p.clone(), faces: vec![] }];
        // A fighter flying away at 250 m/s and turning; a second target alive from 100 s to 400 s.
        let fighter = path("F1", &t, |t| [80_000.0 + 250.0 * t, 30_000.0 * (t / 100.0).sin(), 9000.0 + t]);
        let late: Vec<f64> = (100..=400).map(f64::from).collect();
        let airliner = path("A1", &late, |t| [-60_000.0 + 200.0 * t, -40_000.0, 11_000.0]);
        let truth = vec![fighter, airliner];
        let f = framing(&frame, &radars, &truth, 0.0, 600.0, 10.0);
        assert_eq!(f.lo.len(), 60);
        let mut checked = 0;
        for i in 0..=6000 {
            let ts = i as f64 * 0.1;
            let k = ((ts / 10.0).floor() as usize).min(59);
            let (lo, hi) = (f.lo[k], f.hi[k]);
            let all = radars
                .iter()
                .map(|r| (r.t.as_slice(), points(&r.p)))
                .chain(truth.iter().map(|p| (p.t.as_slice(), points(&p.p))));
            for (tp, pp) in all {
                if ts < tp[0] || ts > tp[tp.len() - 1] {
                    continue;
                }
                let q = interp(tp, &pp, ts).expect("alive");
                for a in 0..3 {
                    assert!(q[a] >= lo[a] as f64 && q[a] <= hi[a] as f64, "t {ts}: {q:?} outside {lo:?}..{hi:?}");
                }
                checked += 1;
            }
            // The earth's surface under the box is above its floor.
            assert!(surface_z_m(&frame, lo[0] as f64, lo[1] as f64) >= lo[2] as f64);
            assert!(surface_z_m(&frame, hi[0] as f64, hi[1] as f64) >= lo[2] as f64);
            // Square in plan.
            assert_eq!(hi[0] - lo[0], hi[1] - lo[1]);
        }
        assert!(checked > 15_000);
        // A step's box is much smaller than the run's (one step of 600 s).
        let whole = framing(&frame, &radars, &truth, 0.0, 600.0, 600.0);
        assert_eq!(whole.lo.len(), 1);
        let run_width = whole.hi[0][0] - whole.lo[0][0];
        assert!(2 * (f.hi[0][0] - f.lo[0][0]) < run_width, "{:?} {:?} against {run_width}", f.lo[0], f.hi[0]);
    }

    #[test]
    fn an_empty_step_gets_the_smallest_box_at_the_origin() {
        let frame = PlotFrame::at(Geodetic::from_deg(0.0, 0.0, 0.0));
        let f = framing(&frame, &[], &[], 0.0, 25.0, 10.0);
        assert_eq!(f.lo.len(), 3);
        assert_eq!(f.hi[2][0] - f.lo[2][0], 2 * MIN_HALF_M as i64);
        assert!(f.lo[0][2] < 0 && f.hi[0][2] == 1000 + HEADROOM_M);
    }
}
