//! Closed-loop throughput, single thread: `cargo bench -p mimo-ta`.
//!
//! For standard scenarios 1 and 7 (1000 s, one run, seed 1): the closed loop with the default
//! test article (engine, radar model and tracker together), background search alone (the `none`
//! TA), and the tracker alone (an open-loop replay of the recorded measurements with
//! `mimo_sim::replay::replay`, which feeds the tracker every recorded dwell, search included).
//! Prints wall times, dwells per second, measurements per second, tracker dwells and
//! measurements per second, whether the replay reproduced the closed loop's tracks, and the
//! peak resident memory (VmHWM, reset before each scenario where the kernel allows it, so it
//! covers that scenario's closed loop, replay and search-only run). Plain `std::time`, no
//! harness. `cargo bench -p mimo-ta -- 7` runs scenario 7 only.

use mimo_core::records::RunTables;
use mimo_sim::{EngineConfig, SearchConfig, World};
use mimo_ta::passive::Passive;
use mimo_ta::registry;
use mimo_ta::replay::{ReplayFrom, replay};
use std::time::Instant;

/// Peak resident set size of this process (MiB), from /proc/self/status.
fn peak_rss_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib / 1024.0)
}

/// Reset the peak RSS to the current RSS (Linux: write 5 to clear_refs). False if not allowed.
fn reset_peak_rss() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

struct Row {
    scenario: u32,
    dwells: u64,
    measurements: u64,
    closed_s: f64,
    search_only_s: f64,
    search_dwells: u64,
    replay_s: f64,
    replayed: u64,
    replayed_dwells: u64,
    replay_identical: bool,
    peak_mib: Option<f64>,
}

fn bench(n: u32) -> Result<Row, Box<dyn std::error::Error>> {
    let scenario = mimo_scenario::load_standard(n)?;
    let world = World::new(scenario)?;
    let cfg = EngineConfig {
        seed: 1,
        duration_s: world.scenario.duration_s,
        record_voltages: false,
        search: SearchConfig::default(),
        ta_config: serde_json::Value::Null,
    };
    let config = registry::default_config("default")?;

    let t = Instant::now();
    let mut ta = registry::build("default", &config, &world)?;
    let mut tables = RunTables::default();
    let stats = mimo_sim::run_one(&world, &cfg, 0, ta.as_mut(), &mut tables)?;
    let closed_s = t.elapsed().as_secs_f64();

    let t = Instant::now();
    let mut ta = registry::build("default", &config, &world)?;
    let mut out = RunTables::default();
    let rs = replay(
        &world,
        &cfg,
        ta.as_mut(),
        0,
        &tables.dwells,
        &[],
        &tables.measurements,
        ReplayFrom::Measurements,
        &mut out,
    )?;
    let replay_s = t.elapsed().as_secs_f64();
    let replay_identical = out.tracks == tables.tracks;
    drop(tables);

    let t = Instant::now();
    let search_stats = mimo_sim::run_one(&world, &cfg, 0, &mut Passive, &mut RunTables::default())?;
    let search_only_s = t.elapsed().as_secs_f64();

    Ok(Row {
        scenario: n,
        dwells: stats.dwells,
        measurements: stats.measurements,
        closed_s,
        search_only_s,
        search_dwells: search_stats.dwells,
        replay_s,
        replayed: rs.measurements,
        replayed_dwells: rs.dwells,
        replay_identical,
        peak_mib: peak_rss_mib(),
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // `cargo bench` passes `--bench`; a name filter may follow.
    let filter: Vec<String> = std::env::args().skip(1).filter(|a| !a.starts_with("--")).collect();
    let scenarios: Vec<u32> =
        [1u32, 7].into_iter().filter(|n| filter.is_empty() || filter.iter().any(|f| f == &n.to_string())).collect();
    let resettable = reset_peak_rss();
    let mut rows = Vec::new();
    for n in scenarios {
        reset_peak_rss();
        let row = bench(n)?;
        eprintln!("scenario {n} done");
        rows.push(row);
    }
    let rss = if resettable { "peak RSS MiB" } else { "peak RSS MiB (cumulative)" };
    println!("mimo-ta closed loop, 1000 s, 1 run, seed 1, single thread");
    println!(
        "| scenario | closed loop s | dwells | dwells/s | measurements | measurements/s | search-only s | search dwells/s | \
         replay s | tracker dwells/s | tracker measurements/s | replay = closed loop | {rss} |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        println!(
            "| {} | {:.2} | {} | {:.0} | {} | {:.0} | {:.2} | {:.0} | {:.3} | {:.0} | {:.0} | {} | {} |",
            r.scenario,
            r.closed_s,
            r.dwells,
            r.dwells as f64 / r.closed_s,
            r.measurements,
            r.measurements as f64 / r.closed_s,
            r.search_only_s,
            r.search_dwells as f64 / r.search_only_s,
            r.replay_s,
            r.replayed_dwells as f64 / r.replay_s,
            r.replayed as f64 / r.replay_s,
            if r.replay_identical { "yes" } else { "NO" },
            r.peak_mib.map_or("n/a".to_string(), |m| format!("{m:.0}")),
        );
    }
    Ok(())
}
