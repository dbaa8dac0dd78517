//! The default test article under a raid: search protection (docs/model.md §7.3) keeps every
//! radar's background search running when MIMO looks at dozens of tracks would otherwise take
//! the receivers' whole timelines.
//!
//! Every run has a fixed seed.

use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, RunTables};
use mimo_sim::{EngineConfig, SearchConfig, World};
use mimo_ta::registry;
use std::collections::BTreeMap;

/// The stability study's master seed (studies/stability.toml), which also draws the raid.
const SEED: u64 = 20261122;

/// Scenario 7 with the raid of `n` aircraft drawn for its full 1000 s (as `mimo simulate --raid`
/// draws it), cut to `duration_s`.
fn raided(n: u32, duration_s: f64) -> World {
    let mut s = mimo_scenario::load_standard(7).expect("scenario 7");
    mimo_scenario::raid::add_raid(&mut s, n, SEED);
    s.duration_s = duration_s;
    World::new(s).expect("world")
}

/// The dwells of one closed-loop run of the default test article with `rx_busy_share` set.
fn dwells(world: &World, duration_s: f64, rx_busy_share: f64) -> Vec<DwellRow> {
    let mut config = registry::default_config("default").expect("config");
    config["resource_manager"]["rx_busy_share"] = serde_json::json!(rx_busy_share);
    let mut ta = registry::build("default", &config, world).expect("default TA");
    let cfg = EngineConfig {
        seed: SEED,
        duration_s,
        record_voltages: false,
        search: SearchConfig::default(),
        ta_config: serde_json::Value::Null,
    };
    let mut tables = RunTables::default();
    mimo_sim::run_one(world, &cfg, 0, ta.as_mut(), &mut tables).expect("run");
    tables.dwells
}

/// Each radar's share of `[from_s, to_s]` spent on search dwells (dwells starting in it).
fn search_shares(dwells: &[DwellRow], from_s: f64, to_s: f64) -> BTreeMap<RadarId, f64> {
    let mut out: BTreeMap<RadarId, f64> = BTreeMap::new();
    for d in dwells.iter().filter(|d| d.t_s >= from_s && d.t_s < to_s) {
        let s = out.entry(d.radar).or_default();
        if d.kind == DwellKind::Search {
            *s += d.duration_s / (to_s - from_s);
        }
    }
    out
}

/// Under 64 raid aircraft MIMO looks alone leave some radar less than a third of its timeline
/// for search; with search protection at its default every radar keeps at least 40 %, and the
/// MIMO looks still go out (with fewer receivers).
#[test]
fn search_protection_keeps_every_radar_searching_under_a_raid() {
    let duration_s = 300.0;
    let world = raided(64, duration_s);
    let window = (100.0, duration_s);
    let off = dwells(&world, duration_s, 1.0);
    let on = dwells(&world, duration_s, mimo_ta::default_ta::ResourceConfig::default().rx_busy_share);
    let (s_off, s_on) = (search_shares(&off, window.0, window.1), search_shares(&on, window.0, window.1));
    assert_eq!(s_on.len(), 4, "{s_on:?}");
    let min = |s: &BTreeMap<RadarId, f64>| s.values().copied().fold(f64::INFINITY, f64::min);
    assert!(min(&s_off) < 1.0 / 3.0, "without protection the raid should starve a radar's search: {s_off:?}");
    assert!(min(&s_on) >= 0.4, "search protection kept too little search: {s_on:?} (off: {s_off:?})");
    // The policy changes who receives, not whether confirmed tracks get MIMO looks.
    let mimo_groups = |d: &[DwellRow]| {
        let mut g: Vec<u64> = d.iter().filter(|d| d.kind == DwellKind::Mimo).map(|d| d.group_id).collect();
        g.dedup();
        g.len()
    };
    let rx_parts = |d: &[DwellRow]| d.iter().filter(|d| d.kind == DwellKind::Mimo).count();
    let per_look = |d: &[DwellRow]| rx_parts(d) as f64 / mimo_groups(d).max(1) as f64;
    assert!(mimo_groups(&on) > 1000, "{} MIMO looks with protection", mimo_groups(&on));
    assert!(per_look(&on) < per_look(&off), "radars per MIMO look: on {} off {}", per_look(&on), per_look(&off));
}
