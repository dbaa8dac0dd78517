//! Running a study: check the plan, prepare the worlds, open the study directory, do the
//! (cell, run) items that are this shard's and not yet done — in parallel, each written
//! atomically — and, unless this is one shard of several, merge (`crate::merge`). A shard notes
//! its start and stop in the study directory (`crate::shard_log`).

use crate::grid::{self, Cell, Item, Shard};
use crate::item::{ItemError, do_item};
use crate::merge::{Merged, merge};
use crate::plan::{Plan, PlanError};
use crate::prepare::{Prepared, prepare};
use crate::record::{RecordError, record_path};
use crate::shard_log::ShardState;
use crate::study_dir::{Access, DirError, StudyMark, open};
use mimo_store::StoreError;
use mimo_store::layout::StudyDir;
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
    /// Only create (or check) the study directory: the plan is checked, its worlds are built,
    /// nothing runs.
    pub init: bool,
}

/// What a call did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outcome {
    /// Cells in the study.
    pub cells: usize,
    /// Items in the study.
    pub items: usize,
    /// Items this call ran.
    pub ran: usize,
    /// Items already done before this call (in this call's share).
    pub skipped: usize,
    /// Items (of those this call ran) whose method failed.
    pub failed: usize,
    /// What the merge found, when this call merged (wrote the study tables, charts and report).
    pub merged: Option<Merged>,
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
    #[error(
        "{}: {missing} of {total} runs are not finished (the first: {first}){shards}; run the missing shards \
         (--status tells which), or --resume",
        dir.display()
    )]
    Incomplete {
        /// The study directory.
        dir: PathBuf,
        /// Missing items.
        missing: usize,
        /// All items.
        total: usize,
        /// The first missing item's cell and run.
        first: String,
        /// The missing items by shard, of the shard count the shards recorded ("" if none did).
        shards: String,
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
    /// The study's page could not be made from its tables.
    #[error(transparent)]
    Page(#[from] crate::page_tables::PageError),
}

impl StudyError {
    /// Whether the user's input is at fault (exit 2) rather than the system (exit 1).
    pub fn is_input(&self) -> bool {
        match self {
            StudyError::Plan(_) | StudyError::Incomplete { .. } => true,
            StudyError::Dir(d) => matches!(d, DirError::Refused { .. }),
            StudyError::Record(r) => matches!(r, RecordError::Bad { .. }),
            StudyError::Page(p) => p.is_input(),
            _ => false,
        }
    }
}

/// The cell directories, in cell order.
pub fn cell_dirs(plan: &Plan, cells: &[Cell], out: &Path) -> Vec<PathBuf> {
    let study = StudyDir::new(out);
    cells.iter().map(|c| study.cell(&c.rel_dir(plan)).root().to_path_buf()).collect()
}

/// Run `todo` on `threads` worker threads, each item starting only when its estimated memory fits
/// beside the worlds' and the other items' in flight (`crate::inflight`); the number of items
/// whose method failed, or the first system fault (which stops the others after their current
/// item).
fn run_items(
    plan: &Plan,
    prep: &Prepared,
    dirs: &[PathBuf],
    todo: &[Item],
    threads: usize,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<usize, StudyError> {
    let total = todo.len() as u64;
    let (done, failed, next) = (AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0));
    // The reference Kalman-filter cycle of this machine, measured before any item competes for
    // the cores (docs/studies.md: compute in machine-independent units).
    let kf_cycle_s = (!todo.is_empty()).then(crate::kfu::measure_kf_cycle_s);
    let worlds: u64 = prep.worlds.iter().map(|w| crate::prepare::world_bytes(&w.scenario, 0)).sum();
    let gate = crate::inflight::InFlight::new(mimo_metrics::memory::MEMORY_BUDGET_BYTES.saturating_sub(worlds));
    let stop = std::sync::atomic::AtomicBool::new(false);
    let first_error: std::sync::Mutex<Option<StudyError>> = std::sync::Mutex::new(None);
    // Plain worker threads pulling items in order, not a rayon pool: a waiting rayon worker
    // could start further items on the same stack and finish them in reverse, so that a study
    // killed midway would have recorded nothing.
    std::thread::scope(|scope| {
        for _ in 0..threads.min(todo.len()).max(1) {
            scope.spawn(|| {
                while !stop.load(Ordering::Relaxed) {
                    let i = next.fetch_add(1, Ordering::Relaxed) as usize;
                    let Some(it) = todo.get(i) else { break };
                    let (cell, world) = (&prep.cells[it.cell], &prep.worlds[prep.world_of[it.cell]]);
                    let share = gate.enter(crate::inflight::item_bytes(world));
                    let done_item = do_item(plan, cell, world, &dirs[it.cell], it.run, kf_cycle_s);
                    drop(share);
                    match done_item {
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
    match first_error.into_inner().ok().flatten() {
        Some(e) => Err(e),
        None => Ok(failed.into_inner() as usize),
    }
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
    // Every cell's directory name fits the file system, checked before anything is written.
    for c in &prep.cells {
        c.check_rel_dir(plan)?;
    }
    // One whole-study writer at a time (docs/studies.md "Shards"): two `--resume` (or a run and
    // a `--merge`) of one study would do the same items into the same files. Shards split the
    // items and take no lock.
    // (A merge of no study is refused by `open`, before a lock's folder is made.)
    let whole = opts.shard.is_none() && !opts.init && (!opts.merge || opts.out.exists());
    let _lock = if whole { Some(study_lock(&opts.out)?) } else { None };
    let shared = opts.resume || opts.shard.is_some() || opts.init;
    open(&opts.out, &mark, Access { resume: shared, force: opts.force, merge: opts.merge })?;
    let mut dirs = cell_dirs(plan, &prep.cells, &opts.out);
    let all = grid::items(prep.cells.len(), plan.runs);
    let mut outcome = Outcome { cells: prep.cells.len(), items: all.len(), ..Outcome::default() };
    if opts.init {
        return Ok(outcome);
    }
    let threads =
        if opts.threads == 0 { std::thread::available_parallelism().map_or(1, |n| n.get()) } else { opts.threads };
    let mut state = opts.shard.map(ShardState::starting);
    if let Some(st) = &state {
        st.write(&opts.out).map_err(|e| shard_io(&opts.out, e))?;
    }
    // Stage 0 is the plan's cells; each refinement round a stage of its own, derived from the
    // records of the stages before it once they are all done (docs/studies.md, "Refinement").
    let (mut plan, mut prep) = (plan.clone(), prep);
    let mut stage_start = 0;
    let mut ran: Result<usize, StudyError> = Ok(0);
    let mut todo_all = 0;
    for round in 0..=plan.refine_rounds {
        if round > 0 {
            if !crate::merge::all_done(&plan, &dirs) {
                break;
            }
            let rows = crate::merge::read_rows(&plan, &dirs)?;
            let stage = crate::refine::next_stage(&plan, &prep.cells, &rows, round)?;
            if stage.cells.is_empty() {
                break;
            }
            stage_start = prep.cells.len();
            extend(&mut plan, &mut prep, stage);
            dirs = cell_dirs(&plan, &prep.cells, &opts.out);
        }
        let all = grid::items(prep.cells.len(), plan.runs);
        // Shards split every stage's items by their index in the whole item list, as the first.
        let mine: Vec<Item> = all
            .iter()
            .enumerate()
            .filter(|(i, it)| it.cell >= stage_start && !opts.merge && opts.shard.is_none_or(|s| i % s.n == s.k))
            .map(|(_, it)| *it)
            .collect();
        let todo: Vec<Item> =
            mine.iter().copied().filter(|it| !record_path(&dirs[it.cell], it.run).is_file()).collect();
        outcome.ran += todo.len();
        outcome.skipped += mine.len() - todo.len();
        todo_all += todo.len();
        let before = ran.as_ref().map_or(0, |x| *x);
        ran = run_items(&plan, &prep, &dirs, &todo, threads, progress).map(|f| f + before);
        if ran.is_err() {
            break;
        }
    }
    (outcome.cells, outcome.items) = (prep.cells.len(), prep.cells.len() * plan.runs as usize);
    if let Some(st) = state.as_mut() {
        st.stopped_unix_s = Some(crate::shard_log::now_unix_s());
        match &ran {
            Ok(failed) => (st.ran, st.failed) = (todo_all, *failed),
            Err(e) => st.error = Some(e.to_string()),
        }
        st.write(&opts.out).map_err(|e| shard_io(&opts.out, e))?;
    }
    outcome.failed = ran?;
    if opts.shard.is_none() || opts.merge {
        outcome.merged = Some(merge(&plan, &prep, &dirs, &opts.out)?);
    }
    Ok(outcome)
}

/// The lock of a whole-study run (`.DIR.lock` beside the study, `mimo_store::output`), or a
/// refusal saying who holds it and what to do instead.
fn study_lock(out: &Path) -> Result<mimo_store::output::OutputLock, StudyError> {
    mimo_store::output::OutputLock::acquire(out).map_err(|e| match e {
        StoreError::Busy { path, why } => StudyError::Store(StoreError::Busy {
            path,
            why: format!(
                "{why}. A study is run whole by one process at a time (a run, --resume or --merge); \
                 to run it in several processes at once, give each a part with --shard K/N, then --merge"
            ),
        }),
        e => e.into(),
    })
}

/// Add a refinement stage's methods and cells to the plan and its prepared cells; a new cell
/// flies in the world of the plan's cells at the same scenario and stress point.
fn extend(plan: &mut Plan, prep: &mut Prepared, stage: crate::refine::Stage) {
    plan.methods.extend(stage.methods);
    for cell in stage.cells {
        let same = |c: &Cell| c.scenario == cell.scenario && c.point == cell.point && c.swept == cell.swept;
        let world = prep.cells.iter().position(same).map_or(0, |c| prep.world_of[c]);
        prep.cells.push(cell);
        prep.world_of.push(world);
    }
}

fn shard_io(out: &Path, source: std::io::Error) -> StudyError {
    StudyError::Store(StoreError::Io { path: StudyDir::new(out).shards(), source })
}
