//! Method sweeps and architectures in study plans (docs/studies.md, "Sweeping a method").
//!
//! A `[[methods]]` entry may sweep one numeric configuration key of its test article:
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
//! with the value set at the key path over the entry's `config`. Each value is checked against the
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

/// The one key a family sweeps and its values, in plan order.
#[derive(Debug, Clone, PartialEq)]
pub struct Knob {
    /// Dotted key path in the test article's configuration.
    pub key: String,
    /// Values, in plan order.
    pub values: Vec<f64>,
}

/// A method's name at a knob value: `family@value`.
pub fn point_name(family: &str, value: f64) -> String {
    format!("{family}@{value}")
}

/// Read `methods[i].sweep` (`p` is `methods[i]`).
pub(crate) fn read_knob(ctx: &Ctx, p: &str, v: &Toml) -> Result<Knob, PlanError> {
    let at = format!("{p}.sweep");
    let t = v.as_table().ok_or_else(|| ctx.err(&at, format!("expected {{ \"key.path\" = [values] }}, got {v}")))?;
    let mut keys = t.iter();
    let (key, list) = match (keys.next(), keys.next()) {
        (Some(one), None) => one,
        _ => {
            return Err(ctx.err(&at, format!("expected exactly one configuration key path to sweep, got {}", t.len())));
        }
    };
    let kat = format!("{at}.{key}");
    if key.is_empty() || key.split('.').any(str::is_empty) {
        return Err(ctx.err(&kat, "expected a dotted configuration key path (resource_manager.power_budget_w)"));
    }
    let list = list
        .as_array()
        .filter(|l| !l.is_empty())
        .ok_or_else(|| ctx.err(&kat, format!("expected a non-empty list of numbers, got {list}")))?;
    let mut values = Vec::with_capacity(list.len());
    for (j, x) in list.iter().enumerate() {
        let k = format!("{kat}[{j}]");
        let x = ctx.number(&k, x)?;
        if key.rsplit('.').next() == Some("power_budget_w") && x <= 0.0 {
            return Err(ctx.err(&k, format!("expected a power budget > 0 W, got {x}")));
        }
        if values.contains(&x) {
            return Err(ctx.err(&k, format!("{x} is listed twice")));
        }
        values.push(x);
    }
    Ok(Knob { key: key.clone(), values })
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
/// per knob value.
pub(crate) fn expand(ctx: &Ctx, p: &str, base: Method, knob: Option<Knob>) -> Result<Vec<Method>, PlanError> {
    let Some(knob) = knob else { return Ok(vec![base]) };
    let mut out = Vec::with_capacity(knob.values.len());
    for (j, &v) in knob.values.iter().enumerate() {
        let mut overrides = base.overrides.clone();
        // A whole number goes in as an integer so that integer settings take it too.
        let json =
            if v.fract() == 0.0 && v.abs() < 9.0e15 { serde_json::json!(v as i64) } else { serde_json::json!(v) };
        set_path(&mut overrides, &knob.key, json);
        let ta = match &base.ta {
            MethodTa::Builtin { ta, .. } => {
                let config = registry::resolve_config(ta, &overrides).map_err(|e| match e {
                    ConfigError::UnknownKey { .. } => config_err(ctx, &format!("{p}.sweep"), e),
                    other => ctx.err(format!("{p}.sweep.{}[{j}]", knob.key), format!("{v} does not fit: {other}")),
                })?;
                MethodTa::Builtin { ta: ta.clone(), config }
            }
            MethodTa::Process { cmd, .. } => MethodTa::Process { cmd: cmd.clone(), config: overrides.clone() },
        };
        out.push(Method {
            name: point_name(&base.family, v),
            ta,
            overrides,
            knob: Some(knob.key.clone()),
            knob_value: Some(v),
            ..base.clone()
        });
    }
    Ok(out)
}
