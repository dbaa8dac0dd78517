//! The objects of the view, as columns the page reads: ships and their faces, truth paths,
//! track states, measurements and the beams of the test article's dwells. Every position is in
//! the plot frame ([`crate::frame`]); every column set is sorted by time, so the page finds the
//! rows of a time window by bisection.

use crate::decimate::{keep_within, points};
use crate::dwell_digest::DwellDigest;
use crate::ellipsoid::{position_block, sigma_axes};
use crate::frame::PlotFrame;
use crate::linked::RunScore;
use crate::truth_samples::{TargetSamples, TruthSamples};
use glam::{DMat3, DVec3};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, MeasurementRow, Requester, TrackRow, TrackStatus};
use mimo_radar::geometry::{bistatic_ruv_to_ecef, ruv_to_ecef_jacobian};
use mimo_scenario::{Ship, ShipFrames};
use serde::Serialize;
use std::collections::{BTreeMap, HashMap};

/// Dwell kinds in the order of the page's kind codes.
pub const KINDS: [DwellKind; 4] = [DwellKind::Search, DwellKind::Confirm, DwellKind::Track, DwellKind::Mimo];

/// The page's code of a dwell kind (index into [`KINDS`]).
pub fn kind_code(k: DwellKind) -> u8 {
    KINDS.iter().position(|x| *x == k).unwrap_or(0) as u8
}

/// Track status code: 0 tentative, 1 confirmed, 2 deleted.
pub fn status_code(s: TrackStatus) -> u8 {
    match s {
        TrackStatus::Tentative => 0,
        TrackStatus::Confirmed => 1,
        TrackStatus::Deleted => 2,
    }
}

/// Round to a millisecond (times) or to 0.1 (dB, metres of an axis).
fn ms(t: f64) -> f64 {
    (t * 1000.0).round() / 1000.0
}
fn tenth(x: f64) -> f64 {
    (x * 10.0).round() / 10.0
}

/// 1σ ellipsoid axes of an ECEF covariance, in the plot frame, flattened (9 values, m).
pub fn axes_json(frame: &PlotFrame, cov_ecef: DMat3) -> [f64; 9] {
    let ax = sigma_axes(frame.cov_to_plot(cov_ecef));
    [ax[0].x, ax[0].y, ax[0].z, ax[1].x, ax[1].y, ax[1].z, ax[2].x, ax[2].y, ax[2].z].map(tenth)
}

/// One radar: its ship's path and its faces.
#[derive(Debug, Clone, Serialize)]
pub struct RadarView {
    /// Radar id (`R1` …).
    pub id: String,
    /// Sample times of the ship's path (s).
    pub t: Vec<f64>,
    /// Array-centre positions at those times (plot frame, m, flattened).
    pub p: Vec<i64>,
    /// Face axes at the window start in the plot frame: x̂_f, ŷ_f, n̂ (docs/model.md §1.3),
    /// 9 values per face. Faces follow the heading, which drifts by well under a degree.
    pub faces: Vec<[f64; 9]>,
}

/// A ship's path sampled every `step_s` over `[t0, t1]` (both included), and its faces at `t0`.
pub fn radar_view(frame: &PlotFrame, ship: &Ship, t0: f64, t1: f64, step_s: f64) -> RadarView {
    let mut t = Vec::new();
    let mut p = Vec::new();
    let n = ((t1 - t0) / step_s).ceil().max(1.0) as usize;
    for i in 0..=n {
        let ti = (t0 + i as f64 * step_s).min(t1);
        t.push(ms(ti));
        p.extend(frame.to_plot(ship.position_at(ti).to_ecef()));
    }
    let faces = ship
        .faces_at(t0)
        .iter()
        .map(|f| {
            let rows = f.face_from_ecef.transpose(); // columns are x̂_f, ŷ_f, n̂ in ECEF
            let a = [rows.x_axis, rows.y_axis, rows.z_axis].map(|c| frame.vec_to_plot(c));
            [a[0].x, a[0].y, a[0].z, a[1].x, a[1].y, a[1].z, a[2].x, a[2].y, a[2].z].map(|x| (x * 1e4).round() / 1e4)
        })
        .collect();
    RadarView { id: ship.id.to_string(), t, p, faces }
}

/// One target's truth path.
#[derive(Debug, Clone, Serialize)]
pub struct TruthPath {
    /// Target id.
    pub id: String,
    /// Sample times (s).
    pub t: Vec<f64>,
    /// Positions (plot frame, m, flattened).
    pub p: Vec<i64>,
    /// Velocities (plot frame, m/s, flattened, rounded).
    pub v: Vec<i64>,
}

/// Truth paths per target (in `targets` order), keeping the samples within `[t0, t1]` that fall
/// on multiples of `step_s` (every sample when `step_s` ≤ 0; and each target's first and last
/// sample in the window), then thinned so that every kept-or-not sample is within `tol_m` of
/// the drawn path at its time ([`crate::decimate::keep_within`]).
pub fn truth_paths(
    frame: &PlotFrame,
    truth: &TruthSamples,
    targets: &[String],
    (t0, t1): (f64, f64),
    step_s: f64,
    tol_m: f64,
) -> Vec<TruthPath> {
    let none = TargetSamples::default();
    targets
        .iter()
        .map(|id| {
            let s = truth.by_target.get(id).unwrap_or(&none);
            // The samples in the window, in time order (rows of one time in file order).
            let mut v: Vec<usize> = (0..s.t_s.len()).filter(|&i| s.t_s[i] >= t0 && s.t_s[i] <= t1).collect();
            v.sort_by(|&a, &b| s.t_s[a].total_cmp(&s.t_s[b]));
            let last = v.len().saturating_sub(1);
            let mut out = TruthPath { id: id.clone(), t: Vec::new(), p: Vec::new(), v: Vec::new() };
            for (i, &k) in v.iter().enumerate() {
                let t_s = s.t_s[k];
                let on_step = step_s <= 0.0 || ((t_s / step_s).round() * step_s - t_s).abs() < 1e-6;
                if on_step || i == 0 || i == last {
                    out.t.push(ms(t_s));
                    out.p.extend(frame.to_plot(s.pos_m[k]));
                    let vel = frame.vec_to_plot(s.vel_mps[k]);
                    out.v.extend([vel.x, vel.y, vel.z].map(|x| x.round() as i64));
                }
            }
            let keep = keep_within(&out.t, &points(&out.p), tol_m);
            TruthPath {
                id: out.id,
                t: retain(&out.t, 1, &keep),
                p: retain(&out.p, 3, &keep),
                v: retain(&out.v, 3, &keep),
            }
        })
        .collect()
}

/// The rows of a column of `width` values per row whose `keep` flag is set.
fn retain<T: Copy>(col: &[T], width: usize, keep: &[bool]) -> Vec<T> {
    col.chunks_exact(width).zip(keep).filter(|(_, k)| **k).flat_map(|(c, _)| c.iter().copied()).collect()
}

/// Track states, one per track row.
#[derive(Debug, Clone, Default, Serialize)]
pub struct TrackCols {
    /// Time (s).
    pub t: Vec<f64>,
    /// Track id.
    pub id: Vec<u64>,
    /// Status code ([`status_code`]).
    pub st: Vec<u8>,
    /// Position (plot frame, m, flattened).
    pub p: Vec<i64>,
    /// Velocity (plot frame, m/s, flattened).
    pub v: Vec<i64>,
    /// 1σ position ellipsoid axes (plot frame, m, 9 per row).
    pub ax: Vec<f64>,
    /// Updates so far.
    pub n: Vec<u32>,
    /// Index of the truth assigned to this track at the scoring time at or after `t`, or −1.
    pub truth: Vec<i32>,
    /// That scoring time (s).
    pub tk: Vec<f64>,
}

/// Track rows within `[t0, t1]`, sorted by time then track id.
pub fn track_cols(
    frame: &PlotFrame,
    rows: &[TrackRow],
    score: &RunScore,
    targets: &[String],
    t0: f64,
    t1: f64,
) -> TrackCols {
    let mut v: Vec<&TrackRow> = rows.iter().filter(|r| r.t_s >= t0 && r.t_s <= t1).collect();
    v.sort_by(|a, b| a.t_s.total_cmp(&b.t_s).then(a.track_id.cmp(&b.track_id)));
    let mut c = TrackCols::default();
    for r in v {
        c.t.push(ms(r.t_s));
        c.id.push(r.track_id);
        c.st.push(status_code(r.status));
        c.p.extend(frame.to_plot(DVec3::new(r.x_m, r.y_m, r.z_m)));
        let vel = frame.vec_to_plot(DVec3::new(r.vx_mps, r.vy_mps, r.vz_mps));
        c.v.extend([vel.x, vel.y, vel.z].map(|x| x.round() as i64));
        c.ax.extend(axes_json(frame, position_block(&r.cov)));
        c.n.push(r.n_updates);
        let k = score.k_at_or_after(r.t_s);
        let truth = score.assigned.get(&(k, r.track_id)).and_then(|id| targets.iter().position(|x| x == id));
        c.truth.push(truth.map_or(-1, |i| i as i32));
        c.tk.push(ms(k as f64 * score.interval_s));
    }
    c
}

/// Thin each track's states within `tol_m` ([`crate::decimate::keep_within`] on each run of
/// one status, so every status change, each track's first and last state and every deletion
/// stay). Returns the thinned columns and the number of states dropped.
pub fn thin_tracks(c: TrackCols, tol_m: f64) -> (TrackCols, usize) {
    let mut runs: BTreeMap<(u64, usize), Vec<usize>> = BTreeMap::new();
    let mut run_of: HashMap<u64, (usize, u8)> = HashMap::new();
    for (i, (&id, &st)) in c.id.iter().zip(&c.st).enumerate() {
        let e = run_of.entry(id).or_insert((0, st));
        if e.1 != st {
            *e = (e.0 + 1, st);
        }
        runs.entry((id, e.0)).or_default().push(i);
    }
    let p = points(&c.p);
    let mut keep = vec![false; c.t.len()];
    for rows in runs.values() {
        let t: Vec<f64> = rows.iter().map(|&i| c.t[i]).collect();
        let q: Vec<[f64; 3]> = rows.iter().map(|&i| p[i]).collect();
        for (&i, k) in rows.iter().zip(keep_within(&t, &q, tol_m)) {
            keep[i] = k;
        }
    }
    let dropped = keep.iter().filter(|k| !**k).count();
    let out = TrackCols {
        t: retain(&c.t, 1, &keep),
        id: retain(&c.id, 1, &keep),
        st: retain(&c.st, 1, &keep),
        p: retain(&c.p, 3, &keep),
        v: retain(&c.v, 3, &keep),
        ax: retain(&c.ax, 9, &keep),
        n: retain(&c.n, 1, &keep),
        truth: retain(&c.truth, 1, &keep),
        tk: retain(&c.tk, 1, &keep),
    };
    (out, dropped)
}

/// Measurements placed in space by the §5.4 conversion (docs/model.md).
#[derive(Debug, Clone, Default, Serialize)]
pub struct MeasCols {
    /// Time (dwell mid-time, s).
    pub t: Vec<f64>,
    /// Measurement id.
    pub id: Vec<u64>,
    /// Dwell kind code of the receiver's dwell part.
    pub kind: Vec<u8>,
    /// Transmitting radar (index into `radars`).
    pub tx: Vec<u8>,
    /// Receiving radar (index into `radars`).
    pub rx: Vec<u8>,
    /// Position (plot frame, m, flattened).
    pub p: Vec<i64>,
    /// 1σ ellipsoid axes of `J R Jᵀ` (plot frame, m, 9 per row).
    pub ax: Vec<f64>,
    /// Observed SNR (dB, 0.1).
    pub snr: Vec<f64>,
    /// Track this measurement updated (the lowest id when several), or −1.
    pub trk: Vec<i64>,
    /// Index of the truth that dominated it (`target_hint`), or −1 (false alarm).
    pub hint: Vec<i32>,
    /// Merged flag (docs/model.md §2.7): 1 or 0.
    pub merged: Vec<u8>,
}

/// Why a measurement could not be drawn.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MeasDropped {
    /// Radar id or face unknown to the scenario.
    pub unknown_radar: usize,
    /// The §5.4 conversion refused it (range sum below the baseline, |u, v| ≥ 1, …).
    pub unplaceable: usize,
}

/// Place the measurements within `[t0, t1]`.
pub fn meas_cols(
    frame: &PlotFrame,
    ships: &[Ship],
    rows: &[MeasurementRow],
    dwells: &DwellDigest,
    used_by: &HashMap<u64, u64>,
    targets: &[String],
    (t0, t1): (f64, f64),
) -> (MeasCols, MeasDropped) {
    let idx = |id: RadarId| ships.iter().position(|s| s.id == id);
    // The engine's own face samples (docs/model.md §1.3), so each measurement is placed with the
    // faces it was measured with, without a geodetic conversion per row.
    let frames: Vec<ShipFrames> = ships.iter().map(|s| ShipFrames::new(s, t1)).collect();
    let mut v: Vec<&MeasurementRow> = rows.iter().filter(|r| r.t_s >= t0 && r.t_s <= t1).collect();
    v.sort_by(|a, b| a.t_s.total_cmp(&b.t_s).then(a.meas_id.cmp(&b.meas_id)));
    let mut c = MeasCols::default();
    let mut dropped = MeasDropped::default();
    for r in v {
        let (Some(ti), Some(ri)) = (idx(r.tx), idx(r.rx)) else {
            dropped.unknown_radar += 1;
            continue;
        };
        let Some(face) = frames[ri].face_at(r.t_s, usize::from(r.rx_face)) else {
            dropped.unknown_radar += 1;
            continue;
        };
        let tx = frames[ti].site_at(r.t_s);
        let r_b = 2.0 * r.range_m;
        let (Some(p), Some(j)) =
            (bistatic_ruv_to_ecef(r_b, r.u, r.v, tx, &face), ruv_to_ecef_jacobian(r_b, r.u, r.v, tx, &face))
        else {
            dropped.unplaceable += 1;
            continue;
        };
        // Measurement covariance in (R_B, u, v): σ_RB² = 4 σ_ρ² (docs/model.md §5.4).
        let rm = DMat3::from_diagonal(DVec3::new(4.0 * r.var_range_m2, r.var_u, r.var_v));
        c.t.push(ms(r.t_s));
        c.id.push(r.meas_id);
        c.kind.push(dwells.kind_of(r.dwell_id).map_or(0, kind_code));
        c.tx.push(ti as u8);
        c.rx.push(ri as u8);
        c.p.extend(frame.to_plot(p));
        c.ax.extend(axes_json(frame, j * rm * j.transpose()));
        c.snr.push(tenth(r.snr_db));
        c.trk.push(used_by.get(&r.meas_id).map_or(-1, |&t| t as i64));
        let hint = r.target_hint.as_ref().and_then(|h| targets.iter().position(|x| x == h));
        c.hint.push(hint.map_or(-1, |i| i as i32));
        c.merged.push(u8::from(r.merged));
    }
    (c, dropped)
}

/// The beams of the test article's dwells: one point per dwell group, at its aim point.
#[derive(Debug, Clone, Default, Serialize)]
pub struct BeamCols {
    /// Start time (s).
    pub t: Vec<f64>,
    /// Dwell group id.
    pub gid: Vec<u64>,
    /// Kind code.
    pub kind: Vec<u8>,
    /// Aim point (plot frame, m, flattened).
    pub p: Vec<i64>,
    /// Transmitting radars: bit i set for radar index i.
    pub tx: Vec<u32>,
    /// Receiving radars: bit i set for radar index i.
    pub rx: Vec<u32>,
    /// Pulses of the longest transmission.
    pub np: Vec<u32>,
    /// Energy emitted by the group (J).
    pub e: Vec<f64>,
}

/// Beam points of the dwell groups the test article requested within `[t0, t1]`.
pub fn beam_cols(frame: &PlotFrame, ships: &[Ship], dwells: &[DwellRow], t0: f64, t1: f64) -> BeamCols {
    let mut groups: BTreeMap<u64, Vec<&DwellRow>> = BTreeMap::new();
    for d in dwells.iter().filter(|d| d.requested_by == Requester::Ta && d.t_s >= t0 && d.t_s <= t1) {
        groups.entry(d.group_id).or_default().push(d);
    }
    let mut v: Vec<(f64, u64, Vec<&DwellRow>)> = groups
        .into_iter()
        .map(|(g, parts)| (parts.iter().map(|d| d.t_s).fold(f64::INFINITY, f64::min), g, parts))
        .collect();
    v.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    let bit = |id: RadarId| ships.iter().position(|s| s.id == id).map_or(0, |i| 1u32 << i.min(31));
    let mut c = BeamCols::default();
    for (t, g, parts) in v {
        let first = parts[0];
        c.t.push(ms(t));
        c.gid.push(g);
        c.kind.push(kind_code(first.kind));
        c.p.extend(frame.to_plot(DVec3::new(first.aim_x_m, first.aim_y_m, first.aim_z_m)));
        c.tx.push(parts.iter().filter(|d| d.role.transmits()).fold(0, |m, d| m | bit(d.radar)));
        c.rx.push(parts.iter().filter(|d| d.role != mimo_core::records::Role::Tx).fold(0, |m, d| m | bit(d.radar)));
        c.np.push(parts.iter().map(|d| d.n_pulses).max().unwrap_or(0));
        c.e.push(tenth(parts.iter().map(|d| d.energy_j).sum()));
    }
    c
}
