//! Running a study: check the plan, prepare the worlds, open the study directory, do the
//! (cell, run) items that are this shard's and not yet done — in parallel, each written
//! atomically — and, unless this is one shard of several, merge: cell manifests, the study
//! tables, charts and `report.md`.

use crate::challenge_table::{family_rows, ratio_rows, write_challenge};
use crate::grid::{self, Cell, Item, Shard};
use crate::item::{ItemError, do_item};
use crate::plan::{MethodTa, Plan, PlanError};
use crate::prepare::{Prepared, prepare, search_of};
use crate::record::{ItemRecord, RecordError, record_path};
use crate::study_dir::{Access, DirError, StudyMark, open};
use crate::tables::{summarize, write_results, write_summary};
use mimo_store::StoreError;
use mimo_store::manifest::{MANIFEST_FILE, Manifest, ScenarioInfo, TableFile, TrackerInfo};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

/// How to run a study.
#[derive(Debug, Clone)]
pub struct Options {
    /// The study directory.
    pub out: PathBuf,
    /// Continue a study of the same plan.
    pub resume: bool,
    /// Replace an existing study directory.
    pub force: bool,
    /// Only this shard's items, and no merge.
    pub shard: Option<Shard>,
    /// Only merge the finished items.
    pub merge: bool,
    /// Worker threads (0: all cores). Results do not depend on it.
    pub threads: usize,
}

/// What a call did.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// Items in the study.
    pub items: usize,
    /// Items this call ran.
    pub ran: usize,
    /// Items already done before this call (in this call's share).
    pub skipped: usize,
    /// Items (of those this call ran) whose method failed.
    pub failed: usize,
    /// Whether the study tables, charts and report were written.
    pub merged: bool,
}

/// Why a study stopped.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The plan is wrong (exit 2).
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// The directory cannot be used.
    #[error(transparent)]
    Dir(#[from] DirError),
    /// Items are missing at the merge (exit 2: run the missing shards).
    #[error("{}: {missing} of {total} runs are not finished (the first: {first}); run the missing shards, or --resume", dir.display())]
    Incomplete {
        /// The study directory.
        dir: PathBuf,
        /// Missing items.
        missing: usize,
        /// All items.
        total: usize,
        /// The first missing item's cell and run.
        first: String,
    },
    /// A system fault while running an item.
    #[error(transparent)]
    Item(#[from] ItemError),
    /// A record could not be read.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// Writing tables failed.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// Drawing or writing the report failed.
    #[error("{0}")]
    Report(String),
}

impl StudyError {
    /// Whether the user's input is at fault (exit 2) rather than the system (exit 1).
    pub fn is_input(&self) -> bool {
        match self {
            StudyError::Plan(_) | StudyError::Incomplete { .. } => true,
            StudyError::Dir(d) => matches!(d, DirError::Refused { .. }),
            StudyError::Record(r) => matches!(r, RecordError::Bad { .. }),
            _ => false,
        }
    }
}

/// The cell directories, in cell order.
pub fn cell_dirs(plan: &Plan, cells: &[Cell], out: &Path) -> Vec<PathBuf> {
    cells.iter().map(|c| out.join("runs").join(c.rel_dir(plan))).collect()
}

/// Run (a share of) a study. `progress(done, total)` is called after each item of this call.
pub fn run_study(
    plan: &Plan,
    plan_text: &str,
    opts: &Options,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<Outcome, StudyError> {
    let prep = prepare(plan)?;
    let mark = StudyMark {
        mimo_version: env!("CARGO_PKG_VERSION").to_string(),
        plan_file: plan.file.display().to_string(),
        plan: plan_text.to_string(),
    };
    let shared = opts.resume || opts.shard.is_some();
    open(&opts.out, &mark, Access { resume: shared, force: opts.force, merge: opts.merge })?;
    let dirs = cell_dirs(plan, &prep.cells, &opts.out);
    let all = grid::items(prep.cells.len(), plan.runs);
    let mine: Vec<Item> = match (opts.merge, opts.shard) {
        (true, _) => Vec::new(),
        (false, Some(s)) => s.select(&all),
        (false, None) => all.clone(),
    };
    let todo: Vec<Item> = mine.iter().copied().filter(|it| !record_path(&dirs[it.cell], it.run).is_file()).collect();
    let skipped = mine.len() - todo.len();
    let total = todo.len() as u64;
    let done = AtomicU64::new(0);
    let failed = AtomicU64::new(0);
    // Plain worker threads pulling items in order, not a rayon pool: scoring runs polars, whose
    // own rayon pool would let a waiting rayon worker start further items on the same stack and
    // finish them in reverse, so that a study killed midway would have recorded nothing.
    let threads =
        if opts.threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { opts.threads };
    // The reference Kalman-filter cycle of this machine, measured before any item competes for
    // the cores (docs/studies.md: compute in machine-independent units).
    let kf_cycle_s = (!todo.is_empty()).then(crate::kfu::measure_kf_cycle_s);
    let next = AtomicU64::new(0);
    let stop = std::sync::atomic::AtomicBool::new(false);
    let first_error: std::sync::Mutex<Option<StudyError>> = std::sync::Mutex::new(None);
    std::thread::scope(|scope| {
        for _ in 0..threads.min(todo.len()).max(1) {
            scope.spawn(|| {
                while !stop.load(Ordering::Relaxed) {
                    let i = next.fetch_add(1, Ordering::Relaxed) as usize;
                    let Some(it) = todo.get(i) else { break };
                    let cell = &prep.cells[it.cell];
                    match do_item(plan, cell, &prep.worlds[prep.world_of[it.cell]], &dirs[it.cell], it.run, kf_cycle_s)
                    {
                        Ok(rec) => {
                            if rec.failure.is_some() {
                                failed.fetch_add(1, Ordering::Relaxed);
                            }
                            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
                        }
                        Err(e) => {
                            stop.store(true, Ordering::Relaxed);
                            if let Ok(mut slot) = first_error.lock() {
                                slot.get_or_insert(e.into());
                            }
                        }
                    }
                }
            });
        }
    });
    if let Some(e) = first_error.into_inner().ok().flatten() {
        return Err(e);
    }
    let merged = opts.shard.is_none() || opts.merge;
    if merged {
        merge(plan, &prep, &dirs, &opts.out)?;
    }
    Ok(Outcome { items: all.len(), ran: todo.len(), skipped, failed: failed.into_inner() as usize, merged })
}

/// Read every record; an error names the missing ones.
fn records(plan: &Plan, prep: &Prepared, dirs: &[PathBuf], out: &Path) -> Result<Vec<Vec<ItemRecord>>, StudyError> {
    let mut all = Vec::with_capacity(dirs.len());
    let (mut missing, mut first) = (0usize, None);
    for dir in dirs {
        let mut recs = Vec::new();
        for run in 0..plan.runs {
            let path = record_path(dir, run);
            match ItemRecord::read(&path)? {
                Some(r) => recs.push(r),
                None => {
                    missing += 1;
                    first
                        .get_or_insert_with(|| format!("{} run {run}", dir.strip_prefix(out).unwrap_or(dir).display()));
                }
            }
        }
        all.push(recs);
    }
    match first {
        Some(first) => Err(StudyError::Incomplete {
            dir: out.to_path_buf(),
            missing,
            total: prep.cells.len() * plan.runs as usize,
            first,
        }),
        None => Ok(all),
    }
}

/// A cell's manifest, from its records.
fn cell_manifest(plan: &Plan, prep: &Prepared, c: usize, recs: &[ItemRecord]) -> Result<Manifest, StudyError> {
    let cell = &prep.cells[c];
    let world = &prep.worlds[prep.world_of[c]];
    let json = |v: serde_json::Result<serde_json::Value>| v.map_err(|e| StudyError::Report(e.to_string()));
    let mut fidelity = json(serde_json::to_value(&world.scenario.fidelity))?;
    let stress: serde_json::Map<String, serde_json::Value> =
        cell.point.iter().map(|(a, v)| (a.name().to_string(), serde_json::json!(v))).collect();
    if let Some(obj) = fidelity.as_object_mut() {
        obj.insert("search".into(), json(serde_json::to_value(search_of(cell)))?);
        obj.insert("stress".into(), serde_json::Value::Object(stress));
        if let Some(a) = cell.swept {
            obj.insert("swept".into(), serde_json::json!(a.name()));
        }
    }
    let mut tables: BTreeMap<String, Vec<TableFile>> = BTreeMap::new();
    for r in recs {
        for (name, tf) in &r.tables {
            tables.entry(name.clone()).or_default().push(tf.clone());
        }
    }
    let method = &plan.methods[cell.method];
    let schedule = match &method.ta {
        MethodTa::Builtin { ta, .. } => mimo_ta::registry::schedule_description(ta),
        MethodTa::Process { cmd, .. } => {
            format!("closed loop: background search plus dwells requested by the test article '{cmd}'")
        }
    };
    let mut timing_s = BTreeMap::new();
    timing_s.insert("runs_wall_sum".to_string(), recs.iter().map(|r| r.costs.wall_s).sum());
    Ok(Manifest {
        mimo_version: env!("CARGO_PKG_VERSION").to_string(),
        schema_version: mimo_store::schema::SCHEMA_VERSION,
        scenario: ScenarioInfo {
            name: world.scenario.name.clone(),
            resolved: json(serde_json::to_value(&world.scenario))?,
        },
        seed: plan.seed,
        runs: plan.runs,
        duration_s: world.scenario.duration_s,
        fidelity,
        tracker: recs.iter().find_map(|r| r.ta.clone()).map(|(name, config)| TrackerInfo { name, config }),
        schedule,
        parent: None,
        parent_check: None,
        tables,
        timing_s,
    })
}

fn write_atomic(path: &Path, text: &str) -> Result<(), StudyError> {
    let io = |e: std::io::Error| StudyError::Store(StoreError::Io { path: path.to_path_buf(), source: e });
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&tmp, text).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}

/// Merge: every cell's manifest, the study tables, the charts and the report.
fn merge(plan: &Plan, prep: &Prepared, dirs: &[PathBuf], out: &Path) -> Result<(), StudyError> {
    let recs = records(plan, prep, dirs, out)?;
    for (c, dir) in dirs.iter().enumerate() {
        let m = cell_manifest(plan, prep, c, &recs[c])?;
        write_atomic(&dir.join(MANIFEST_FILE), &m.to_json())?;
    }
    write_results(plan, &prep.cells, &recs, out)?;
    let summaries = summarize(&recs);
    write_summary(plan, &prep.cells, &summaries, out)?;
    let families = family_rows(plan, &prep.cells, &recs);
    let ratios = ratio_rows(plan, &prep.cells, &families);
    write_challenge(plan, &prep.cells, &families, &ratios, out)?;
    let charts = crate::charts::study_charts(plan, &prep.cells, &summaries, &families);
    mimo_store::rundir::replace_dir(&out.join("charts"), |d: &Path| -> Result<(), StudyError> {
        mimo_report::study::render_study(&charts, d).map_err(|e| StudyError::Report(e.to_string()))?;
        Ok(())
    })?;
    let challenge = crate::challenge_report::Challenge { families: &families, ratios: &ratios };
    let report = crate::report::report_md(plan, &prep.cells, &summaries, &recs, &challenge, &charts);
    write_atomic(&out.join("report.md"), &report)?;
    Ok(())
}
