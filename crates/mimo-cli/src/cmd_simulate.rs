//! `mimo simulate`.

use crate::CliError;
use crate::ta_args::TaArgs;
use mimo_scenario::Scenario;
use mimo_sim::{EngineConfig, RunStats, SearchConfig, TaInfo, World};
use mimo_store::manifest::{Manifest, ScenarioInfo, TableFile, TrackerInfo};
use mimo_store::run_sink::ParquetRunSink;
use mimo_store::rundir::RunDirWriter;
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Instant;

use mimo_sim::DEFAULT_SEED;

/// Run the closed-loop simulation of a scenario.
///
/// Every radar searches on its own; the test article (--tracker) receives every dwell's
/// detections, forms tracks and orders monostatic and MIMO dwells. Each Monte Carlo run is
/// written to its own files (truth, dwells, primitives, measurements, tracks, and voltages
/// with --record voltages) under OUT, with OUT/manifest.json written last.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// Standard scenario number 1–7, or the path of a scenario TOML file.
    #[arg(long, value_name = "N|PATH")]
    pub scenario: String,
    /// Number of Monte Carlo runs (above 1000 only with --many-runs; at most 100000).
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub runs: u32,
    /// Allow --runs above 1000 (each run writes five or six files).
    #[arg(long)]
    pub many_runs: bool,
    /// Master random seed (every draw is keyed by seed, run, radar and dwell).
    #[arg(long, default_value_t = DEFAULT_SEED)]
    pub seed: u64,
    /// Simulated duration of each run in seconds [default: the scenario's, 1000 s for 1–7].
    #[arg(long, value_name = "SECONDS")]
    pub duration: Option<f64>,
    /// Worker threads for Monte Carlo runs [default: all cores]. Results do not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Extra tables to record: `voltages` (complex I/Q per range cell; large).
    #[arg(long, value_name = "TABLE")]
    pub record: Vec<String>,
    /// Rung of the fidelity ladder (docs/model.md §4.8): `voltage` (I/Q per cell, ML monopulse),
    /// `measurement` (drawn from the voltage level's statistics, no cells) or `auto` (voltage where
    /// targets are close, measurement elsewhere) [default: the scenario's `[fidelity] level`, auto].
    #[arg(long, value_name = "LEVEL")]
    pub fidelity: Option<String>,
    #[command(flatten)]
    pub ta: TaArgs,
    /// Pulses per background search dwell in the low (0–2.5°) search band.
    #[arg(long, default_value_t = 2, value_name = "N")]
    pub search_pulses: u32,
    /// Add N aircraft to the scenario, drawn from --seed (docs/model.md §8.4): fighters and
    /// airliners crossing the ships' coverage, scored like the scenario's own targets. 0 to 4096.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub raid: Option<String>,
    /// Output run directory (must not exist unless --force).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Replace OUT if it exists.
    #[arg(long)]
    pub force: bool,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
}

/// Most runs without --many-runs (docs/decisions/0035-bounds-and-exit-statuses.md).
pub const RUNS_WITHOUT_FLAG: u32 = 1000;
/// Most search pulses per dwell (the radar's own limit is at most 10 000 pulses, docs/model.md §3.4).
pub const MAX_SEARCH_PULSES: u32 = 1000;
/// Most worker threads.
pub const MAX_THREADS: usize = 4096;

/// Check `--threads` (shared by the commands that take it).
pub fn check_threads(threads: Option<usize>) -> Result<(), CliError> {
    match threads {
        Some(0) => Err(CliError::input("--threads: expected at least 1")),
        Some(n) if n > MAX_THREADS => {
            Err(CliError::input(format!("--threads: {n} is above the limit of {MAX_THREADS}")))
        }
        _ => Ok(()),
    }
}

/// The file a scenario came from, for messages that do not name one (a trajectory that leaves
/// its flight envelope is found only when trajectories are built).
pub fn scenario_error(arg: &str, e: mimo_scenario::ScenarioError) -> CliError {
    match e {
        mimo_scenario::ScenarioError::Envelope { .. } => match arg.trim().parse::<u32>() {
            Ok(n) => CliError::input(format!("scenarios/{n}.toml (standard scenario {n}): {e}")),
            Err(_) => CliError::input(format!("{arg}: {e}")),
        },
        e => CliError::from(e),
    }
}

/// Parse `--fidelity voltage|measurement|auto` (shared by the commands that take it).
pub fn parse_fidelity_level(s: &str) -> Result<mimo_core::params::FidelityLevel, CliError> {
    mimo_core::params::FidelityLevel::parse(s.trim()).ok_or_else(|| {
        CliError::input(format!("--fidelity: unknown level '{s}', expected 'voltage', 'measurement' or 'auto'"))
    })
}

/// Resolve `--scenario`: a number 1–7 or a path.
pub fn load_scenario(arg: &str) -> Result<Scenario, CliError> {
    match arg.trim().parse::<u32>() {
        Ok(n) => Ok(mimo_scenario::load_standard(n)?),
        Err(_) => Ok(mimo_scenario::load_path(arg)?),
    }
}

/// Parse `--raid N`: a whole number of aircraft from 0 to the raid limit.
pub fn parse_raid(text: &str) -> Result<u32, CliError> {
    let max = mimo_scenario::raid::MAX_RAID_TARGETS;
    text.trim().parse::<u32>().ok().filter(|n| *n <= max).ok_or_else(|| {
        CliError::input(format!("--raid: expected a whole number of aircraft from 0 to {max}, got '{text}'"))
    })
}

/// Add `--raid` aircraft to a scenario whose duration is final (their paths depend on it).
fn add_raid(scenario: &mut Scenario, raid: Option<&str>, seed: u64) -> Result<(), CliError> {
    let Some(text) = raid else { return Ok(()) };
    let targets = parse_raid(text)?;
    if targets > 0 {
        let stress =
            mimo_scenario::Stress { raid: Some(mimo_scenario::stress::Raid { targets, seed }), ..Default::default() };
        stress.apply(scenario).map_err(|e| CliError::input(format!("--raid: {e}")))?;
    }
    Ok(())
}

/// `--runs` within its limits.
fn check_runs(a: &Args) -> Result<(), CliError> {
    if a.runs == 0 {
        return Err(CliError::input("--runs: expected at least 1 run"));
    }
    if a.runs > mimo_store::manifest::MAX_RUNS {
        return Err(CliError::input(format!(
            "--runs: {} is above the limit of {}",
            a.runs,
            mimo_store::manifest::MAX_RUNS
        )));
    }
    if a.runs > RUNS_WITHOUT_FLAG && !a.many_runs {
        return Err(CliError::input(format!(
            "--runs: {} is above {RUNS_WITHOUT_FLAG} (each run writes five or six files); add --many-runs to go up to {}",
            a.runs,
            mimo_store::manifest::MAX_RUNS
        )));
    }
    Ok(())
}

/// `--record`: whether voltages are recorded.
fn parse_record(record: &[String]) -> Result<bool, CliError> {
    match record {
        [] => Ok(false),
        r if r.iter().all(|x| x == "voltages") => Ok(true),
        r => {
            let bad: Vec<&String> = r.iter().filter(|x| *x != "voltages").collect();
            Err(CliError::input(format!("--record: unknown table '{}', expected 'voltages'", bad[0])))
        }
    }
}

/// The scenario with `--duration` and `--fidelity` applied, every flag checked (before anything
/// is written).
fn checked_scenario(a: &Args) -> Result<Scenario, CliError> {
    let mut scenario = load_scenario(&a.scenario)?;
    check_runs(a)?;
    if let Some(d) = a.duration {
        if !(d.is_finite() && d > 0.0 && d <= mimo_scenario::MAX_DURATION_S) {
            return Err(CliError::input(format!(
                "--duration: expected seconds in (0, {}], got {d}",
                mimo_scenario::MAX_DURATION_S
            )));
        }
        scenario.duration_s = d;
    }
    check_threads(a.threads)?;
    add_raid(&mut scenario, a.raid.as_deref(), a.seed)?;
    if let Some(f) = &a.fidelity {
        scenario.fidelity.level = parse_fidelity_level(f)?;
    }
    Ok(scenario)
}

/// What the Monte Carlo runs gave: files by table (in run order), totals, the test article.
struct Simulated {
    tables: BTreeMap<String, Vec<TableFile>>,
    stats: RunStats,
    info: TaInfo,
}

fn poisoned<T>(_: T) -> CliError {
    CliError::Other("lock poisoned".into())
}

/// Run every Monte Carlo run, each run's tables streamed into the staging directory as its rows
/// come (memory flat in duration and `--runs`).
fn simulate_runs(
    a: &Args,
    world: &World,
    cfg: &EngineConfig,
    ta: &crate::ta_args::TaChoice,
    writer: &RunDirWriter,
) -> Result<Simulated, CliError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| CliError::Other(format!("thread pool: {e}")))?;
    let runs: Vec<u32> = (0..a.runs).collect();
    let pb = crate::progress::bar(u64::from(a.runs), "simulate", a.quiet);
    let files: Mutex<BTreeMap<String, Vec<TableFile>>> = Mutex::new(BTreeMap::new());
    let totals: Mutex<RunStats> = Mutex::new(RunStats::default());
    let ta_info: Mutex<Option<TaInfo>> = Mutex::new(None);
    let make_ta = |_run: u32| ta.build(world);
    let make_sink = |run: u32| -> Result<ParquetRunSink, CliError> {
        let sink = ParquetRunSink::create(writer, run, cfg.record_voltages)?;
        // The drawn registration biases, only when the scenario has them (docs/model.md §5.5).
        if world.scenario.biases.is_off() {
            Ok(sink)
        } else {
            Ok(sink.with_biases(writer, run)?.with_registration(writer, run)?)
        }
    };
    let done = |run: u32, sink: ParquetRunSink, s: RunStats, info: TaInfo| -> Result<(), CliError> {
        let written = sink.finish()?;
        let mut f = files.lock().map_err(poisoned)?;
        for (name, tf) in written {
            f.entry(name.to_string()).or_default().push(tf);
        }
        totals.lock().map_err(poisoned)?.add(&s);
        let mut i = ta_info.lock().map_err(poisoned)?;
        if run == 0 || i.is_none() {
            *i = Some(info);
        }
        pb.inc(1);
        Ok(())
    };
    pool.install(|| mimo_sim::run_monte_carlo(world, cfg, &runs, &make_ta, &make_sink, &done))?;
    pb.finish_and_clear();
    let mut tables = files.into_inner().map_err(poisoned)?;
    for v in tables.values_mut() {
        v.sort_by(|x, y| x.file.cmp(&y.file));
    }
    let stats = totals.into_inner().map_err(poisoned)?;
    let info = ta_info.into_inner().map_err(poisoned)?.ok_or_else(|| CliError::Other("no run finished".into()))?;
    Ok(Simulated { tables, stats, info })
}

/// The manifest of the finished runs.
fn manifest_of(
    a: &Args,
    world: &World,
    cfg: &EngineConfig,
    schedule: String,
    (tables, info): (BTreeMap<String, Vec<TableFile>>, TaInfo),
    timing: BTreeMap<String, f64>,
) -> Result<Manifest, CliError> {
    let resolved = serde_json::to_value(&world.scenario).map_err(|e| CliError::Other(e.to_string()))?;
    let mut fidelity = serde_json::to_value(&world.scenario.fidelity).map_err(|e| CliError::Other(e.to_string()))?;
    if let Some(obj) = fidelity.as_object_mut() {
        obj.insert("search".into(), serde_json::to_value(&cfg.search).unwrap_or_default());
    }
    Ok(Manifest {
        mimo_version: env!("CARGO_PKG_VERSION").to_string(),
        schema_version: mimo_store::schema::SCHEMA_VERSION,
        scenario: ScenarioInfo { name: world.scenario.name.clone(), resolved },
        seed: a.seed,
        runs: a.runs,
        duration_s: world.scenario.duration_s,
        fidelity,
        tracker: Some(TrackerInfo { name: info.name, config: info.config }),
        schedule,
        parent: None,
        parent_check: None,
        tables,
        timing_s: timing,
    })
}

pub fn run(a: Args) -> Result<(), CliError> {
    let t_start = Instant::now();
    // Validate everything before anything is written.
    let scenario = checked_scenario(&a)?;
    let record_voltages = parse_record(&a.record)?;
    let ta = a.ta.resolve()?;
    if a.search_pulses == 0 || a.search_pulses > MAX_SEARCH_PULSES {
        return Err(CliError::input(format!(
            "--search-pulses: expected 1 to {MAX_SEARCH_PULSES}, got {}",
            a.search_pulses
        )));
    }
    let world = World::new(scenario).map_err(|e| scenario_error(&a.scenario, e))?;
    let t_setup = t_start.elapsed().as_secs_f64();
    let writer = RunDirWriter::create(&a.out, a.force)?;
    let cfg = EngineConfig {
        seed: a.seed,
        duration_s: world.scenario.duration_s,
        record_voltages,
        search: SearchConfig::default().scaled_pulses(a.search_pulses),
        ta_config: ta.overrides().clone(),
    };
    let t_sim = Instant::now();
    let Simulated { tables, stats, info } = simulate_runs(&a, &world, &cfg, &ta, &writer)?;
    let sim_s = t_sim.elapsed().as_secs_f64();
    let mut timing = BTreeMap::new();
    timing.insert("setup".to_string(), t_setup);
    timing.insert("simulate_and_write".to_string(), sim_s);
    timing.insert("total".to_string(), t_start.elapsed().as_secs_f64());
    let manifest = manifest_of(&a, &world, &cfg, ta.schedule(), (tables, info), timing)?;
    let out = writer.finish(&manifest)?;
    let repairs =
        mimo_store::checked::Repairs { rows: stats.repaired_covariances, worst_ratio: stats.worst_covariance_ratio };
    if let Some(w) = repairs.warning(&format!("{}: the test article's track rows", out.display())).filter(|_| !a.quiet)
    {
        eprintln!("{w}");
    }
    if !a.quiet {
        crate::outln!(
            "simulated {} × {} s of {} in {:.1} s: {} dwells ({} search, {} TA), {} measurements -> {}",
            a.runs,
            world.scenario.duration_s,
            world.scenario.name,
            sim_s,
            stats.dwells,
            stats.search_dwells,
            stats.ta_dwells,
            stats.measurements,
            out.display()
        );
    }
    Ok(())
}
