//! Online registration in the closed loop (docs/model.md §6.9): over Monte Carlo runs with biases
//! drawn at the typical σ's (docs/model.md §5.5), the estimate's NEES against the drawn biases
//! lies in its χ² band, and the estimate beats the prior.

use mimo_core::records::RunTables;
use mimo_sim::{EngineConfig, SearchConfig, World};
use mimo_ta::default_ta::{DefaultTa, DefaultTaConfig};
use mimo_ta::registry;
use serde_json::json;

const DURATION_S: f64 = 200.0;
const SEED: u64 = 39;

fn world() -> World {
    let mut s = mimo_scenario::load_standard(1).expect("scenario 1");
    s.duration_s = DURATION_S;
    s.biases.scale = 1.0;
    World::new(s).expect("world")
}

#[test]
fn registration_nees_is_in_its_chi2_band() {
    let w = world();
    let c = registry::resolve_config("default", &json!({ "registration": { "enabled": true } })).expect("config");
    let cfg: DefaultTaConfig = serde_json::from_value(c).expect("typed config");
    let engine = EngineConfig {
        seed: SEED,
        duration_s: DURATION_S,
        record_voltages: false,
        search: SearchConfig::default(),
        ta_config: serde_json::Value::Null,
    };
    let runs = 6u32;
    let n = w.n_radars();
    let (mut nees, mut prior_sq, mut post_sq) = (0.0, 0.0, 0.0);
    for run in 0..runs {
        let mut ta = DefaultTa::new("default", cfg.clone());
        let mut tables = RunTables::default();
        mimo_sim::run_one(&w, &engine, run, &mut ta, &mut tables).expect("run");
        let drawn = w.scenario.biases.draw(SEED, run, n);
        let reg = ta.registration().expect("registration on");
        assert!(reg.looks_used() > 20, "run {run}: {} looks used", reg.looks_used());
        nees += reg.nees(&drawn);
        // The range biases: the estimate's error against the prior's (the drawn value itself).
        for (e, d) in reg.estimate().iter().zip(&drawn) {
            prior_sq += d.range_m.powi(2);
            post_sq += (e.range_m - d.range_m).powi(2);
        }
    }
    // Σ NEES over the runs is χ² with 4 biases × 4 radars × runs degrees of freedom (96: mean 96,
    // σ 13.9); loose band [0.5, 1.8] × 96 for the linearization and the gate.
    let dof = f64::from(runs) * 4.0 * n as f64;
    assert!(nees > 0.5 * dof && nees < 1.8 * dof, "NEES {nees} over {dof} degrees of freedom");
    assert!(post_sq < 0.5 * prior_sq, "range error² {post_sq} against the prior's {prior_sq}");
}
