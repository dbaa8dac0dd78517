//! Usage by purpose on a hand-made recording whose answer is known: two radars, a stationary and
//! a moving target, and one dwell of each case, every energy a different power of two so that
//! any misattribution shows in the sums.

use glam::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::params::{PatternModel, RadarParams};
use mimo_core::records::{DwellKind, DwellRow, Requester, Role, TrackRow, TruthRow};
use mimo_metrics::{BeamGeometry, Purpose, Score, ScoreInput, ScoreOptions, always_scorable, score};
use std::collections::BTreeMap;

/// Face 0 of R1 (36° N, 70° W) and of R2, 30 km east of it, both looking north-east; face 1 of
/// each looks south-west.
fn frame(radar: u8, face: u8) -> FaceFrame {
    let lon = if radar == 0 { -70.0 } else { -70.0 + 30_000.0 / (111_320.0 * 36f64.to_radians().cos()) };
    let az = if face == 0 { 45.0 } else { 225.0 };
    FaceFrame::new(Geodetic::from_deg(36.0, lon, 20.0), f64::to_radians(az), f64::to_radians(15.0))
}

fn geometry() -> BeamGeometry {
    let p = RadarParams::default();
    let faces = |radar: u8| -> mimo_metrics::purpose_rule::FaceAt {
        Box::new(move |_, face| (face < 2).then(|| frame(radar, face)))
    };
    BeamGeometry::none().with_radar("R1", &p, PatternModel::Gaussian, faces(0)).with_radar(
        "R2",
        &p,
        PatternModel::Gaussian,
        faces(1),
    )
}

/// Target A, stationary 100 km out on R1's face 0 at (u, v) = (0.1, 0.05).
fn a_pos() -> DVec3 {
    frame(0, 0).from_ruv(100_000.0, 0.1, 0.05)
}

const VB: DVec3 = DVec3::new(150.0, -200.0, 0.0);

/// Target B, flying at 250 m/s from 80 km out at (u, v) = (−0.2, 0.02).
fn b_pos(t_s: f64) -> DVec3 {
    frame(0, 0).from_ruv(80_000.0, -0.2, 0.02) + VB * t_s
}

fn truth() -> Vec<TruthRow> {
    let row = |target: &str, t_s: f64, p: DVec3, v: DVec3| TruthRow {
        run: 0,
        t_s,
        target: target.into(),
        x_m: p.x,
        y_m: p.y,
        z_m: p.z,
        vx_mps: v.x,
        vy_mps: v.y,
        vz_mps: v.z,
        lat_deg: 0.0,
        lon_deg: 0.0,
        alt_m: 10_000.0,
        rcs_m2: 2.0,
    };
    let mut rows = Vec::new();
    for i in 0..=100 {
        let t = f64::from(i) / 10.0;
        rows.push(row("A", t, a_pos(), DVec3::ZERO));
        rows.push(row("B", t, b_pos(t), VB));
    }
    rows
}

struct Look {
    group: u64,
    radar: u8,
    role: Role,
    kind: DwellKind,
    by: Requester,
    t_s: f64,
    energy_j: f64,
    face: u8,
    /// Beam centre: the direction of `beam_at` in the face.
    beam_at: DVec3,
    aim: DVec3,
}

fn row(id: u64, l: &Look) -> DwellRow {
    let s = frame(l.radar, l.face).to_sine(l.beam_at);
    DwellRow {
        run: 0,
        dwell_id: id,
        group_id: l.group,
        radar: RadarId(l.radar),
        role: l.role,
        kind: l.kind,
        requested_by: l.by,
        t_s: l.t_s,
        duration_s: 0.02,
        pulse_width_s: 10e-6,
        n_pulses: 1,
        peak_power_w: 1e5,
        energy_j: if l.role == Role::Rx { 0.0 } else { l.energy_j },
        waveform: 0,
        face: l.face,
        beam_u: s.u,
        beam_v: s.v,
        aim_x_m: l.aim.x,
        aim_y_m: l.aim.y,
        aim_z_m: l.aim.z,
    }
}

/// Every case, with the purpose and interval its transmit row must get (`None` for rx rows).
fn looks() -> Vec<(Look, Option<(Purpose, u32)>)> {
    use DwellKind::*;
    use Purpose as P;
    use Requester::{Radar as ByRadar, Ta};
    use Role::*;
    let a = a_pos();
    // 5 km beyond A, same direction: in the beam, outside the range window.
    let beyond_a = frame(0, 0).from_ruv(105_000.0, 0.1, 0.05);
    // 0.6 beamwidth off A in u: A is outside the 3 dB footprint (0.5 beamwidth).
    let off_a = frame(0, 0).from_ruv(100_000.0, 0.1 + 0.6 * 0.0252, 0.05);
    let b_mid = b_pos(3.11);
    let l = |group, radar, role, kind, by, t_s, energy_j, face, beam_at, aim| Look {
        group,
        radar,
        role,
        kind,
        by,
        t_s,
        energy_j,
        face,
        beam_at,
        aim,
    };
    vec![
        (l(1, 0, Txrx, Search, ByRadar, 0.5, 1.0, 0, a, a), Some((P::Search, 1))),
        (l(2, 1, Rx, Search, ByRadar, 0.5, 0.0, 0, a, a), None),
        (l(3, 0, Txrx, Confirm, Ta, 1.2, 2.0, 0, a, a), Some((P::ConfirmTrue, 2))),
        (l(4, 0, Txrx, Confirm, Ta, 1.5, 4.0, 0, beyond_a, beyond_a), Some((P::ConfirmFalse, 2))),
        (l(5, 0, Txrx, Track, Ta, 2.3, 8.0, 0, off_a, off_a), Some((P::TrackFalse, 3))),
        (l(6, 0, Txrx, Track, Ta, 2.6, 16.0, 0, a, a), Some((P::Track, 3))),
        // MIMO at the moving target, aimed at its mid-dwell position (3.1 s + 10 ms).
        (l(7, 0, Txrx, Mimo, Ta, 3.1, 32.0, 0, b_mid, b_mid), Some((P::Track, 4))),
        (l(7, 1, Rx, Mimo, Ta, 3.1, 0.0, 0, b_mid, b_mid), None),
        // R2 transmits only; R1 receives: the channel R2 → R1 holds A.
        (l(8, 1, Tx, Mimo, Ta, 3.6, 64.0, 0, a, a), Some((P::Track, 4))),
        (l(8, 0, Rx, Mimo, Ta, 3.6, 0.0, 0, a, a), None),
        // A search dwell the test article asked for is search.
        (l(9, 0, Txrx, Search, Ta, 4.2, 256.0, 0, a, a), Some((P::Search, 5))),
        // R1's back face, steered where A's direction cosines fall in it: A is behind the face.
        (l(10, 0, Txrx, Confirm, Ta, 4.5, 128.0, 1, a, a), Some((P::ConfirmFalse, 5))),
        // The MIMO look at B a second later: B has moved 250 m, still in the beam; then the
        // same look with its receiver R2 steered away: no channel holds B.
        (l(11, 0, Txrx, Track, Ta, 5.1, 512.0, 0, b_pos(5.11), b_pos(5.11)), Some((P::Track, 6))),
        (l(12, 0, Tx, Mimo, Ta, 6.1, 1024.0, 0, b_pos(6.11), b_pos(6.11)), Some((P::TrackFalse, 7))),
        (l(12, 1, Rx, Mimo, Ta, 6.1, 0.0, 0, a, b_pos(6.11)), None),
    ]
}

fn score_case(beams: BeamGeometry) -> (Score, tempfile::TempDir) {
    let dir = tempfile::tempdir().expect("tempdir");
    let cases = looks();
    let rows: Vec<DwellRow> = cases.iter().enumerate().map(|(i, (l, _))| row(i as u64 + 1, l)).collect();
    mimo_store::write_table(&dir.path().join("truth/run-0000.parquet"), &truth()).expect("truth");
    mimo_store::write_table(&dir.path().join("dwells/run-0000.parquet"), &rows).expect("dwells");
    mimo_store::write_table::<TrackRow>(&dir.path().join("tracks/run-0000.parquet"), &[]).expect("tracks");
    let input = ScoreInput::from_run_dir(dir.path(), always_scorable()).expect("input").with_beams(beams);
    let opts = ScoreOptions { radars: vec!["R1".into(), "R2".into()], ..ScoreOptions::default() };
    (score(&input, &opts).expect("score"), dir)
}

#[test]
fn each_hand_made_look_gets_its_purpose() {
    // The geometry the cases rely on.
    let s = frame(0, 1).to_sine(a_pos());
    assert!(s.w < 0.0, "A is behind R1's face 1");
    assert!(frame(1, 0).to_sine(a_pos()).w > 0.5 && frame(1, 0).to_sine(b_pos(3.11)).w > 0.5);

    let (score, _dir) = score_case(geometry());
    let mut want: BTreeMap<(String, u32, &str), (u32, f64)> = BTreeMap::new();
    for (l, expect) in looks() {
        if let Some((p, k)) = expect {
            let e = want.entry((format!("R{}", l.radar + 1), k, p.name())).or_default();
            e.0 += 1;
            e.1 += l.energy_j;
        }
    }
    // One row per radar, interval 1..=10 and purpose, zeros included.
    assert_eq!(score.usage_by_purpose.len(), 2 * 10 * 5);
    for r in &score.usage_by_purpose {
        let (n, e) = want.get(&(r.radar.clone(), r.interval, r.purpose.as_str())).copied().unwrap_or_default();
        assert_eq!((r.dwells, r.energy_j), (n, e), "{} interval {} {}", r.radar, r.interval, r.purpose);
        assert!((r.dwell_time_s - 0.02 * f64::from(n)).abs() < 1e-15);
        assert_eq!((r.t_start_s, r.t_end_s), (f64::from(r.interval - 1), f64::from(r.interval)));
    }
    let by = score.summary.usage.totals.by_purpose;
    assert_eq!(by.search.energy_j, 257.0);
    assert_eq!(by.confirm_true.energy_j, 2.0);
    assert_eq!(by.confirm_false.energy_j, 132.0);
    assert_eq!(by.track.energy_j, 16.0 + 32.0 + 64.0 + 512.0);
    assert_eq!(by.track_false.energy_j, 8.0 + 1024.0);
    assert!((by.track.dwell_time_s - 4.0 * 0.02).abs() < 1e-15);
    assert_eq!(score.summary.per_run[0].usage.by_purpose, by);
    // Summed over purposes: the usage totals of each radar.
    for u in &score.usage_run {
        let rows = score.usage_by_purpose.iter().filter(|r| r.run == u.run && r.radar == u.radar);
        let (t, e) = rows.fold((0.0, 0.0), |(t, e), r| (t + r.dwell_time_s, e + r.energy_j));
        assert!(
            (e - u.totals.energy_j).abs() <= 1e-12 * u.totals.energy_j.max(1.0),
            "{}: {e} vs {}",
            u.radar,
            u.totals.energy_j
        );
        assert!((t - u.totals.dwell_time_s).abs() <= 1e-12, "{}: {t} vs {}", u.radar, u.totals.dwell_time_s);
    }
}

#[test]
fn without_beams_every_look_holds_nothing_and_the_outputs_are_written() {
    let (score, dir) = score_case(BeamGeometry::none());
    let by = score.summary.usage.totals.by_purpose;
    assert_eq!((by.confirm_true.energy_j, by.track.energy_j), (0.0, 0.0));
    assert_eq!(by.confirm_false.energy_j, 134.0);
    assert_eq!(by.track_false.energy_j, 8.0 + 16.0 + 32.0 + 64.0 + 512.0 + 1024.0);
    assert_eq!(by.search.energy_j, 257.0);

    let out = dir.path().join("score");
    mimo_metrics::write_outputs(&score, &out).expect("write");
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary");
    let json: serde_json::Value = serde_json::from_str(&text).expect("json");
    // New keys after the old ones: `usage.by_purpose` last in `usage`, before `challenge`.
    let at = |key: &str| text.find(&format!("\"{key}\"")).expect("key");
    assert!(at("ta_energy_j") < at("by_purpose") && at("total_energy_j") < at("by_purpose"));
    assert!(at("by_purpose") < at("challenge"));
    for p in Purpose::ALL {
        for key in ["dwell_time_s", "energy_j"] {
            assert!(json["usage"]["by_purpose"][p.name()][key].is_number(), "usage.by_purpose.{}.{key}", p.name());
            assert!(json["per_run"][0]["by_purpose"][p.name()][key].is_number());
        }
    }
    assert!(out.join("usage_by_purpose.parquet").is_file());
}
