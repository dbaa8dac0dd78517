//! One study item end to end: a method that works, and methods that fail in the ways a study
//! must record rather than stop on.

use mimo_core::records::RunTables;
use mimo_study::execute::{ItemRun, run_item};
use mimo_study::plan::Plan;
use mimo_study::prepare::{Prepared, prepare};
use mimo_study::run_usage::RunUsage;
use std::path::Path;

fn plan(methods: &str) -> Plan {
    let text = format!("scenarios = [7]\nruns = 1\nduration_s = 30\n{methods}");
    Plan::parse(&text, Path::new("t.toml")).expect("plan")
}

/// Item 0 of cell `i`, its rows kept in memory.
fn item(p: &Plan, prep: &Prepared, i: usize) -> (ItemRun, RunTables) {
    let mut tables = RunTables::default();
    let r = run_item(p, &prep.cells[i], &prep.worlds[prep.world_of[i]], 0, &mut tables, 1.0, false);
    (r, tables)
}

#[test]
fn a_working_method_completes_and_its_costs_add_up() {
    let p = plan("[[methods]]\nname = \"ekf\"\nta = \"default\"\n");
    let prep = prepare(&p).expect("prepare");
    let (r, tables) = item(&p, &prep, 0);
    assert_eq!((r.failure, r.fault), (None, None));
    assert!(!tables.tracks.is_empty() && r.stats.ta_dwells > 0);
    assert!(tables.tracks.iter().all(|t| t.run == 0));
    // The usage summed as the dwells passed is the usage of the dwells the sink took.
    assert_eq!(r.usage, RunUsage::of(&tables.dwells, 1.0));
    assert!(r.usage.totals[1] > 0.0);
    assert!(r.ta_cpu > std::time::Duration::ZERO && r.ta_cpu < r.cpu, "{:?} of {:?}", r.ta_cpu, r.cpu);
    assert_eq!(r.ta.map(|t| t.name), Some("default".to_string()));
}

#[test]
fn failing_methods_are_recorded_not_fatal() {
    // A process that exits at once, one that answers with garbage, and a method that starts more
    // tracks than the plan allows.
    let p = plan(
        "[limits]\nmax_tracks = 2\n\
         [[methods]]\nname = \"crash\"\nta_cmd = \"sh -c 'exit 3'\"\n\
         [[methods]]\nname = \"garbage\"\nta_cmd = \"sh -c 'read l; echo nonsense; exec sleep 5'\"\n\
         [[methods]]\nname = \"ekf\"\nta = \"default\"\n",
    );
    let prep = prepare(&p).expect("prepare");
    let why = item(&p, &prep, 0).0.failure.expect("the crash is recorded");
    assert!(why.starts_with("test article fault: crashed"), "{why}");
    let why = item(&p, &prep, 1).0.failure.expect("the garbage is recorded");
    assert!(why.starts_with("test article fault: bad reply"), "{why}");
    let (runaway, tables) = item(&p, &prep, 2);
    let why = runaway.failure.expect("the runaway is recorded");
    assert!(why.starts_with("track count ran away"), "{why}");
    assert_eq!(runaway.fault, None, "a failure of the method, not of the sink");
    assert!(!tables.dwells.is_empty(), "the partial run is kept");
}

#[test]
fn the_shipped_plans_read() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../studies");
    for name in ["challenge.toml", "stability.toml"] {
        let p = Plan::read(&root.join(name)).expect(name);
        let prep = prepare(&p).expect("every cell can be flown");
        assert!(!prep.cells.is_empty());
    }
}
