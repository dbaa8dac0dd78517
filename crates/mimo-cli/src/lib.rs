//! # mimo-cli
//!
//! Argument parsing, wiring, progress and errors of the `mimo` command. Library crates return
//! typed errors; here they become one-line `error:` messages with exit status 2 when the input
//! was at fault (a file, a field, a flag value) and 1 otherwise. [`main_with_args`] is what the
//! binary runs, and what the end-to-end tests call in-process.

mod cmd_plot;
mod cmd_scenarios;
mod cmd_score;
mod cmd_simulate;
mod cmd_study;
mod cmd_track;
mod error;
mod interrupt;
mod progress;
mod ta_args;
mod usage_error;

pub use error::CliError;

/// `println!` that does not panic when standard output is closed (`mimo score RUN | head -1`):
/// what cannot be printed is dropped and the command finishes as it would have.
#[macro_export]
macro_rules! outln {
    ($($t:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($t)*);
    }};
}

use clap::{Parser, Subcommand};
use std::ffi::OsString;

/// mimo: an open benchmark for MIMO radar tracking.
///
/// Simulate ship-borne S-band monopulse radars down to I/Q voltages, track with a test article,
/// and score track completeness against the energy and dwell time spent.
#[derive(Debug, Parser)]
#[command(name = "mimo", version, about, long_about = None, propagate_version = true)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// List the standard scenarios 1–7, their targets and ships.
    Scenarios(cmd_scenarios::Args),
    /// Run the closed-loop simulation of a scenario and record every table in a run directory.
    ///
    /// Every radar searches on its own; the test article (--tracker) receives every dwell's
    /// detections, forms tracks and orders monostatic and MIMO dwells. Each Monte Carlo run is
    /// written to its own files (truth, dwells, primitives, measurements, tracks, and voltages
    /// with --record voltages) under OUT, with OUT/manifest.json written last. Same seed, same
    /// bytes, whatever --threads is.
    Simulate(cmd_simulate::Args),
    /// Re-run a tracker offline over a recorded run (open loop) into a new run directory.
    ///
    /// Reads RUN's dwells and its primitives (re-forming measurements with the radar model's own
    /// clustering and centroiding) or its measurements, and runs the tracker over them in the
    /// order the closed loop delivered them. The recording's dwell schedule is fixed: a re-run is
    /// OPEN LOOP (the tracker cannot ask for new dwells), so it measures a tracker, not a
    /// resource manager. Writes OUT with new measurements (from primitives), tracks, and a
    /// manifest naming RUN as its parent; `mimo score OUT` reads truth and dwells through it.
    Track(cmd_track::Args),
    /// Score a run: track and usage metrics, summary.json and charts into RUN/score/.
    ///
    /// Reads RUN's tracks and the truth and dwells of RUN (or of its parent, for a `mimo track`
    /// output). A truth is scorable when some radar could see it (horizon, scan limit,
    /// instrumented range). At every scoring time, scorable truths and live confirmed tracks are
    /// paired by a gated, globally optimal assignment. RUN/score/ is derived and reproducible,
    /// so it is replaced (and the command says so).
    Score(cmd_score::Args),
    /// Run a study: methods side by side over scenarios and stress values, scored and charted.
    ///
    /// Every cell (method × scenario × stress point) is an ordinary run directory under
    /// OUT/runs/ in hive-style paths. OUT gets results.parquet (one row per cell and run, with a
    /// failure reason where a method failed), costs.parquet (timings), summary.parquet (means and
    /// 95 % confidence intervals), charts/ (energy against completeness, compute against
    /// accuracy, stability per axis) and report.md. Resumable (--resume) and spread over machines
    /// (--shard K/N, then --merge).
    Study(cmd_study::Args),
    /// Plot a run in 3-D on the globe into one self-contained, offline HTML page.
    ///
    /// Truth, tracks (by id and status), measurements (monostatic and bistatic apart) and the
    /// test article's beams over Natural Earth coastlines, with a time slider, a click panel
    /// (position, SNR, radars, track, assigned truth, 1σ/3σ ellipsoid, sensor lines) and
    /// completeness and energy linked to the 3-D view. Uses RUN/score when present, otherwise
    /// scores run K in memory (nothing is written to RUN).
    Plot(cmd_plot::Args),
}

/// Parse arguments and run; returns the process exit status.
pub fn main_with_args<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cmd = usage_error::allow_negative_numbers(<Cli as clap::CommandFactory>::command());
    let parsed = cmd.try_get_matches_from(args).and_then(|m| <Cli as clap::FromArgMatches>::from_arg_matches(&m));
    let cli = match parsed {
        Ok(c) => c,
        // --help and --version print as clap lays them out; a usage error is one line.
        Err(e) if !e.use_stderr() => {
            let _ = e.print();
            return 0;
        }
        Err(e) => {
            eprintln!("error: {}", usage_error::one_line(&e));
            return 2;
        }
    };
    match run(cli) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("error: {e}");
            e.exit_code()
        }
    }
}

/// Run a parsed command.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        Command::Scenarios(a) => cmd_scenarios::run(a),
        Command::Simulate(a) => cmd_simulate::run(a),
        Command::Track(a) => cmd_track::run(a),
        Command::Score(a) => cmd_score::run(a),
        Command::Study(a) => cmd_study::run(a),
        Command::Plot(a) => cmd_plot::run(a),
    }
}
