//! Hand-made cases with known answers. Every case writes small Parquet tables (arrow-rs, with the
//! table's name and schema version in the metadata, as mimo writes them) into a temporary run
//! directory and scores them. Files holding several runs are named `part-K.parquet` (a
//! `run-K.parquet` file holds run K only).

use arrow::array::{
    ArrayRef, FixedSizeListArray, Float64Array, Int64Array, RecordBatch, StringArray, UInt8Array, UInt32Array,
    UInt64Array,
};
use arrow::datatypes::{Field, Schema};
use glam::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, Role, TrackRow, TrackStatus, TruthRow};
use mimo_metrics::{MetricsError, ScorablePredicate, Score, ScoreInput, ScoreOptions, always_scorable, score};
use mimo_store::StoreError;
use std::fs::File;
use std::path::Path;
use std::sync::Arc;
use tempfile::TempDir;

// ---------------------------------------------------------------------------------------------
// Table builders

/// Truth of one target moving at constant velocity, sampled at 10 Hz over [t0, t1].
fn truth_line(run: u32, target: &str, p0: DVec3, v: DVec3, t0: f64, t1: f64) -> Vec<TruthRow> {
    let n = ((t1 - t0) * 10.0).round() as usize;
    (0..=n)
        .map(|i| {
            let t = t0 + i as f64 / 10.0;
            let p = p0 + v * t;
            TruthRow {
                run,
                t_s: t,
                target: target.to_string(),
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
            }
        })
        .collect()
}

/// A covariance (1 m², 1 m²/s²): every track row's.
const IDENTITY: [[f64; 6]; 6] = {
    let mut m = [[0.0; 6]; 6];
    let mut i = 0;
    while i < 6 {
        m[i][i] = 1.0;
        i += 1;
    }
    m
};

fn track_row(run: u32, id: u64, t: f64, status: TrackStatus, p: DVec3, v: DVec3) -> TrackRow {
    TrackRow {
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
        cov: mimo_core::records::pack_cov(&IDENTITY),
        n_updates: 1,
        last_meas_id: None,
    }
}

/// A track that follows `p0 + v·t + offset`: a tentative row 0.3 s before `t_confirm`, then
/// confirmed rows every `period` s until `t_end` (exclusive), then a deleted row at `t_end` if
/// `deleted`.
#[allow(clippy::too_many_arguments)]
fn follow(
    run: u32,
    id: u64,
    p0: DVec3,
    v: DVec3,
    offset: DVec3,
    t_confirm: f64,
    t_end: f64,
    deleted: bool,
) -> Vec<TrackRow> {
    let at = |t: f64| p0 + v * t + offset;
    let mut rows = vec![track_row(run, id, t_confirm - 0.3, TrackStatus::Tentative, at(t_confirm - 0.3), v)];
    let mut i = 0;
    loop {
        let t = t_confirm + 0.5 * i as f64;
        if t >= t_end - 1e-9 {
            break;
        }
        rows.push(track_row(run, id, t, TrackStatus::Confirmed, at(t), v));
        i += 1;
    }
    if deleted {
        rows.push(track_row(run, id, t_end, TrackStatus::Deleted, at(t_end), v));
    }
    rows
}

#[allow(clippy::too_many_arguments)]
fn dwell(
    run: u32,
    id: u64,
    group: u64,
    radar: u8,
    role: Role,
    kind: DwellKind,
    by: Requester,
    t: f64,
    duration_s: f64,
    energy_j: f64,
) -> DwellRow {
    DwellRow {
        run,
        dwell_id: id,
        group_id: group,
        radar: RadarId(radar),
        role,
        kind,
        requested_by: by,
        t_s: t,
        duration_s,
        pulse_width_s: 10e-6,
        n_pulses: 1,
        peak_power_w: 1e5,
        energy_j,
        waveform: 0,
        face: 0,
        beam_u: 0.0,
        beam_v: 0.0,
        aim_x_m: 0.0,
        aim_y_m: 0.0,
        aim_z_m: 0.0,
    }
}

/// A table to write: named Arrow columns.
#[derive(Clone)]
struct DataFrame(Vec<(String, ArrayRef)>);

impl DataFrame {
    fn new_infer_height(columns: Vec<(String, ArrayRef)>) -> Result<DataFrame, String> {
        Ok(DataFrame(columns))
    }

    fn replace(&mut self, name: &str, column: (String, ArrayRef)) -> Result<(), String> {
        let slot = self.0.iter_mut().find(|(n, _)| n == name).ok_or_else(|| format!("no column {name}"))?;
        slot.1 = column.1;
        Ok(())
    }

    fn drop(mut self, name: &str) -> Result<DataFrame, String> {
        self.0.retain(|(n, _)| n != name);
        Ok(self)
    }
}

/// A vector as an Arrow array.
trait ToArray {
    fn to_array(self) -> ArrayRef;
}
impl ToArray for Vec<u32> {
    fn to_array(self) -> ArrayRef {
        Arc::new(UInt32Array::from(self))
    }
}
impl ToArray for Vec<u64> {
    fn to_array(self) -> ArrayRef {
        Arc::new(UInt64Array::from(self))
    }
}
impl ToArray for Vec<Option<u64>> {
    fn to_array(self) -> ArrayRef {
        Arc::new(UInt64Array::from(self))
    }
}
impl ToArray for Vec<u8> {
    fn to_array(self) -> ArrayRef {
        Arc::new(UInt8Array::from(self))
    }
}
impl ToArray for Vec<i64> {
    fn to_array(self) -> ArrayRef {
        Arc::new(Int64Array::from(self))
    }
}
impl ToArray for Vec<f64> {
    fn to_array(self) -> ArrayRef {
        Arc::new(Float64Array::from(self))
    }
}
impl ToArray for Vec<String> {
    fn to_array(self) -> ArrayRef {
        Arc::new(StringArray::from(self))
    }
}

fn col_of<T: ToArray>(name: &str, v: T) -> (String, ArrayRef) {
    (name.to_string(), v.to_array())
}

fn truth_frame(rows: &[TruthRow]) -> DataFrame {
    macro_rules! c {
        ($f:ident) => {
            col_of(stringify!($f), rows.iter().map(|r| r.$f.clone()).collect::<Vec<_>>())
        };
    }
    DataFrame::new_infer_height(vec![
        c!(run),
        c!(t_s),
        c!(target),
        c!(x_m),
        c!(y_m),
        c!(z_m),
        c!(vx_mps),
        c!(vy_mps),
        c!(vz_mps),
        c!(lat_deg),
        c!(lon_deg),
        c!(alt_m),
        c!(rcs_m2),
    ])
    .expect("truth frame")
}

fn tracks_frame(rows: &[TrackRow]) -> DataFrame {
    macro_rules! c {
        ($f:ident) => {
            col_of(stringify!($f), rows.iter().map(|r| r.$f).collect::<Vec<_>>())
        };
    }
    DataFrame::new_infer_height(vec![
        c!(run),
        c!(t_s),
        c!(track_id),
        col_of("status", rows.iter().map(|r| r.status.as_str().to_string()).collect::<Vec<_>>()),
        c!(x_m),
        c!(y_m),
        c!(z_m),
        c!(vx_mps),
        c!(vy_mps),
        c!(vz_mps),
        ("cov".to_string(), cov_column(rows)),
        c!(n_updates),
        c!(last_meas_id),
    ])
    .expect("tracks frame")
}

fn dwells_frame(rows: &[DwellRow]) -> DataFrame {
    macro_rules! c {
        ($f:ident) => {
            col_of(stringify!($f), rows.iter().map(|r| r.$f).collect::<Vec<_>>())
        };
    }
    DataFrame::new_infer_height(vec![
        c!(run),
        c!(dwell_id),
        c!(group_id),
        col_of("radar", rows.iter().map(|r| r.radar.to_string()).collect::<Vec<_>>()),
        col_of("role", rows.iter().map(|r| r.role.as_str().to_string()).collect::<Vec<_>>()),
        col_of("kind", rows.iter().map(|r| r.kind.as_str().to_string()).collect::<Vec<_>>()),
        col_of("requested_by", rows.iter().map(|r| r.requested_by.as_str().to_string()).collect::<Vec<_>>()),
        c!(t_s),
        c!(duration_s),
        c!(pulse_width_s),
        c!(n_pulses),
        c!(peak_power_w),
        c!(energy_j),
        c!(waveform),
        c!(face),
        c!(beam_u),
        c!(beam_v),
        c!(aim_x_m),
        c!(aim_y_m),
        c!(aim_z_m),
    ])
    .expect("dwells frame")
}

/// The tracks' covariances as the fixed-size list of 21 the table holds.
fn cov_column(rows: &[TrackRow]) -> ArrayRef {
    let values = Float64Array::from_iter_values(rows.iter().flat_map(|r| r.cov));
    let item = Arc::new(Field::new("item", arrow::datatypes::DataType::Float64, false));
    Arc::new(FixedSizeListArray::new(item, 21, Arc::new(values), None))
}

/// Write a frame as a file of the table its directory names (`truth/…`), with that table's name
/// and schema version in the file's metadata.
fn write(path: &Path, df: DataFrame) {
    let dir = path.parent().expect("parent");
    std::fs::create_dir_all(dir).expect("mkdir");
    let table = dir.file_name().expect("table directory").to_string_lossy().to_string();
    let fields: Vec<Field> = df.0.iter().map(|(n, a)| Field::new(n, a.data_type().clone(), true)).collect();
    let metadata = [
        (mimo_store::schema::META_TABLE.to_string(), table),
        (mimo_store::schema::META_SCHEMA_VERSION.to_string(), mimo_store::schema::SCHEMA_VERSION.to_string()),
    ];
    let schema =
        Arc::new(Schema::new(fields).with_metadata(metadata.into_iter().collect::<std::collections::HashMap<_, _>>()));
    let batch = RecordBatch::try_new(schema.clone(), df.0.into_iter().map(|(_, a)| a).collect()).expect("batch");
    let f = File::create(path).expect("create");
    let mut w = parquet::arrow::ArrowWriter::try_new(f, schema, None).expect("writer");
    w.write(&batch).expect("write parquet");
    w.close().expect("close");
}

fn default_dwells() -> Vec<DwellRow> {
    vec![dwell(0, 1, 1, 0, Role::Txrx, DwellKind::Search, Requester::Radar, 0.1, 0.01, 1.0)]
}

/// Write a run directory with the three tables (one file each).
fn run_dir(truth: &[TruthRow], tracks: &[TrackRow], dwells: &[DwellRow]) -> TempDir {
    let dir = tempfile::tempdir().expect("tempdir");
    write(&dir.path().join("truth/part-0000.parquet"), truth_frame(truth));
    write(&dir.path().join("tracks/part-0000.parquet"), tracks_frame(tracks));
    write(&dir.path().join("dwells/part-0000.parquet"), dwells_frame(dwells));
    dir
}

fn score_dir(dir: &TempDir, scorable: ScorablePredicate, opts: &ScoreOptions) -> Result<Score, MetricsError> {
    let input = ScoreInput::from_run_dir(dir.path(), scorable)?;
    score(&input, opts)
}

fn score_case(truth: &[TruthRow], tracks: &[TrackRow]) -> Score {
    let dir = run_dir(truth, tracks, &default_dwells());
    score_dir(&dir, always_scorable(), &ScoreOptions::default()).expect("score")
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

const A0: DVec3 = DVec3::new(6_400_000.0, 0.0, 0.0);
const VA: DVec3 = DVec3::new(0.0, 100.0, 0.0);
const B0: DVec3 = DVec3::new(6_400_000.0, 50_000.0, 0.0);
const VB: DVec3 = DVec3::new(0.0, 0.0, 150.0);

// ---------------------------------------------------------------------------------------------
// Track metrics

#[test]
fn perfect_tracker() {
    let truth = truth_line(0, "A", A0, VA, 0.0, 10.0);
    let tracks = follow(0, 7, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    let s = score_case(&truth, &tracks);
    assert_eq!(s.track_metrics.len(), 10, "scoring times 1..=10");
    for r in &s.track_metrics {
        assert_eq!(r.completeness, Some(1.0), "{r:?}");
        assert_eq!((r.breaks, r.switches, r.n_redundant, r.n_spurious), (0, 0, 0, 0));
        assert!(r.position_rmse_m.expect("rmse") < 1e-6 && r.velocity_rmse_mps.expect("rmse") < 1e-9);
        assert!(r.ospa_m.expect("ospa") < 1e-6);
    }
    let t = &s.summary.track;
    assert_eq!(t.completeness, Some(1.0));
    assert_eq!((t.breaks, t.switches), (0.0, 0.0));
    assert_eq!((t.redundant_ratio, t.spurious_ratio), (Some(0.0), Some(0.0)));
    assert!(t.position_rmse_m.expect("rmse") < 1e-6);
    assert!(t.velocity_rmse_mps.expect("rmse") < 1e-9);
    assert!(s.summary.challenge.met);
}

#[test]
fn drop_and_pick_up_is_one_break_and_one_switch() {
    let truth = truth_line(0, "A", A0, VA, 0.0, 10.0);
    let mut tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 4.5, true);
    tracks.extend(follow(0, 2, A0, VA, DVec3::ZERO, 6.5, 99.0, false));
    let s = score_case(&truth, &tracks);
    let assigned: Vec<bool> = s.track_metrics.iter().map(|r| r.n_assigned == 1).collect();
    assert_eq!(assigned, [true, true, true, true, false, false, true, true, true, true]);
    let breaks: Vec<u32> = s.track_metrics.iter().map(|r| r.breaks).collect();
    let switches: Vec<u32> = s.track_metrics.iter().map(|r| r.switches).collect();
    assert_eq!(breaks, [0, 0, 0, 0, 1, 0, 0, 0, 0, 0]);
    assert_eq!(switches, [0, 0, 0, 0, 0, 0, 1, 0, 0, 0]);
    assert_eq!((s.summary.track.breaks, s.summary.track.switches), (1.0, 1.0));
    assert!(close(s.summary.track.completeness.expect("c"), 0.8));
    assert!(!s.summary.challenge.met);
    // Track ids in the assignment table.
    let ids: Vec<Option<u64>> = s.assignments.iter().map(|a| a.track_id).collect();
    assert_eq!(ids[3], Some(1));
    assert_eq!(ids[4], None);
    assert_eq!(ids[6], Some(2));
}

#[test]
fn two_tracks_on_one_truth_are_redundant() {
    let mut truth = truth_line(0, "A", A0, VA, 0.0, 10.0);
    truth.extend(truth_line(0, "B", B0, VB, 0.0, 10.0));
    let mut tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    tracks.extend(follow(0, 2, A0, VA, DVec3::new(0.0, 0.0, 300.0), 0.5, 99.0, false));
    tracks.extend(follow(0, 3, B0, VB, DVec3::ZERO, 0.5, 99.0, false));
    let s = score_case(&truth, &tracks);
    for r in &s.track_metrics {
        assert_eq!((r.n_scorable, r.n_tracks, r.n_assigned, r.n_redundant, r.n_spurious), (2, 3, 2, 1, 0));
        assert_eq!(r.redundant_ratio, Some(0.5));
    }
    assert_eq!(s.summary.track.redundant_ratio, Some(0.5));
    assert_eq!(s.summary.track.completeness, Some(1.0));
    // The closer track wins the assignment: zero error.
    assert!(s.summary.track.position_rmse_m.expect("rmse") < 1e-6);
}

#[test]
fn far_track_is_spurious() {
    let mut truth = truth_line(0, "A", A0, VA, 0.0, 10.0);
    truth.extend(truth_line(0, "B", B0, VB, 0.0, 10.0));
    let mut tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    tracks.extend(follow(0, 2, B0, VB, DVec3::ZERO, 0.5, 99.0, false));
    tracks.extend(follow(0, 3, A0, VA, DVec3::new(0.0, -80_000.0, 0.0), 0.5, 99.0, false));
    let s = score_case(&truth, &tracks);
    for r in &s.track_metrics {
        assert_eq!((r.n_tracks, r.n_spurious, r.n_redundant), (3, 1, 0));
        assert!(close(r.spurious_ratio.expect("s"), 1.0 / 3.0));
    }
    assert!(close(s.summary.track.spurious_ratio.expect("s"), 1.0 / 3.0));
    assert_eq!(s.summary.track.completeness, Some(1.0));
}

#[test]
fn unscorable_truth_does_not_lower_completeness() {
    let mut truth = truth_line(0, "A", A0, VA, 0.0, 10.0);
    truth.extend(truth_line(0, "B", B0, VB, 0.0, 10.0));
    // A is tracked. B is seen by no radar, yet someone holds a track on it: not scorable, and the
    // track on it is neither spurious nor redundant.
    let mut tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    tracks.extend(follow(0, 2, B0, VB, DVec3::new(100.0, 0.0, 0.0), 0.5, 99.0, false));
    let dir = run_dir(&truth, &tracks, &default_dwells());
    let only_a: ScorablePredicate = Box::new(|_, p: DVec3, _| p.y < 20_000.0);
    let s = score_dir(&dir, only_a, &ScoreOptions::default()).expect("score");
    for r in &s.track_metrics {
        assert_eq!((r.n_truths, r.n_scorable, r.n_assigned, r.n_tracks), (2, 1, 1, 2));
        assert_eq!((r.n_spurious, r.n_redundant), (0, 0));
        assert_eq!(r.completeness, Some(1.0));
    }
    assert_eq!(s.summary.track.completeness, Some(1.0));
    assert_eq!(s.summary.per_target.get("B").expect("B").scorable_times, 0);
    assert_eq!(s.summary.per_target.get("B").expect("B").completeness, None);
    // Nothing scorable at all: completeness is undefined (null), never 0 or 1.
    let none: ScorablePredicate = Box::new(|_, _, _| false);
    let s = score_dir(&dir, none, &ScoreOptions::default()).expect("score");
    assert!(s.track_metrics.iter().all(|r| r.completeness.is_none() && r.redundant_ratio.is_none()));
    assert_eq!(s.summary.track.completeness, None);
    assert!(!s.summary.challenge.met);
    let json = s.summary_json().expect("json");
    assert!(json.contains("\"completeness\": null"), "{json}");
}

#[test]
fn crossing_truths_whose_tracks_swap_count_two_switches() {
    // A flies +y, B flies −y, 50 m apart in x; they pass at t = 10 s.
    let a0 = DVec3::new(6_400_000.0, -1000.0, 0.0);
    let b0 = DVec3::new(6_400_050.0, 1000.0, 0.0);
    let (va, vb) = (DVec3::new(0.0, 100.0, 0.0), DVec3::new(0.0, -100.0, 0.0));
    let mut truth = truth_line(0, "A", a0, va, 0.0, 20.0);
    truth.extend(truth_line(0, "B", b0, vb, 0.0, 20.0));
    // Track 1 follows A, then from t = 10 follows B; track 2 the other way round.
    let mut tracks = Vec::new();
    for i in 0..40 {
        let t = 0.5 + 0.5 * i as f64;
        let st = TrackStatus::Confirmed;
        let (p1, v1, p2, v2) =
            if t < 10.0 { (a0 + va * t, va, b0 + vb * t, vb) } else { (b0 + vb * t, vb, a0 + va * t, va) };
        tracks.push(track_row(0, 1, t, st, p1, v1));
        tracks.push(track_row(0, 2, t, st, p2, v2));
    }
    let s = score_case(&truth, &tracks);
    let switches: Vec<u32> = s.track_metrics.iter().map(|r| r.switches).collect();
    assert_eq!(switches[9], 2, "both truths switch at t = 10: {switches:?}");
    assert_eq!(switches.iter().sum::<u32>(), 2);
    assert_eq!(s.summary.track.switches, 2.0);
    assert_eq!(s.summary.track.breaks, 0.0);
    assert_eq!(s.summary.per_target.get("A").expect("A").switches, 1.0);
    assert_eq!(s.summary.track.completeness, Some(1.0));
}

#[test]
fn ospa_and_gospa_hand_case() {
    // A tracked with a 30 m offset, B untracked, one track 80 km from everything. c = 100, p = 2:
    // OSPA = sqrt((30² + 100²)/2), GOSPA = sqrt(30² + 100²/2 + 100²/2).
    let mut truth = truth_line(0, "A", A0, VA, 0.0, 5.0);
    truth.extend(truth_line(0, "B", B0, VB, 0.0, 5.0));
    let mut tracks = follow(0, 1, A0, VA, DVec3::new(0.0, 0.0, 30.0), 0.5, 99.0, false);
    tracks.extend(follow(0, 2, A0, VA, DVec3::new(80_000.0, 0.0, 0.0), 0.5, 99.0, false));
    let dir = run_dir(&truth, &tracks, &default_dwells());
    let opts = ScoreOptions { ospa_c_m: 100.0, ospa_p: 2.0, ..ScoreOptions::default() };
    let s = score_dir(&dir, always_scorable(), &opts).expect("score");
    let ospa = (5450.0f64).sqrt();
    let gospa = (10_900.0f64).sqrt();
    for r in &s.track_metrics {
        assert!(close(r.ospa_m.expect("ospa"), ospa), "{r:?}");
        assert!(close(r.gospa_m.expect("gospa"), gospa), "{r:?}");
        assert!(close(r.position_rmse_m.expect("rmse"), 30.0));
        assert_eq!(r.completeness, Some(0.5));
    }
    assert!(close(s.summary.ospa.mean_m.expect("ospa"), ospa));
    assert!(close(s.summary.gospa.mean_m.expect("gospa"), gospa));
    assert_eq!(s.summary.gospa.alpha, Some(2.0));
}

#[test]
fn track_lifetime_rules() {
    let truth = truth_line(0, "A", A0, VA, 0.0, 10.0);
    // Track 1 is only ever tentative: never counts. Track 2 is confirmed at 3.0 exactly (counts
    // at t = 3), deleted at 6.0 exactly (not counted at t = 6), and has a stale state from 3.0
    // that must be extrapolated (no further updates).
    let mut tracks = vec![
        track_row(0, 1, 0.5, TrackStatus::Tentative, A0 + VA * 0.5, VA),
        track_row(0, 1, 5.5, TrackStatus::Tentative, A0 + VA * 5.5, VA),
    ];
    tracks.push(track_row(0, 2, 2.0, TrackStatus::Tentative, A0 + VA * 2.0, VA));
    tracks.push(track_row(0, 2, 3.0, TrackStatus::Confirmed, A0 + VA * 3.0, VA));
    tracks.push(track_row(0, 2, 6.0, TrackStatus::Deleted, A0 + VA * 6.0, VA));
    // Rows after deletion are ignored.
    tracks.push(track_row(0, 2, 7.0, TrackStatus::Confirmed, A0 + VA * 7.0, VA));
    let s = score_case(&truth, &tracks);
    let live: Vec<u32> = s.track_metrics.iter().map(|r| r.n_tracks).collect();
    assert_eq!(live, [0, 0, 1, 1, 1, 0, 0, 0, 0, 0]);
    assert!(s.summary.track.position_rmse_m.expect("rmse") < 1e-6, "constant-velocity extrapolation is exact");
    // No tracks at all: spurious ratio undefined, completeness 0.
    let s = score_case(&truth, &[]);
    assert!(s.track_metrics.iter().all(|r| r.spurious_ratio.is_none() && r.completeness == Some(0.0)));
    assert_eq!(s.summary.track.spurious_ratio, None);
    assert_eq!(s.summary.track.completeness, Some(0.0));
    assert_eq!(s.summary.track.position_rmse_m, None);
    assert!(s.track_metrics.iter().all(|r| close(r.ospa_m.expect("ospa"), 1000.0)));
}

#[test]
fn maximum_cardinality_assignment() {
    // Track 1 is 10 m from A and 900 m from B; track 2 is 950 m from A and far from B. A pure
    // minimum-distance pairing with a miss cost of one gate would take A–1 and leave B out;
    // maximum cardinality pairs A–2 and B–1.
    let a0 = DVec3::new(6_400_000.0, 0.0, 0.0);
    let b0 = DVec3::new(6_400_000.0, 910.0, 0.0);
    let v = DVec3::new(0.0, 0.0, 100.0);
    let mut truth = truth_line(0, "A", a0, v, 0.0, 3.0);
    truth.extend(truth_line(0, "B", b0, v, 0.0, 3.0));
    let mut tracks = follow(0, 1, a0, v, DVec3::new(0.0, 10.0, 0.0), 0.5, 99.0, false);
    tracks.extend(follow(0, 2, a0, v, DVec3::new(0.0, -950.0, 0.0), 0.5, 99.0, false));
    let s = score_case(&truth, &tracks);
    for r in &s.track_metrics {
        assert_eq!(r.n_assigned, 2);
    }
    let a = s.assignments.iter().find(|a| a.target == "A").expect("A");
    assert_eq!(a.track_id, Some(2));
}

// ---------------------------------------------------------------------------------------------
// Usage

#[test]
fn usage_by_hand() {
    // Two runs with the same truth; run 1 has no dwell at all (so every mean over runs halves).
    // A (x < 1e6… here y < 20 km) is scorable except at t = 3; B only up to t = 1.
    // Scorable counts at t = 1, 2, 3, 4: N = 2, 1, 0, 1.
    let mut truth = Vec::new();
    for run in 0..2 {
        truth.extend(truth_line(run, "A", A0, VA, 0.0, 4.0));
        truth.extend(truth_line(run, "B", B0, VB, 0.0, 4.0));
    }
    use DwellKind::*;
    use Requester::*;
    use Role::*;
    let dwells = vec![
        dwell(0, 1, 1, 0, Txrx, Search, Radar, 0.2, 0.01, 1.0),
        dwell(0, 2, 2, 0, Txrx, Track, Ta, 0.5, 0.02, 2.0),
        // A MIMO dwell: R1 transmits only, R3 transmits and receives, R2 and R4 only receive
        // (their rows carry the dwell's duration but cost nothing).
        dwell(0, 3, 3, 0, Tx, Mimo, Ta, 1.5, 0.03, 3.0),
        dwell(0, 4, 3, 1, Rx, Mimo, Ta, 1.5, 0.03, 0.0),
        dwell(0, 5, 3, 2, Txrx, Mimo, Ta, 1.5, 0.03, 4.0),
        dwell(0, 6, 3, 3, Rx, Mimo, Ta, 1.5, 0.03, 0.0),
        // Interval 3 has no scorable object.
        dwell(0, 7, 7, 1, Txrx, Search, Radar, 2.5, 0.05, 5.0),
        dwell(0, 8, 8, 0, Txrx, Track, Ta, 3.5, 0.04, 6.0),
        // After the last scoring time (4 s): only in the sensor totals.
        dwell(0, 9, 9, 1, Txrx, Search, Radar, 4.5, 0.01, 7.0),
    ];
    let dir = tempfile::tempdir().expect("tempdir");
    write(&dir.path().join("truth/part-0000.parquet"), truth_frame(&truth));
    write(&dir.path().join("tracks/part-0000.parquet"), tracks_frame(&[]));
    write(&dir.path().join("dwells/part-0000.parquet"), dwells_frame(&dwells));
    write(&dir.path().join("dwells/part-0001.parquet"), dwells_frame(&[]));
    let pred: ScorablePredicate =
        Box::new(|t, p: DVec3, _| if p.y < 20_000.0 { (t - 3.0).abs() > 0.01 } else { t <= 1.01 });
    let opts = ScoreOptions { scenario: "hand".into(), ..ScoreOptions::default() };
    let s = score_dir(&dir, pred, &opts).expect("score");

    let n: Vec<u32> = s.track_metrics.iter().filter(|r| r.run == 0).map(|r| r.n_scorable).collect();
    assert_eq!(n, [2, 1, 0, 1]);
    assert_eq!(s.radars, ["R1", "R2", "R3", "R4"]);
    let row = |radar: &str, j: u32| s.usage.iter().find(|u| u.radar == radar && u.interval == j).expect("row");
    let approx = |a: f64, b: f64| (a - b).abs() < 1e-12;
    let approx_opt = |a: Option<f64>, b: f64| a.is_some_and(|a| approx(a, b));

    // R1, interval 1: 0.01 + 0.02 s and 1 + 2 J in run 0, N = 2; halved by run 1.
    let r = row("R1", 1);
    assert!(approx(r.dwell_time_s, 0.015) && approx(r.energy_j, 1.5));
    assert!(approx(r.ta_dwell_time_s, 0.01) && approx(r.ta_energy_j, 1.0));
    assert!(approx_opt(r.dwell_time_per_object_s, 0.0075) && approx_opt(r.energy_per_object_j, 0.75));
    assert!(approx_opt(r.ta_dwell_time_per_object_s, 0.005) && approx_opt(r.ta_energy_per_object_j, 0.5));
    // R1, interval 2 (MIMO tx): N = 1.
    let r = row("R1", 2);
    assert!(
        approx(r.energy_j, 1.5) && approx_opt(r.energy_per_object_j, 1.5) && approx_opt(r.ta_energy_per_object_j, 1.5)
    );
    // Receive-only participation costs nothing.
    for j in 1..=4 {
        let r = row("R4", j);
        assert!(r.dwell_time_s == 0.0 && r.energy_j == 0.0 && r.energy_per_object_j == Some(0.0) || j == 3);
    }
    assert!(approx(row("R2", 2).dwell_time_s, 0.0));
    assert!(approx(row("R3", 2).dwell_time_s, 0.015) && approx(row("R3", 2).energy_j, 2.0));
    // Interval 3: nothing scorable → normalized null, raw still reported.
    let r = row("R2", 3);
    assert!(approx(r.dwell_time_s, 0.025) && approx(r.energy_j, 2.5));
    assert_eq!((r.dwell_time_per_object_s, r.energy_per_object_j), (None, None));
    assert_eq!(row("R1", 3).energy_per_object_j, None);
    // Cumulative.
    assert!(approx(row("R1", 4).cum_energy_j, 6.0) && approx(row("R1", 4).cum_dwell_time_s, 0.05));
    assert!(approx(row("R1", 4).cum_ta_energy_j, 5.5));
    // Totals over radars per interval.
    let tot2 = s.usage_total.iter().find(|u| u.interval == 2).expect("total");
    assert!(approx(tot2.energy_j, 3.5) && approx_opt(tot2.energy_per_object_j, 3.5));
    let tot3 = s.usage_total.iter().find(|u| u.interval == 3).expect("total");
    assert!(approx(tot3.energy_j, 2.5) && tot3.energy_per_object_j.is_none());
    // Sensor totals over the whole run (including the dwell after the last scoring time),
    // averaged over the two runs.
    let u = &s.summary.usage;
    let pr = |r: &str| u.per_radar.get(r).expect("radar");
    assert!(approx(pr("R1").dwell_time_s, 0.05) && approx(pr("R1").energy_j, 6.0));
    assert!(approx(pr("R1").ta_dwell_time_s, 0.045) && approx(pr("R1").ta_energy_j, 5.5));
    assert!(approx(pr("R2").dwell_time_s, 0.03) && approx(pr("R2").energy_j, 6.0) && pr("R2").ta_energy_j == 0.0);
    assert!(approx(pr("R3").energy_j, 2.0) && approx(pr("R3").ta_energy_j, 2.0));
    // Per scorable object over the run: run 0 spends 3 J on N = 2, 7 J on N = 1, (5 J on N = 0:
    // left out) and 6 J on N = 1: 14.5 J, of which the test article's 1 + 7 + 6 = 14 J; its dwell
    // time 0.03/2 + 0.06 + 0.04 = 0.115 s (its own 0.02/2 + 0.06 + 0.04). Run 1 spends nothing: 0.
    let r0 = &s.summary.per_run[0].usage;
    assert!(approx_opt(r0.energy_per_object_j, 14.5) && approx_opt(r0.ta_energy_per_object_j, 14.0));
    assert!(approx_opt(r0.dwell_time_per_object_s, 0.115) && approx_opt(r0.ta_dwell_time_per_object_s, 0.11));
    assert_eq!(s.summary.per_run[1].usage.energy_per_object_j, Some(0.0));
    assert!(approx_opt(u.totals.energy_per_object_j, 7.25) && approx_opt(u.totals.dwell_time_per_object_s, 0.0575));
    // No track at all: every (run, target) scorable at some time is never tracked.
    let ft = s.summary.first_track;
    assert_eq!((ft.targets, ft.never_tracked, ft.mean_s, ft.max_s), (4, 4, None, None));
    assert!(s.first_track.iter().all(|r| r.first_track_s.is_none() && r.scorable_from_s == 1.0));
    assert!(pr("R4").energy_j == 0.0 && pr("R4").dwell_time_s == 0.0);
    assert!(approx(u.totals.total_dwell_time_s, 0.095) && approx(u.totals.total_energy_j, 14.0));
    assert!(approx(u.totals.ta_dwell_time_s, 0.06) && approx(u.totals.ta_energy_j, 7.5));
    let run0 = &s.summary.per_run[0];
    assert!(approx(run0.usage.total_energy_j, 28.0) && approx(run0.usage.ta_energy_j, 15.0));
    assert_eq!(s.summary.per_run[1].usage.total_energy_j, 0.0);
}

// ---------------------------------------------------------------------------------------------
// Outputs

#[test]
fn writes_outputs_with_the_design_keys() {
    let truth = truth_line(0, "A", A0, VA, 0.0, 5.0);
    let tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    let dir = run_dir(&truth, &tracks, &default_dwells());
    let opts = ScoreOptions { scenario: "s1".into(), radars: vec!["R1".into(), "R2".into()], ..Default::default() };
    let s = score_dir(&dir, always_scorable(), &opts).expect("score");
    let out = dir.path().join("score");
    mimo_metrics::write_outputs(&s, &out).expect("write");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).expect("read")).expect("json");
    for key in ["scenario", "runs", "interval_s", "gate_m", "track", "usage", "challenge"] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    for key in [
        "completeness",
        "redundant_ratio",
        "spurious_ratio",
        "breaks",
        "switches",
        "position_rmse_m",
        "velocity_rmse_mps",
    ] {
        assert!(json["track"].get(key).is_some(), "missing track.{key}");
    }
    for key in ["per_radar", "total_dwell_time_s", "total_energy_j", "ta_dwell_time_s", "ta_energy_j"] {
        assert!(json["usage"].get(key).is_some(), "missing usage.{key}");
    }
    for key in ["dwell_time_s", "energy_j", "ta_dwell_time_s", "ta_energy_j"] {
        assert!(json["usage"]["per_radar"]["R2"].get(key).is_some(), "missing usage.per_radar.R2.{key}");
    }
    assert_eq!(json["scenario"], "s1");
    assert_eq!(json["runs"], 1);
    assert_eq!(json["challenge"]["completeness_required"], 0.98);
    assert_eq!(json["challenge"]["met"], true);
    assert_eq!(json["track"]["completeness"], 1.0);
    for spec in mimo_store::score_schema::SCORE_TABLES {
        let file = out.join(mimo_store::score_schema::score_file_name(&spec));
        let reader =
            parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(File::open(&file).expect("open"))
                .expect("parquet");
        assert!(reader.metadata().file_metadata().num_rows() > 0, "{} is empty", spec.name);
        // The columns are the spec's, in its order, and the file carries the units.
        let names: Vec<&str> = reader.schema().fields().iter().map(|f| f.name().as_str()).collect();
        let want: Vec<&str> = spec.columns.iter().map(|c| c.name).collect();
        assert_eq!(names, want, "{}", spec.name);
        let arrow =
            parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(File::open(&file).expect("open"))
                .expect("parquet")
                .schema()
                .clone();
        for c in spec.columns {
            let field = arrow.field_with_name(c.name).expect("field");
            assert_eq!(field.metadata().get("unit").map(String::as_str), Some(c.unit), "{}.{}", spec.name, c.name);
            assert_eq!(field.is_nullable(), c.nullable, "{}.{}", spec.name, c.name);
        }
    }
    let tm = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(
        File::open(out.join("track_metrics.parquet")).expect("open"),
    )
    .expect("parquet");
    assert_eq!(tm.metadata().file_metadata().num_rows(), 5);
    assert_eq!(
        tm.schema().field_with_name("completeness").expect("col").data_type(),
        &arrow::datatypes::DataType::Float64
    );
}

#[test]
fn reads_tables_written_by_mimo_store() {
    // The real writer adds a fixed-size-list covariance and a u8 face column, which the metrics
    // never read; scoring must not trip over them.
    let dir = tempfile::tempdir().expect("tempdir");
    let truth = truth_line(0, "A", A0, VA, 0.0, 5.0);
    let tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    mimo_store::write_table(&dir.path().join("truth/run-0000.parquet"), &truth).expect("truth");
    mimo_store::write_table(&dir.path().join("tracks/run-0000.parquet"), &tracks).expect("tracks");
    mimo_store::write_table(&dir.path().join("dwells/run-0000.parquet"), &default_dwells()).expect("dwells");
    let s = score_dir(&dir, always_scorable(), &ScoreOptions::default()).expect("score");
    assert_eq!(s.summary.track.completeness, Some(1.0));
    assert!((s.summary.usage.totals.total_energy_j - 1.0).abs() < 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Bad input

#[test]
fn missing_tracks_table() {
    let dir = run_dir(&truth_line(0, "A", A0, VA, 0.0, 2.0), &[], &default_dwells());
    std::fs::remove_dir_all(dir.path().join("tracks")).expect("rm");
    let e = score_dir(&dir, always_scorable(), &ScoreOptions::default()).expect_err("must fail");
    assert!(matches!(e, MetricsError::MissingTable { table: "tracks", .. }), "{e}");
    let msg = e.to_string();
    assert!(msg.contains("tracks") && msg.contains("does not exist"), "{msg}");
    assert!(e.is_bad_input());
    // An explicitly listed file that is absent.
    let input = ScoreInput {
        truth: vec![dir.path().join("truth/part-0000.parquet")],
        dwells: vec![dir.path().join("dwells/part-0000.parquet")],
        tracks: vec![dir.path().join("tracks/part-0000.parquet")],
        scorable: always_scorable(),
        beams: mimo_metrics::BeamGeometry::none(),
    };
    let e = score(&input, &ScoreOptions::default()).expect_err("must fail");
    assert!(matches!(e, MetricsError::MissingTable { table: "tracks", .. }), "{e}");
}

#[test]
fn tracks_with_a_wrong_column_type() {
    let dir = run_dir(&truth_line(0, "A", A0, VA, 0.0, 2.0), &[], &default_dwells());
    let tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    let mut df = tracks_frame(&tracks);
    let t_str: Vec<String> = tracks.iter().map(|r| r.t_s.to_string()).collect();
    df.replace("t_s", col_of("t_s", t_str)).expect("replace");
    let path = dir.path().join("tracks/part-0000.parquet");
    write(&path, df);
    let e = score_dir(&dir, always_scorable(), &ScoreOptions::default()).expect_err("must fail");
    assert!(e.is_bad_input());
    match &e {
        MetricsError::Table(StoreError::BadColumn { file, column, why }) => {
            assert_eq!((file, column.as_str()), (&path, "t_s"));
            assert_eq!(why, "has type Utf8, expected float64");
        }
        other => panic!("wrong error: {other}"),
    }
}

/// The message of a store check's refusal of a column (panics on another error).
fn bad_column(e: &MetricsError) -> (String, String) {
    match e {
        MetricsError::Table(StoreError::BadColumn { column, why, .. }) => (column.clone(), why.clone()),
        other => panic!("not a bad column: {other}"),
    }
}

#[test]
fn other_bad_input() {
    let truth = truth_line(0, "A", A0, VA, 0.0, 2.0);
    let tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    let fails = |truth: DataFrame, tracks: DataFrame, dwells: DataFrame| {
        let dir = tempfile::tempdir().expect("tempdir");
        write(&dir.path().join("truth/part-0000.parquet"), truth);
        write(&dir.path().join("tracks/part-0000.parquet"), tracks);
        write(&dir.path().join("dwells/part-0000.parquet"), dwells);
        score_dir(&dir, always_scorable(), &ScoreOptions::default()).expect_err("must fail")
    };
    // NaN in a truth position.
    let mut bad = truth.clone();
    bad[7].y_m = f64::NAN;
    let e = fails(truth_frame(&bad), tracks_frame(&tracks), dwells_frame(&default_dwells()));
    assert_eq!(bad_column(&e), ("y_m".into(), "is NaN at row 7 (expected a finite number)".into()));
    // NaN in a track velocity.
    let mut bad = tracks.clone();
    bad[2].vz_mps = f64::NAN;
    let e = fails(truth_frame(&truth), tracks_frame(&bad), dwells_frame(&default_dwells()));
    assert_eq!(bad_column(&e), ("vz_mps".into(), "is NaN at row 2 (expected a finite number)".into()));
    // Missing column.
    let e =
        fails(truth_frame(&truth).drop("alt_m").expect("drop"), tracks_frame(&tracks), dwells_frame(&default_dwells()));
    assert_eq!(bad_column(&e), ("alt_m".into(), "missing (expected float64)".into()));
    // Unknown status.
    let mut df = tracks_frame(&tracks);
    let st: Vec<String> = (0..tracks.len()).map(|i| if i == 3 { "lost".into() } else { "confirmed".into() }).collect();
    df.replace("status", col_of("status", st)).expect("replace");
    let e = fails(truth_frame(&truth), df, dwells_frame(&default_dwells()));
    let (column, why) = bad_column(&e);
    assert_eq!(column, "status");
    assert!(why.starts_with("is 'lost' at row 3"), "{why}");
    // Negative energy, bad radar id.
    let mut d = default_dwells();
    d[0].energy_j = -1.0;
    let e = fails(truth_frame(&truth), tracks_frame(&tracks), dwells_frame(&d));
    assert_eq!(bad_column(&e), ("energy_j".into(), "is -1 at row 0 (expected a finite number >= 0)".into()));
    let mut df = dwells_frame(&default_dwells());
    df.replace("radar", col_of("radar", vec!["Radar-1".to_string()])).expect("replace");
    let e = fails(truth_frame(&truth), tracks_frame(&tracks), df);
    assert_eq!(bad_column(&e).0, "radar");
    // A track of a run the truth does not have.
    let mut bad = tracks.clone();
    bad[0].run = 5;
    let e = fails(truth_frame(&truth), tracks_frame(&bad), dwells_frame(&default_dwells()));
    assert!(matches!(e, MetricsError::InvalidValue { table: "tracks", column: "run", .. }), "{e}");
    // Options.
    let dir = run_dir(&truth, &tracks, &default_dwells());
    let e = score_dir(&dir, always_scorable(), &ScoreOptions { interval_s: 0.0, ..Default::default() })
        .expect_err("must fail");
    assert!(matches!(e, MetricsError::InvalidOption { option: "interval_s", .. }), "{e}");
}

/// A table of other integer widths (as pandas and pyarrow write ids and runs) is not the table
/// its metadata names: refused, naming the column, rather than converted.
#[test]
fn integer_widths_from_other_writers_are_refused() {
    let truth = truth_line(0, "A", A0, VA, 0.0, 3.0);
    let tracks = follow(0, 1, A0, VA, DVec3::ZERO, 0.5, 99.0, false);
    let mut tdf = tracks_frame(&tracks);
    let ids: Vec<i64> = tracks.iter().map(|r| r.track_id as i64).collect();
    tdf.replace("track_id", col_of("track_id", ids)).expect("replace");
    let dir = tempfile::tempdir().expect("tempdir");
    write(&dir.path().join("truth/part-0000.parquet"), truth_frame(&truth));
    write(&dir.path().join("tracks/part-0000.parquet"), tdf);
    write(&dir.path().join("dwells/part-0000.parquet"), dwells_frame(&default_dwells()));
    let e = score_dir(&dir, always_scorable(), &ScoreOptions::default()).expect_err("must fail");
    assert_eq!(bad_column(&e), ("track_id".into(), "has type Int64, expected uint64".into()));
}

/// Usage is computed file by file (docs/design.md §6): one file per run, a run split over
/// several files and every run in one file give the same figures, and they agree with sums over
/// the rows computed here by hand (eqs. 1–6).
#[test]
fn usage_does_not_depend_on_how_the_dwells_are_split_into_files() {
    use DwellKind::*;
    use Requester::*;
    use Role::*;
    let runs = 3u32;
    let mut truth = Vec::new();
    for run in 0..runs {
        truth.extend(truth_line(run, "A", A0, VA, 0.0, 20.0));
        truth.extend(truth_line(run, "B", B0, VB, 0.0, 12.0));
    }
    // Pseudo-random dwells (a fixed LCG), every role, kind and requester, some after the end.
    let mut state = 12345u64;
    let mut next = || {
        state = state.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut per_run: Vec<Vec<DwellRow>> = Vec::new();
    for run in 0..runs {
        let mut rows = Vec::new();
        let mut t = 0.0;
        for id in 0..2000u64 {
            t += 0.011 * next();
            let radar = (next() * 4.0) as u8;
            let role = [Tx, Rx, Txrx][(next() * 3.0) as usize];
            let (kind, by) = [(Search, Radar), (Track, Ta), (Confirm, Ta), (Mimo, Ta)][(next() * 4.0) as usize];
            let energy = if role == Rx { 0.0 } else { 100.0 * next() };
            rows.push(dwell(run, id, id, radar, role, kind, by, t, 0.001 + 0.01 * next(), energy));
        }
        per_run.push(rows);
    }
    let opts = ScoreOptions { scenario: "split".into(), ..ScoreOptions::default() };
    let score_with = |files: Vec<Vec<DwellRow>>| -> Score {
        let dir = tempfile::tempdir().expect("tempdir");
        write(&dir.path().join("truth/part-0000.parquet"), truth_frame(&truth));
        write(&dir.path().join("tracks/part-0000.parquet"), tracks_frame(&[]));
        for (i, rows) in files.iter().enumerate() {
            write(&dir.path().join(format!("dwells/part-{i:04}.parquet")), dwells_frame(rows));
        }
        score_dir(&dir, always_scorable(), &opts).expect("score")
    };
    let one_per_run = score_with(per_run.clone());
    let all_in_one = score_with(vec![per_run.concat()]);
    // Each run in two files, split where a scoring interval starts (so that no sum is split).
    let halves = score_with(
        per_run
            .iter()
            .flat_map(|r| {
                let cut = r.iter().position(|d| d.t_s >= 10.0).unwrap_or(r.len());
                [r[..cut].to_vec(), r[cut..].to_vec()]
            })
            .collect(),
    );
    // The per-interval figures are the same numbers; the sensor totals sum the intervals in the
    // order their sums come out, so they may differ in the last bits.
    for other in [&all_in_one, &halves] {
        assert_eq!(one_per_run.usage, other.usage);
        assert_eq!(one_per_run.usage_total, other.usage_total);
        assert_eq!(one_per_run.usage_radar.len(), other.usage_radar.len());
        for (a, b) in one_per_run.usage_radar.iter().zip(&other.usage_radar) {
            assert_eq!(a.radar, b.radar);
            for (x, y) in [(a.dwell_time_s, b.dwell_time_s), (a.energy_j, b.energy_j), (a.ta_energy_j, b.ta_energy_j)] {
                assert!((x - y).abs() <= 1e-12 * y.abs(), "{a:?} {b:?}");
            }
        }
    }
    // By hand: raw sums per radar and interval averaged over runs, and the normalized figures.
    let rel = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-9);
    let s = &one_per_run;
    assert!(!s.usage.is_empty());
    for u in &s.usage {
        let (mut time, mut energy, mut ta_energy, mut norm) = (0.0, 0.0, 0.0, 0.0);
        let mut defined = 0;
        for (run, rows) in per_run.iter().enumerate() {
            let sel = rows.iter().filter(|d| {
                d.radar.to_string() == u.radar && d.role != Rx && (d.t_s / opts.interval_s) as u32 + 1 == u.interval
            });
            let (t, e, te) = sel.fold((0.0, 0.0, 0.0), |(t, e, te), d| {
                (t + d.duration_s, e + d.energy_j, te + if d.requested_by == Ta { d.energy_j } else { 0.0 })
            });
            time += t;
            energy += e;
            ta_energy += te;
            let n =
                s.track_metrics.iter().find(|m| m.run == run as u32 && m.k == u.interval).map_or(0, |m| m.n_scorable);
            if n > 0 {
                norm += e / f64::from(n);
                defined += 1;
            }
        }
        let k = f64::from(runs);
        assert!(rel(u.dwell_time_s, time / k), "{u:?}");
        assert!(rel(u.energy_j, energy / k), "{u:?}");
        assert!(rel(u.ta_energy_j, ta_energy / k), "{u:?}");
        match u.energy_per_object_j {
            Some(v) => assert!(rel(v, norm / f64::from(defined)), "{u:?}"),
            None => assert_eq!(defined, 0),
        }
    }
    for r in &s.usage_radar {
        let e: f64 = per_run
            .iter()
            .flatten()
            .filter(|d| d.radar.to_string() == r.radar && d.role != Rx)
            .map(|d| d.energy_j)
            .sum();
        assert!(rel(r.energy_j, e / f64::from(runs)), "{r:?}");
    }
}

/// The track metrics are the same however truth and tracks are spread over files: one file per
/// run (scored part by part, one run at a time), everything in one file (scored at once), and a
/// mix of files sharing runs, with an empty tracks file, and a target (`C`) that only one run
/// has. The summary's per-target tallies merge the parts by name.
#[test]
fn track_metrics_do_not_depend_on_how_truth_and_tracks_are_split_into_files() {
    let c0 = DVec3::new(6_400_000.0, -30_000.0, 0.0);
    let runs = 4u32;
    let mut truth: Vec<Vec<TruthRow>> = Vec::new();
    let mut tracks: Vec<Vec<TrackRow>> = Vec::new();
    for run in 0..runs {
        let mut t = truth_line(run, "A", A0, VA, 0.0, 20.0);
        let mut k = follow(run, 1, A0, VA, DVec3::new(30.0, 0.0, 0.0), 1.0, 20.0, false);
        if run < 3 {
            t.extend(truth_line(run, "B", B0, VB, 0.0, 15.0));
            // Run r's track on B drops at 6 + r s and a new one picks it up 2 s later.
            let cut = 6.0 + f64::from(run);
            k.extend(follow(run, 2, B0, VB, DVec3::ZERO, 2.0, cut, true));
            k.extend(follow(run, 3, B0, VB, DVec3::new(0.0, 50.0, 0.0), cut + 2.0, 15.0, false));
        } else {
            t.extend(truth_line(run, "C", c0, VB, 0.0, 12.0));
            k.extend(follow(run, 4, c0, VB, DVec3::ZERO, 4.0, 12.0, false));
        }
        truth.push(t);
        tracks.push(k);
    }
    let opts = ScoreOptions { scenario: "split".into(), ..ScoreOptions::default() };
    // Files as lists of runs: (truth files, tracks files).
    let score_with = |truth_files: &[&[u32]], tracks_files: &[&[u32]]| -> Score {
        let dir = tempfile::tempdir().expect("tempdir");
        let pick = |rows: &[Vec<TruthRow>], f: &[u32]| f.iter().flat_map(|&r| rows[r as usize].clone()).collect();
        for (i, f) in truth_files.iter().enumerate() {
            let rows: Vec<TruthRow> = pick(&truth, f);
            write(&dir.path().join(format!("truth/part-{i:04}.parquet")), truth_frame(&rows));
        }
        for (i, f) in tracks_files.iter().enumerate() {
            let rows: Vec<TrackRow> = f.iter().flat_map(|&r| tracks[r as usize].clone()).collect();
            write(&dir.path().join(format!("tracks/part-{i:04}.parquet")), tracks_frame(&rows));
        }
        write(&dir.path().join("dwells/part-0000.parquet"), dwells_frame(&default_dwells()));
        score_dir(&dir, always_scorable(), &opts).expect("score")
    };
    let one_per_run = score_with(&[&[0], &[1], &[2], &[3]], &[&[0], &[1], &[2], &[3]]);
    let all_in_one = score_with(&[&[0, 1, 2, 3]], &[&[0, 1, 2, 3]]);
    let mixed = score_with(&[&[3], &[0, 1], &[2]], &[&[], &[1, 2], &[3], &[0]]);
    for other in [&all_in_one, &mixed] {
        assert_eq!(one_per_run.runs, other.runs);
        assert_eq!(one_per_run.track_metrics, other.track_metrics);
        assert_eq!(one_per_run.track_metrics_mean, other.track_metrics_mean);
        assert_eq!(one_per_run.assignments, other.assignments);
        assert_eq!(one_per_run.summary, other.summary);
    }
    // The hand count: runs 0–2 each break B once and switch it once; C is run 3's alone.
    let s = &one_per_run.summary;
    assert_eq!(one_per_run.runs, vec![0, 1, 2, 3]);
    let names: Vec<&str> = s.per_target.0.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["A", "B", "C"]);
    let b = &s.per_target.0[1].1;
    assert!(close(b.breaks, 3.0 / 4.0) && close(b.switches, 3.0 / 4.0), "B: {b:?}");
    let c = &s.per_target.0[2].1;
    assert_eq!(c.scorable_times, 12);
}
