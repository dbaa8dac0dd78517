//! Errors of the view builder. Each names the file, flag or field at fault, so the CLI prints it
//! on one `error:` line (exit status 2 for bad input, design.md §7).

use std::path::PathBuf;
use thiserror::Error;

/// Everything that can go wrong while building a view.
#[derive(Debug, Error)]
pub enum PlotError {
    /// A table or manifest could not be read or is malformed.
    #[error(transparent)]
    Store(#[from] mimo_store::StoreError),

    /// The scoring engine refused its input or failed.
    #[error(transparent)]
    Metrics(#[from] mimo_metrics::MetricsError),

    /// The manifest's resolved scenario is not a valid scenario.
    #[error("{}: field 'scenario.resolved': {why}", file.display())]
    Scenario {
        /// The manifest file.
        file: PathBuf,
        /// What is wrong.
        why: String,
    },

    /// A run directory named by `parent` does not exist.
    #[error("{}: field 'parent': run directory '{parent}' not found (expected the run this one was tracked from)", file.display())]
    MissingParent {
        /// The manifest naming the parent.
        file: PathBuf,
        /// The parent as written.
        parent: String,
    },

    /// `--run K` names a run the recording does not hold.
    #[error("--run {run}: no such run in {} (it holds runs 0 to {last})", dir.display())]
    NoSuchRun {
        /// The run directory.
        dir: PathBuf,
        /// The run asked for.
        run: u32,
        /// The last run id present.
        last: u32,
    },

    /// The time window is empty, reversed or outside the run.
    #[error(
        "--from/--to: window [{from_s} s, {to_s} s] is outside the run (0 to {duration_s} s; expected 0 <= FROM < TO <= {duration_s})"
    )]
    BadWindow {
        /// Window start (s).
        from_s: f64,
        /// Window end (s).
        to_s: f64,
        /// The run's duration (s).
        duration_s: f64,
    },

    /// The output exists and `--force` was not given.
    #[error("{}: already exists (use --force to replace it)", path.display())]
    Exists {
        /// The output file.
        path: PathBuf,
    },

    /// The output cannot be written.
    #[error("{}: cannot write the page: {why}", path.display())]
    Io {
        /// The output file.
        path: PathBuf,
        /// The system's reason.
        why: String,
    },

    /// A failure that is not the input's fault.
    #[error("{0}")]
    Internal(String),

    /// A score table exists but cannot be used.
    #[error("{}: {why}", file.display())]
    BadScore {
        /// The score file.
        file: PathBuf,
        /// What is wrong.
        why: String,
    },
}

impl PlotError {
    /// Whether the user's input is at fault (exit status 2) rather than an internal failure (1).
    pub fn is_bad_input(&self) -> bool {
        match self {
            PlotError::Store(e) => e.is_input_error(),
            PlotError::Metrics(e) => e.is_bad_input(),
            PlotError::Io { .. } | PlotError::Internal(_) => false,
            _ => true,
        }
    }
}
