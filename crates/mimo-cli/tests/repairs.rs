//! Near-valid input accepted and counted, and the last faults of the matrix closed
//! (docs/design.md §7, docs/decisions/0302 and 0303), through the real binary: a covariance
//! slightly not positive semi-definite is repaired and counted by score and plot, one beyond the
//! bound refused with its eigenvalue; `--force` onto an empty directory; plot's missing folder;
//! a damaged score file; `mimo track` on a study cell; a second whole-study run; bounded quotes.

use arrow::array::{ArrayRef, RecordBatch, StringArray};
use mimo_core::records::TrackRow;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::{Arc, OnceLock};

const MIMO: &str = env!("CARGO_BIN_EXE_mimo");

fn mimo(dir: &Path, args: &[&str]) -> Output {
    Command::new(MIMO).args(args).current_dir(dir).output().expect("mimo runs")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// A one-run, 60-s simulation of scenario 1, made once; each test copies it (`DIR/r`).
fn fresh() -> tempfile::TempDir {
    static T: OnceLock<tempfile::TempDir> = OnceLock::new();
    let template = T.get_or_init(|| {
        let t = tempfile::tempdir().expect("tmp");
        let o = mimo(t.path(), &["simulate", "--scenario", "1", "--duration", "60", "--out", "r", "--quiet"]);
        assert!(o.status.success(), "template run: {}", stderr(&o));
        t
    });
    let d = tempfile::tempdir().expect("tmp");
    let status = Command::new("cp").arg("-a").arg(template.path().join("r")).arg(d.path()).status().expect("cp");
    assert!(status.success());
    d
}

fn tracks_file(d: &Path) -> PathBuf {
    d.join("r/tracks/run-0000.parquet")
}

/// Row `i`'s covariance given the smallest eigenvalue `ratio` × its largest, the eigenvectors
/// and other eigenvalues kept.
fn set_smallest_eigenvalue(d: &Path, i: usize, ratio: f64) {
    let f = tracks_file(d);
    let mut rows: Vec<TrackRow> = mimo_store::read_table(&f).expect("tracks");
    let m = mimo_core::records::unpack_cov(&rows[i].cov);
    let (mut lam, v) = mimo_core::covariance::symmetric_eigen(&m);
    lam[5] = ratio * lam[0];
    let out: [[f64; 6]; 6] =
        std::array::from_fn(|a| std::array::from_fn(|b| (0..6).map(|k| v[k][a] * lam[k] * v[k][b]).sum()));
    rows[i].cov = mimo_core::records::pack_cov(&out);
    mimo_store::write_table(&f, &rows).expect("write");
}

fn summary(d: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(d.join("r/score/summary.json")).expect("summary")).expect("json")
}

#[test]
fn a_slightly_indefinite_covariance_is_repaired_and_counted_one_beyond_the_bound_refused() {
    // -1e-6 of the largest: scored, counted in the summary, one warning line; plotted, warned.
    let d = fresh();
    set_smallest_eigenvalue(d.path(), 2, -1e-6);
    let raw =
        mimo_store::checked::repaired_covariances(&tracks_file(d.path()), &mimo_store::schema::TRACKS).expect("count");
    assert_eq!(raw.rows, 1);
    let o = mimo(d.path(), &["score", "r", "--no-charts"]);
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert_eq!(summary(d.path())["repaired_covariances"], serde_json::json!({"tracks": 1}));
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(warnings[0].contains("1 covariance(s)") && warnings[0].contains("-1.00e-6 of the largest"), "{err}");
    let o = mimo(d.path(), &["plot", "r", "--out", "p.html"]);
    assert!(o.status.success() && stderr(&o).contains("warning:"), "{}", stderr(&o));
    // The same run scored before the change and after its repair: the same figures but the count.
    let valid = fresh();
    let o = mimo(valid.path(), &["score", "r", "--no-charts", "--quiet"]);
    assert!(o.status.success() && o.stderr.is_empty(), "{}", stderr(&o));
    let mut a = summary(valid.path());
    assert!(a.get("repaired_covariances").is_none(), "valid input: no count, summary unchanged");
    let mut b = summary(d.path());
    b.as_object_mut().expect("object").remove("repaired_covariances");
    a.as_object_mut().expect("object").remove("repaired_covariances");
    assert_eq!(a, b, "a repair within the bound changes no figure of the score");

    // -1e-2 of the largest: refused by score and plot, the row and eigenvalue named, nothing written.
    let d = fresh();
    set_smallest_eigenvalue(d.path(), 2, -1e-2);
    for args in [&["score", "r", "--no-charts", "--quiet"][..], &["plot", "r", "--out", "p.html", "--quiet"]] {
        let o = mimo(d.path(), args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            err.contains("tracks/run-0000.parquet")
                && err.contains("column 'cov'")
                && err.contains("row 2")
                && err.contains("smallest eigenvalue is -")
                && err.contains("-1.000e-2 of it"),
            "{err}"
        );
    }
    assert!(!d.path().join("r/score").exists() && !d.path().join("p.html").exists());
}

#[test]
fn force_onto_an_empty_directory_writes_there_as_documented() {
    let d = tempfile::tempdir().expect("tmp");
    for force in [true, false] {
        let e = d.path().join(format!("e-{force}"));
        std::fs::create_dir(&e).expect("mkdir");
        let mut args =
            vec!["simulate", "--scenario", "1", "--duration", "5", "--out", e.to_str().expect("utf8"), "--quiet"];
        if force {
            args.push("--force");
        }
        let o = mimo(d.path(), &args);
        assert!(o.status.success(), "force {force}: {}", stderr(&o));
        assert!(e.join("manifest.json").is_file());
        let hidden: Vec<_> = std::fs::read_dir(&e)
            .expect("ls")
            .flatten()
            .filter(|x| x.file_name().to_string_lossy().starts_with('.'))
            .map(|x| x.path())
            .collect();
        assert!(hidden.is_empty(), "{hidden:?}");
    }
}

#[test]
fn plot_creates_its_output_folder() {
    let d = fresh();
    let o = mimo(d.path(), &["plot", "r", "--out", "figs/deep/p.html", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(mimo_store::recognise::is_plot_page(&d.path().join("figs/deep/p.html")));
}

#[test]
fn a_damaged_file_of_mimos_score_is_replaced_by_a_rescore() {
    let d = fresh();
    let o = mimo(d.path(), &["score", "r", "--no-charts", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let good = std::fs::read(d.path().join("r/score/track_metrics.parquet")).expect("read");
    let f = std::fs::OpenOptions::new().write(true).open(d.path().join("r/score/track_metrics.parquet")).expect("open");
    f.set_len(100).expect("truncate");
    std::fs::write(d.path().join("r/score/summary.json"), "{\n  \"scenario\": \"scenario-1\",\n  \"ru").expect("cut");
    let o = mimo(d.path(), &["score", "r", "--no-charts"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("replaced the damaged") && out.contains("track_metrics.parquet"), "{out}");
    assert_eq!(std::fs::read(d.path().join("r/score/track_metrics.parquet")).expect("read"), good, "rescored");
    // A user's file is still refused, and the message says how to start over.
    std::fs::write(d.path().join("r/score/summary.json"), "{}").expect("user's");
    let o = mimo(d.path(), &["score", "r", "--no-charts", "--quiet"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("summary.json") && err.contains("rm -r"), "{err}");
}

#[test]
fn track_on_a_study_cell_without_primitives_says_what_to_run_and_that_works() {
    let d = tempfile::tempdir().expect("tmp");
    let plan = "title = \"k\"\nscenarios = [1]\nruns = 1\nduration_s = 20\nkeep_runs = true\n[[methods]]\nname = \"m\"\nta = \"default\"\n";
    std::fs::write(d.path().join("keep.toml"), plan).expect("plan");
    let o = mimo(d.path(), &["study", "keep.toml", "--out", "ks", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let method = std::fs::read_dir(d.path().join("ks/runs")).expect("runs").flatten().next().expect("method").path();
    let cell = std::fs::read_dir(&method).expect("cells").flatten().next().expect("cell").path();
    let c = cell.to_str().expect("utf8");
    let o = mimo(d.path(), &["track", c, "--out", "t", "--quiet"]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("holds no 'primitives' table") && err.contains("--from measurements --out OUT"), "{err}");
    assert!(!d.path().join("t").exists());
    let o = mimo(d.path(), &["track", c, "--from", "measurements", "--out", "t", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = mimo(d.path(), &["score", "t", "--no-charts", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A study of scenario 7 long enough to be running when a second whole run starts.
const LONG: &str =
    "title = \"long\"\nscenarios = [7]\nruns = 4\nduration_s = 300\n[[methods]]\nname = \"m\"\nta = \"default\"\n";

#[test]
fn a_second_whole_study_run_is_refused_at_once_naming_shards() {
    let d = tempfile::tempdir().expect("tmp");
    std::fs::write(d.path().join("long.toml"), LONG).expect("plan");
    let child = Command::new(MIMO)
        .args(["study", "long.toml", "--out", "st", "--quiet", "--threads", "1"])
        .current_dir(d.path())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let t0 = std::time::Instant::now();
    while !d.path().join("st/study.json").is_file() && t0.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let o = mimo(d.path(), &["study", "long.toml", "--out", "st", "--resume", "--quiet"]);
    let err = stderr(&o);
    let _ = Command::new("kill").args(["-TERM", &child.id().to_string()]).status();
    let first = child.wait_with_output().expect("wait");
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("another mimo process") && err.contains("--shard K/N"), "{err}");
    assert_eq!(first.status.code(), Some(130), "{}", String::from_utf8_lossy(&first.stderr));
}

#[test]
fn a_huge_bad_label_is_quoted_by_a_bounded_prefix() {
    let d = fresh();
    let f = tracks_file(d.path());
    let builder =
        parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(std::fs::File::open(&f).expect("open"))
            .expect("parquet");
    let schema = builder.schema().clone();
    let batches: Vec<RecordBatch> = builder.build().expect("reader").collect::<Result<_, _>>().expect("batches");
    let batch = arrow::compute::concat_batches(&schema, &batches).expect("concat");
    let status = schema.index_of("status").expect("status");
    let huge = "x".repeat(1 << 20);
    let labels: Vec<&str> = (0..batch.num_rows()).map(|i| if i == 0 { huge.as_str() } else { "tentative" }).collect();
    let mut columns: Vec<ArrayRef> = batch.columns().to_vec();
    columns[status] = Arc::new(StringArray::from(labels));
    let batch = RecordBatch::try_new(schema.clone(), columns).expect("batch");
    let mut w =
        parquet::arrow::ArrowWriter::try_new(std::fs::File::create(&f).expect("create"), schema, None).expect("writer");
    w.write(&batch).expect("write");
    w.close().expect("close");
    for args in [&["score", "r", "--no-charts", "--quiet"][..], &["plot", "r", "--out", "p.html", "--quiet"]] {
        let o = mimo(d.path(), args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", &err[..err.len().min(300)]);
        assert!(err.len() < 600, "{args:?}: {} bytes", err.len());
        assert!(err.contains("column 'status'") && err.contains("(cut after 80 of 1048576 bytes)"), "{err}");
    }
}
