//! Usage errors as one `error:` line (docs/design.md §7): a value a flag cannot take names the
//! flag as typed and the range it accepts (`--runs: expected a whole number of runs from 1 to
//! 1000 (…), got '-1'`), never clap's several lines. Negative numbers are taken as values
//! (`--duration -5` is a duration, refused by its own check), not as unknown flags.

use crate::cmd_simulate::{MAX_SEARCH_PULSES, MAX_THREADS};
use clap::error::{ContextKind, ContextValue, ErrorKind};

/// `cmd` and every subcommand of it taking negative numbers as values.
pub fn allow_negative_numbers(cmd: clap::Command) -> clap::Command {
    let names: Vec<String> = cmd.get_subcommands().map(|s| s.get_name().to_string()).collect();
    names.iter().fold(cmd.allow_negative_numbers(true), |c, n| c.mut_subcommand(n, |s| s.allow_negative_numbers(true)))
}

/// What a whole-number flag accepts, for its error.
fn expected(flag: &str) -> Option<String> {
    Some(match flag {
        "--runs" => {
            format!("a whole number of runs from 1 to 1000 (to {} with --many-runs)", mimo_store::manifest::MAX_RUNS)
        }
        "--threads" => format!("a whole number of threads from 1 to {MAX_THREADS}"),
        "--search-pulses" => format!("a whole number of pulses from 1 to {MAX_SEARCH_PULSES}"),
        "--seed" => format!("a whole number from 0 to {}", u64::MAX),
        "--run" => "a Monte Carlo run id, a whole number from 0".to_string(),
        _ => return None,
    })
}

fn context(e: &clap::Error, kind: ContextKind) -> Option<String> {
    match e.get(kind)? {
        ContextValue::String(s) => Some(s.clone()),
        ContextValue::Strings(v) => Some(v.join(", ")),
        other => Some(other.to_string()),
    }
}

/// The one line to print after `error: ` for a usage error.
pub fn one_line(e: &clap::Error) -> String {
    if matches!(e.kind(), ErrorKind::InvalidValue | ErrorKind::ValueValidation)
        && let (Some(arg), Some(value)) = (context(e, ContextKind::InvalidArg), context(e, ContextKind::InvalidValue))
    {
        // `--runs <N>` → `--runs`
        let flag = arg.split_whitespace().next().unwrap_or(&arg).to_string();
        if let Some(what) = expected(&flag) {
            return format!("{flag}: expected {what}, got {}", mimo_core::quote::quoted(&value));
        }
    }
    let text = e.render().to_string();
    let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("invalid usage");
    let first = first.trim().strip_prefix("error: ").unwrap_or(first.trim());
    let tip = text.lines().map(str::trim).find(|l| l.starts_with("tip:"));
    match tip {
        Some(t) => format!("{first} ({t}; see --help)"),
        None => format!("{first} (see --help)"),
    }
}
