//! The default test article under a power budget in the closed loop (docs/model.md §7.6): the
//! windowed transmit power of its dwells, measured from the dwells table, never exceeds the
//! budget; a larger budget spends more; a budget that never binds schedules exactly what no budget
//! does. Every run has a fixed seed.

use mimo_core::ids::RadarId;
use mimo_core::records::{DwellRow, Requester, Role, RunTables};
use mimo_sim::{EngineConfig, SearchConfig, World};
use mimo_ta::registry;
use serde_json::json;
use std::collections::BTreeMap;

const WINDOW_S: f64 = 10.0;

fn world(n: u32, duration_s: f64) -> World {
    let mut s = mimo_scenario::load_standard(n).expect("standard scenario");
    s.duration_s = duration_s;
    World::new(s).expect("world")
}

/// One run of the default test article with these resource-manager overrides.
fn run(world: &World, duration_s: f64, rm: serde_json::Value) -> RunTables {
    let cfg = EngineConfig {
        seed: 20261126,
        duration_s,
        record_voltages: false,
        search: SearchConfig::default(),
        ta_config: serde_json::Value::Null,
    };
    let c = registry::resolve_config("default", &json!({ "resource_manager": rm })).expect("config");
    let mut ta = registry::build("default", &c, world).expect("TA");
    let mut tables = RunTables::default();
    mimo_sim::run_one(world, &cfg, 0, ta.as_mut(), &mut tables).expect("run");
    tables
}

/// The test article's transmit rows (role tx or txrx), per radar, by start time.
fn ta_transmits(dwells: &[DwellRow]) -> BTreeMap<RadarId, Vec<(f64, f64)>> {
    let mut out: BTreeMap<RadarId, Vec<(f64, f64)>> = BTreeMap::new();
    for d in dwells.iter().filter(|d| d.requested_by == Requester::Ta && d.role != Role::Rx) {
        out.entry(d.radar).or_default().push((d.t_s, d.energy_j));
    }
    for v in out.values_mut() {
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    out
}

/// Each radar's largest energy over any window `(t − W, t]` of dwell start times (J): the
/// windows ending at a dwell's start are the ones to check.
fn max_window_energy_j(dwells: &[DwellRow]) -> BTreeMap<RadarId, f64> {
    ta_transmits(dwells)
        .into_iter()
        .map(|(r, v)| {
            let mut best = 0.0f64;
            let (mut lo, mut sum) = (0, 0.0);
            for &(t, e) in &v {
                sum += e;
                while v[lo].0 <= t - WINDOW_S {
                    sum -= v[lo].1;
                    lo += 1;
                }
                best = best.max(sum);
            }
            (r, best)
        })
        .collect()
}

fn ta_energy_j(t: &RunTables) -> f64 {
    ta_transmits(&t.dwells).values().flatten().map(|&(_, e)| e).sum()
}

/// Scenario 7's first 200 s (the formation and the airliners, the densest false-alarm load):
/// under budgets of 0.5, 2 and 8 W each radar's windowed power stays within its budget, the
/// tightest budgets bind (some window is at least 80 % full), and a larger budget spends more
/// energy than a smaller one, while no budget spends more than unlimited.
#[test]
fn windowed_power_never_exceeds_the_budget_and_grows_with_it() {
    let duration_s = 200.0;
    let w = world(7, duration_s);
    let unlimited = ta_energy_j(&run(&w, duration_s, json!({})));
    let mut last: Option<(f64, f64)> = None;
    for budget_w in [0.5, 2.0, 8.0] {
        let t = run(&w, duration_s, json!({ "power_budget_w": budget_w }));
        let cap_j = budget_w * WINDOW_S;
        let windows = max_window_energy_j(&t.dwells);
        for (r, &e) in &windows {
            assert!(e <= cap_j + 1e-9, "{budget_w} W: radar {r:?} spent {e} J in {WINDOW_S} s");
        }
        let fullest = windows.values().copied().fold(0.0, f64::max);
        if budget_w < 8.0 {
            assert!(fullest >= 0.8 * cap_j, "{budget_w} W never binds: fullest window {fullest} J");
        }
        let energy = ta_energy_j(&t);
        assert!(energy <= unlimited, "{budget_w} W spends {energy} J, more than unlimited {unlimited} J");
        if let Some((b0, e0)) = last {
            assert!(energy > e0, "{budget_w} W spends {energy} J, {b0} W spent {e0} J");
        }
        last = Some((budget_w, energy));
    }
}

/// A budget no window ever reaches changes nothing: the same tables as no budget, bit for bit
/// (scenario 1, 150 s).
#[test]
fn a_budget_that_never_binds_is_no_budget() {
    let duration_s = 150.0;
    let w = world(1, duration_s);
    let free = run(&w, duration_s, json!({}));
    let huge = run(&w, duration_s, json!({ "power_budget_w": 1e9 }));
    assert!(!free.dwells.is_empty() && !free.tracks.is_empty());
    assert_eq!(free, huge);
}
