//! Running one (cell, run) item: the method's test article in the closed loop on the cell's
//! world, its rows handed to a sink as they come (the cell's table files, [`crate::item`]), with
//! failures caught and recorded instead of stopping the study.

use crate::cpu::thread_cpu;
use crate::grid::Cell;
use crate::guard::Guarded;
use crate::plan::{MethodTa, Plan};
use crate::prepare::search_of;
use crate::run_usage::RunUsage;
use crate::timed::Timed;
use mimo_core::sink::RunSink;
use mimo_sim::test_article::TestArticle;
use mimo_sim::{EngineConfig, EngineError, RunStats, TaInfo, World};
use mimo_ta::process::ProcessTa;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::{Duration, Instant};

/// What one item produced (its rows went to the sink).
pub struct ItemRun {
    /// The transmit usage of the dwells the sink took.
    pub usage: RunUsage,
    /// Engine counters.
    pub stats: RunStats,
    /// What the test article said about itself (for the cell's manifest).
    pub ta: Option<TaInfo>,
    /// Why the run failed; `None` when it completed.
    pub failure: Option<String>,
    /// Why the sink could not take the rows (a fault of the system, not of the method: the
    /// study stops); `None` when it took them all.
    pub fault: Option<String>,
    /// CPU (or, for a process, wall) time inside the test article.
    pub ta_cpu: Duration,
    /// CPU time of the whole item on this thread.
    pub cpu: Duration,
    /// Wall time of the item.
    pub wall: Duration,
    /// The run's drawn registration biases (empty with biases off).
    pub biases: Vec<mimo_core::records::BiasRow>,
    /// The test article's registration estimates (empty if it reported none).
    pub registration: Vec<mimo_core::records::RegistrationRow>,
    /// The run's dwells reduced for its score, when asked for.
    pub dwell_rows: Option<mimo_metrics::DwellRows>,
}

/// The engine settings of a cell.
pub fn engine_config(plan: &Plan, cell: &Cell, world: &World) -> EngineConfig {
    EngineConfig {
        seed: plan.seed,
        duration_s: world.scenario.duration_s,
        record_voltages: plan.tables.iter().any(|t| t == "voltages"),
        search: search_of(cell),
        ta_config: plan.methods[cell.method].overrides.clone(),
    }
}

fn panic_text(p: &(dyn std::any::Any + Send)) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".into())
}

/// Run item `run` of `cell`, its rows handed to `out` as they come (those of a failed run up to
/// its failure) and its usage summed per scoring interval of `interval_s`; with `reduce_dwells`
/// its dwells are also reduced for its score ([`ItemRun::dwell_rows`]). Never fails: a failure
/// of the method is in [`ItemRun::failure`], one of `out` in [`ItemRun::fault`].
pub fn run_item(
    plan: &Plan,
    cell: &Cell,
    world: &World,
    run: u32,
    out: &mut dyn RunSink,
    interval_s: f64,
    reduce_dwells: bool,
) -> ItemRun {
    let (c0, w0) = (thread_cpu(), Instant::now());
    let cfg = engine_config(plan, cell, world);
    let method = &plan.methods[cell.method];
    let deadline = w0 + Duration::from_secs_f64(plan.limits.wall_s_per_run);
    let mut sink = Guarded::new(out, plan.limits.max_tracks, deadline, interval_s);
    if reduce_dwells {
        sink = sink.reducing_dwells(run, interval_s);
    }
    let made: Result<Box<dyn TestArticle + '_>, String> = match &method.ta {
        MethodTa::Builtin { ta, config } => mimo_ta::registry::build(ta, config, world).map_err(|e| e.to_string()),
        MethodTa::Process { cmd, .. } => ProcessTa::spawn(cmd, plan.limits.wall_s_per_run)
            .map(|p| Box::new(p) as Box<dyn TestArticle>)
            .map_err(|e| e.to_string()),
    };
    let mut failure = None;
    let mut stats = RunStats::default();
    let mut ta_info = None;
    let mut ta_cpu = Duration::ZERO;
    match made {
        Err(e) => failure = Some(format!("test article fault: {e}")),
        Ok(inner) => {
            let wall = matches!(method.ta, MethodTa::Process { .. });
            let mut ta = Timed::new(inner, wall);
            let out = catch_unwind(AssertUnwindSafe(|| mimo_sim::run_one(world, &cfg, run, &mut ta, &mut sink)));
            match out {
                Ok(Ok(s)) => stats = s,
                Ok(Err(EngineError::Ta { fault, .. })) => failure = Some(format!("test article fault: {fault}")),
                // The guard's failure, or else the sink's fault (`sink.fault`, below).
                Ok(Err(EngineError::Sink(e))) => failure = sink.failure.clone().or(sink.fault.is_none().then_some(e.0)),
                Err(p) => failure = Some(format!("test article panicked: {}", panic_text(p.as_ref()))),
            }
            ta_info = Some(TaInfo { name: ta.name().to_string(), config: ta.config() });
            ta_cpu = ta.spent;
        }
    }
    ItemRun {
        usage: sink.usage,
        stats,
        ta: ta_info,
        failure,
        fault: sink.fault,
        ta_cpu,
        cpu: thread_cpu().saturating_sub(c0),
        wall: w0.elapsed(),
        biases: sink.biases,
        registration: sink.registration,
        dwell_rows: sink.dwell_rows,
    }
}
