//! Study plans: what to compare (methods), on what (scenarios), under which stress (axes), how
//! many Monte Carlo runs per cell — read from a TOML file and checked key by key.
//!
//! ```toml
//! title = "MIMO against a conventional network"
//! scenarios = [1, 7, "my/scenario.toml"]   # standard numbers or files (relative to the plan)
//! runs = 4                                  # Monte Carlo runs per cell
//! duration_s = 600.0                        # optional: the scenarios' own by default
//! fidelity = "auto"                         # optional: rung of the fidelity ladder for every cell
//! seed = 20261122                           # optional
//! sweep = "grid"                            # "grid" (every combination) or "each" (one axis at a time)
//! tables = ["truth", "dwells", "measurements", "tracks"]   # optional: what each cell records
//!
//! [[methods]]
//! name = "mimo-ekf"                         # its label on every chart
//! ta = "default"                            # a built-in test article …
//! config = { resource_manager = { mimo = true } }   # … merged over its defaults
//!
//! [[methods]]
//! name = "my-python-ta"
//! ta_cmd = "python3 my_ta.py"               # … or a test article in another process
//!
//! [axes]
//! rcs_offset_db = [-6.0, -3.0, 0.0]
//! pfa = [1e-6, 1e-4]
//! formation_spacing_scale = [0.5, 1.0]
//! peak_power_offset_db = [0.0]
//! search_pulses = [1, 2]
//! raid_targets = [0, 32, 128]               # aircraft added, drawn from the seed
//!
//! [limits]                                  # optional: when a run counts as failed
//! wall_s_per_run = 900.0
//! max_tracks = 1000
//! ```
//!
//! Every error names the plan file, the key path (`methods[1].config.resource_manager.mimoo`)
//! and what was expected; nothing is run or written before the whole plan is checked.

use crate::method_sweep;
pub use crate::method_sweep::Architecture;
use mimo_scenario::stress::{StressError, bounds, check};
use mimo_ta::overrides::ConfigError;
use mimo_ta::registry;
use serde_json::Value;
use std::path::{Path, PathBuf};
use toml::Value as Toml;

/// A bad plan: the file, the key path and what was expected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}: {key}: {expected}")]
pub struct PlanError {
    /// The plan file.
    pub file: String,
    /// Dotted key path, e.g. `methods[1].config.resource_manager.mimoo`.
    pub key: String,
    /// What was expected.
    pub expected: String,
}

/// A scenario of the plan.
#[derive(Debug, Clone, PartialEq)]
pub enum ScenarioRef {
    /// Standard scenario 1–7.
    Standard(u32),
    /// A scenario file (resolved relative to the plan's directory).
    File(PathBuf),
}

impl ScenarioRef {
    /// The label used in paths and tables: the number, or the file stem.
    pub fn label(&self) -> String {
        match self {
            ScenarioRef::Standard(n) => n.to_string(),
            ScenarioRef::File(p) => p.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default(),
        }
    }
}

/// How a method's test article is made.
#[derive(Debug, Clone, PartialEq)]
pub enum MethodTa {
    /// A built-in, with its merged and checked configuration.
    Builtin {
        /// Built-in name.
        ta: String,
        /// Its configuration.
        config: Value,
    },
    /// A child process; `config` is passed in its `start` event.
    Process {
        /// The command line.
        cmd: String,
        /// Overrides passed on.
        config: Value,
    },
}

/// One method: a label and a test article.
#[derive(Debug, Clone, PartialEq)]
pub struct Method {
    /// The label on every chart: the entry's name (letters, digits, `-`, `_`, `.`), or
    /// `family@value` for a point of a swept entry.
    pub name: String,
    /// The test article.
    pub ta: MethodTa,
    /// The overrides as written in the plan, the knob's value included (recorded in results).
    pub overrides: Value,
    /// The `[[methods]]` entry's name.
    pub family: String,
    /// The configuration key path the entry sweeps (`None`: not swept).
    pub knob: Option<String>,
    /// The knob's value at this method.
    pub knob_value: Option<f64>,
    /// MIMO or conventional (for the challenge's paired comparison).
    pub architecture: Architecture,
}

/// A stress axis of a study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Axis {
    /// Added to every target's RCS (dB).
    RcsOffsetDb,
    /// Every radar's false-alarm probability.
    Pfa,
    /// Multiplies the spacing of formation fighters.
    FormationSpacingScale,
    /// Added to every radar's peak power (dB).
    PeakPowerOffsetDb,
    /// Pulses of the low search band.
    SearchPulses,
    /// Aircraft added as a raid (docs/model.md §8.4).
    RaidTargets,
}

impl Axis {
    /// Every axis, in the order of paths and columns.
    pub const ALL: [Axis; 6] = [
        Axis::RcsOffsetDb,
        Axis::Pfa,
        Axis::FormationSpacingScale,
        Axis::PeakPowerOffsetDb,
        Axis::SearchPulses,
        Axis::RaidTargets,
    ];

    /// The key in plans, paths and tables.
    pub fn name(self) -> &'static str {
        match self {
            Axis::RcsOffsetDb => "rcs_offset_db",
            Axis::Pfa => "pfa",
            Axis::FormationSpacingScale => "formation_spacing_scale",
            Axis::PeakPowerOffsetDb => "peak_power_offset_db",
            Axis::SearchPulses => "search_pulses",
            Axis::RaidTargets => "raid_targets",
        }
    }

    /// The value that leaves a scenario as it is (`pfa`: the standard radars' 1e-6).
    pub fn baseline(self) -> f64 {
        match self {
            Axis::RcsOffsetDb | Axis::PeakPowerOffsetDb | Axis::RaidTargets => 0.0,
            Axis::Pfa => mimo_core::params::RadarParams::default().pfa,
            Axis::FormationSpacingScale => 1.0,
            Axis::SearchPulses => f64::from(mimo_sim::SearchConfig::default().bands[0].n_pulses),
        }
    }

    /// The axis label on charts, with its unit.
    pub fn label(self) -> &'static str {
        match self {
            Axis::RcsOffsetDb => "RCS offset of every target (dB)",
            Axis::Pfa => "false-alarm probability of every radar (log)",
            Axis::FormationSpacingScale => "formation spacing scale",
            Axis::PeakPowerOffsetDb => "peak power offset of every radar (dB)",
            Axis::SearchPulses => "pulses per low-band search dwell",
            Axis::RaidTargets => "raid aircraft added",
        }
    }

    /// Whether a larger value stresses a tracker more (more false alarms, more raid aircraft);
    /// for every other axis a smaller value does (weaker echoes, closer targets, fewer pulses).
    pub fn harder_when_larger(self) -> bool {
        matches!(self, Axis::Pfa | Axis::RaidTargets)
    }

    /// Values ordered from the least to the most stressing.
    pub fn by_stress(self, values: &[f64]) -> Vec<f64> {
        let mut v = values.to_vec();
        v.sort_by(|a, b| if self.harder_when_larger() { a.total_cmp(b) } else { b.total_cmp(a) });
        v
    }

    fn check(self, v: f64) -> Result<(), String> {
        let r = |b| {
            check(self.name(), v, b)
                .map_err(|e: StressError| format!("expected a value in [{}, {}], got {v}", e.lo, e.hi))
        };
        match self {
            Axis::RcsOffsetDb => r(bounds::RCS_OFFSET_DB),
            Axis::Pfa => r(bounds::PFA),
            Axis::FormationSpacingScale => r(bounds::FORMATION_SPACING_SCALE),
            Axis::PeakPowerOffsetDb => r(bounds::PEAK_POWER_OFFSET_DB),
            Axis::RaidTargets => mimo_scenario::stress::check_raid_targets(v)
                .map(|_| ())
                .map_err(|e| format!("expected a whole number of aircraft in [{}, {}], got {v}", e.lo, e.hi)),
            Axis::SearchPulses => {
                if v.fract() == 0.0 && (1.0..=16.0).contains(&v) {
                    Ok(())
                } else {
                    Err(format!("expected a whole number of pulses from 1 to 16 (a radar's max_pulses), got {v}"))
                }
            }
        }
    }
}

/// How the axes are combined.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sweep {
    /// Every combination of every axis's values.
    Grid,
    /// One axis at a time, the others at their baseline.
    Each,
}

/// When a run counts as failed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Wall seconds one run may take.
    pub wall_s_per_run: f64,
    /// Tracks a run may start.
    pub max_tracks: u64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits { wall_s_per_run: 1800.0, max_tracks: 20_000 }
    }
}

/// Most Monte Carlo runs per cell a plan may ask for (more needs several studies).
pub const MAX_RUNS: u32 = 10_000;
/// The tables a cell may record.
pub const TABLES: [&str; 6] = ["truth", "dwells", "primitives", "measurements", "tracks", "voltages"];

/// A checked study plan.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The plan file.
    pub file: PathBuf,
    /// A title for the report.
    pub title: String,
    /// Scenarios, in plan order.
    pub scenarios: Vec<ScenarioRef>,
    /// Monte Carlo runs per cell.
    pub runs: u32,
    /// Duration override (s).
    pub duration_s: Option<f64>,
    /// Fidelity-ladder override for every cell (docs/model.md §4.8); the scenarios' own by default.
    pub fidelity: Option<mimo_core::params::FidelityLevel>,
    /// Master seed: run k of every cell uses it (common random numbers across methods).
    pub seed: u64,
    /// How the axes combine.
    pub sweep: Sweep,
    /// Methods, in plan order.
    pub methods: Vec<Method>,
    /// Axes and their values, in [`Axis::ALL`] order.
    pub axes: Vec<(Axis, Vec<f64>)>,
    /// Tables each cell records.
    pub tables: Vec<String>,
    /// Failure limits.
    pub limits: Limits,
}

pub(crate) struct Ctx<'a> {
    pub(crate) file: &'a str,
}

impl Ctx<'_> {
    pub(crate) fn err(&self, key: impl Into<String>, expected: impl Into<String>) -> PlanError {
        PlanError { file: self.file.to_string(), key: key.into(), expected: expected.into() }
    }

    fn known(&self, t: &toml::Table, prefix: &str, keys: &[&str]) -> Result<(), PlanError> {
        for k in t.keys() {
            if !keys.contains(&k.as_str()) {
                let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
                return Err(self.err(key, format!("unknown key (expected one of: {})", keys.join(", "))));
            }
        }
        Ok(())
    }

    pub(crate) fn number(&self, key: &str, v: &Toml) -> Result<f64, PlanError> {
        match v {
            Toml::Float(x) if x.is_finite() => Ok(*x),
            Toml::Integer(i) => Ok(*i as f64),
            _ => Err(self.err(key, format!("expected a finite number, got {v}"))),
        }
    }

    pub(crate) fn string<'v>(&self, key: &str, v: &'v Toml) -> Result<&'v str, PlanError> {
        v.as_str().ok_or_else(|| self.err(key, format!("expected a string, got {v}")))
    }
}

pub(crate) fn config_err(ctx: &Ctx, prefix: &str, e: ConfigError) -> PlanError {
    match e {
        ConfigError::UnknownKey { key, known } => {
            ctx.err(format!("{prefix}.{key}"), format!("unknown key (expected one of: {known})"))
        }
        ConfigError::BadValue { key, why } => ctx.err(format!("{prefix}.{key}"), why),
        ConfigError::UnknownTa { name, known } => ctx.err(
            prefix.trim_end_matches(".config").to_string() + ".ta",
            format!("unknown test article '{name}' (expected one of: {known})"),
        ),
        other => ctx.err(prefix, other.to_string()),
    }
}

/// The methods of entry `methods[i]`: one, or one per value of its sweep.
fn method(ctx: &Ctx, i: usize, v: &Toml) -> Result<Vec<Method>, PlanError> {
    let p = format!("methods[{i}]");
    let t = v.as_table().ok_or_else(|| ctx.err(&p, "expected a table with name and ta (or ta_cmd)"))?;
    ctx.known(t, &p, &["name", "ta", "ta_cmd", "config", "sweep", "architecture"])?;
    let knob = t.get("sweep").map(|k| method_sweep::read_knob(ctx, &p, k)).transpose()?;
    let name = ctx.string(
        &format!("{p}.name"),
        t.get("name").ok_or_else(|| ctx.err(format!("{p}.name"), "missing: every method needs a name"))?,
    )?;
    if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c)) {
        return Err(ctx.err(
            format!("{p}.name"),
            format!("expected letters, digits, '-', '_' or '.' (it names a directory), got '{name}'"),
        ));
    }
    let overrides = match t.get("config") {
        None => Value::Object(serde_json::Map::new()),
        Some(c) if c.is_table() => {
            mimo_ta::overrides::toml_to_json(c, "").map_err(|e| config_err(ctx, &format!("{p}.config"), e))?
        }
        Some(c) => return Err(ctx.err(format!("{p}.config"), format!("expected a table, got {c}"))),
    };
    let ta = match (t.get("ta"), t.get("ta_cmd")) {
        (Some(_), Some(_)) => return Err(ctx.err(&p, "expected either ta or ta_cmd, not both")),
        (None, None) => {
            return Err(ctx.err(format!("{p}.ta"), "missing: a built-in test article (ta) or a command (ta_cmd)"));
        }
        (Some(ta), None) => {
            let ta = ctx.string(&format!("{p}.ta"), ta)?;
            let config =
                registry::resolve_config(ta, &overrides).map_err(|e| config_err(ctx, &format!("{p}.config"), e))?;
            if !registry::builtin(ta).is_ok_and(|b| b.tracks) {
                return Err(ctx.err(format!("{p}.ta"), format!("'{ta}' forms no tracks: a study compares trackers")));
            }
            MethodTa::Builtin { ta: ta.to_string(), config }
        }
        (None, Some(cmd)) => {
            let cmd = ctx.string(&format!("{p}.ta_cmd"), cmd)?;
            if shlex_ok(cmd) {
                MethodTa::Process { cmd: cmd.to_string(), config: overrides.clone() }
            } else {
                return Err(ctx.err(format!("{p}.ta_cmd"), "expected a command line (not empty, quotes balanced)"));
            }
        }
    };
    let mut m = Method {
        name: name.to_string(),
        ta,
        overrides,
        family: name.to_string(),
        knob: None,
        knob_value: None,
        architecture: Architecture::Mimo,
    };
    m.architecture = method_sweep::read_architecture(ctx, &p, t.get("architecture"), &m)?;
    method_sweep::expand(ctx, &p, m, knob)
}

fn shlex_ok(cmd: &str) -> bool {
    mimo_ta::process::split_command(cmd).is_some()
}

impl Plan {
    /// Read and check a plan file.
    pub fn read(path: &Path) -> Result<Plan, PlanError> {
        let file = path.display().to_string();
        let ctx = Ctx { file: &file };
        let text = std::fs::read_to_string(path).map_err(|e| ctx.err("(file)", format!("cannot read it: {e}")))?;
        Plan::parse(&text, path)
    }

    /// Check a plan's text (`path` names it and anchors relative scenario files).
    pub fn parse(text: &str, path: &Path) -> Result<Plan, PlanError> {
        let file = path.display().to_string();
        let ctx = Ctx { file: &file };
        let t: toml::Table = toml::from_str(text).map_err(|e| {
            let at = e.span().map(|s| {
                let before = &text[..s.start.min(text.len())];
                format!("line {}", before.matches('\n').count() + 1)
            });
            ctx.err(at.unwrap_or_else(|| "(toml)".into()), format!("not valid TOML: {}", e.message()))
        })?;
        ctx.known(
            &t,
            "",
            &[
                "title",
                "scenarios",
                "runs",
                "duration_s",
                "fidelity",
                "seed",
                "sweep",
                "tables",
                "methods",
                "axes",
                "limits",
            ],
        )?;
        let title = match t.get("title") {
            Some(v) => ctx.string("title", v)?.to_string(),
            None => path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default(),
        };
        let base = path.parent().unwrap_or(Path::new("."));
        let scenarios = match t.get("scenarios") {
            Some(Toml::Array(a)) if !a.is_empty() => a
                .iter()
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
                .collect::<Result<Vec<_>, _>>()?,
            _ => return Err(ctx.err("scenarios", "expected a non-empty list of scenario numbers or paths")),
        };
        let runs = match t.get("runs") {
            Some(Toml::Integer(n)) if (1..=i64::from(MAX_RUNS)).contains(n) => *n as u32,
            Some(v) => {
                return Err(ctx.err("runs", format!("expected a whole number of runs from 1 to {MAX_RUNS}, got {v}")));
            }
            None => return Err(ctx.err("runs", "missing: Monte Carlo runs per cell")),
        };
        let duration_s = match t.get("duration_s") {
            Some(v) => {
                let d = ctx.number("duration_s", v)?;
                if !(d > 0.0 && d <= mimo_scenario::MAX_DURATION_S) {
                    return Err(ctx.err(
                        "duration_s",
                        format!("expected seconds in (0, {}], got {d}", mimo_scenario::MAX_DURATION_S),
                    ));
                }
                Some(d)
            }
            None => None,
        };
        let fidelity = match t.get("fidelity").map(|v| ctx.string("fidelity", v)).transpose()? {
            None => None,
            Some(l) => Some(mimo_core::params::FidelityLevel::parse(l).ok_or_else(|| {
                ctx.err("fidelity", format!("expected \"voltage\", \"measurement\" or \"auto\", got \"{l}\""))
            })?),
        };
        let seed = match t.get("seed") {
            Some(Toml::Integer(n)) if *n >= 0 => *n as u64,
            Some(v) => return Err(ctx.err("seed", format!("expected a whole number >= 0, got {v}"))),
            None => mimo_sim::DEFAULT_SEED,
        };
        let sweep = match t.get("sweep").map(|v| ctx.string("sweep", v)).transpose()? {
            None | Some("grid") => Sweep::Grid,
            Some("each") => Sweep::Each,
            Some(o) => return Err(ctx.err("sweep", format!("expected \"grid\" or \"each\", got \"{o}\""))),
        };
        let tables = match t.get("tables") {
            None => ["truth", "dwells", "measurements", "tracks"].map(String::from).to_vec(),
            Some(Toml::Array(a)) => {
                let mut out = Vec::new();
                for (i, v) in a.iter().enumerate() {
                    let s = ctx.string(&format!("tables[{i}]"), v)?;
                    if !TABLES.contains(&s) {
                        return Err(ctx.err(format!("tables[{i}]"), format!("expected one of {}", TABLES.join(", "))));
                    }
                    out.push(s.to_string());
                }
                for needed in ["truth", "dwells", "tracks"] {
                    if !out.iter().any(|x| x == needed) {
                        return Err(ctx
                            .err("tables", format!("must include {needed} (scoring reads truth, dwells and tracks)")));
                    }
                }
                out
            }
            Some(v) => return Err(ctx.err("tables", format!("expected a list of table names, got {v}"))),
        };
        let entries = match t.get("methods") {
            Some(Toml::Array(a)) if !a.is_empty() => {
                a.iter().enumerate().map(|(i, v)| method(&ctx, i, v)).collect::<Result<Vec<_>, _>>()?
            }
            _ => return Err(ctx.err("methods", "expected at least one [[methods]] table")),
        };
        // Entry names never hold '@', so distinct entries expand into distinct method names.
        for (i, m) in entries.iter().enumerate() {
            if entries[..i].iter().any(|o| o[0].family == m[0].family) {
                return Err(ctx.err(
                    format!("methods[{i}].name"),
                    format!("'{}' is used twice: method names label charts and directories", m[0].family),
                ));
            }
        }
        let methods: Vec<Method> = entries.into_iter().flatten().collect();
        let mut axes = Vec::new();
        if let Some(a) = t.get("axes") {
            let at = a.as_table().ok_or_else(|| ctx.err("axes", "expected a table of axis = [values]"))?;
            let names: Vec<&str> = Axis::ALL.iter().map(|a| a.name()).collect();
            ctx.known(at, "axes", &names)?;
            for axis in Axis::ALL {
                let Some(v) = at.get(axis.name()) else { continue };
                let key = format!("axes.{}", axis.name());
                let list = v
                    .as_array()
                    .filter(|l| !l.is_empty())
                    .ok_or_else(|| ctx.err(&key, "expected a non-empty list of values"))?;
                let mut values = Vec::new();
                for (i, x) in list.iter().enumerate() {
                    let k = format!("{key}[{i}]");
                    let x = ctx.number(&k, x)?;
                    axis.check(x).map_err(|e| ctx.err(&k, e))?;
                    if values.contains(&x) {
                        return Err(ctx.err(&k, format!("{x} is listed twice")));
                    }
                    values.push(x);
                }
                axes.push((axis, values));
            }
        }
        let mut limits = Limits::default();
        if let Some(l) = t.get("limits") {
            let lt = l.as_table().ok_or_else(|| ctx.err("limits", "expected a table"))?;
            ctx.known(lt, "limits", &["wall_s_per_run", "max_tracks"])?;
            if let Some(v) = lt.get("wall_s_per_run") {
                let x = ctx.number("limits.wall_s_per_run", v)?;
                if x <= 0.0 {
                    return Err(ctx.err("limits.wall_s_per_run", "expected a positive number of seconds"));
                }
                limits.wall_s_per_run = x;
            }
            if let Some(v) = lt.get("max_tracks") {
                match v {
                    Toml::Integer(n) if *n >= 1 => limits.max_tracks = *n as u64,
                    _ => return Err(ctx.err("limits.max_tracks", format!("expected a whole number >= 1, got {v}"))),
                }
            }
        }
        Ok(Plan {
            file: path.to_path_buf(),
            title,
            scenarios,
            runs,
            duration_s,
            fidelity,
            seed,
            sweep,
            methods,
            axes,
            tables,
            limits,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
title = "t"
scenarios = [7, "mine.toml"]
runs = 2
duration_s = 60
[[methods]]
name = "mimo-ekf"
ta = "default"
[[methods]]
name = "conv"
ta = "default"
config = { resource_manager = { mimo = false } }
[[methods]]
name = "py"
ta_cmd = "python3 'my ta.py'"
[axes]
pfa = [1e-6, 1e-5]
search_pulses = [1, 2]
"#;

    fn parse(text: &str) -> Result<Plan, PlanError> {
        Plan::parse(text, Path::new("studies/x.toml"))
    }

    #[test]
    fn a_good_plan_reads() {
        let p = parse(GOOD).expect("plan");
        assert_eq!(p.scenarios, vec![ScenarioRef::Standard(7), ScenarioRef::File(PathBuf::from("studies/mine.toml"))]);
        assert_eq!(p.runs, 2);
        assert_eq!(p.duration_s, Some(60.0));
        assert_eq!(p.fidelity, None);
        let with = parse(&GOOD.replacen("duration_s = 60", "duration_s = 60\nfidelity = \"measurement\"", 1));
        assert_eq!(with.expect("plan").fidelity, Some(mimo_core::params::FidelityLevel::Measurement));
        assert_eq!(p.seed, mimo_sim::DEFAULT_SEED);
        assert_eq!(p.methods.len(), 3);
        let MethodTa::Builtin { config, .. } = &p.methods[1].ta else { panic!("builtin") };
        assert_eq!(config["resource_manager"]["mimo"], serde_json::json!(false));
        assert!(matches!(&p.methods[2].ta, MethodTa::Process { cmd, .. } if cmd == "python3 'my ta.py'"));
        assert_eq!(p.axes, vec![(Axis::Pfa, vec![1e-6, 1e-5]), (Axis::SearchPulses, vec![1.0, 2.0])]);
        assert_eq!(p.sweep, Sweep::Grid);
    }

    #[test]
    fn every_mistake_names_its_key() {
        let cases: &[(&str, &str, &str)] = &[
            ("runs = 2", "runs = 0", "runs"),
            ("runs = 2", "runs = 2\nbogus = 1", "bogus"),
            (
                "ta = \"default\"\n[[methods]]\nname = \"conv\"",
                "ta = \"kalman\"\n[[methods]]\nname = \"conv\"",
                "methods[0].ta",
            ),
            ("{ mimo = false }", "{ mimoo = false }", "methods[1].config.resource_manager.mimoo"),
            ("{ mimo = false }", "{ pd_target = 2.0 }", "methods[1].config.resource_manager.pd_target"),
            ("{ mimo = false }", "{ power_budget_w = 0.0 }", "methods[1].config.resource_manager.power_budget_w"),
            ("{ mimo = false }", "{ power_budget_w = inf }", "methods[1].config.resource_manager.power_budget_w"),
            ("{ mimo = false }", "{ power_budget_w = \"4\" }", "methods[1].config.resource_manager.power_budget_w"),
            ("pfa = [1e-6, 1e-5]", "pfa = [2.0]", "axes.pfa[0]"),
            ("pfa = [1e-6, 1e-5]", "formation_spacing_scale = [-1.0]", "axes.formation_spacing_scale[0]"),
            ("pfa = [1e-6, 1e-5]", "pfa = []", "axes.pfa"),
            ("pfa = [1e-6, 1e-5]", "spacing = [1.0]", "axes.spacing"),
            ("search_pulses = [1, 2]", "search_pulses = [1.5]", "axes.search_pulses[0]"),
            ("name = \"conv\"", "name = \"mimo-ekf\"", "methods[1].name"),
            ("name = \"conv\"", "name = \"a/b\"", "methods[1].name"),
            ("scenarios = [7, \"mine.toml\"]", "scenarios = [9]", "scenarios[0]"),
            ("scenarios = [7, \"mine.toml\"]", "scenarios = []", "scenarios"),
            ("ta_cmd = \"python3 'my ta.py'\"", "ta_cmd = \"python3 'unbalanced\"", "methods[2].ta_cmd"),
            ("duration_s = 60", "duration_s = -1", "duration_s"),
            ("duration_s = 60", "duration_s = 60\nfidelity = \"cells\"", "fidelity"),
        ];
        for (from, to, key) in cases {
            let text = GOOD.replacen(from, to, 1);
            assert_ne!(text, GOOD, "case {key}: replacement did not apply");
            let e = parse(&text).expect_err(key);
            assert_eq!(e.key, *key, "{e}");
            assert!(e.to_string().starts_with("studies/x.toml: "), "{e}");
        }
        let e = parse("runs = [").expect_err("toml");
        assert!(e.expected.contains("not valid TOML"), "{e}");
    }
}
