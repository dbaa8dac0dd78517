//! Method sweeps and architectures in study plans (docs/studies.md, "Sweeping a method").
//!
//! A `[[methods]]` entry may sweep numeric configuration keys of its test article: one (a curve)
//! or several (a product grid, every combination of their values):
//!
//! ```toml
//! [[methods]]
//! name = "mimo"
//! ta = "default"
//! sweep = { "resource_manager.max_ta_share" = [0.1, 0.2, 0.4] }
//! architecture = "mimo"          # optional: "mimo" or "conventional"
//! ```
//!
//! The entry is a *family*; it expands into one method per value, named `name@value` (the
//! value as Rust prints an `f64`: the shortest text that reads back the same, `0.25`, `16`),
//! with the value set at the key path over the entry's `config`; a grid's points are named
//! `name@short:value,short:value` (short: each key's last segment, its whole path when two keys
//! share one), the keys in alphabetical order of their paths (as TOML reads a table), the first
//! varying slowest. Each value is checked against the
//! test article's configuration exactly like a `config` override (an unknown key or a value of
//! the wrong type names `methods[i].sweep.<key path>`); a child-process test article's keys are
//! its own and pass unchecked, as its `config` does. A key whose last segment is
//! `power_budget_w` takes positive values only.
//!
//! `architecture` labels the family for the challenge's paired comparison; without it, a method
//! whose configuration sets `resource_manager.mimo = false` is conventional and every other is
//! MIMO.

use crate::plan::{Ctx, Method, MethodTa, PlanError, config_err};
use mimo_ta::overrides::{ConfigError, set_path};
use mimo_ta::registry;
use serde_json::Value;
use toml::Value as Toml;

/// Whether a family transmits MIMO dwells or only monostatic ones.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Architecture {
    /// MIMO dwells allowed.
    Mimo,
    /// Monostatic dwells only (a conventional phased-array network).
    Conventional,
}

impl Architecture {
    /// The name in plans and tables.
    pub fn name(self) -> &'static str {
        match self {
            Architecture::Mimo => "mimo",
            Architecture::Conventional => "conventional",
        }
    }
}

/// The keys a family sweeps and their values, in plan order: one key (a curve), or several (a
/// product grid: every combination of their values).
#[derive(Debug, Clone, PartialEq)]
pub struct Knob {
    /// Dotted key paths in the test article's configuration (alphabetical), with their values in
    /// plan order.
    pub keys: Vec<(String, Vec<f64>)>,
}

impl Knob {
    /// The family's points: every combination of the keys' values, the first key (in
    /// alphabetical order of the paths) varying slowest.
    pub fn points(&self) -> Vec<Vec<f64>> {
        let mut out: Vec<Vec<f64>> = vec![Vec::new()];
        for (_, values) in &self.keys {
            out = out.iter().flat_map(|p| values.iter().map(move |v| [p.clone(), vec![*v]].concat())).collect();
        }
        out
    }

    /// The `knob` column of a family: its key path, or the key paths joined by ` × ` for a grid.
    pub fn label(&self) -> String {
        self.keys.iter().map(|(k, _)| k.as_str()).collect::<Vec<_>>().join(" × ")
    }
}

/// A method's name at a knob value: `family@value`.
pub fn point_name(family: &str, value: f64) -> String {
    format!("{family}@{value}")
}

/// The short name of each key of a grid in method names: its last segment, or its whole path
/// when two keys share a last segment.
fn short_keys(keys: &[String]) -> Vec<String> {
    let last = |k: &str| k.rsplit('.').next().unwrap_or(k).to_string();
    keys.iter()
        .map(|k| if keys.iter().filter(|o| last(o) == last(k)).count() > 1 { k.clone() } else { last(k) })
        .collect()
}

/// A method's name at a point of a family sweeping `keys`: `family@value` for one key,
/// `family@short:value,short:value` for a grid (short: the key's last segment, unless two keys
/// share it).
pub fn grid_point_name(family: &str, keys: &[String], values: &[f64]) -> String {
    if keys.len() == 1 {
        return point_name(family, values[0]);
    }
    let parts: Vec<String> = short_keys(keys).iter().zip(values).map(|(k, v)| format!("{k}:{v}")).collect();
    format!("{family}@{}", parts.join(","))
}

/// Read one key's list of values (`kat` its key path in the plan).
fn read_values(ctx: &Ctx, kat: &str, key: &str, list: &Toml) -> Result<Vec<f64>, PlanError> {
    if key.is_empty() || key.split('.').any(str::is_empty) {
        return Err(ctx.err(kat, "expected a dotted configuration key path (resource_manager.power_budget_w)"));
    }
    let list = list
        .as_array()
        .filter(|l| !l.is_empty())
        .ok_or_else(|| ctx.err(kat, format!("expected a non-empty list of numbers, got {list}")))?;
    let mut values = Vec::with_capacity(list.len());
    for (j, x) in list.iter().enumerate() {
        let k = format!("{kat}[{j}]");
        let x = ctx.number(&k, x)?;
        check_value(ctx, &k, key, x)?;
        if values.contains(&x) {
            return Err(ctx.err(&k, format!("{x} is listed twice")));
        }
        values.push(x);
    }
    Ok(values)
}

/// A knob value's own range (a power budget is positive).
pub(crate) fn check_value(ctx: &Ctx, at: &str, key: &str, x: f64) -> Result<(), PlanError> {
    if key.rsplit('.').next() == Some("power_budget_w") && x <= 0.0 {
        return Err(ctx.err(at, format!("expected a power budget > 0 W, got {x}")));
    }
    Ok(())
}

/// The most points a grid family may have.
pub const MAX_GRID_POINTS: usize = 1000;

/// Read `methods[i].sweep` (`p` is `methods[i]`): one key path or several (a product grid).
pub(crate) fn read_knob(ctx: &Ctx, p: &str, v: &Toml) -> Result<Knob, PlanError> {
    let at = format!("{p}.sweep");
    let t = v.as_table().ok_or_else(|| ctx.err(&at, format!("expected {{ \"key.path\" = [values] }}, got {v}")))?;
    if t.is_empty() {
        return Err(ctx.err(&at, "expected at least one configuration key path to sweep"));
    }
    let mut keys = Vec::with_capacity(t.len());
    for (key, list) in t {
        keys.push((key.clone(), read_values(ctx, &format!("{at}.{key}"), key, list)?));
    }
    let n: usize = keys.iter().map(|(_, v)| v.len()).product();
    if n > MAX_GRID_POINTS {
        return Err(ctx.err(&at, format!("expected at most {MAX_GRID_POINTS} points in a family's grid, got {n}")));
    }
    Ok(Knob { keys })
}

/// Read `methods[i].architecture`, or infer it from the method's configuration.
pub(crate) fn read_architecture(ctx: &Ctx, p: &str, v: Option<&str>, m: &Method) -> Result<Architecture, PlanError> {
    match v {
        Some(v) => match v {
            "mimo" => Ok(Architecture::Mimo),
            "conventional" => Ok(Architecture::Conventional),
            o => {
                Err(ctx.err(format!("{p}.architecture"), format!("expected \"mimo\" or \"conventional\", got \"{o}\"")))
            }
        },
        None => {
            let config = match &m.ta {
                MethodTa::Builtin { config, .. } | MethodTa::Process { config, .. } => config,
            };
            let off = config.pointer("/resource_manager/mimo") == Some(&Value::Bool(false));
            Ok(if off { Architecture::Conventional } else { Architecture::Mimo })
        }
    }
}

/// The methods of a `[[methods]]` entry: `base` itself when it sweeps nothing, else one method
/// per point of its knob. Each key's values are checked on their own first (the other keys at
/// their first value), so that a value the test article refuses is named `sweep.<key>[j]`.
pub(crate) fn expand(ctx: &Ctx, p: &str, base: Method, knob: Option<Knob>) -> Result<Vec<Method>, PlanError> {
    let Some(knob) = knob else { return Ok(vec![base]) };
    let keys: Vec<String> = knob.keys.iter().map(|(k, _)| k.clone()).collect();
    let first: Vec<f64> = knob.keys.iter().map(|(_, v)| v[0]).collect();
    let mut one = Vec::new();
    for (i, (key, values)) in knob.keys.iter().enumerate() {
        for (j, &v) in values.iter().enumerate() {
            let mut probe = first.clone();
            probe[i] = v;
            let m = build(base.clone(), &keys, &probe).map_err(|e| match e {
                ConfigError::UnknownKey { .. } => config_err(ctx, &format!("{p}.sweep"), e),
                other => ctx.err(format!("{p}.sweep.{key}[{j}]"), format!("{v} does not fit: {other}")),
            })?;
            one.push(m);
        }
    }
    if keys.len() == 1 {
        return Ok(one);
    }
    knob.points().iter().map(|values| method_at(ctx, p, &base, &keys, values)).collect()
}

/// The method of family `base` at the point `values` of `keys`, or the test article's refusal.
fn build(base: Method, keys: &[String], values: &[f64]) -> Result<Method, ConfigError> {
    let mut overrides = base.overrides.clone();
    for (key, &v) in keys.iter().zip(values) {
        // A whole number goes in as an integer so that integer settings take it too.
        let json =
            if v.fract() == 0.0 && v.abs() < 9.0e15 { serde_json::json!(v as i64) } else { serde_json::json!(v) };
        set_path(&mut overrides, key, json);
    }
    let ta = match &base.ta {
        MethodTa::Builtin { ta, .. } => {
            MethodTa::Builtin { ta: ta.clone(), config: registry::resolve_config(ta, &overrides)? }
        }
        MethodTa::Process { cmd, .. } => MethodTa::Process { cmd: cmd.clone(), config: overrides.clone() },
    };
    Ok(Method {
        name: grid_point_name(&base.family, keys, values),
        ta,
        overrides,
        knob: Some(keys.join(" × ")),
        knob_value: if keys.len() == 1 { values.first().copied() } else { None },
        grid: keys.iter().cloned().zip(values.iter().copied()).collect(),
        ..base
    })
}

/// The method of family `base` (unswept, as `methods[i]` = `p` gives it) at the point `values`
/// of `keys`: the values set at the key paths over the entry's `config`.
pub(crate) fn method_at(
    ctx: &Ctx,
    p: &str,
    base: &Method,
    keys: &[String],
    values: &[f64],
) -> Result<Method, PlanError> {
    build(base.clone(), keys, values).map_err(|e| match e {
        ConfigError::UnknownKey { .. } => config_err(ctx, &format!("{p}.sweep"), e),
        other => ctx.err(format!("{p}.sweep"), format!("{values:?} at {} does not fit: {other}", keys.join(", "))),
    })
}
