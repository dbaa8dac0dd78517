//! The usage by purpose of a real closed-loop run (docs/design.md §6): on scenario 7 the default
//! test article confirms false alarms and tracks real objects, the purposes add up to the usage
//! totals, and search is the radars' own background load.

mod common;

use common::{mimo, p};

#[test]
fn a_scenario_7_run_spends_energy_on_false_alarms_and_on_objects() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let run = tmp.path().join("s7");
    let args = ["simulate", "--scenario", "7", "--runs", "1", "--duration", "120", "--quiet", "--out"];
    let mut args = args.to_vec();
    args.push(p(&run));
    assert_eq!(mimo(&args), 0);
    assert_eq!(mimo(&["score", p(&run), "--quiet"]), 0);
    let text = std::fs::read_to_string(run.join("score/summary.json")).expect("summary");
    let json: serde_json::Value = serde_json::from_str(&text).expect("json");
    let usage = &json["usage"];
    let e = |purpose: &str| usage["by_purpose"][purpose]["energy_j"].as_f64().expect("energy");
    let t = |purpose: &str| usage["by_purpose"][purpose]["dwell_time_s"].as_f64().expect("dwell time");
    let names = ["search", "confirm_true", "confirm_false", "track", "track_false"];
    println!("energy by purpose (J): {:?}", names.map(|n| (n, e(n))));
    assert!(e("confirm_false") > 0.0, "looks at false alarms cost energy");
    assert!(e("track") > 0.0, "looks at real objects cost energy");
    assert!(e("confirm_true") > 0.0, "real objects are confirmed");
    // The default test article asks for no search: search is the radars' own, all of it.
    let total = usage["total_energy_j"].as_f64().expect("total");
    let ta = usage["ta_energy_j"].as_f64().expect("ta");
    assert!((e("search") - (total - ta)).abs() <= 1e-9 * total, "search {} vs {}", e("search"), total - ta);
    let sum: f64 = names.iter().map(|n| e(n)).sum();
    assert!((sum - total).abs() <= 1e-9 * total, "{sum} vs {total}");
    let time_sum: f64 = names.iter().map(|n| t(n)).sum();
    let total_t = usage["total_dwell_time_s"].as_f64().expect("time");
    assert!((time_sum - total_t).abs() <= 1e-9 * total_t, "{time_sum} vs {total_t}");
    assert_eq!(json["per_run"][0]["by_purpose"], usage["by_purpose"], "one run: its own figures are the mean");
    for ext in ["png", "svg"] {
        assert!(run.join(format!("score/charts/energy_by_purpose.{ext}")).is_file());
    }
    assert!(run.join("score/usage_by_purpose.parquet").is_file());
}
