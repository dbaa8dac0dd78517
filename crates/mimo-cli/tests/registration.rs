//! Registration end to end through the binary (docs/model.md §5.5, §6.9; docs/design.md §6,
//! "Registration error"): a scenario with biases, the default test article registering its
//! radars, its estimates in the run's `registration` table, and the score comparing them with the
//! drawn biases; without registration no estimate and no registration error; a `mimo track`
//! re-run keeps its own estimates and is scored against its parent's biases.

mod common;

use common::{mimo, p};
use std::path::Path;

const SCENARIO: &str = r#"name = "s1-biased"
description = "scenario 1 with typical registration biases"
duration_s = 200.0
include = ["builtin:ships.toml", "builtin:fighters.toml", "builtin:airliners.toml"]
targets = ["F-1", "A", "B", "C"]
[fidelity]
two_target = true
[biases]
scale = 1.0
"#;

fn summary(run: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(run.join("score/summary.json")).expect("summary");
    serde_json::from_str(&text).expect("json")
}

fn ok(args: &[&str]) {
    assert_eq!(mimo(args), 0, "{args:?}");
}

#[test]
fn the_default_test_article_registers_its_radars_and_the_score_says_how_well() {
    let d = tempfile::tempdir().expect("tmp");
    let scen = d.path().join("s.toml");
    std::fs::write(&scen, SCENARIO).expect("write");
    let (on, off, re) = (d.path().join("on"), d.path().join("off"), d.path().join("re"));
    let s = p(&scen);
    ok(&["simulate", "--scenario", s, "--runs", "2", "--out", p(&on), "--quiet", "--set", "registration.enabled=true"]);
    ok(&["score", p(&on), "--no-charts", "--quiet"]);
    let est: Vec<mimo_core::records::RegistrationRow> =
        mimo_store::read_table_dir(&on, "registration").expect("registration table");
    // One estimate per radar and run, at the end of the run, learnt from MIMO looks.
    assert_eq!(est.len(), 8);
    assert!(est.iter().all(|r| r.t_s == 200.0 && r.looks > 50), "{est:?}");
    let j = summary(&on);
    let reg = &j["registration"];
    assert_eq!(reg["estimates"], 8);
    // The drawn range biases have σ = 10 m: the estimate is far better than knowing nothing.
    let range_rms = reg["range_error_rms_m"].as_f64().expect("range rms");
    assert!(range_rms < 6.0, "{reg}");
    // Mean of 8 NEES values with 4 degrees of freedom: mean 4, σ 1; a loose band.
    let nees = reg["nees_mean"].as_f64().expect("nees");
    assert!((1.0..9.0).contains(&nees), "{reg}");
    assert!(on.join("score/registration.parquet").is_file());

    // Without registration: the biases are drawn, nothing estimates them, nothing is scored.
    ok(&["simulate", "--scenario", s, "--runs", "1", "--out", p(&off), "--quiet"]);
    ok(&["score", p(&off), "--no-charts", "--quiet"]);
    assert!(summary(&off).get("registration").is_none());
    assert!(!off.join("score/registration.parquet").exists());
    let drawn: Vec<mimo_core::records::BiasRow> = mimo_store::read_table_dir(&off, "biases").expect("biases");
    assert_eq!(drawn.len(), 4);

    // A re-run with registration on keeps its own estimates, scored against the parent's biases.
    ok(&["track", p(&off), "--out", p(&re), "--quiet", "--set", "registration.enabled=true"]);
    ok(&["score", p(&re), "--no-charts", "--quiet"]);
    assert_eq!(summary(&re)["registration"]["estimates"], 4);
}
