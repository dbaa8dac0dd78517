//! # mimo-cli
//!
//! Argument parsing, wiring, progress and errors of the `mimo` command. Library crates return
//! typed errors; here they become one-line `error:` messages with exit status 2 when the input
//! was at fault (a file, a field, a flag value) and 1 otherwise. [`main_with_args`] is what the
//! binary runs, and what the end-to-end tests call in-process.

mod cmd_scenarios;
mod cmd_score;
mod cmd_simulate;
mod cmd_track;
mod error;
mod progress;

pub use error::CliError;

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
    Simulate(cmd_simulate::Args),
    /// Re-run a tracker offline over a recorded run (open loop) into a new run directory.
    Track(cmd_track::Args),
    /// Score a run: track and usage metrics, summary.json and charts into RUN/score/.
    Score(cmd_score::Args),
}

/// Parse arguments and run; returns the process exit status.
pub fn main_with_args<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return code;
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
    }
}
