//! A whole study end to end: at once, as three shards plus a merge, and resumed after a partial
//! run — the same bytes every way; and a failing method recorded while the others finish.

use arrow::array::{Array, AsArray};
use arrow::datatypes::Float64Type;
use mimo_study::grid::Shard;
use mimo_study::{Options, Plan, run_study};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::path::{Path, PathBuf};

const PLAN: &str = "title = \"test\"\nscenarios = [1]\nruns = 2\nduration_s = 25\n\
    [[methods]]\nname = \"mimo\"\nta = \"default\"\n\
    [[methods]]\nname = \"conventional\"\nta = \"default\"\nconfig = { resource_manager = { mimo = false } }\n\
    [axes]\nrcs_offset_db = [0, -6]\n";

fn opts(out: &Path) -> Options {
    Options { out: out.to_path_buf(), resume: false, force: false, shard: None, merge: false, threads: 2, init: false }
}

fn plan(text: &str, dir: &Path) -> Plan {
    Plan::parse(text, &dir.join("plan.toml")).expect("plan")
}

fn bytes(p: PathBuf) -> Vec<u8> {
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Every file under `dir` except timings, by relative path, with its bytes.
fn tree(dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("dir") {
            let p = e.expect("entry").path();
            if p.is_dir() {
                stack.push(p);
            } else {
                let rel = p.strip_prefix(dir).expect("prefix").to_path_buf();
                let name = rel.to_string_lossy();
                // Timings differ from run to run: costs, the item records (their costs) and the
                // manifests (their timing).
                let timed =
                    name.ends_with("costs.parquet") || name.contains(".items") || name.ends_with("manifest.json");
                let drawn = name.starts_with("charts") || name.ends_with("report.md");
                // Which shard ran where and when: only a sharded study has them.
                let shards = name.starts_with("shards");
                if !timed && !drawn && !shards {
                    out.push((rel, bytes(p)));
                }
            }
        }
    }
    out.sort();
    out
}

#[test]
fn shards_and_resume_give_the_bytes_of_one_run() {
    let tmp = tempfile::tempdir().expect("tmp");
    let p = plan(PLAN, tmp.path());
    let whole = tmp.path().join("whole");
    let o = run_study(&p, PLAN, &opts(&whole), &|_, _| {}).expect("study");
    assert_eq!((o.items, o.ran, o.skipped, o.failed, o.merged.map(|m| m.items)), (8, 8, 0, 0, Some(8)));
    let files = ["results.parquet", "costs.parquet", "summary.parquet", "failure_points.parquet", "report.md"];
    for f in files.iter().chain(&["charts/energy_vs_completeness.png"]) {
        assert!(whole.join(f).is_file(), "{f}");
    }
    assert!(whole.join("charts/stability_rcs_offset_db.svg").is_file());
    // A cell keeps its manifest and its runs' records; the runs' tables went once scored.
    let cell = whole.join("runs/method=mimo/scenario=1/rcs_offset_db=-6");
    let m = mimo_store::manifest::Manifest::read(&cell).expect("cell manifest");
    assert_eq!(m.runs, 2);
    assert_eq!(m.fidelity["stress"]["rcs_offset_db"], serde_json::json!(-6.0));
    assert!(m.tables.is_empty(), "{:?}", m.tables);
    for t in ["truth", "dwells", "measurements", "tracks"] {
        assert!(!cell.join(t).exists(), "{t}/ is left");
    }
    assert!(cell.join(".items/run-0001.json").is_file());
    // The failure points: one row per method and axis.
    let fp = column(&whole.join("failure_points.parquet"), "axis");
    assert_eq!(fp, vec![Some("rcs_offset_db".to_string()); 2]);

    // Three shards on one thread each, then the merge.
    let sharded = tmp.path().join("sharded");
    let mut ran = 0;
    for k in 0..3 {
        let o =
            run_study(&p, PLAN, &Options { shard: Some(Shard { k, n: 3 }), threads: 1, ..opts(&sharded) }, &|_, _| {})
                .expect("shard");
        assert!(o.merged.is_none());
        ran += o.ran;
    }
    assert_eq!(ran, 8);
    assert!(!sharded.join("results.parquet").exists(), "shards do not merge");
    let o = run_study(&p, PLAN, &Options { merge: true, ..opts(&sharded) }, &|_, _| {}).expect("merge");
    assert_eq!((o.ran, o.merged), (0, Some(mimo_study::merge::Merged { items: 8, failed: 0 })));
    let (a, b) = (tree(&whole), tree(&sharded));
    assert_eq!(a.iter().map(|x| &x.0).collect::<Vec<_>>(), b.iter().map(|x| &x.0).collect::<Vec<_>>());
    for ((name, x), (_, y)) in a.iter().zip(&b) {
        assert!(x == y, "{} differs between the whole and the sharded study", name.display());
    }

    // Half a study, then --resume: only the rest runs, and the result is the same.
    let resumed = tmp.path().join("resumed");
    run_study(&p, PLAN, &Options { shard: Some(Shard { k: 1, n: 2 }), ..opts(&resumed) }, &|_, _| {}).expect("half");
    let merge_early = run_study(&p, PLAN, &Options { merge: true, ..opts(&resumed) }, &|_, _| {});
    let e = merge_early.expect_err("an incomplete study does not merge");
    assert!(e.is_input() && e.to_string().contains("4 of 8 runs are not finished"), "{e}");
    assert!(e.to_string().contains("missing by shard: shard 0/2: 4"), "{e}");
    let again = run_study(&p, PLAN, &opts(&resumed), &|_, _| {}).expect_err("no --resume");
    assert!(again.to_string().contains("--resume"), "{again}");
    let o = run_study(&p, PLAN, &Options { resume: true, ..opts(&resumed) }, &|_, _| {}).expect("resume");
    assert_eq!((o.ran, o.skipped, o.merged.map(|m| m.items)), (4, 4, Some(8)));
    assert!(tree(&whole) == tree(&resumed), "resumed study differs");
}

#[test]
fn keep_runs_keeps_every_run_as_a_run_directory() {
    let text = PLAN.replacen("runs = 2", "runs = 2\nkeep_runs = true", 1);
    let tmp = tempfile::tempdir().expect("tmp");
    let p = plan(&text, tmp.path());
    let out = tmp.path().join("kept");
    run_study(&p, &text, &opts(&out), &|_, _| {}).expect("study");
    let cell = out.join("runs/method=mimo/scenario=1/rcs_offset_db=-6");
    let m = mimo_store::manifest::Manifest::read(&cell).expect("cell manifest");
    assert_eq!(m.tables["tracks"].len(), 2);
    assert!(cell.join("tracks/run-0001.parquet").is_file() && cell.join("dwells/run-0000.parquet").is_file());
    // The same results as a study that deleted its runs' tables.
    let deleted = tmp.path().join("deleted");
    run_study(&plan(PLAN, tmp.path()), PLAN, &opts(&deleted), &|_, _| {}).expect("study");
    for f in ["results.parquet", "summary.parquet", "failure_points.parquet", "challenge.parquet"] {
        assert!(bytes(out.join(f)) == bytes(deleted.join(f)), "{f} differs");
    }
}

fn column(path: &Path, name: &str) -> Vec<Option<String>> {
    let f = std::fs::File::open(path).expect("open");
    let r = ParquetRecordBatchReaderBuilder::try_new(f).expect("parquet").build().expect("reader");
    let mut out = Vec::new();
    for b in r {
        let b = b.expect("batch");
        let c = b.column_by_name(name).expect(name);
        if let Some(s) = c.as_string_opt::<i32>() {
            out.extend((0..s.len()).map(|i| s.is_valid(i).then(|| s.value(i).to_string())));
        } else {
            let f = c.as_primitive::<Float64Type>();
            out.extend((0..f.len()).map(|i| f.is_valid(i).then(|| f.value(i).to_string())));
        }
    }
    out
}

#[test]
fn a_failing_method_is_recorded_and_the_others_finish() {
    let text = "scenarios = [1]\nruns = 2\nduration_s = 20\n\
        [[methods]]\nname = \"crashes\"\nta_cmd = \"sh -c 'read line; exit 3'\"\n\
        [[methods]]\nname = \"works\"\nta = \"default\"\n";
    let tmp = tempfile::tempdir().expect("tmp");
    let p = plan(text, tmp.path());
    let out = tmp.path().join("s");
    let o = run_study(&p, text, &opts(&out), &|_, _| {}).expect("the study finishes");
    assert_eq!((o.ran, o.failed, o.merged), (4, 2, Some(mimo_study::merge::Merged { items: 4, failed: 2 })));
    let results = out.join("results.parquet");
    let method = column(&results, "method");
    let failure = column(&results, "failure");
    let completeness = column(&results, "completeness");
    for i in 0..4 {
        if method[i].as_deref() == Some("crashes") {
            let why = failure[i].clone().expect("recorded");
            assert!(why.starts_with("test article fault: crashed"), "{why}");
            assert_eq!(completeness[i], None);
        } else {
            assert_eq!(failure[i], None);
            let c: f64 = completeness[i].as_deref().expect("scored").parse().expect("number");
            assert!((0.0..=1.0).contains(&c));
        }
    }
    let summary = out.join("summary.parquet");
    assert_eq!(column(&summary, "method"), vec![Some("crashes".into()), Some("works".into())]);
    let report = std::fs::read_to_string(out.join("report.md")).expect("report");
    assert!(report.contains("## Failed runs") && report.contains("crashes / scenario 1"), "{report}");
    // No knob is swept and no axis stressed: the challenge section says the energy at 98 % is
    // undefined, and points to no failure-point section the report does not have.
    assert!(report.contains("No method sweeps a knob"), "{report}");
    assert!(!report.contains("Where each method fails"), "{report}");
    // A failed run's partial tables stay for a post-mortem; a completed run's went once scored.
    assert!(out.join("runs/method=crashes/scenario=1/truth/run-0000.parquet").is_file());
    assert!(!out.join("runs/method=works/scenario=1/truth").exists());
}
