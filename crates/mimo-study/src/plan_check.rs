//! The validate step of a plan: every value read by [`crate::plan_toml`] checked against what it
//! may be — scenario numbers, run counts, durations, table names, axis ranges, the methods' test
//! articles and configurations — each error naming the plan file, the key path and what was
//! expected.

use crate::frontier_energy::FrontierEnergy;
use crate::method_sweep;
use crate::plan::{
    Architecture, Axis, Ctx, Limits, MAX_RUNS, Method, MethodTa, Plan, PlanError, ScenarioRef, Sweep, TABLES,
    config_err,
};
use crate::plan_toml::{RawLimits, RawMethod, RawPlan};
use crate::refine::Refine;
use mimo_ta::registry;
use serde_json::Value;
use std::collections::BTreeMap;
use std::path::Path;
use toml::Value as Toml;

fn scenarios(ctx: &Ctx, raw: Option<Vec<Toml>>, base: &Path) -> Result<Vec<ScenarioRef>, PlanError> {
    let list = raw.filter(|a| !a.is_empty());
    let list = list.ok_or_else(|| ctx.err("scenarios", "expected a non-empty list of scenario numbers or paths"))?;
    list.iter()
        .enumerate()
        .map(|(i, v)| match v {
            Toml::Integer(n) if (1..=i64::from(*mimo_scenario::STANDARD_SCENARIOS.end())).contains(n) => {
                Ok(ScenarioRef::Standard(*n as u32))
            }
            Toml::String(s) => Ok(ScenarioRef::File(base.join(s))),
            _ => Err(ctx.err(
                format!("scenarios[{i}]"),
                format!("expected a standard scenario number 1–7 or a file path, got {v}"),
            )),
        })
        .collect()
}

fn runs(ctx: &Ctx, raw: Option<i64>) -> Result<u32, PlanError> {
    match raw {
        Some(n) if (1..=i64::from(MAX_RUNS)).contains(&n) => Ok(n as u32),
        Some(n) => Err(ctx.err("runs", format!("expected a whole number of runs from 1 to {MAX_RUNS}, got {n}"))),
        None => Err(ctx.err("runs", "missing: Monte Carlo runs per cell")),
    }
}

fn duration_s(ctx: &Ctx, raw: Option<f64>) -> Result<Option<f64>, PlanError> {
    let max = mimo_scenario::MAX_DURATION_S;
    match raw {
        Some(d) if !(d > 0.0 && d <= max) => {
            Err(ctx.err("duration_s", format!("expected seconds in (0, {max}], got {d}")))
        }
        d => Ok(d),
    }
}

fn tables(ctx: &Ctx, raw: Option<Vec<String>>) -> Result<Vec<String>, PlanError> {
    let Some(out) = raw else { return Ok(["truth", "dwells", "measurements", "tracks"].map(String::from).to_vec()) };
    for (i, s) in out.iter().enumerate() {
        if !TABLES.contains(&s.as_str()) {
            return Err(ctx.err(format!("tables[{i}]"), format!("expected one of {}", TABLES.join(", "))));
        }
    }
    for needed in ["truth", "dwells", "tracks"] {
        if !out.iter().any(|x| x == needed) {
            return Err(ctx.err("tables", format!("must include {needed} (scoring reads truth, dwells and tracks)")));
        }
    }
    Ok(out)
}

fn axes(ctx: &Ctx, raw: Option<BTreeMap<Axis, Vec<f64>>>) -> Result<Vec<(Axis, Vec<f64>)>, PlanError> {
    let mut out = Vec::new();
    for (axis, list) in raw.unwrap_or_default() {
        let key = format!("axes.{}", axis.name());
        if list.is_empty() {
            return Err(ctx.err(&key, "expected a non-empty list of values"));
        }
        for (i, &x) in list.iter().enumerate() {
            let k = format!("{key}[{i}]");
            if !x.is_finite() {
                return Err(ctx.err(&k, format!("expected a finite number, got {x}")));
            }
            axis.check(x).map_err(|e| ctx.err(&k, e))?;
            if list[..i].contains(&x) {
                return Err(ctx.err(&k, format!("{x} is listed twice")));
            }
        }
        out.push((axis, list));
    }
    Ok(out)
}

fn limits(ctx: &Ctx, raw: Option<RawLimits>) -> Result<Limits, PlanError> {
    let mut limits = Limits::default();
    let Some(l) = raw else { return Ok(limits) };
    if let Some(x) = l.wall_s_per_run {
        if !x.is_finite() || x <= 0.0 {
            return Err(ctx.err("limits.wall_s_per_run", "expected a positive number of seconds"));
        }
        limits.wall_s_per_run = x;
    }
    if let Some(n) = l.max_tracks {
        if n < 1 {
            return Err(ctx.err("limits.max_tracks", format!("expected a whole number >= 1, got {n}")));
        }
        limits.max_tracks = n as u64;
    }
    Ok(limits)
}

/// The test article of entry `p` (`methods[i]`).
fn method_ta(ctx: &Ctx, p: &str, m: &RawMethod, overrides: &Value) -> Result<MethodTa, PlanError> {
    match (&m.ta, &m.ta_cmd) {
        (Some(_), Some(_)) => Err(ctx.err(p, "expected either ta or ta_cmd, not both")),
        (None, None) => Err(ctx.err(format!("{p}.ta"), "missing: a built-in test article (ta) or a command (ta_cmd)")),
        (Some(ta), None) => {
            let config =
                registry::resolve_config(ta, overrides).map_err(|e| config_err(ctx, &format!("{p}.config"), e))?;
            if !registry::builtin(ta).is_ok_and(|b| b.tracks) {
                return Err(ctx.err(format!("{p}.ta"), format!("'{ta}' forms no tracks: a study compares trackers")));
            }
            Ok(MethodTa::Builtin { ta: ta.clone(), config })
        }
        (None, Some(cmd)) if mimo_ta::process::split_command(cmd).is_some() => {
            Ok(MethodTa::Process { cmd: cmd.clone(), config: overrides.clone() })
        }
        (None, Some(_)) => Err(ctx.err(format!("{p}.ta_cmd"), "expected a command line (not empty, quotes balanced)")),
    }
}

/// The methods of entry `methods[i]`: one, or one per value of its sweep.
fn method(ctx: &Ctx, i: usize, m: RawMethod, global: Option<&Refine>) -> Result<Vec<Method>, PlanError> {
    let p = format!("methods[{i}]");
    let knob = m.sweep.as_ref().map(|k| method_sweep::read_knob(ctx, &p, k)).transpose()?;
    let name = m.name.as_deref().ok_or_else(|| ctx.err(format!("{p}.name"), "missing: every method needs a name"))?;
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c)) {
        return Err(ctx.err(
            format!("{p}.name"),
            format!("expected letters, digits, '-', '_' or '.' (it names a directory), got '{name}'"),
        ));
    }
    let overrides = match &m.config {
        None => Value::Object(serde_json::Map::new()),
        Some(c) => mimo_ta::overrides::toml_to_json(&Toml::Table(c.clone()), "")
            .map_err(|e| config_err(ctx, &format!("{p}.config"), e))?,
    };
    let ta = method_ta(ctx, &p, &m, &overrides)?;
    let mut out = Method {
        name: name.to_string(),
        ta,
        overrides,
        family: name.to_string(),
        knob: None,
        knob_value: None,
        grid: Vec::new(),
        architecture: Architecture::Mimo,
        refine: None,
        refined: false,
    };
    out.architecture = method_sweep::read_architecture(ctx, &p, m.architecture.as_deref(), &out)?;
    out.refine = match (&m.refine, global) {
        (Some(r), _) => crate::refine::read(ctx, &format!("{p}.refine"), r)?,
        (None, Some(g)) if knob.is_some() => Some(*g),
        (None, _) => None,
    };
    if out.refine.is_some() {
        let at = if m.refine.is_some() { format!("{p}.refine") } else { "refine".to_string() };
        crate::refine::check_family(ctx, &p, &at, &out, knob.as_ref())?;
    }
    method_sweep::expand(ctx, &p, out, knob)
}

fn methods(ctx: &Ctx, raw: Option<Vec<RawMethod>>, global: Option<&Refine>) -> Result<Vec<Method>, PlanError> {
    let raw =
        raw.filter(|a| !a.is_empty()).ok_or_else(|| ctx.err("methods", "expected at least one [[methods]] table"))?;
    let entries = raw.into_iter().enumerate().map(|(i, m)| method(ctx, i, m, global)).collect::<Result<Vec<_>, _>>()?;
    // Entry names never hold '@', so distinct entries expand into distinct method names.
    for (i, m) in entries.iter().enumerate() {
        if entries[..i].iter().any(|o| o[0].family == m[0].family) {
            return Err(ctx.err(
                format!("methods[{i}].name"),
                format!("'{}' is used twice: method names label charts and directories", m[0].family),
            ));
        }
    }
    Ok(entries.into_iter().flatten().collect())
}

impl RawPlan {
    /// Check every value, in the order of the plan's documentation; `path` names the plan and
    /// anchors relative scenario files.
    pub(crate) fn validate(self, ctx: &Ctx, path: &Path) -> Result<Plan, PlanError> {
        let stem = || path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
        let title = self.title.unwrap_or_else(stem);
        let scenarios = scenarios(ctx, self.scenarios, path.parent().unwrap_or(Path::new(".")))?;
        let (runs, duration_s) = (runs(ctx, self.runs)?, duration_s(ctx, self.duration_s)?);
        let fidelity = match self.fidelity {
            None => None,
            Some(l) => Some(mimo_core::params::FidelityLevel::parse(&l).ok_or_else(|| {
                ctx.err("fidelity", format!("expected \"voltage\", \"measurement\" or \"auto\", got \"{l}\""))
            })?),
        };
        let seed = match self.seed {
            Some(n) if n < 0 => return Err(ctx.err("seed", format!("expected a whole number >= 0, got {n}"))),
            Some(n) => n as u64,
            None => mimo_sim::DEFAULT_SEED,
        };
        let sweep = match self.sweep.as_deref() {
            None | Some("grid") => Sweep::Grid,
            Some("each") => Sweep::Each,
            Some(o) => return Err(ctx.err("sweep", format!("expected \"grid\" or \"each\", got \"{o}\""))),
        };
        let frontier_energy = match self.frontier_energy.as_deref() {
            None => FrontierEnergy::Total,
            Some(o) => FrontierEnergy::parse(o).ok_or_else(|| {
                ctx.err("frontier_energy", format!("expected \"total\" or \"test_article\", got \"{o}\""))
            })?,
        };
        let global = match &self.refine {
            Some(r) => crate::refine::read(ctx, "refine", r)?,
            None => None,
        };
        let methods = methods(ctx, self.methods, global.as_ref())?;
        let refine_rounds = methods.iter().filter_map(|m| m.refine.map(|r| r.rounds)).max().unwrap_or(0);
        Ok(Plan {
            file: path.to_path_buf(),
            title,
            scenarios,
            runs,
            duration_s,
            fidelity,
            seed,
            sweep,
            tables: tables(ctx, self.tables)?,
            keep_runs: self.keep_runs.unwrap_or(false),
            methods,
            refine_rounds,
            frontier_energy,
            axes: axes(ctx, self.axes)?,
            limits: limits(ctx, self.limits)?,
        })
    }
}
