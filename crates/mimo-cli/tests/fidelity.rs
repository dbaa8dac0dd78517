//! The fidelity ladder end to end (docs/model.md §4.8): `mimo simulate --fidelity LEVEL` records
//! the level in the manifest, and the closed loop's track completeness at the `measurement` and
//! `auto` rungs agrees with the `voltage` rung's on the same scenario and seeds.

mod common;

use common::{mimo, p};
use mimo_core::records::MeasurementRow;
use std::path::Path;

/// Per-run completeness of a scored run directory.
fn per_run_completeness(run: &Path) -> Vec<f64> {
    assert_eq!(mimo(&["score", p(run), "--no-charts", "--quiet"]), 0);
    let text = std::fs::read_to_string(run.join("score/summary.json")).expect("summary.json");
    let v: serde_json::Value = serde_json::from_str(&text).expect("json");
    v["per_run"]
        .as_array()
        .expect("per_run")
        .iter()
        .map(|r| r["completeness"].as_f64().expect("completeness"))
        .collect()
}

/// Per-run fraction of the measurements with a target hint that are flagged merged.
fn per_run_merged_fraction(run: &Path, runs: u32) -> Vec<f64> {
    (0..runs)
        .map(|k| {
            let path = run.join(format!("measurements/run-{k:04}.parquet"));
            let m: Vec<MeasurementRow> = mimo_store::read_table(&path).expect("measurements");
            let hinted: Vec<&MeasurementRow> = m.iter().filter(|x| x.target_hint.is_some()).collect();
            hinted.iter().filter(|x| x.merged).count() as f64 / hinted.len().max(1) as f64
        })
        .collect()
}

fn mean_var(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    (m, x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0))
}

/// Scenario 7 (the four-fighter formation and three airliners), 4 runs of 300 s at each rung with
/// the same seeds. Band: the difference of the mean completeness within 4 standard errors of a
/// difference of two means (per-run spread of both rungs, 4 runs each), and at least 0.01 (the
/// per-run spread of 4 runs can come out near zero). The end-to-end merged fraction (merged among
/// the measurements with a target hint) of `auto` must be the voltage rung's within the same kind
/// of band (at least 0.005); the measurement rung's is printed, not asserted: it groups only
/// returns within one cell and one beamwidth, so the formation's returns a few cells apart, which
/// the voltage level's clusters flag, are not flagged (docs/decisions/0038-fidelity-ladder.md).
#[test]
fn completeness_agrees_across_the_rungs() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let mut results = Vec::new();
    for level in ["voltage", "measurement", "auto"] {
        let out = tmp.path().join(level);
        let args = [
            "simulate",
            "--scenario",
            "7",
            "--runs",
            "4",
            "--duration",
            "300",
            "--fidelity",
            level,
            "--quiet",
            "--out",
            p(&out),
        ];
        assert_eq!(mimo(&args), 0);
        let m = mimo_store::manifest::Manifest::read(&out).expect("manifest");
        assert_eq!(m.fidelity["level"].as_str(), Some(level), "the manifest records the rung");
        results.push((level, per_run_completeness(&out), per_run_merged_fraction(&out, 4)));
    }
    let (mv, vv) = mean_var(&results[0].1);
    let (fv, fvv) = mean_var(&results[0].2);
    for (level, c, f) in &results[1..] {
        let (mx, vx) = mean_var(c);
        let band = (4.0 * ((vv + vx) / 4.0).sqrt()).max(0.01);
        eprintln!("completeness: voltage {mv:.4}, {level} {mx:.4} (band ±{band:.4}); per run {c:?}");
        assert!((mx - mv).abs() <= band, "{level}: completeness {mx} vs voltage {mv} (band {band})");
        let (fx, fvx) = mean_var(f);
        let fband = (4.0 * ((fvv + fvx) / 4.0).sqrt()).max(0.005);
        eprintln!("merged fraction: voltage {fv:.4}, {level} {fx:.4} (band ±{fband:.4}); per run {f:?}");
        if *level == "auto" {
            assert!((fx - fv).abs() <= fband, "auto: merged fraction {fx} vs voltage {fv} (band {fband})");
        }
    }
    // A bad level is an input error and writes nothing.
    let bad = tmp.path().join("bad");
    assert_eq!(mimo(&["simulate", "--scenario", "1", "--fidelity", "cells", "--quiet", "--out", p(&bad)]), 2);
    assert!(!bad.exists());
}
