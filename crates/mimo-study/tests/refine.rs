//! Refinement where a family crosses 98 % (docs/studies.md, "Refinement"): on hand-made records of
//! a known curve, each round adds the midpoint of the bracketing frontier points until the
//! rounds are spent, stops once the bracketing energies are within the fraction, and refines a
//! grid along the key that differs.

use mimo_store::schema::STUDY_METRICS;
use mimo_study::Plan;
use mimo_study::grid::{Cell, cells};
use mimo_study::record::ItemCosts;
use mimo_study::refine::next_stage;
use mimo_study::tables::ResultRow;
use std::path::Path;

/// Two runs of a point with completeness `c` and total energy `e` per object.
fn rows(c: f64, e: f64) -> Vec<ResultRow> {
    let metrics: Vec<Option<f64>> = STUDY_METRICS
        .iter()
        .map(|(n, _, _)| match *n {
            "completeness" => Some(c),
            "energy_per_object_j" => Some(e),
            _ => None,
        })
        .collect();
    let costs = ItemCosts { ta_cpu_s: 0.0, sim_cpu_s: 0.0, wall_s: 0.0, kf_cycle_s: None };
    (0..2)
        .map(|run| ResultRow { run, seed: 1, duration_s: 100.0, failure: None, metrics: metrics.clone(), costs })
        .collect()
}

fn plan(sweep: &str, refine: &str) -> Plan {
    let text =
        format!("scenarios = [1]\nruns = 2\n{refine}\n[[methods]]\nname = \"m\"\nta = \"default\"\nsweep = {sweep}\n");
    Plan::parse(&text, Path::new("studies/r.toml")).expect("plan")
}

/// The known curve of a budget `b` (W): completeness and energy.
fn curve(b: f64) -> (f64, f64) {
    let c = if b >= 3.0 { 0.99 + 0.0025 * (b - 3.0) } else { 0.9 + 0.045 * (b - 1.0) };
    (c, 100.0 * b)
}

#[test]
fn each_round_adds_the_midpoint_of_the_bracket_until_the_rounds_are_spent() {
    let mut p = plan("{ \"resource_manager.power_budget_w\" = [1, 5] }", "[refine]\nfraction = 0.05\nrounds = 3");
    let mut cs: Vec<Cell> = cells(&p);
    let record = |p: &Plan, c: &Cell| {
        let (c, e) = curve(p.methods[c.method].knob_value.expect("knob"));
        rows(c, e)
    };
    let mut added = Vec::new();
    for round in 1..=4 {
        let recs: Vec<Vec<ResultRow>> = cs.iter().map(|c| record(&p, c)).collect();
        let stage = next_stage(&p, &cs, &recs, round).expect("stage");
        // The same records give the same stage.
        assert_eq!(next_stage(&p, &cs, &recs, round).expect("again"), stage);
        added.push(stage.methods.iter().map(|m| m.name.clone()).collect::<Vec<_>>());
        assert_eq!(stage.methods.len(), stage.cells.len());
        p.methods.extend(stage.methods);
        cs.extend(stage.cells);
    }
    // 1 W (0.90, 100 J) and 5 W (1.0, 500 J) bracket 98 % at 420 J: 3 W (0.99, 300 J) is added;
    // then 1 W–3 W (0.90–0.99) brackets it: 2 W (0.945); then 2 W–3 W: 2.5 W; the fourth round
    // is beyond the three asked for.
    assert_eq!(added, [vec!["m@3"], vec!["m@2"], vec!["m@2.5"], vec![]]);
    assert!(p.methods[3].refined && !p.methods[0].refined);
}

#[test]
fn refinement_stops_within_the_fraction() {
    // 1 W (0.97, 1000 J) and 2 W (0.99, 1040 J): 98 % at 1020 J, a gap of 3.9 % < 5 %.
    let p = plan("{ \"resource_manager.power_budget_w\" = [1, 2] }", "[refine]\nfraction = 0.05");
    let cs = cells(&p);
    let recs = vec![rows(0.97, 1000.0), rows(0.99, 1040.0)];
    assert!(next_stage(&p, &cs, &recs, 1).expect("stage").cells.is_empty());
    // With 2 % it refines at 1.5 W.
    let p = plan("{ \"resource_manager.power_budget_w\" = [1, 2] }", "[refine]\nfraction = 0.02");
    let stage = next_stage(&p, &cs, &recs, 1).expect("stage");
    assert_eq!(stage.methods.iter().map(|m| m.name.as_str()).collect::<Vec<_>>(), ["m@1.5"]);
    // A crossing outside the sweep is not refined.
    let recs = vec![rows(0.5, 1000.0), rows(0.6, 1040.0)];
    assert!(next_stage(&p, &cs, &recs, 1).expect("stage").cells.is_empty());
}

#[test]
fn a_grid_is_refined_along_the_key_that_differs() {
    let p = plan(
        "{ \"resource_manager.power_budget_w\" = [1, 3], \"resource_manager.max_ta_share\" = [0.2, 0.4] }",
        "[refine]\nfraction = 0.05\nrounds = 1",
    );
    let cs = cells(&p);
    let names: Vec<&str> = cs.iter().map(|c| p.methods[c.method].name.as_str()).collect();
    assert_eq!(
        names,
        [
            "m@max_ta_share:0.2,power_budget_w:1",
            "m@max_ta_share:0.2,power_budget_w:3",
            "m@max_ta_share:0.4,power_budget_w:1",
            "m@max_ta_share:0.4,power_budget_w:3"
        ]
    );
    // Keys in alphabetical order (the share first). Frontier: (0.2, 1 W) 100 J 0.90 → (0.2, 3 W)
    // 300 J 0.99; the share 0.4 points cost more for no more completeness. The bracket differs in
    // the budget only: its midpoint is (0.2, 2 W).
    let recs = vec![rows(0.90, 100.0), rows(0.99, 300.0), rows(0.90, 150.0), rows(0.99, 350.0)];
    let stage = next_stage(&p, &cs, &recs, 1).expect("stage");
    assert_eq!(
        stage.methods.iter().map(|m| m.name.as_str()).collect::<Vec<_>>(),
        ["m@max_ta_share:0.2,power_budget_w:2"]
    );
    assert_eq!(stage.cells.len(), 1);
}

#[test]
fn once_the_frontier_is_settled_a_grid_line_that_could_beat_it_is_refined() {
    let p = plan(
        "{ \"resource_manager.power_budget_w\" = [1, 3], \"resource_manager.max_ta_share\" = [0.2, 0.4] }",
        "[refine]\nfraction = 0.05\nrounds = 1",
    );
    let cs = cells(&p);
    let names = |stage: mimo_study::refine::Stage| stage.methods.iter().map(|m| m.name.clone()).collect::<Vec<_>>();
    // (0.2, 1 W) 0.90 at 100 J, (0.2, 3 W) 0.99 at 1000 J, (0.4, 1 W) 0.95 at 200 J, (0.4, 3 W)
    // 0.985 at 400 J. The frontier is all four; it brackets 98 % between (0.4, 1 W) and (0.4, 3 W)
    // (371 J), 54 % apart: that bracket is refined first, (0.4, 2 W).
    let recs = vec![rows(0.90, 100.0), rows(0.99, 1000.0), rows(0.95, 200.0), rows(0.985, 400.0)];
    assert_eq!(names(next_stage(&p, &cs, &recs, 1).expect("stage")), ["m@max_ta_share:0.4,power_budget_w:2"]);
    // With (0.4, 1 W) at 0.979 and 380 J, (0.4, 3 W) at 395 J, the frontier's bracket is settled
    // (15 J of 381 J). The line of share 0.2 crosses between 100 J and 1000 J: a point on it
    // might reach 98 % for as little as 100 J, so it is refined: (0.2, 2 W).
    let recs = vec![rows(0.90, 100.0), rows(0.99, 1000.0), rows(0.979, 380.0), rows(0.985, 395.0)];
    let stage = next_stage(&p, &cs, &recs, 1).expect("stage");
    assert_eq!(names(stage.clone()), ["m@max_ta_share:0.2,power_budget_w:2"]);
    // Once the family has that point and it is no cheaper way to 98 % (0.93 at 550 J, above the
    // family's 381 J), nothing is left to refine.
    let (mut p2, mut cs2) = (p.clone(), cs.clone());
    p2.methods.extend(stage.methods);
    cs2.extend(stage.cells);
    let mut recs2 = recs.clone();
    recs2.push(rows(0.93, 550.0));
    assert!(next_stage(&p2, &cs2, &recs2, 1).expect("stage").cells.is_empty());
}
