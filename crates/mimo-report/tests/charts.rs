//! Renders every chart of a small synthetic score and checks the files are real, non-trivial
//! PNGs (and SVGs). Set `MIMO_CHARTS_OUT=dir` to keep the charts for a look.

use glam::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, Role, TrackRow, TrackStatus, TruthRow};
use mimo_metrics::{ScoreInput, ScoreOptions, score};
use std::path::{Path, PathBuf};

/// Width and height from a PNG's IHDR chunk, checking the signature.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).expect("read png");
    assert!(bytes.len() > 33, "{} too short", path.display());
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{} is not a PNG", path.display());
    assert_eq!(&bytes[12..16], b"IHDR");
    let w = u32::from_be_bytes([bytes[16], bytes[17], bytes[18], bytes[19]]);
    let h = u32::from_be_bytes([bytes[20], bytes[21], bytes[22], bytes[23]]);
    (w, h)
}

fn out_dir(name: &str) -> (Option<tempfile::TempDir>, PathBuf) {
    match std::env::var_os("MIMO_CHARTS_OUT") {
        Some(d) => {
            let p = PathBuf::from(d).join(name);
            std::fs::create_dir_all(&p).expect("mkdir");
            (None, p)
        }
        None => {
            let t = tempfile::tempdir().expect("tempdir");
            let p = t.path().to_path_buf();
            (Some(t), p)
        }
    }
}

/// Two runs of 300 s: three targets, tracks that drop now and then, a false track, three radars
/// (R3 starts working at 100 s).
fn synthetic_run_dir(dir: &Path) {
    let r0 = 6_378_137.0 + 8_000.0;
    let target = |i: usize, t: f64| {
        let p = DVec3::new(r0, -60_000.0 + 30_000.0 * i as f64 + 200.0 * t, 10_000.0 * i as f64 - 50.0 * t);
        (p, DVec3::new(0.0, 200.0, -50.0))
    };
    for run in 0..2u32 {
        let mut truth = Vec::new();
        for i in 0..3 {
            for s in 0..=3000 {
                let t = s as f64 / 10.0;
                let (p, v) = target(i, t);
                truth.push(TruthRow {
                    run,
                    t_s: t,
                    target: ["A", "B", "C"][i].to_string(),
                    x_m: p.x,
                    y_m: p.y,
                    z_m: p.z,
                    vx_mps: v.x,
                    vy_mps: v.y,
                    vz_mps: v.z,
                    lat_deg: 0.0,
                    lon_deg: 0.0,
                    alt_m: 8000.0,
                    rcs_m2: 2.0,
                });
            }
        }
        let mut tracks = Vec::new();
        let row = |id: u64, t: f64, status: TrackStatus, p: DVec3, v: DVec3| TrackRow {
            run,
            t_s: t,
            track_id: id,
            status,
            x_m: p.x,
            y_m: p.y,
            z_m: p.z,
            vx_mps: v.x,
            vy_mps: v.y,
            vz_mps: v.z,
            cov: unit_cov(),
            n_updates: 1,
            last_meas_id: None,
        };
        let mut id = 0;
        for i in 0..3 {
            // Each target: tracked from 5 + 10·i s, dropped for 6 s every 90 s.
            let mut start = 5.0 + 10.0 * i as f64 + f64::from(run) * 3.0;
            while start < 300.0 {
                id += 1;
                let end = (start + 84.0).min(301.0);
                let mut t = start;
                while t < end {
                    let (p, v) = target(i, t);
                    let wobble = DVec3::new(0.0, 40.0 * (t * 0.3 + i as f64).sin(), 25.0 * (t * 0.17).cos());
                    tracks.push(row(id, t, TrackStatus::Confirmed, p + wobble, v));
                    t += 1.0;
                }
                let (p, v) = target(i, end);
                tracks.push(row(id, end, TrackStatus::Deleted, p, v));
                start = end + 6.0;
            }
        }
        // A false track and a redundant one.
        id += 1;
        for k in 0..40 {
            let t = 150.0 + k as f64;
            tracks.push(row(id, t, TrackStatus::Confirmed, DVec3::new(r0, 300_000.0, 0.0), DVec3::ZERO));
        }
        id += 1;
        for k in 0..30 {
            let t = 200.0 + k as f64;
            let (p, v) = target(1, t);
            tracks.push(row(id, t, TrackStatus::Confirmed, p + DVec3::new(0.0, 0.0, 400.0), v));
        }
        let mut dwells = Vec::new();
        let mut did = 0;
        for k in 0..3000 {
            let t = k as f64 * 0.1;
            for r in 0..3u8 {
                if r == 2 && t < 100.0 {
                    continue;
                }
                did += 1;
                let ta = (k + usize::from(r)) % 4 == 0;
                let np = 1 + ((k * 7 + usize::from(r) * 3) % 8) as u32;
                dwells.push(DwellRow {
                    run,
                    dwell_id: did,
                    group_id: did,
                    radar: RadarId(r),
                    role: if k % 37 == 0 && r == 1 { Role::Rx } else { Role::Txrx },
                    kind: if ta { DwellKind::Track } else { DwellKind::Search },
                    requested_by: if ta { Requester::Ta } else { Requester::Radar },
                    t_s: t,
                    duration_s: f64::from(np) / 300.0,
                    pulse_width_s: 10e-6,
                    n_pulses: np,
                    peak_power_w: 1e5,
                    energy_j: f64::from(np) * (1.0 + f64::from(r)),
                    waveform: 0,
                    face: 0,
                    beam_u: 0.0,
                    beam_v: 0.0,
                    aim_x_m: 0.0,
                    aim_y_m: 0.0,
                    aim_z_m: 0.0,
                });
            }
        }
        let name = format!("run-{run:04}.parquet");
        mimo_store::write_table(&dir.join("truth").join(&name), &truth).expect("truth");
        mimo_store::write_table(&dir.join("tracks").join(&name), &tracks).expect("tracks");
        mimo_store::write_table(&dir.join("dwells").join(&name), &dwells).expect("dwells");
    }
}

#[test]
fn renders_every_chart() {
    let data = tempfile::tempdir().expect("tempdir");
    synthetic_run_dir(data.path());
    // Target C is out of coverage for the first 40 s.
    let scorable = Box::new(|t: f64, p: DVec3, _alt: f64| !(p.z > 15_000.0 && t < 40.0));
    let input = ScoreInput::from_run_dir(data.path(), scorable).expect("input");
    let opts = ScoreOptions { scenario: "synthetic".into(), radars: vec!["R4".into()], ..Default::default() };
    let s = score(&input, &opts).expect("score");
    let (_keep, out) = out_dir("score");
    let charts = out.join("charts");
    let files = mimo_report::render_all(&s, &charts).expect("render");
    let stems = [
        "completeness",
        "energy_per_interval",
        "dwell_time_per_interval",
        "cumulative_energy",
        "cumulative_dwell_time",
        "radar_energy",
        "radar_dwell_time",
        "redundant_ratio",
        "spurious_ratio",
        "breaks",
        "switches",
        "position_rmse",
        "velocity_rmse",
        "ospa",
        "energy_by_purpose",
    ];
    assert_eq!(files.len(), 2 * stems.len());
    for stem in stems {
        let png = charts.join(format!("{stem}.png"));
        let (w, h) = png_size(&png);
        assert!(w >= 1000 && h >= 600, "{stem}: {w}×{h}");
        let len = std::fs::metadata(&png).expect("png").len();
        assert!(len > 20_000, "{stem}.png is only {len} bytes");
        let svg = std::fs::read_to_string(charts.join(format!("{stem}.svg"))).expect("svg");
        // Marked as mimo's (a comment before the root element), then the drawing.
        assert!(svg.starts_with("<!-- mimo -->\n<svg") && svg.len() > 5_000 && svg.contains("<text"), "{stem}.svg");
        for chart in [&png, &charts.join(format!("{stem}.svg"))] {
            assert!(mimo_store::recognise::is_chart_image(chart), "{} carries mimo's mark", chart.display());
        }
    }
    // No temporary files left behind.
    for f in std::fs::read_dir(&charts).expect("dir") {
        let name = f.expect("entry").file_name().to_string_lossy().to_string();
        assert!(!name.starts_with('.'), "left over: {name}");
    }
}

#[test]
fn renders_an_empty_score() {
    // A score with no scoring time at all (truth shorter than one interval) still draws.
    let data = tempfile::tempdir().expect("tempdir");
    let truth = vec![TruthRow {
        run: 0,
        t_s: 0.0,
        target: "A".into(),
        x_m: 6.4e6,
        y_m: 0.0,
        z_m: 0.0,
        vx_mps: 0.0,
        vy_mps: 0.0,
        vz_mps: 0.0,
        lat_deg: 0.0,
        lon_deg: 0.0,
        alt_m: 0.0,
        rcs_m2: 1.0,
    }];
    mimo_store::write_table(&data.path().join("truth/run-0000.parquet"), &truth).expect("truth");
    mimo_store::write_table::<TrackRow>(&data.path().join("tracks/run-0000.parquet"), &[]).expect("tracks");
    mimo_store::write_table::<DwellRow>(&data.path().join("dwells/run-0000.parquet"), &[]).expect("dwells");
    let input = ScoreInput::from_run_dir(data.path(), mimo_metrics::always_scorable()).expect("input");
    let s = score(&input, &ScoreOptions::default()).expect("score");
    assert!(s.track_metrics.is_empty());
    let out = tempfile::tempdir().expect("tempdir");
    let files = mimo_report::render_all(&s, out.path()).expect("render");
    for f in files.iter().filter(|f| f.extension().is_some_and(|e| e == "png")) {
        let (w, h) = png_size(f);
        assert!(w > 0 && h > 0);
    }
}

#[test]
fn geometry_map() {
    let (_keep, out) = out_dir("geometry");
    let ships = vec![("R1".to_string(), 35.0, 139.0), ("R2".to_string(), 35.2, 139.6), ("R3".to_string(), 34.7, 139.3)];
    let line = |lat0: f64, lon0: f64, dlat: f64, dlon: f64| -> Vec<(f64, f64)> {
        (0..=100).map(|k| (lat0 + dlat * k as f64 / 100.0, lon0 + dlon * k as f64 / 100.0)).collect()
    };
    let truth = vec![
        ("F-1".to_string(), line(36.5, 140.5, -1.2, -1.0)),
        ("F-2".to_string(), line(36.52, 140.55, -1.2, -1.0)),
        ("A".to_string(), line(33.5, 138.0, 2.5, 2.2)),
    ];
    let path = out.join("geometry.png");
    mimo_report::draw_geometry(&ships, &truth, "Scenario 7: ships and targets", &path).expect("draw");
    let (w, h) = png_size(&path);
    assert_eq!((w, h), (1100, 1000));
    assert!(std::fs::metadata(&path).expect("png").len() > 20_000);
    mimo_report::draw_geometry(&ships, &truth, "Scenario 7", &out.join("geometry.svg")).expect("svg");
    assert!(std::fs::read_to_string(out.join("geometry.svg")).expect("svg").contains("F-1"));
}

#[test]
fn fidelity_chart() {
    let (_keep, out) = out_dir("fidelity");
    let pt = |label: &str, x: f64, y: f64| mimo_report::FidelityPoint {
        label: label.to_string(),
        sim_s_per_wall_s: x,
        agreement: y,
    };
    let points = vec![pt("voltage", 108.0, 1.0), pt("measurement", 126.7, 0.978), pt("auto", 105.0, 0.990)];
    let path = out.join("fidelity.png");
    mimo_report::draw_fidelity(&points, "Fidelity ladder", &path).expect("draw");
    assert_eq!(png_size(&path), (1000, 700));
    mimo_report::draw_fidelity(&points, "Fidelity ladder", &out.join("fidelity.svg")).expect("svg");
    let svg = std::fs::read_to_string(out.join("fidelity.svg")).expect("svg");
    assert!(svg.contains("measurement (126.7, 0.9780)"), "every rung is labelled with its figures");
}

#[test]
fn trend_helpers() {
    let pts: Vec<(f64, Option<f64>)> = (0..10).map(|i| (i as f64, Some(2.0 + 3.0 * i as f64))).collect();
    let (a, b) = mimo_report::linear_fit(&pts).expect("fit");
    assert!((a - 2.0).abs() < 1e-12 && (b - 3.0).abs() < 1e-12);
    let ma = mimo_report::moving_average(&pts, 1);
    assert_eq!(ma[0].1, Some(3.5)); // (2 + 5) / 2 at the edge
    assert_eq!(ma[5].1, Some(17.0));
    let gap = vec![(0.0, Some(1.0)), (1.0, None), (2.0, Some(3.0))];
    let ma = mimo_report::moving_average(&gap, 1);
    assert_eq!(ma[1].1, None);
    assert_eq!(ma[0].1, Some(1.0));
    assert_eq!(ma[2].1, Some(3.0));
}

/// A covariance of 1 m² and 1 m²/s² on the diagonal (the readers refuse a zero variance).
fn unit_cov() -> [f64; 21] {
    let mut c = [0.0; 21];
    for i in 0..6 {
        c[mimo_core::records::cov_index(i, i)] = 1.0;
    }
    c
}
