//! Round trips of every table, the schema check against `schemas/`, and bad-input errors.

use mimo_core::ids::RadarId;
use mimo_core::records::*;
use mimo_store::manifest::{Manifest, ScenarioInfo};
use mimo_store::rundir::RunDirWriter;
use mimo_store::{StoreError, read_table, write_table};
use std::path::Path;

fn truth() -> Vec<TruthRow> {
    (0..5)
        .map(|i| TruthRow {
            run: 1,
            t_s: i as f64 * 0.1,
            target: if i % 2 == 0 { "F-1".into() } else { "A".into() },
            x_m: 1.0e6 + i as f64,
            y_m: -4.0e6,
            z_m: 3.7e6,
            vx_mps: 250.0,
            vy_mps: -1.5,
            vz_mps: 0.25,
            lat_deg: 36.0,
            lon_deg: -70.0,
            alt_m: 6000.0,
            rcs_m2: 2.0,
        })
        .collect()
}

fn dwells() -> Vec<DwellRow> {
    vec![
        DwellRow {
            run: 0,
            dwell_id: 7,
            group_id: 7,
            radar: RadarId(0),
            role: Role::Txrx,
            kind: DwellKind::Mimo,
            requested_by: Requester::Ta,
            t_s: 1.5,
            duration_s: 0.011,
            pulse_width_s: 1e-5,
            n_pulses: 3,
            peak_power_w: 1e5,
            energy_j: 3.0,
            waveform: 1,
            face: 2,
            beam_u: 0.1,
            beam_v: -0.2,
            aim_x_m: 1.0,
            aim_y_m: 2.0,
            aim_z_m: 3.0,
        },
        DwellRow {
            run: 0,
            dwell_id: 8,
            group_id: 7,
            radar: RadarId(3),
            role: Role::Rx,
            kind: DwellKind::Mimo,
            requested_by: Requester::Ta,
            t_s: 1.5,
            duration_s: 0.011,
            pulse_width_s: 1e-5,
            n_pulses: 3,
            peak_power_w: 0.0,
            energy_j: 0.0,
            waveform: 0,
            face: 0,
            beam_u: 0.0,
            beam_v: 0.0,
            aim_x_m: 1.0,
            aim_y_m: 2.0,
            aim_z_m: 3.0,
        },
    ]
}

fn voltages() -> Vec<VoltageRow> {
    vec![VoltageRow {
        run: 0,
        dwell_id: 3,
        rx: RadarId(1),
        tx: RadarId(2),
        range_cell: -4,
        range_m: 1234.5,
        sum_i: 0.1,
        sum_q: -0.2,
        az_i: 0.3,
        az_q: 0.4,
        el_i: -0.5,
        el_q: 0.6,
    }]
}

fn primitives() -> Vec<PrimitiveRow> {
    vec![
        PrimitiveRow {
            run: 0,
            dwell_id: 3,
            t_s: 2.0,
            rx: RadarId(1),
            tx: RadarId(1),
            rx_face: 3,
            range_cell: 4000,
            range_m: 120_000.5,
            u: 0.01,
            v: -0.02,
            snr_db: 21.5,
            eta_q: 1.2,
            merged: false,
            beam_u: 0.0,
            beam_v: 0.0,
            var_range_m2: 4.0,
            var_u: 1e-6,
            var_v: 2e-6,
            target_hint: Some("F-2".into()),
        },
        PrimitiveRow {
            run: 0,
            dwell_id: 3,
            t_s: 2.0,
            rx: RadarId(1),
            tx: RadarId(1),
            rx_face: 3,
            range_cell: 9000,
            range_m: 270_000.0,
            u: 0.0,
            v: 0.0,
            snr_db: 12.0,
            eta_q: 0.3,
            merged: true,
            beam_u: 0.0,
            beam_v: 0.0,
            var_range_m2: 9.0,
            var_u: 1e-5,
            var_v: 1e-5,
            target_hint: None,
        },
    ]
}

fn measurements() -> Vec<MeasurementRow> {
    vec![MeasurementRow {
        run: 0,
        meas_id: 11,
        dwell_id: 3,
        t_s: 2.0,
        rx: RadarId(1),
        tx: RadarId(0),
        rx_face: 1,
        range_m: 150_000.0,
        u: 0.3,
        v: 0.1,
        snr_db: 18.0,
        var_range_m2: 25.0,
        var_u: 1e-6,
        var_v: 1e-6,
        n_primitives: 2,
        merged: false,
        target_hint: None,
    }]
}

fn tracks() -> Vec<TrackRow> {
    // A covariance: variances 1…6 on the diagonal, a few correlations of 0.1–0.5.
    let mut m = [[0.0; 6]; 6];
    for (i, row) in m.iter_mut().enumerate() {
        row[i] = 1.0 + i as f64;
    }
    for (i, j, r) in [(0, 3, 0.5), (1, 4, 0.3), (2, 5, 0.1)] {
        let c = r * (m[i][i] * m[j][j]).sqrt();
        (m[i][j], m[j][i]) = (c, c);
    }
    let cov = mimo_core::records::pack_cov(&m);
    vec![
        TrackRow {
            run: 0,
            t_s: 3.0,
            track_id: 1,
            status: TrackStatus::Confirmed,
            x_m: 1.0,
            y_m: 2.0,
            z_m: 3.0,
            vx_mps: 4.0,
            vy_mps: 5.0,
            vz_mps: 6.0,
            cov,
            n_updates: 4,
            last_meas_id: Some(11),
        },
        TrackRow {
            run: 0,
            t_s: 9.0,
            track_id: 1,
            status: TrackStatus::Deleted,
            x_m: 1.0,
            y_m: 2.0,
            z_m: 3.0,
            vx_mps: 4.0,
            vy_mps: 5.0,
            vz_mps: 6.0,
            cov,
            n_updates: 4,
            last_meas_id: None,
        },
    ]
}

fn round_trip<R: mimo_store::rows::TableRow + PartialEq + std::fmt::Debug>(dir: &Path, rows: Vec<R>) {
    let p = dir.join(format!("{}.parquet", R::SPEC.name));
    write_table(&p, &rows).expect("write");
    let back: Vec<R> = read_table(&p).expect("read");
    assert_eq!(back, rows, "table {}", R::SPEC.name);
    // Same rows, same bytes.
    let bytes = std::fs::read(&p).expect("bytes");
    write_table(&p, &rows).expect("rewrite");
    assert_eq!(std::fs::read(&p).expect("bytes"), bytes);
    // Empty tables round-trip too.
    write_table::<R>(&p, &[]).expect("write empty");
    assert!(read_table::<R>(&p).expect("read empty").is_empty());
}

#[test]
fn every_table_round_trips() {
    let dir = tempfile::tempdir().expect("tempdir");
    round_trip(dir.path(), truth());
    round_trip(dir.path(), dwells());
    round_trip(dir.path(), voltages());
    round_trip(dir.path(), primitives());
    round_trip(dir.path(), measurements());
    round_trip(dir.path(), tracks());
}

#[test]
fn schemas_dir_matches_code() {
    // Regenerate with: MIMO_BLESS=1 cargo test -p mimo-store --test tables schemas_dir_matches_code
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../schemas");
    let bless = std::env::var("MIMO_BLESS").is_ok();
    for (name, text) in mimo_store::schema::schema_files() {
        let p = dir.join(&name);
        if bless {
            std::fs::write(&p, &text).expect("write schema");
        }
        let on_disk = std::fs::read_to_string(&p).unwrap_or_default();
        assert_eq!(on_disk, text, "schemas/{name} differs from the code: rerun with MIMO_BLESS=1");
    }
}

#[test]
fn wrong_table_and_wrong_type_are_named() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("t.parquet");
    write_table(&p, &truth()).expect("write");
    let err = read_table::<TrackRow>(&p).expect_err("wrong table");
    assert!(err.to_string().contains("holds table 'truth', expected 'tracks'"), "{err}");

    // A file with a column of the wrong type: write a batch by hand.
    use arrow::array::{ArrayRef, RecordBatch, StringArray, UInt32Array};
    use arrow::datatypes::{DataType, Field, Schema};
    use std::sync::Arc;
    let mut md = std::collections::HashMap::new();
    md.insert("mimo.table".to_string(), "truth".to_string());
    md.insert("mimo.schema_version".to_string(), mimo_store::schema::SCHEMA_VERSION.to_string());
    let schema = Arc::new(
        Schema::new(vec![Field::new("run", DataType::UInt32, false), Field::new("t_s", DataType::Utf8, false)])
            .with_metadata(md),
    );
    let cols: Vec<ArrayRef> = vec![Arc::new(UInt32Array::from(vec![0u32])), Arc::new(StringArray::from(vec!["0.0"]))];
    let batch = RecordBatch::try_new(schema.clone(), cols).expect("batch");
    let f = std::fs::File::create(&p).expect("create");
    let mut w = parquet::arrow::ArrowWriter::try_new(f, schema, None).expect("writer");
    w.write(&batch).expect("write");
    w.close().expect("close");
    let err = read_table::<TruthRow>(&p).expect_err("bad type");
    let msg = err.to_string();
    assert!(msg.contains("column 't_s'") && msg.contains("expected float64"), "{msg}");

    std::fs::write(&p, b"not parquet").expect("write");
    let err = read_table::<TruthRow>(&p).expect_err("corrupt");
    assert!(matches!(err, StoreError::Parquet { .. }), "{err}");
}

#[test]
fn non_finite_values_are_rejected() {
    let dir = tempfile::tempdir().expect("tempdir");
    let p = dir.path().join("t.parquet");
    let mut rows = truth();
    rows[2].x_m = f64::NAN;
    write_table(&p, &rows).expect("write");
    let err = read_table::<TruthRow>(&p).expect_err("nan");
    assert!(err.to_string().contains("column 'x_m' is NaN at row 2 (expected a finite number)"), "{err}");
}

fn manifest() -> Manifest {
    Manifest {
        mimo_version: "0".into(),
        schema_version: mimo_store::schema::SCHEMA_VERSION,
        scenario: ScenarioInfo { name: "t".into(), resolved: serde_json::json!({}) },
        seed: 1,
        runs: 1,
        duration_s: 1.0,
        fidelity: serde_json::json!({}),
        tracker: None,
        schedule: "test".into(),
        parent: None,
        parent_check: None,
        tables: Default::default(),
        timing_s: Default::default(),
    }
}

#[test]
fn run_dir_is_atomic_and_never_overwritten_without_force() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("runs/s1");
    {
        let w = RunDirWriter::create(&out, false).expect("create");
        w.write_run_table("truth", 0, &truth()).expect("write");
        // Dropped unfinished: nothing is left behind.
    }
    assert!(!out.exists());
    let leftovers: Vec<_> = std::fs::read_dir(dir.path().join("runs")).map(|d| d.count()).into_iter().collect();
    assert_eq!(leftovers, vec![0]);

    let w = RunDirWriter::create(&out, false).expect("create");
    let tf = w.write_run_table("truth", 0, &truth()).expect("write");
    assert_eq!(tf.file, "truth/run-0000.parquet");
    assert_eq!(tf.rows, 5);
    let mut m = manifest();
    m.tables.insert("truth".into(), vec![tf]);
    w.finish(&m).expect("finish");
    assert_eq!(Manifest::read(&out).expect("manifest"), m);

    let err = RunDirWriter::create(&out, false).expect_err("exists");
    assert!(err.to_string().contains("use --force"), "{err}");
    let w = RunDirWriter::create(&out, true).expect("force");
    w.finish(&manifest()).expect("finish");
    assert!(Manifest::read(&out).expect("manifest").tables.is_empty());
}

/// Many dwell rows: ids counting up, times increasing, a few radars, kinds and beams.
fn many_dwells(n: u64) -> Vec<DwellRow> {
    let base = dwells();
    (0..n)
        .map(|i| {
            let mut r = base[(i % 2) as usize].clone();
            r.dwell_id = i;
            r.group_id = i - i % 2;
            r.radar = RadarId((i % 4) as u8);
            r.kind = if i % 7 == 0 { DwellKind::Track } else { DwellKind::Search };
            r.t_s = i as f64 * 1e-3;
            r.beam_u = ((i % 97) as f64 - 48.0) * 0.01;
            r.aim_x_m = 1.0e6 + (i as f64).sqrt();
            r
        })
        .collect()
}

#[test]
fn rows_streamed_through_the_run_sink_are_the_rows_written_at_once() {
    use mimo_core::sink::RunSink;
    use mimo_store::run_sink::ParquetRunSink;
    use mimo_store::table_writer::CHUNK_ROWS;
    let dir = tempfile::tempdir().expect("tempdir");
    // Several chunks and a remainder, pushed one by one and in uneven slices.
    let rows = many_dwells(3 * CHUNK_ROWS as u64 + 17);
    let once = dir.path().join("once.parquet");
    write_table(&once, &rows).expect("write");
    let out = dir.path().join("run");
    let w = RunDirWriter::create(&out, false).expect("create");
    let mut sink = ParquetRunSink::create(&w, 0, false).expect("sink");
    sink.truth(truth()).expect("truth");
    for r in &rows {
        sink.dwell(r.clone()).expect("dwell");
    }
    for chunk in primitives().chunks(1) {
        sink.primitives(chunk.to_vec()).expect("primitives");
    }
    let files = sink.finish().expect("finish");
    let by_name: std::collections::BTreeMap<_, _> = files.into_iter().collect();
    assert_eq!(by_name["dwells"].rows, rows.len() as u64);
    assert_eq!(by_name["primitives"].rows, primitives().len() as u64);
    assert_eq!(by_name["measurements"].rows, 0);
    let streamed = w.staging().join(&by_name["dwells"].file);
    assert_eq!(std::fs::read(&streamed).expect("read"), std::fs::read(&once).expect("read"), "same bytes");
    assert_eq!(read_table::<DwellRow>(&streamed).expect("read"), rows);
    let prims = w.staging().join(&by_name["primitives"].file);
    assert_eq!(read_table::<PrimitiveRow>(&prims).expect("read"), primitives());
    // An empty table is a readable file with no rows.
    let meas = w.staging().join(&by_name["measurements"].file);
    assert!(read_table::<MeasurementRow>(&meas).expect("read").is_empty());
}
