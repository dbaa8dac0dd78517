//! A plan file as TOML gives it: the keys a plan may hold, read by serde with unknown keys
//! refused, before [`crate::plan_check`] checks the values. A TOML error (bad syntax, an unknown
//! key, a value of the wrong type) names the file, the line and column, the key path
//! (`methods[0].config`) and what the key expects: the key path is found from the error's
//! position in the document's own parse tree.

use crate::plan::{Axis, MAX_RUNS, PlanError, TABLES};
use serde::Deserialize;
use std::collections::BTreeMap;
use toml::Value as Toml;
use toml::de::{DeTable, DeValue};

/// The top level of a plan.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawPlan {
    pub(crate) title: Option<String>,
    pub(crate) scenarios: Option<Vec<Toml>>,
    pub(crate) runs: Option<i64>,
    pub(crate) duration_s: Option<f64>,
    pub(crate) fidelity: Option<String>,
    pub(crate) seed: Option<i64>,
    pub(crate) sweep: Option<String>,
    pub(crate) tables: Option<Vec<String>>,
    pub(crate) keep_runs: Option<bool>,
    pub(crate) methods: Option<Vec<RawMethod>>,
    pub(crate) axes: Option<BTreeMap<Axis, Vec<f64>>>,
    pub(crate) limits: Option<RawLimits>,
    pub(crate) refine: Option<RawRefine>,
    pub(crate) frontier_energy: Option<String>,
}

/// A `[refine]` table, or a `[[methods]]` entry's `refine`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawRefine {
    pub(crate) fraction: Option<f64>,
    pub(crate) rounds: Option<i64>,
}

/// A `[[methods]]` entry.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawMethod {
    pub(crate) name: Option<String>,
    pub(crate) ta: Option<String>,
    pub(crate) ta_cmd: Option<String>,
    pub(crate) config: Option<toml::Table>,
    pub(crate) sweep: Option<Toml>,
    pub(crate) architecture: Option<String>,
    pub(crate) refine: Option<RawRefine>,
}

/// The `[limits]` table.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RawLimits {
    pub(crate) wall_s_per_run: Option<f64>,
    pub(crate) max_tracks: Option<i64>,
}

/// What a key expects, for a message about a value of the wrong type (`[i]` in a key path is
/// written `[]` here).
fn expects(key: &str) -> Option<String> {
    let mut k = String::with_capacity(key.len());
    let mut in_index = false;
    for c in key.chars() {
        match c {
            '[' | ']' => {
                in_index = c == '[';
                k.push(c);
            }
            _ if in_index => {}
            _ => k.push(c),
        }
    }
    let s = |s: &str| Some(s.to_string());
    match k.as_str() {
        "title" | "methods[].name" | "methods[].ta" | "methods[].ta_cmd" | "methods[].architecture" => {
            s("expected a string")
        }
        "scenarios" => s("expected a non-empty list of scenario numbers or paths"),
        "runs" => Some(format!("expected a whole number of runs from 1 to {MAX_RUNS}")),
        "duration_s" => Some(format!("expected seconds in (0, {}]", mimo_scenario::MAX_DURATION_S)),
        "fidelity" => s("expected \"voltage\", \"measurement\" or \"auto\""),
        "seed" => s("expected a whole number >= 0"),
        "sweep" => s("expected \"grid\" or \"each\""),
        "tables" | "tables[]" => Some(format!("expected a list of table names ({})", TABLES.join(", "))),
        "keep_runs" => s("expected true or false"),
        "methods" => s("expected at least one [[methods]] table"),
        "methods[]" => s("expected a table with name and ta (or ta_cmd)"),
        "methods[].config" => s("expected a table of the test article's configuration"),
        "axes" => s("expected a table of axis = [values]"),
        "limits" => s("expected a table"),
        "limits.wall_s_per_run" => s("expected a positive number of seconds"),
        "limits.max_tracks" => s("expected a whole number >= 1"),
        "refine" | "methods[].refine" => s("expected a table { fraction = 0.05, rounds = 3 }"),
        "refine.fraction" | "methods[].refine.fraction" => s("expected a number in (0, 1)"),
        "refine.rounds" | "methods[].refine.rounds" => s("expected a whole number from 0 to 20"),
        "frontier_energy" => s("expected \"total\" or \"test_article\""),
        _ if k.starts_with("axes.") && k.ends_with("[]") => s("expected a number"),
        _ if k.starts_with("axes.") => s("expected a non-empty list of numbers"),
        _ => None,
    }
}

/// `line:column` (from 1) of byte `pos` of `text`.
fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let before = &text[..pos.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

fn inside(span: std::ops::Range<usize>, pos: usize) -> bool {
    span.contains(&pos) || span.start == pos
}

/// The key path of the deepest key or value of `v` at byte `pos` (`path` is `v`'s own).
fn path_at(v: &DeValue, pos: usize, path: &str) -> Option<String> {
    match v {
        DeValue::Table(t) => t.iter().find_map(|(k, val)| {
            let p = if path.is_empty() { k.get_ref().to_string() } else { format!("{path}.{}", k.get_ref()) };
            if inside(k.span(), pos) {
                return Some(p);
            }
            path_at(val.get_ref(), pos, &p).or_else(|| inside(val.span(), pos).then_some(p))
        }),
        DeValue::Array(a) => a.iter().enumerate().find_map(|(i, e)| {
            let p = format!("{path}[{i}]");
            path_at(e.get_ref(), pos, &p).or_else(|| inside(e.span(), pos).then_some(p))
        }),
        _ => None,
    }
}

/// serde's "unknown field `x`, expected one of `a`, `b`" as the plan's own words.
fn unknown_key(message: &str) -> Option<String> {
    if !(message.starts_with("unknown field") || message.starts_with("unknown variant")) {
        return None;
    }
    let known = message.split_once("expected ").map_or("", |(_, k)| k).trim_start_matches("one of ").replace('`', "");
    Some(format!("unknown key (expected one of: {known})"))
}

/// A TOML error as a plan error: file, line and column, key path and expectation.
fn toml_error(text: &str, file: &str, e: &toml::de::Error) -> PlanError {
    let err = |key: String, expected: String, at| PlanError { file: file.to_string(), key, expected, at };
    let Some(span) = e.span() else { return err("(toml)".into(), format!("not valid TOML: {}", e.message()), None) };
    let at = Some(line_col(text, span.start));
    let Ok(tree) = DeTable::parse(text) else {
        return err("(toml)".into(), format!("not valid TOML: {}", e.message().trim()), at);
    };
    let root = DeValue::Table(tree.into_inner());
    let key = path_at(&root, span.start, "").unwrap_or_else(|| "(toml)".into());
    let got = text.get(span.clone()).map(str::trim).filter(|g| !g.is_empty() && g.len() <= 60);
    let expected = match (unknown_key(e.message()), expects(&key)) {
        (Some(u), _) => u,
        (None, Some(x)) => match got {
            Some(g) => format!("{x}, got {g}"),
            None => x,
        },
        (None, None) => e.message().trim().to_string(),
    };
    err(key, expected, at)
}

/// Read a plan's keys and their types.
pub(crate) fn read(text: &str, file: &str) -> Result<RawPlan, PlanError> {
    toml::from_str(text).map_err(|e| toml_error(text, file, &e))
}
