//! End-to-end tests of the `mimo` command, run in-process through `mimo_cli::main_with_args`.

mod common;

use common::{mimo, p};
use mimo_core::records::{MeasurementRow, TrackRow, TruthRow};
use std::path::{Path, PathBuf};

fn files_of(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for t in ["truth", "dwells", "primitives", "measurements", "tracks", "voltages"] {
        if let Ok(rd) = std::fs::read_dir(dir.join(t)) {
            let mut v: Vec<PathBuf> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
            v.sort();
            out.extend(v);
        }
    }
    out
}

#[test]
fn simulate_writes_every_table_and_is_byte_identical_across_thread_counts() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let a = tmp.path().join("a");
    let b = tmp.path().join("b");
    let common = ["simulate", "--scenario", "7", "--runs", "2", "--duration", "40", "--quiet"];
    let mut args_a: Vec<&str> = common.to_vec();
    args_a.extend(["--threads", "1", "--out", p(&a)]);
    assert_eq!(mimo(&args_a), 0);
    let mut args_b: Vec<&str> = common.to_vec();
    args_b.extend(["--threads", "2", "--out", p(&b)]);
    assert_eq!(mimo(&args_b), 0);

    let fa = files_of(&a);
    let fb = files_of(&b);
    assert_eq!(fa.len(), 10, "five tables × two runs: {fa:?}");
    for (x, y) in fa.iter().zip(&fb) {
        assert_eq!(x.file_name(), y.file_name());
        assert_eq!(std::fs::read(x).expect("read"), std::fs::read(y).expect("read"), "{} differs", x.display());
    }
    // Truth: 10 Hz over 40 s for seven targets, in run 1's file with run = 1.
    let truth: Vec<TruthRow> = mimo_store::read_table(&a.join("truth/run-0001.parquet")).expect("truth");
    assert_eq!(truth.len(), 7 * 401);
    assert!(truth.iter().all(|r| r.run == 1));
    let m = mimo_store::manifest::Manifest::read(&a).expect("manifest");
    assert_eq!(m.runs, 2);
    assert_eq!(m.duration_s, 40.0);
    assert_eq!(m.tables["truth"][1].rows, 7 * 401);
    assert!(m.tables.contains_key("measurements"));
    assert_eq!(m.tracker.as_ref().map(|t| t.name.as_str()), Some("default"));
    // A different seed gives different measurements.
    let c = tmp.path().join("c");
    let mut args_c: Vec<&str> = common.to_vec();
    args_c.extend(["--seed", "5", "--out", p(&c)]);
    assert_eq!(mimo(&args_c), 0);
    assert_ne!(
        std::fs::read(a.join("measurements/run-0000.parquet")).expect("read"),
        std::fs::read(c.join("measurements/run-0000.parquet")).expect("read")
    );
}

#[test]
fn voltages_are_recorded_only_when_asked() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let a = tmp.path().join("v");
    let args = ["simulate", "--scenario", "1", "--duration", "3", "--record", "voltages", "--quiet", "--out", p(&a)];
    assert_eq!(mimo(&args), 0);
    let v: Vec<mimo_core::records::VoltageRow> =
        mimo_store::read_table(&a.join("voltages/run-0000.parquet")).expect("voltages");
    assert!(!v.is_empty());
    let b = tmp.path().join("nv");
    assert_eq!(mimo(&["simulate", "--scenario", "1", "--duration", "3", "--quiet", "--out", p(&b)]), 0);
    assert!(!b.join("voltages").exists());
}

#[test]
fn replay_reproduces_the_closed_loop() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let run = tmp.path().join("run");
    assert_eq!(mimo(&["simulate", "--scenario", "5", "--duration", "60", "--quiet", "--out", p(&run)]), 0);
    let from_m = tmp.path().join("m");
    let from_p = tmp.path().join("p");
    assert_eq!(mimo(&["track", p(&run), "--from", "measurements", "--quiet", "--out", p(&from_m)]), 0);
    assert_eq!(mimo(&["track", p(&run), "--from", "primitives", "--quiet", "--out", p(&from_p)]), 0);

    let closed: Vec<TrackRow> = mimo_store::read_table(&run.join("tracks/run-0000.parquet")).expect("tracks");
    assert!(closed.iter().any(|t| t.status == mimo_core::records::TrackStatus::Confirmed));
    for dir in [&from_m, &from_p] {
        let replayed: Vec<TrackRow> = mimo_store::read_table(&dir.join("tracks/run-0000.parquet")).expect("tracks");
        assert_eq!(replayed, closed, "{} differs from the closed loop", dir.display());
        let m = mimo_store::manifest::Manifest::read(dir).expect("manifest");
        // Relative to the re-tracked run's own directory, and resolving to the run.
        assert_eq!(m.parent.as_deref(), Some("../run"));
        assert_eq!(
            mimo_store::lineage::source_dir(dir, &m).expect("parent").canonicalize().ok(),
            run.canonicalize().ok()
        );
    }
    let mut rec: Vec<MeasurementRow> = mimo_store::read_table(&run.join("measurements/run-0000.parquet")).expect("m");
    let re: Vec<MeasurementRow> = mimo_store::read_table(&from_p.join("measurements/run-0000.parquet")).expect("m");
    rec.sort_by_key(|m| m.meas_id);
    assert_eq!(re, rec);
    // The IMM runs on the same recording.
    let imm = tmp.path().join("imm");
    assert_eq!(mimo(&["track", p(&run), "--tracker", "imm", "--quiet", "--out", p(&imm)]), 0);
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let f = dir.join(name);
    std::fs::write(&f, text).expect("write");
    f
}

const GOOD: &str = r#"
name = "mine"
duration_s = 5.0
include = ["builtin:ships.toml", "builtin:airliners.toml"]
targets = ["A"]
"#;

#[test]
fn bad_input_exits_2_and_leaves_nothing() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let o = p(&out).to_string();
    let good = write(tmp.path(), "good.toml", GOOD);
    assert_eq!(mimo(&["simulate", "--scenario", p(&good), "--quiet", "--out", &o]), 0, "a user's own scenario runs");
    std::fs::remove_dir_all(&out).expect("clean");

    let cases: Vec<(&str, String)> = vec![
        ("unknown scenario number", "9".into()),
        ("missing file", p(&tmp.path().join("nope.toml")).into()),
        ("TOML syntax", p(&write(tmp.path(), "syntax.toml", "name = \"x\"\nduration_s = = 3\n")).into()),
        ("unknown field", p(&write(tmp.path(), "field.toml", &format!("{GOOD}\ncolour = \"red\"\n"))).into()),
        (
            "latitude 95",
            p(&write(
                tmp.path(),
                "lat.toml",
                "name = \"x\"\nduration_s = 5.0\ninclude = [\"builtin:airliners.toml\"]\ntargets = [\"A\"]\n[[ships]]\nid = \"R1\"\nlat_deg = 95.0\nlon_deg = 0.0\nheading_deg = 0.0\n",
            ))
            .into(),
        ),
        (
            "negative speed",
            p(&write(
                tmp.path(),
                "speed.toml",
                "name = \"x\"\nduration_s = 5.0\ninclude = [\"builtin:airliners.toml\"]\ntargets = [\"A\"]\n[[ships]]\nid = \"R1\"\nlat_deg = 36.0\nlon_deg = -70.0\nheading_deg = 0.0\nspeed_mps = -3.0\n",
            ))
            .into(),
        ),
        (
            "zero targets",
            p(&write(tmp.path(), "none.toml", "name = \"x\"\nduration_s = 5.0\ninclude = [\"builtin:ships.toml\"]\ntargets = []\n"))
                .into(),
        ),
    ];
    for (what, scenario) in &cases {
        assert_eq!(mimo(&["simulate", "--scenario", scenario, "--quiet", "--out", &o]), 2, "{what}");
        assert!(!out.exists(), "{what}: output left behind");
    }
    // Bad flag values.
    for args in [
        vec!["simulate", "--scenario", "1", "--runs", "0", "--out", &o],
        vec!["simulate", "--scenario", "1", "--duration", "-5", "--out", &o],
        vec!["simulate", "--scenario", "1", "--tracker", "magic", "--out", &o],
        vec!["simulate", "--scenario", "1", "--record", "everything", "--out", &o],
        vec!["simulate", "--scenario", "1", "--bogus-flag", "--out", &o],
    ] {
        assert_eq!(mimo(&args), 2, "{args:?}");
        assert!(!out.exists());
    }
    // Existing output without --force: refused, and the user's file is untouched.
    std::fs::create_dir_all(&out).expect("mkdir");
    let mine = write(&out, "precious.txt", "mine");
    assert_eq!(mimo(&["simulate", "--scenario", "1", "--duration", "2", "--quiet", "--out", &o]), 2);
    assert_eq!(std::fs::read_to_string(&mine).expect("still there"), "mine");
    // --force replaces only a mimo run directory, never a folder of the user's.
    assert_eq!(mimo(&["simulate", "--scenario", "1", "--duration", "2", "--quiet", "--force", "--out", &o]), 2);
    assert!(mine.exists() && !out.join("manifest.json").exists());

    // mimo track on something that is not a run.
    let t_out = tmp.path().join("t");
    assert_eq!(mimo(&["track", p(&tmp.path().join("nope")), "--out", p(&t_out)]), 2);
    assert_eq!(mimo(&["track", p(tmp.path()), "--out", p(&t_out)]), 2);
    assert_eq!(mimo(&["track", &o, "--from", "voltages", "--out", p(&t_out)]), 2);
    assert!(!t_out.exists());
}

#[test]
fn score_writes_summary_and_charts_and_rejects_bad_runs() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let run = tmp.path().join("run");
    assert_eq!(mimo(&["simulate", "--scenario", "1", "--duration", "30", "--quiet", "--out", p(&run)]), 0);
    assert_eq!(mimo(&["score", p(&run), "--quiet"]), 0);
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("score/summary.json")).expect("summary")).expect("json");
    for key in ["scenario", "runs", "interval_s", "gate_m", "track", "usage", "challenge"] {
        assert!(summary.get(key).is_some(), "summary.json lacks {key}");
    }
    for key in ["completeness", "redundant_ratio", "spurious_ratio", "breaks", "switches", "position_rmse_m"] {
        assert!(summary["track"].get(key).is_some(), "summary.json track lacks {key}");
    }
    for r in ["R1", "R2", "R3", "R4"] {
        assert!(summary["usage"]["per_radar"][r]["energy_j"].as_f64().is_some_and(|e| e > 0.0), "{r}");
    }
    assert!(run.join("score/charts/completeness.png").is_file());
    // Scoring again replaces score/.
    assert_eq!(mimo(&["score", p(&run), "--quiet", "--no-charts"]), 0);
    assert!(!run.join("score/charts").exists());

    // A tracked run scores through its parent link; without the parent it is an input error.
    let tracked = tmp.path().join("tracked");
    assert_eq!(mimo(&["track", p(&run), "--from", "measurements", "--quiet", "--out", p(&tracked)]), 0);
    assert_eq!(mimo(&["score", p(&tracked), "--quiet", "--no-charts"]), 0);
    let moved = tmp.path().join("moved");
    std::fs::rename(&run, &moved).expect("move parent away");
    assert_eq!(mimo(&["score", p(&tracked), "--quiet"]), 2);
    std::fs::rename(&moved, &run).expect("move back");

    // No tracks table.
    std::fs::remove_dir_all(run.join("tracks")).expect("rm tracks");
    assert_eq!(mimo(&["score", p(&run), "--quiet"]), 2);
    // A file in tracks/ that is not a tracks table (wrong and missing columns) is refused.
    std::fs::create_dir_all(run.join("tracks")).expect("mkdir");
    std::fs::copy(run.join("truth/run-0000.parquet"), run.join("tracks/run-0000.parquet")).expect("copy");
    assert_eq!(mimo(&["score", p(&run), "--quiet"]), 2);
    // Bad option values.
    assert_eq!(mimo(&["score", p(&tracked), "--gate", "-1", "--quiet"]), 2);
}
