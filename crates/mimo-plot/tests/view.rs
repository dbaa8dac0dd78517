//! The view's embedded data against a hand-made run: coordinates round-trip to the tables,
//! ellipsoid axes are the eigen-decomposition of the covariance, sensor lines join the right
//! radars, the linked metrics and assignments are those of the scoring rules, and bad input is
//! refused.

use glam::{DMat3, DVec3};
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::records::{
    DwellKind, DwellRow, MeasurementRow, Requester, Role, TrackRow, TrackStatus, TruthRow, pack_cov,
};
use mimo_plot::frame::PlotFrame;
use mimo_plot::{PlotError, RunSource, View, ViewOptions, build_view};
use mimo_scenario::Scenario;
use mimo_store::manifest::{Manifest, ScenarioInfo, TrackerInfo};
use std::collections::BTreeMap;
use std::path::Path;

const DURATION_S: f64 = 60.0;

fn r(n: u8) -> RadarId {
    RadarId(n - 1)
}

/// F-1 flies east at 250 m/s, 6 km up, 100 km north of the scenario centre.
fn f1_at(t: f64) -> (DVec3, DVec3) {
    let g = Geodetic::from_deg(36.9, -70.0, 6000.0);
    let f = mimo_core::geo::EnuFrame::at(g);
    let v = f.vec_to_ecef(DVec3::new(250.0, 0.0, 0.0));
    (g.to_ecef() + v * t, v)
}

fn truth_rows() -> Vec<TruthRow> {
    (0..=600)
        .map(|i| {
            let t = i as f64 / 10.0;
            let (p, v) = f1_at(t);
            let g = mimo_core::geo::ecef_to_geodetic(p);
            TruthRow {
                run: 0,
                t_s: t,
                target: "F-1".into(),
                x_m: p.x,
                y_m: p.y,
                z_m: p.z,
                vx_mps: v.x,
                vy_mps: v.y,
                vz_mps: v.z,
                lat_deg: g.lat_deg(),
                lon_deg: g.lon_deg(),
                alt_m: g.alt_m,
                rcs_m2: 2.0,
            }
        })
        .collect()
}

#[allow(clippy::too_many_arguments)]
fn dwell(id: u64, group: u64, radar: u8, role: Role, kind: DwellKind, by: Requester, t: f64, aim: DVec3) -> DwellRow {
    DwellRow {
        run: 0,
        dwell_id: id,
        group_id: group,
        radar: r(radar),
        role,
        kind,
        requested_by: by,
        t_s: t,
        duration_s: 0.01,
        pulse_width_s: 1e-5,
        n_pulses: 4,
        peak_power_w: 1e5,
        energy_j: if role.transmits() { 4.0 } else { 0.0 },
        waveform: 0,
        face: 0,
        beam_u: 0.0,
        beam_v: 0.0,
        aim_x_m: aim.x,
        aim_y_m: aim.y,
        aim_z_m: aim.z,
    }
}

/// A measurement of `p` on channel tx → rx at `t` (exact, no noise).
fn measure(s: &Scenario, id: u64, dwell_id: u64, tx: u8, rx: u8, t: f64, p: DVec3) -> MeasurementRow {
    let ship = |n: u8| s.ships.iter().find(|x| x.id == r(n)).expect("ship");
    let (face, _) = ship(rx).best_face(t, p).expect("receiver sees the target");
    let sine = ship(rx).faces_at(t)[face].to_sine(p);
    let t_pos = ship(tx).position_at(t).to_ecef();
    MeasurementRow {
        run: 0,
        meas_id: id,
        dwell_id,
        t_s: t,
        rx: r(rx),
        tx: r(tx),
        rx_face: face as u8,
        range_m: 0.5 * ((p - t_pos).length() + sine.range_m),
        u: sine.u,
        v: sine.v,
        snr_db: 23.45,
        var_range_m2: 100.0,
        var_u: 1e-6,
        var_v: 4e-6,
        n_primitives: 1,
        merged: false,
        target_hint: Some("F-1".into()),
    }
}

/// A covariance with distinct, tilted axes (ECEF, m²).
#[allow(clippy::needless_range_loop)]
fn track_cov() -> [[f64; 6]; 6] {
    let rot = DMat3::from_rotation_z(0.3) * DMat3::from_rotation_y(0.2);
    let p = rot * DMat3::from_diagonal(DVec3::new(400.0, 2500.0, 90.0)) * rot.transpose();
    let mut m = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            m[i][j] = p.col(j)[i];
        }
        m[i + 3][i + 3] = 100.0;
    }
    m
}

fn track_rows() -> Vec<TrackRow> {
    let cov = pack_cov(&track_cov());
    (0..40)
        .map(|i| {
            let t = 10.0 + i as f64;
            let (p, v) = f1_at(t);
            TrackRow {
                run: 0,
                t_s: t,
                track_id: 7,
                status: if i == 0 { TrackStatus::Tentative } else { TrackStatus::Confirmed },
                x_m: p.x,
                y_m: p.y,
                z_m: p.z,
                vx_mps: v.x,
                vy_mps: v.y,
                vz_mps: v.z,
                cov,
                n_updates: i + 1,
                last_meas_id: if i == 0 { Some(1 << 12) } else { None },
            }
        })
        .collect()
}

struct Run {
    _tmp: tempfile::TempDir,
    dir: std::path::PathBuf,
    scenario: Scenario,
}

fn make_run(tracks: Vec<TrackRow>) -> Run {
    let tmp = tempfile::tempdir().expect("tempdir");
    let dir = tmp.path().join("run");
    let scenario = mimo_scenario::load_standard(7).expect("scenario 7");
    let (p10, _) = f1_at(10.005);
    let (p20, _) = f1_at(20.0);
    let dwells = vec![
        dwell(1, 1, 1, Role::Txrx, DwellKind::Search, Requester::Radar, 10.0, p10),
        dwell(2, 2, 1, Role::Txrx, DwellKind::Mimo, Requester::Ta, 20.0, p20),
        dwell(3, 2, 2, Role::Rx, DwellKind::Mimo, Requester::Ta, 20.0, p20),
        dwell(4, 2, 3, Role::Rx, DwellKind::Mimo, Requester::Ta, 20.0, p20),
    ];
    let meas =
        vec![measure(&scenario, 1 << 12, 1, 1, 1, 10.005, p10), measure(&scenario, (2 << 12) + 1, 3, 1, 2, 20.0, p20)];
    mimo_store::write_table(&dir.join("truth/run-0000.parquet"), &truth_rows()).expect("truth");
    mimo_store::write_table(&dir.join("dwells/run-0000.parquet"), &dwells).expect("dwells");
    mimo_store::write_table(&dir.join("measurements/run-0000.parquet"), &meas).expect("measurements");
    mimo_store::write_table(&dir.join("tracks/run-0000.parquet"), &tracks).expect("tracks");
    let manifest = Manifest {
        mimo_version: "test".into(),
        schema_version: mimo_store::schema::SCHEMA_VERSION,
        scenario: ScenarioInfo {
            name: scenario.name.clone(),
            resolved: serde_json::to_value(&scenario).expect("scenario json"),
        },
        seed: 1,
        runs: 1,
        duration_s: DURATION_S,
        fidelity: serde_json::Value::Null,
        tracker: Some(TrackerInfo { name: "hand-made".into(), config: serde_json::Value::Null }),
        schedule: "hand-made".into(),
        parent: None,
        parent_check: None,
        tables: BTreeMap::new(),
        timing_s: BTreeMap::new(),
    };
    std::fs::write(dir.join("manifest.json"), manifest.to_json()).expect("manifest");
    Run { _tmp: tmp, dir, scenario }
}

fn view_of(run: &Run, opts: &ViewOptions) -> Result<View, PlotError> {
    build_view(&RunSource::open(&run.dir)?, opts)
}

fn at(v: &[i64], i: usize) -> [i64; 3] {
    [v[3 * i], v[3 * i + 1], v[3 * i + 2]]
}

/// Truth at 1 Hz and every track row (no thinning within a tolerance).
fn every_row() -> ViewOptions {
    ViewOptions { truth_step_s: 1.0, tolerance_m: 0.0, ..ViewOptions::default() }
}

fn frame(run: &Run) -> PlotFrame {
    PlotFrame::at(run.scenario.centre())
}

#[test]
fn coordinates_round_trip_to_the_tables() {
    let run = make_run(track_rows());
    let view = view_of(&run, &every_row()).expect("view");
    let f = frame(&run);
    let tol = 0.5 * 3f64.sqrt() + 1e-6; // whole metres per axis
    // Truth at 1 Hz: every kept sample is a table row, to the metre.
    let truth = truth_rows();
    let path = &view.truth[view.targets.iter().position(|t| t == "F-1").expect("F-1")];
    assert_eq!(path.t.len(), 61, "0…60 s at 1 Hz");
    for (i, &t) in path.t.iter().enumerate() {
        let row = truth.iter().find(|r| (r.t_s - t).abs() < 1e-9).expect("a table row");
        let back = f.to_ecef(at(&path.p, i));
        assert!((back - DVec3::new(row.x_m, row.y_m, row.z_m)).length() <= tol);
    }
    // Tracks: every row, to the metre, in time order.
    let tracks = track_rows();
    assert_eq!(view.tracks.t.len(), tracks.len());
    for (i, row) in tracks.iter().enumerate() {
        assert_eq!(view.tracks.t[i], row.t_s);
        assert!((f.to_ecef(at(&view.tracks.p, i)) - DVec3::new(row.x_m, row.y_m, row.z_m)).length() <= tol);
    }
    assert_eq!(view.tracks.st[0], 0);
    assert_eq!(view.tracks.st[1], 1);
    // Measurements land back on the point they measured (docs/model.md §5.4), mono- and bistatic.
    assert_eq!(view.meas.t, vec![10.005, 20.0]);
    for (i, t) in [10.005, 20.0].into_iter().enumerate() {
        let (p, _) = f1_at(t);
        let back = f.to_ecef(at(&view.meas.p, i));
        assert!((back - p).length() <= tol + 1e-3, "measurement {i}: {} m off", (back - p).length());
    }
    // The beam point is the dwell's aim point.
    assert_eq!(view.beams.t, vec![20.0]);
    assert!((f.to_ecef(at(&view.beams.p, 0)) - f1_at(20.0).0).length() <= tol);
    // Ships: positions at the sample times.
    for (k, ship) in run.scenario.ships.iter().enumerate() {
        let rv = &view.radars[k];
        assert_eq!(rv.id, ship.id.to_string());
        for i in [0, 30, rv.t.len() - 1] {
            let want = ship.position_at(rv.t[i]).to_ecef();
            assert!((f.to_ecef(at(&rv.p, i)) - want).length() <= tol);
        }
        assert_eq!(rv.faces.len(), ship.radar.face_azimuths_deg.len());
    }
}

/// Axes rebuild the covariance (Σ aᵢ aᵢᵀ = P, so with orthogonal axes they are its scaled
/// eigenvectors), are orthogonal, and come longest first; tolerances follow from rounding each
/// component to 0.1 m.
fn assert_axes_rebuild(ax: &[f64], cov_plot: DMat3) {
    let a: Vec<DVec3> = ax.chunks_exact(3).map(|c| DVec3::new(c[0], c[1], c[2])).collect();
    let amax = a.iter().map(|v| v.length()).fold(0.0, f64::max);
    let mut back = DMat3::ZERO;
    for v in &a {
        back += DMat3::from_cols(*v * v.x, *v * v.y, *v * v.z);
    }
    let err = (back - cov_plot).to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(err <= 0.3 * amax + 1e-6, "rebuilt covariance off by {err} m² (longest axis {amax} m)");
    for (i, v) in a.iter().enumerate() {
        for w in &a[i + 1..] {
            assert!(v.dot(*w).abs() <= 0.1 * (v.length() + w.length()), "axes {i} not orthogonal");
        }
    }
    assert!(a[0].length() >= a[1].length() && a[1].length() >= a[2].length());
}

#[test]
fn ellipsoid_axes_match_the_eigen_decomposition_of_the_covariance() {
    let run = make_run(track_rows());
    let view = view_of(&run, &ViewOptions::default()).expect("view");
    let f = frame(&run);
    let m = track_cov();
    let p_ecef = DMat3::from_cols_array_2d(&[
        [m[0][0], m[1][0], m[2][0]],
        [m[0][1], m[1][1], m[2][1]],
        [m[0][2], m[1][2], m[2][2]],
    ]);
    assert_axes_rebuild(&view.tracks.ax[..9], f.cov_to_plot(p_ecef));
    // The known decomposition: P = Q diag(400, 2500, 90) Qᵀ with Q = R_enu · rot, so the axes are
    // ±50 m along Q's 2nd column, ±20 m along its 1st and ±√90 m along its 3rd.
    let q = f.enu.enu_from_ecef * DMat3::from_rotation_z(0.3) * DMat3::from_rotation_y(0.2);
    for (k, (col, sigma)) in [(1, 50.0), (0, 20.0), (2, 90f64.sqrt())].into_iter().enumerate() {
        let want = q.col(col) * sigma;
        let got = DVec3::from_slice(&view.tracks.ax[3 * k..3 * k + 3]);
        let err = (got - want).length().min((got + want).length());
        assert!(err < 0.1, "axis {k}: {got} vs ±{want}");
    }
    // A measurement's ellipsoid is J R Jᵀ of its (R_B, u, v) variances (docs/model.md §5.4).
    let s = &run.scenario;
    let (p, _) = f1_at(10.005);
    let ship = &s.ships[0];
    let (face, _) = ship.best_face(10.005, p).expect("face");
    let fr = ship.faces_at(10.005)[face];
    let sine = fr.to_sine(p);
    let j = mimo_radar::geometry::ruv_to_ecef_jacobian(2.0 * sine.range_m, sine.u, sine.v, fr.origin_ecef, &fr)
        .expect("jacobian");
    let rm = DMat3::from_diagonal(DVec3::new(400.0, 1e-6, 4e-6));
    assert_axes_rebuild(&view.meas.ax[..9], f.cov_to_plot(j * rm * j.transpose()));
}

#[test]
fn sensor_lines_join_the_right_radars() {
    let run = make_run(track_rows());
    let view = view_of(&run, &ViewOptions::default()).expect("view");
    let idx = |id: &str| view.radars.iter().position(|r| r.id == id).expect("radar");
    // The monostatic measurement: R1 → R1; the bistatic one: R1 transmits, R2 receives.
    assert_eq!((view.meas.tx[0], view.meas.rx[0]), (idx("R1") as u8, idx("R1") as u8));
    assert_eq!((view.meas.tx[1], view.meas.rx[1]), (idx("R1") as u8, idx("R2") as u8));
    // The MIMO dwell: R1 transmits (and receives), R2 and R3 receive.
    let bit = |id: &str| 1u32 << idx(id);
    assert_eq!(view.beams.tx[0], bit("R1"));
    assert_eq!(view.beams.rx[0], bit("R1") | bit("R2") | bit("R3"));
    assert_eq!(view.beams.kind[0], 3, "mimo");
    assert_eq!(view.beams.e[0], 4.0, "only the transmitting part emits");
    // Kinds of the measurements' dwells; the track that used the first; the truth it came from.
    assert_eq!(view.meas.kind, vec![0, 3]);
    assert_eq!(view.meas.trk, vec![7, -1]);
    let f1 = view.targets.iter().position(|t| t == "F-1").expect("F-1") as i32;
    assert_eq!(view.meas.hint, vec![f1, f1]);
    assert!((view.meas.snr[0] - 23.45).abs() <= 0.05 + 1e-9, "SNR to 0.1 dB: {}", view.meas.snr[0]);
}

#[test]
fn linked_metrics_follow_the_scoring_rules() {
    let run = make_run(track_rows());
    let view = view_of(&run, &ViewOptions::default()).expect("view");
    let m = &view.metrics;
    assert!(m.source.contains("computed in memory"), "{}", m.source);
    assert_eq!(m.interval_s, 1.0);
    assert_eq!(m.t.first(), Some(&1.0));
    assert_eq!(m.t.last(), Some(&60.0));
    // One scorable target: tracked (confirmed at 11 s, last row at 49 s) from 11 s to 49 s and
    // extrapolated at constant velocity to the end, exactly on the truth.
    let c = |t: f64| m.completeness[m.t.iter().position(|&x| x == t).expect("time")];
    assert_eq!(c(5.0), Some(0.0));
    assert_eq!(c(11.0), Some(1.0));
    assert_eq!(c(60.0), Some(1.0));
    // Energy: the search dwell at 10 s falls in interval 11 (closed by t = 11 s), the MIMO
    // transmission at 20 s in interval 21; receive-only parts cost nothing.
    let e = |t: f64| m.energy_j[m.t.iter().position(|&x| x == t).expect("time")];
    let ta = |t: f64| m.ta_energy_j[m.t.iter().position(|&x| x == t).expect("time")];
    assert_eq!((e(11.0), ta(11.0)), (4.0, 0.0));
    assert_eq!((e(21.0), ta(21.0)), (4.0, 4.0));
    assert_eq!(m.energy_j.iter().sum::<f64>(), 8.0);
    // The track row at 10 s is tentative (never assigned); the one at 11 s is assigned to F-1.
    let f1 = view.targets.iter().position(|t| t == "F-1").expect("F-1") as i32;
    assert_eq!(view.tracks.truth[0], -1);
    assert_eq!((view.tracks.truth[1], view.tracks.tk[1]), (f1, 11.0));
}

#[test]
fn straight_paths_are_thinned_to_their_ends_and_the_page_says_within_what() {
    let run = make_run(track_rows());
    let view = view_of(&run, &ViewOptions::default()).expect("view");
    // F-1 flies straight and level at 250 m/s: of its 601 samples (10 Hz) the ends are kept.
    let path = &view.truth[view.targets.iter().position(|t| t == "F-1").expect("F-1")];
    assert_eq!(path.t, vec![0.0, 60.0]);
    assert_eq!(path.v.len(), 6);
    // Track 7: its tentative first state, the first and last confirmed ones.
    assert_eq!(view.tracks.t, vec![10.0, 11.0, 49.0]);
    assert_eq!(view.tracks.st, vec![0, 1, 1]);
    assert_eq!(view.tracks.ax.len(), 27);
    assert_eq!(view.tracks.n, vec![1, 2, 40]);
    let said = view.meta.dropped.join("\n");
    assert!(said.contains("within 20 m") && said.contains("37 of 40 track states"), "{said}");
    // The framing boxes cover the window in 10-s steps and hold F-1.
    assert_eq!(view.framing.lo.len(), 6);
    for (k, (lo, hi)) in view.framing.lo.iter().zip(&view.framing.hi).enumerate() {
        let p = [path.p[0] as f64, path.p[1] as f64, path.p[2] as f64];
        let q = [path.p[3] as f64, path.p[4] as f64, path.p[5] as f64];
        let w = (k as f64 * 10.0 + 5.0) / 60.0;
        for a in 0..3 {
            let x = p[a] + w * (q[a] - p[a]);
            assert!(x >= lo[a] as f64 && x <= hi[a] as f64, "step {k}: F-1 outside the box");
        }
    }
}

#[test]
fn a_window_keeps_only_its_objects() {
    let run = make_run(track_rows());
    let view = view_of(&run, &ViewOptions { from_s: Some(15.0), to_s: Some(25.0), ..every_row() }).expect("view");
    assert!(view.tracks.t.iter().all(|&t| (15.0..=25.0).contains(&t)));
    assert_eq!(view.tracks.t.len(), 11);
    assert_eq!(view.meas.t, vec![20.0]);
    assert_eq!(view.metrics.t.first(), Some(&15.0));
    assert_eq!(view.metrics.t.last(), Some(&25.0));
    assert_eq!((view.meta.from_s, view.meta.to_s), (15.0, 25.0));
}

#[test]
fn bad_input_is_refused_with_a_message_naming_it() {
    let run = make_run(track_rows());
    let e = view_of(&run, &ViewOptions { run: 3, ..ViewOptions::default() }).expect_err("no run 3");
    assert!(e.is_bad_input() && e.to_string().contains("--run 3"), "{e}");
    for (from, to) in [(Some(70.0), Some(80.0)), (Some(30.0), Some(20.0)), (Some(-5.0), None), (None, Some(61.0))] {
        let e = view_of(&run, &ViewOptions { from_s: from, to_s: to, ..ViewOptions::default() }).expect_err("window");
        assert!(e.is_bad_input() && e.to_string().starts_with("--from/--to"), "{e}");
    }
    // A window without tracks, and a run without tracks, still show the truth (a run recorded
    // with `--tracker none` is worth looking at).
    let quiet = view_of(&run, &ViewOptions { from_s: Some(0.0), to_s: Some(5.0), ..ViewOptions::default() })
        .expect("a window without tracks");
    assert!(quiet.tracks.t.is_empty() && !quiet.truth.is_empty());
    let empty = make_run(Vec::new());
    let view = view_of(&empty, &ViewOptions::default()).expect("a run without tracks");
    assert!(view.tracks.t.is_empty() && view.truth.len() == view.targets.len() && !view.truth.is_empty());
    // A missing run directory.
    let e = RunSource::open(Path::new("/nonexistent/mimo-run")).expect_err("missing");
    assert!(e.is_bad_input(), "{e}");
}

#[test]
fn the_page_is_self_contained() {
    let run = make_run(track_rows());
    let page = mimo_plot::plot_run(&run.dir, &ViewOptions::default()).expect("page");
    assert!(page.starts_with("<!DOCTYPE html>"));
    assert!(page.contains("plotly.js (gl3d - minified) v4.1.1") && page.contains("MIT License"));
    assert!(page.contains("\"scenario\":\"") && page.contains("Content-Security-Policy"));
    // No resource is loaded from anywhere: outside the inline scripts (plotly.js's source holds
    // link strings such as its disabled logo's), no element or attribute names a URL, and no
    // script element has a `src`.
    let mut markup = String::new();
    let mut rest = page.as_str();
    while let Some(open) = rest.find("<script") {
        let body = open + rest[open..].find('>').expect("script tag end") + 1;
        assert!(!rest[open..body].contains("src="), "external script: {}", &rest[open..body]);
        markup.push_str(&rest[..body]);
        rest = &rest[body + rest[body..].find("</script>").expect("script end")..];
    }
    markup.push_str(rest);
    assert!(markup.len() < 20_000, "the markup outside scripts is small: {}", markup.len());
    for bad in ["http:", "https:", "<link", "@import", "<iframe", "<img"] {
        assert!(!markup.contains(bad), "page references {bad}");
    }
    assert_eq!(
        page.matches("<script").count(),
        5,
        "the recorder, plotly.js, the data, the click details and the page's script"
    );
    // The data element parses back to the view.
    let start = page.find("id=\"mimo-data\">").expect("data element") + "id=\"mimo-data\">".len();
    let end = start + page[start..].find("</script>").expect("end of data");
    let v: serde_json::Value = serde_json::from_str(&page[start..end].replace("<\\/", "</")).expect("json");
    assert_eq!(v["tracks"]["id"][0], 7);
    assert_eq!(v["meta"]["run"], 0);
    // The click details are in their own element, parsed on the first click; with the drawn
    // columns they make up the whole view.
    let start = page.find("id=\"mimo-detail\">").expect("detail element") + "id=\"mimo-detail\">".len();
    let end = start + page[start..].find("</script>").expect("end of details");
    let d: serde_json::Value = serde_json::from_str(&page[start..end].replace("<\\/", "</")).expect("json");
    let view = view_of(&run, &ViewOptions::default()).expect("view");
    let full = serde_json::to_value(&view).expect("view json");
    assert!(v["tracks"].get("ax").is_none() && v["meas"].get("ax").is_none() && v["truth"][0].get("v").is_none());
    assert_eq!(d["tracks"]["ax"], full["tracks"]["ax"]);
    assert_eq!(d["meas"]["id"], full["meas"]["id"]);
    assert_eq!(d["beams"]["e"], full["beams"]["e"]);
    assert_eq!(d["truth"][0], full["truth"][0]["v"]);
    assert_eq!(v["tracks"]["p"], full["tracks"]["p"]);
}
