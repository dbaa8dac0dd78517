//! `mimo study`.

use crate::CliError;
use mimo_scenario::text_file::{MAX_TEXT_FILE_BYTES, read_text_file};
use mimo_store::layout::StudyDir;
use mimo_study::grid::Shard;
use mimo_study::{Options, Outcome, Plan, StudyError, run_study};
use std::path::PathBuf;

/// Run a study: methods × scenarios × stress values, Monte Carlo runs per cell, all scored.
///
/// Every cell is a run directory under OUT/runs/ in hive-style paths
/// (method=…/scenario=…/axis=value/); a run's tables are deleted once it is scored unless the
/// plan says `keep_runs = true`, which keeps every cell a complete run directory for `mimo
/// score`, `mimo track` and polars. At the end OUT holds results.parquet (one row per cell and
/// run), costs.parquet (timings), summary.parquet (means and 95 % confidence intervals per
/// cell), failure_points.parquet (where each method fails on each axis), charts/, report.md and
/// report.html (the same as one offline page: click a point to list its runs and the command
/// re-creating each with --rerun). A method that fails in a cell is recorded (results.parquet
/// `failure`) and the study goes on. See docs/studies.md.
#[derive(Debug, clap::Args)]
pub struct Args {
    /// The study plan (TOML): methods, scenarios, runs, stress axes.
    pub plan: PathBuf,
    /// The study directory.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Continue a study of the same plan in OUT, redoing only unfinished runs.
    #[arg(long)]
    pub resume: bool,
    /// Run only the K-th of N parts of the (cell × run) list (K from 0, as Slurm array and
    /// Kubernetes job indices); no merge. Shards may share OUT.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Only merge the finished runs of OUT into the study tables, charts and report.
    #[arg(long, conflicts_with_all = ["shard", "resume"])]
    pub merge: bool,
    /// Only create OUT for the plan (or check that it holds this plan's study), after checking
    /// the plan and building its worlds; nothing runs. A batch script does this before it submits
    /// the shards.
    #[arg(long, conflicts_with_all = ["shard", "resume", "merge", "force"])]
    pub init: bool,
    /// Only tell how far the study in OUT is: items done, per shard, failed items; writes nothing.
    #[arg(long, conflicts_with_all = ["shard", "resume", "merge", "force", "init"])]
    pub status: bool,
    /// Only write OUT/report.html again from the study tables and report.md in OUT (nothing runs
    /// or merges; a directory holding only a study's tables, like reports/studies/*, will do).
    #[arg(long, conflicts_with_all = ["shard", "resume", "merge", "force", "init", "status"])]
    pub page: bool,
    /// Only re-run one run of the study's cell CELL (its path under the study's runs/, as
    /// report.html shows it) into the run directory OUT, keeping its tables, for `mimo plot OUT
    /// --run K`: the same plan, seed, cell and run as the study's.
    #[arg(long, value_name = "CELL", conflicts_with_all = ["shard", "resume", "merge", "init", "status", "page"])]
    pub rerun: Option<String>,
    /// The run re-run by --rerun (from 0).
    #[arg(long, value_name = "K", requires = "rerun", default_value_t = 0)]
    pub run: u32,
    /// Replace OUT if it holds a study (never a directory that is not one); with --rerun, if it
    /// holds a run.
    #[arg(long)]
    pub force: bool,
    /// Worker threads [default: all cores]. Results do not depend on it.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
}

fn study_err(e: StudyError) -> CliError {
    if e.is_input() { CliError::Input(e.to_string()) } else { CliError::Other(e.to_string()) }
}

pub fn run(a: Args) -> Result<(), CliError> {
    if a.threads == Some(0) {
        return Err(CliError::input("--threads: expected at least 1"));
    }
    let shard = match &a.shard {
        Some(s) => Some(Shard::parse(s).map_err(|e| CliError::input(format!("--shard: {e}")))?),
        None => None,
    };
    let text = read_text_file(&a.plan, MAX_TEXT_FILE_BYTES).map_err(|e| {
        let msg = format!("{}: cannot read the plan: {e}", a.plan.display());
        if e.is_bad_input() { CliError::input(msg) } else { CliError::Other(msg) }
    })?;
    let plan = Plan::parse(&text, &a.plan).map_err(|e| CliError::input(e.to_string()))?;
    if a.page {
        let path = mimo_study::report_page::write_page(&plan, &a.plan.display().to_string(), &a.out)
            .map_err(|e| if e.is_input() { CliError::Input(e.to_string()) } else { CliError::Other(e.to_string()) })?;
        if !a.quiet {
            crate::outln!("study page -> {}", path.display());
        }
        return Ok(());
    }
    if let Some(cell) = &a.rerun {
        let out = mimo_study::rerun::rerun(&plan, cell, a.run, &a.out, a.force)
            .map_err(|e| if e.is_input() { CliError::Input(e.to_string()) } else { CliError::Other(e.to_string()) })?;
        if !a.quiet {
            let q = |p: &std::path::Path| mimo_study::rerun::quote(&p.display().to_string());
            crate::outln!("re-ran {cell} run {} -> {}", a.run, out.display());
            crate::outln!(
                "open it: mimo plot {} --run {} --out {}",
                q(&out),
                a.run,
                q(&std::path::PathBuf::from(format!("{}.html", out.display())))
            );
        }
        return Ok(());
    }
    if a.status {
        let st = mimo_study::status::study_status(&plan, &text, &a.out).map_err(study_err)?;
        crate::outln!("{}", st.text(&a.out).trim_end());
        return Ok(());
    }
    let opts = Options {
        out: a.out.clone(),
        resume: a.resume,
        force: a.force,
        shard,
        merge: a.merge,
        threads: a.threads.unwrap_or(0),
        init: a.init,
    };
    let pb = crate::progress::bar(0, "study", a.quiet);
    let progress = |done: u64, total: u64| {
        pb.set_length(total);
        pb.set_position(done);
    };
    let t0 = std::time::Instant::now();
    let outcome = run_study(&plan, &text, &opts, &progress).map_err(study_err)?;
    pb.finish_and_clear();
    if !a.quiet {
        say(&a, shard, &outcome, t0.elapsed().as_secs_f64());
    }
    Ok(())
}

/// What the call did, in a sentence or two.
fn say(a: &Args, shard: Option<Shard>, o: &Outcome, wall_s: f64) {
    let (plan, out) = (a.plan.display(), a.out.display());
    if a.init {
        crate::outln!("{out}: ready for {plan} ({} runs in {} cells)", o.items, o.cells);
        return;
    }
    match (shard, o.merged) {
        (_, Some(m)) if a.merge => crate::outln!(
            "merged {} runs of {} cells ({} failed) in {wall_s:.1} s: results, summary, charts and report -> {}",
            m.items,
            o.cells,
            m.failed,
            StudyDir::new(&a.out).report().display()
        ),
        (Some(s), _) => {
            crate::outln!(
                "shard {}/{}: ran {} of its {} runs in {wall_s:.1} s ({} already done, {} failed; the study has {})",
                s.k,
                s.n,
                o.ran,
                o.ran + o.skipped,
                o.skipped,
                o.failed,
                o.items
            );
            crate::outln!("when every shard is done: mimo study {plan} --out {out} --merge");
        }
        (None, _) => {
            crate::outln!(
                "ran {} of {} runs in {wall_s:.1} s ({} already done, {} failed)",
                o.ran,
                o.items,
                o.skipped,
                o.failed
            );
            crate::outln!("results, summary, charts and report -> {}", StudyDir::new(&a.out).report().display());
        }
    }
}
