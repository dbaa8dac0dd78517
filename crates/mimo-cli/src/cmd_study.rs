//! `mimo study`.

use crate::CliError;
use mimo_study::grid::Shard;
use mimo_study::{Options, Plan, StudyError, run_study};
use std::path::PathBuf;

/// Run a study: methods × scenarios × stress values, Monte Carlo runs per cell, all scored.
///
/// Every cell is an ordinary run directory under OUT/runs/ in hive-style paths
/// (method=…/scenario=…/axis=value/), so `mimo score` and `mimo track` work on any cell and
/// polars reads the whole study as one partitioned dataset. At the end OUT holds results.parquet
/// (one row per cell and run), costs.parquet (timings), summary.parquet (means and 95 %
/// confidence intervals per cell), charts/ and report.md. A method that fails in a cell is
/// recorded (results.parquet `failure`) and the study goes on. See docs/studies.md.
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
    /// Replace OUT if it holds a study (never a directory that is not one).
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
    let text = std::fs::read_to_string(&a.plan)
        .map_err(|e| CliError::input(format!("{}: cannot read the plan: {e}", a.plan.display())))?;
    let plan = Plan::parse(&text, &a.plan).map_err(|e| CliError::input(e.to_string()))?;
    let opts = Options {
        out: a.out.clone(),
        resume: a.resume,
        force: a.force,
        shard,
        merge: a.merge,
        threads: a.threads.unwrap_or(0),
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
        let share = match shard {
            Some(s) => format!("shard {}/{}: ", s.k, s.n),
            None => String::new(),
        };
        crate::outln!(
            "{share}ran {} of {} runs in {:.1} s ({} already done, {} failed)",
            outcome.ran,
            outcome.items,
            t0.elapsed().as_secs_f64(),
            outcome.skipped,
            outcome.failed
        );
        if outcome.merged {
            crate::outln!("results, summary, charts and report -> {}", a.out.join("report.md").display());
        } else {
            crate::outln!(
                "when every shard is done: mimo study {} --out {} --merge",
                a.plan.display(),
                a.out.display()
            );
        }
    }
    Ok(())
}
