//! The checked readers of the run tables, through the real binary: `mimo score`, `mimo plot` and
//! `mimo track` refuse a table that is not what its declaration says (metadata, column types,
//! runs, values, covariances, variances, rows the table cannot order) with one `error:` line
//! naming the file and the field, exit status 2, and nothing written; and a table whose rows of
//! one track at one time are stored in another order scores the same.

use arrow::array::{Array, ArrayRef, AsArray, FixedSizeListArray, RecordBatch};
use arrow::datatypes::{DataType, Field, Float64Type, Schema};
use mimo_core::records::{DwellRow, MeasurementRow, PrimitiveRow, TrackRow, TruthRow};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::{Arc, OnceLock};

const MIMO: &str = env!("CARGO_BIN_EXE_mimo");

fn mimo(dir: &Path, args: &[&str]) -> Output {
    Command::new(MIMO).args(args).current_dir(dir).output().expect("mimo runs")
}

/// A finished two-run, 60-s simulation of scenario 1 (tracks, measurements and primitives in
/// both runs), made once; each test copies it.
fn template() -> &'static Path {
    static T: OnceLock<tempfile::TempDir> = OnceLock::new();
    T.get_or_init(|| {
        let t = tempfile::tempdir().expect("tmp");
        let args = ["simulate", "--scenario", "1", "--duration", "60", "--runs", "2", "--out", "r", "--quiet"];
        let o = mimo(t.path(), &args);
        assert!(o.status.success(), "template run: {}", String::from_utf8_lossy(&o.stderr));
        t
    })
    .path()
}

/// A fresh copy of the template run; the run is `DIR/r`.
fn fresh() -> tempfile::TempDir {
    let d = tempfile::tempdir().expect("tmp");
    let status = Command::new("cp").arg("-a").arg(template().join("r")).arg(d.path()).status().expect("cp runs");
    assert!(status.success(), "cp -a of the template run");
    d
}

fn file(run: &Path, table: &str, k: u32) -> PathBuf {
    run.join(table).join(format!("run-{k:04}.parquet"))
}

/// Rewrite a table file's typed rows (written back with the store's writer, unchecked).
fn edit_rows<R: mimo_store::rows::TableRow>(f: &Path, edit: impl FnOnce(&mut Vec<R>)) {
    let mut rows: Vec<R> = mimo_store::read_table(f).expect("valid table");
    edit(&mut rows);
    mimo_store::write_table(f, &rows).expect("write");
}

/// Rewrite a table file's Arrow batch (all its rows in one), schema metadata included.
fn edit_batch(f: &Path, edit: impl FnOnce(RecordBatch) -> RecordBatch) {
    let builder =
        parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(f).expect("open"))
            .expect("parquet");
    // The file's schema, with its metadata (the batches read carry none).
    let schema = builder.schema().clone();
    let batches: Vec<RecordBatch> = builder.build().expect("reader").collect::<Result<_, _>>().expect("batches");
    let batches: Vec<RecordBatch> = batches
        .into_iter()
        .map(|b| RecordBatch::try_new(schema.clone(), b.columns().to_vec()).expect("batch"))
        .collect();
    let batch = edit(arrow::compute::concat_batches(&schema, &batches).expect("concat"));
    let mut w = parquet::arrow::ArrowWriter::try_new(std::fs::File::create(f).expect("create"), batch.schema(), None)
        .expect("writer");
    w.write(&batch).expect("write");
    w.close().expect("close");
}

/// The batch with schema metadata `key` set to `value` (removed for `None`).
fn with_meta(b: RecordBatch, key: &str, value: Option<&str>) -> RecordBatch {
    let mut md = b.schema().metadata().clone();
    match value {
        Some(v) => md.insert(key.to_string(), v.to_string()),
        None => md.remove(key),
    };
    let schema = Arc::new(Schema::new(b.schema().fields().clone()).with_metadata(md));
    RecordBatch::try_new(schema, b.columns().to_vec()).expect("batch")
}

/// The batch with column `name` replaced by `array` (its field's type follows the array).
fn with_column(b: RecordBatch, name: &str, array: ArrayRef) -> RecordBatch {
    let schema = b.schema();
    let i = schema.index_of(name).expect("column");
    let mut fields: Vec<Field> = schema.fields().iter().map(|f| f.as_ref().clone()).collect();
    fields[i] = Field::new(name, array.data_type().clone(), false).with_metadata(fields[i].metadata().clone());
    let mut columns = b.columns().to_vec();
    columns[i] = array;
    RecordBatch::try_new(Arc::new(Schema::new(fields).with_metadata(schema.metadata().clone())), columns)
        .expect("batch")
}

fn cast(b: RecordBatch, name: &str, to: DataType) -> RecordBatch {
    let c = arrow::compute::cast(b.column_by_name(name).expect("column"), &to).expect("cast");
    with_column(b, name, c)
}

/// Run `args` in `dir`: exit status 2, one `error:` line holding every fragment, and `out`
/// (relative to `dir`) not written.
fn refused(dir: &Path, args: &[&str], fragments: &[&str], out: &str) {
    let o = mimo(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(lines.len(), 1, "{args:?}: one error line expected: {err}");
    for f in fragments {
        assert!(lines[0].contains(f), "{args:?}: '{f}' not in: {}", lines[0]);
    }
    assert!(!dir.join(out).exists(), "{args:?} wrote {out}");
}

fn score_refuses(dir: &Path, fragments: &[&str]) {
    refused(dir, &["score", "r", "--no-charts"], fragments, "r/score");
}

fn plot_refuses(dir: &Path, fragments: &[&str]) {
    refused(dir, &["plot", "r", "--out", "p.html"], fragments, "p.html");
}

#[test]
fn a_file_of_another_table_or_version_or_none_is_refused() {
    for (value, fragment) in
        [(Some("truth"), "holds table 'truth', expected 'tracks'"), (None, "no 'mimo.table' metadata")]
    {
        let d = fresh();
        edit_batch(&file(&d.path().join("r"), "tracks", 0), |b| with_meta(b, "mimo.table", value));
        score_refuses(d.path(), &["tracks/run-0000.parquet", fragment]);
        plot_refuses(d.path(), &["tracks/run-0000.parquet", fragment]);
    }
    let d = fresh();
    edit_batch(&file(&d.path().join("r"), "tracks", 1), |b| with_meta(b, "mimo.schema_version", Some("99")));
    score_refuses(d.path(), &["tracks/run-0001.parquet", "schema version 99"]);
}

#[test]
fn a_column_of_another_type_is_refused() {
    let d = fresh();
    edit_batch(&file(&d.path().join("r"), "tracks", 0), |b| cast(b, "t_s", DataType::Float32));
    score_refuses(d.path(), &["tracks/run-0000.parquet", "column 't_s' has type Float32, expected float64"]);
    plot_refuses(d.path(), &["tracks/run-0000.parquet", "column 't_s'"]);
    let d = fresh();
    edit_batch(&file(&d.path().join("r"), "truth", 0), |b| cast(b, "run", DataType::Int64));
    score_refuses(d.path(), &["truth/run-0000.parquet", "column 'run' has type Int64, expected uint32"]);
}

/// The covariance with `keep` of its 21 values per row (20: a list of another length).
fn cov_of(b: &RecordBatch, edit: impl Fn(usize, &mut Vec<f64>)) -> ArrayRef {
    let list = b.column_by_name("cov").expect("cov").as_fixed_size_list().clone();
    let values = list.values().as_primitive::<Float64Type>().values().to_vec();
    let mut rows: Vec<Vec<f64>> = values.chunks(21).map(<[f64]>::to_vec).collect();
    for (i, r) in rows.iter_mut().enumerate() {
        edit(i, r);
    }
    let n = rows[0].len() as i32;
    let flat = arrow::array::Float64Array::from(rows.concat());
    let item = Arc::new(Field::new("item", DataType::Float64, false));
    Arc::new(FixedSizeListArray::new(item, n, Arc::new(flat), None))
}

#[test]
fn a_bad_covariance_is_refused() {
    let d = fresh();
    edit_batch(&file(&d.path().join("r"), "tracks", 0), |b| {
        let c = cov_of(&b, |_, r| {
            r.pop();
        });
        with_column(b, "cov", c)
    });
    score_refuses(d.path(), &["tracks/run-0000.parquet", "column 'cov' has type"]);
    plot_refuses(d.path(), &["tracks/run-0000.parquet", "column 'cov'"]);

    let d = fresh();
    edit_rows::<TrackRow>(&file(&d.path().join("r"), "tracks", 0), |rows| rows[3].cov[7] = f64::NAN);
    score_refuses(d.path(), &["tracks/run-0000.parquet", "column 'cov'", "row 3", "finite"]);
    plot_refuses(d.path(), &["tracks/run-0000.parquet", "column 'cov'", "row 3"]);

    // A position–velocity correlation above one: not a covariance.
    let d = fresh();
    edit_rows::<TrackRow>(&file(&d.path().join("r"), "tracks", 0), |rows| {
        let c = &mut rows[2].cov;
        c[mimo_core::records::cov_index(0, 3)] = 2.0 * (c[0] * c[mimo_core::records::cov_index(3, 3)]).sqrt();
    });
    score_refuses(d.path(), &["tracks/run-0000.parquet", "column 'cov'", "row 2", "positive semi-definite"]);

    let d = fresh();
    edit_rows::<TrackRow>(&file(&d.path().join("r"), "tracks", 1), |rows| rows[0].cov[0] = -4.0);
    score_refuses(d.path(), &["tracks/run-0001.parquet", "column 'cov'", "variance 0"]);
}

#[test]
fn rows_of_another_run_than_the_file_are_refused() {
    let d = fresh();
    edit_rows::<TruthRow>(&file(&d.path().join("r"), "truth", 0), |rows| rows[4].run = 5);
    score_refuses(d.path(), &["truth/run-0000.parquet", "column 'run' row 4: 5 in the file of run 0"]);
    plot_refuses(d.path(), &["truth/run-0000.parquet", "column 'run' row 4"]);

    let d = fresh();
    edit_rows::<TrackRow>(&file(&d.path().join("r"), "tracks", 1), |rows| rows.iter_mut().for_each(|r| r.run = 0));
    score_refuses(d.path(), &["tracks/run-0001.parquet", "column 'run' row 0: 0 in the file of run 1"]);
}

#[test]
fn variances_that_are_not_positive_are_refused() {
    let d = fresh();
    edit_rows::<MeasurementRow>(&file(&d.path().join("r"), "measurements", 0), |rows| rows[1].var_u = -1e-6);
    refused(
        d.path(),
        &["track", "r", "--from", "measurements", "--out", "t"],
        &["measurements/run-0000.parquet", "column 'var_u' is -0.000001 at row 1 (expected a finite number > 0)"],
        "t",
    );
    let d = fresh();
    edit_rows::<PrimitiveRow>(&file(&d.path().join("r"), "primitives", 1), |rows| rows[0].var_range_m2 = 0.0);
    refused(d.path(), &["track", "r", "--out", "t"], &["primitives/run-0001.parquet", "column 'var_range_m2'"], "t");
}

#[test]
fn times_outside_the_run_are_refused_by_every_reader() {
    // After the run's end (60 s, its manifest's duration_s).
    let d = fresh();
    let truth = file(&d.path().join("r"), "truth", 0);
    let mut last = 0;
    edit_rows::<TruthRow>(&truth, |rows| {
        last = rows.len() - 1;
        rows[last].t_s = 61.0;
    });
    let after = format!("column 't_s' is 61 at row {last}, after the run's end at 60 s");
    score_refuses(d.path(), &["truth/run-0000.parquet", &after]);
    plot_refuses(d.path(), &["truth/run-0000.parquet", &after]);
    let d = fresh();
    edit_rows::<DwellRow>(&file(&d.path().join("r"), "dwells", 1), |rows| {
        last = rows.len() - 1;
        rows[last].t_s = 1.0e9;
    });
    let after = format!("column 't_s' is 1000000000 at row {last}, after the run's end at 60 s");
    score_refuses(d.path(), &["dwells/run-0001.parquet", &after]);
    refused(d.path(), &["track", "r", "--out", "t"], &["dwells/run-0001.parquet", &after], "t");
    // Before its start.
    let d = fresh();
    edit_rows::<TrackRow>(&file(&d.path().join("r"), "tracks", 1), |rows| rows[0].t_s = -1.0);
    let before = "column 't_s' is -1 at row 0 (expected a finite number >= 0)";
    score_refuses(d.path(), &["tracks/run-0001.parquet", before]);
    refused(d.path(), &["plot", "r", "--run", "1", "--out", "p.html"], &["tracks/run-0001.parquet", before], "p.html");
    let d = fresh();
    edit_rows::<PrimitiveRow>(&file(&d.path().join("r"), "primitives", 0), |rows| rows[0].t_s = -1.0);
    refused(d.path(), &["track", "r", "--out", "t"], &["primitives/run-0000.parquet", before], "t");
}

/// Two rows of one track: the indices of the first pair of consecutive confirmed rows of one
/// track whose `n_updates` differ (a later update and the one before).
fn pair(rows: &[TrackRow]) -> (usize, usize) {
    let confirmed = |i: usize| rows[i].status == mimo_core::records::TrackStatus::Confirmed;
    (1..rows.len())
        .find(|&i| {
            rows[i].track_id == rows[i - 1].track_id
                && rows[i].n_updates > rows[i - 1].n_updates
                && confirmed(i)
                && confirmed(i - 1)
        })
        .map(|i| (i - 1, i))
        .expect("a track with two updates")
}

#[test]
fn rows_of_one_track_at_one_time_that_the_table_cannot_order_are_refused() {
    let d = fresh();
    edit_rows::<TrackRow>(&file(&d.path().join("r"), "tracks", 0), |rows| {
        let (a, b) = pair(rows);
        rows[b].t_s = rows[a].t_s;
        rows[b].n_updates = rows[a].n_updates;
    });
    score_refuses(d.path(), &["tracks/run-0000.parquet", "n_updates", "two rows at t_s"]);
    plot_refuses(d.path(), &["tracks/run-0000.parquet", "column 'n_updates'"]);
}

/// The summary of run `r` in `dir` after `edit` of its first tracks file.
fn summary_after(edit: impl FnOnce(&mut Vec<TrackRow>)) -> String {
    let d = fresh();
    edit_rows::<TrackRow>(&file(&d.path().join("r"), "tracks", 0), edit);
    let o = mimo(d.path(), &["score", "r", "--no-charts", "--quiet"]);
    assert!(o.status.success(), "score: {}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(d.path().join("r/score/summary.json")).expect("summary")
}

#[test]
fn rows_of_one_track_at_one_time_score_the_same_in_any_row_order() {
    // Two updates of one track at one time (sequential updates of one dwell), the later one 400 m
    // off: the scorer must take the later by n_updates, whichever row the file holds first.
    let same_time = |rows: &mut Vec<TrackRow>| {
        let (a, b) = pair(rows);
        rows[b].t_s = rows[a].t_s;
        rows[b].x_m += 400.0;
        (a, b)
    };
    let in_order = summary_after(|rows| {
        same_time(rows);
    });
    let swapped = summary_after(|rows| {
        let (a, b) = same_time(rows);
        rows.swap(a, b);
    });
    assert_eq!(in_order, swapped, "the row order of the file changed the score");
    // The ranks decide: the same rows with their n_updates exchanged score differently (so the
    // comparison above can fail).
    let ranks_exchanged = summary_after(|rows| {
        let (a, b) = same_time(rows);
        let (na, nb) = (rows[a].n_updates, rows[b].n_updates);
        (rows[a].n_updates, rows[b].n_updates) = (nb, na);
    });
    assert_ne!(in_order, ranks_exchanged, "the ranks of the two rows did not matter");
}
