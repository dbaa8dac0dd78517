//! The raid stress through the binary (docs/model.md §8.4): `mimo simulate --raid N` adds N
//! aircraft that the truth table and the scoring treat like the scenario's own targets, and a
//! bad `--raid` or plan `raid_targets` is one `error:` line naming the flag or key, exit 2,
//! nothing written.

mod common;

use common::SMALL;
use std::path::Path;
use std::process::{Command, Output};

const MIMO: &str = env!("CARGO_BIN_EXE_mimo");

const PLAN: &str = r#"
scenarios = ["small.toml"]
runs = 1
[[methods]]
name = "a"
ta = "default"
[axes]
"#;

fn mimo(dir: &Path, args: &[&str]) -> Output {
    Command::new(MIMO).args(args).current_dir(dir).output().expect("mimo runs")
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).expect("ls").flatten().map(|e| e.file_name().to_string_lossy().to_string()).collect();
    v.sort();
    v
}

/// Run `args` in a directory holding small.toml and plan.toml (axes line `axes`); expect exit 2,
/// one `error:` line containing `fragment`, and no new file.
fn refused(args: &[&str], axes: &str, fragment: &str) {
    let t = tempfile::tempdir().expect("tmp");
    std::fs::write(t.path().join("small.toml"), SMALL).expect("write");
    std::fs::write(t.path().join("plan.toml"), format!("{PLAN}{axes}\n")).expect("write");
    let before = entries(t.path());
    let o = mimo(t.path(), args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert!(lines.len() == 1 && lines[0].starts_with("error: "), "{args:?}: {err:?}");
    assert!(lines[0].contains(fragment), "{args:?}: {} lacks {fragment:?}", lines[0]);
    assert_eq!(entries(t.path()), before, "{args:?} wrote something");
}

#[test]
fn a_bad_raid_flag_is_one_error_line_and_writes_nothing() {
    for bad in ["-1", "2.5", "4097", "many", ""] {
        let args = ["simulate", "--scenario", "small.toml", "--raid", bad, "--out", "o"];
        refused(&args, "", "--raid: expected a whole number of aircraft from 0 to 4096");
    }
}

#[test]
fn a_bad_raid_axis_is_one_error_line_naming_the_key() {
    for bad in ["-1", "1.5", "5000", "\"ten\""] {
        let axes = format!("raid_targets = [0, {bad}]");
        refused(&["study", "plan.toml", "--out", "s"], &axes, "axes.raid_targets[1]");
    }
}

fn column_utf8(path: &Path, name: &str) -> Vec<String> {
    use arrow::array::{Array, StringArray};
    let f = std::fs::File::open(path).expect("open");
    let r = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(f).expect("parquet").build();
    let mut out = Vec::new();
    for b in r.expect("reader") {
        let b = b.expect("batch");
        let c = b.column_by_name(name).expect("column");
        let c = c.as_any().downcast_ref::<StringArray>().expect("utf8");
        out.extend((0..c.len()).map(|i| c.value(i).to_string()));
    }
    out
}

#[test]
fn raid_aircraft_are_simulated_and_scored_as_ordinary_targets() {
    let t = tempfile::tempdir().expect("tmp");
    std::fs::write(t.path().join("small.toml"), SMALL).expect("write");
    let o = mimo(t.path(), &["simulate", "--scenario", "small.toml", "--raid", "6", "--out", "r", "--quiet"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m: serde_json::Value =
        serde_json::from_slice(&std::fs::read(t.path().join("r/manifest.json")).expect("manifest")).expect("json");
    let ids: Vec<&str> = m["scenario"]["resolved"]["targets"]
        .as_array()
        .expect("targets")
        .iter()
        .filter_map(|x| x["id"].as_str())
        .collect();
    assert_eq!(ids, ["X", "RAID-0001", "RAID-0002", "RAID-0003", "RAID-0004", "RAID-0005", "RAID-0006"]);
    // The truth table has every target at every truth time (ids in scenario order).
    let truth = t.path().join("r/truth");
    let file = std::fs::read_dir(&truth).expect("truth").flatten().next().expect("a truth file").path();
    let targets = column_utf8(&file, "target");
    let distinct: std::collections::BTreeSet<&str> = targets.iter().map(String::as_str).collect();
    assert_eq!(distinct, ids.iter().copied().collect(), "every target in the truth table");
    assert_eq!(targets.len() % 7, 0);
    // Scoring counts the raid aircraft among the truths it scores.
    let o = mimo(t.path(), &["score", "r"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(t.path().join("r/score/summary.json")).expect("summary")).expect("json");
    let per_target = s["per_target"].as_object().expect("per_target");
    for id in &ids[1..] {
        let scorable = per_target.get(*id).and_then(|t| t["scorable_times"].as_u64());
        assert!(scorable.is_some(), "{id} is scored: {per_target:?}");
    }
}
