//! Helpers shared by the engine's tests and the closed-loop tests of `mimo-ta` (which includes
//! this file by path): standard worlds, configurations, a run into memory, and the counters'
//! consistency with the tables.
#![allow(dead_code)]

use mimo_core::ids::RadarId;
use mimo_core::records::{DwellRow, Requester, RunTables};
use mimo_sim::test_article::TestArticle;
use mimo_sim::{EngineConfig, RunStats, SearchConfig, World};
use std::collections::BTreeMap;

/// Standard scenario `n`, cut to `duration_s`.
pub fn standard(n: u32, duration_s: f64) -> World {
    let mut s = mimo_scenario::load_standard(n).expect("standard scenario");
    s.duration_s = duration_s;
    World::new(s).expect("world")
}

/// An engine configuration with the default search and no voltages.
pub fn config(seed: u64, duration_s: f64) -> EngineConfig {
    EngineConfig {
        seed,
        duration_s,
        record_voltages: false,
        search: SearchConfig::default(),
        ta_config: serde_json::Value::Null,
    }
}

/// Run a test article; the run must succeed.
pub fn run(world: &World, cfg: &EngineConfig, ta: &mut dyn TestArticle) -> (RunTables, RunStats) {
    let mut tables = RunTables::default();
    let stats = mimo_sim::run_one(world, cfg, 0, ta, &mut tables).expect("run");
    (tables, stats)
}

/// Dwell rows per radar, sorted by start time.
pub fn timelines(dwells: &[DwellRow]) -> BTreeMap<RadarId, Vec<&DwellRow>> {
    let mut out: BTreeMap<RadarId, Vec<&DwellRow>> = BTreeMap::new();
    for d in dwells {
        out.entry(d.radar).or_default().push(d);
    }
    for v in out.values_mut() {
        v.sort_by(|a, b| a.t_s.total_cmp(&b.t_s).then(a.dwell_id.cmp(&b.dwell_id)));
    }
    out
}

/// Dwell rows per group.
pub fn groups(dwells: &[DwellRow]) -> BTreeMap<u64, Vec<&DwellRow>> {
    let mut out: BTreeMap<u64, Vec<&DwellRow>> = BTreeMap::new();
    for d in dwells {
        out.entry(d.group_id).or_default().push(d);
    }
    for v in out.values_mut() {
        v.sort_by_key(|d| d.dwell_id);
    }
    out
}

/// When a dwell ends (s).
pub fn end_of(d: &DwellRow) -> f64 {
    d.t_s + d.duration_s
}

/// Consistency of the counters with the tables, for every run a test makes.
pub fn check_stats(t: &RunTables, s: &RunStats) {
    let g = groups(&t.dwells);
    assert_eq!(s.dwells, g.len() as u64);
    assert_eq!(s.search_dwells + s.ta_dwells, s.dwells);
    let search = g.values().filter(|v| v[0].requested_by == Requester::Radar).count() as u64;
    assert_eq!(s.search_dwells, search);
    assert_eq!(s.measurements, t.measurements.len() as u64);
    assert_eq!(s.primitives, t.primitives.len() as u64);
}
