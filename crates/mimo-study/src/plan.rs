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
//! keep_runs = false                         # optional: keep each run's tables once it is scored
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
//!
//! [refine]                                  # optional: refine every swept family where it
//! fraction = 0.05                           # crosses 98 % (a [[methods]] entry's own
//! rounds = 3                                # `refine = { … }` overrides it; docs/studies.md)
//! ```
//!
//! A top-level `frontier_energy = "total"` (the default) or `"test_article"` says which energy
//! the families' efficient frontiers are built on ([`crate::frontier_energy`]).
//!
//! Every error names the plan file, the key path (`methods[1].config.resource_manager.mimoo`)
//! and what was expected; nothing is run or written before the whole plan is checked.

pub use crate::method_sweep::Architecture;
use mimo_scenario::stress::{StressError, bounds, check};
use mimo_ta::overrides::ConfigError;
use serde_json::Value;
use std::path::{Path, PathBuf};
use toml::Value as Toml;

/// A bad plan: the file (with the line and column of a TOML error), the key path and what was
/// expected.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanError {
    /// The plan file.
    pub file: String,
    /// Dotted key path, e.g. `methods[1].config.resource_manager.mimoo`.
    pub key: String,
    /// What was expected.
    pub expected: String,
    /// Line and column (from 1) of a TOML error: bad syntax, an unknown key, a wrong type.
    pub at: Option<(usize, usize)>,
}

impl std::fmt::Display for PlanError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.at {
            Some((line, col)) => write!(f, "{}:{line}:{col}: {}: {}", self.file, self.key, self.expected),
            None => write!(f, "{}: {}: {}", self.file, self.key, self.expected),
        }
    }
}

impl std::error::Error for PlanError {}

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
    /// The knob's value at this method (a family sweeping one key).
    pub knob_value: Option<f64>,
    /// Every swept key path with its value at this method, in the plan's key order (one for a
    /// curve, several for a grid, none when not swept).
    pub grid: Vec<(String, f64)>,
    /// MIMO or conventional (for the challenge's paired comparison).
    pub architecture: Architecture,
    /// How the family is refined where its frontier crosses the requirement (its own `refine`,
    /// else the plan's `[refine]`; `None`: not refined).
    pub refine: Option<crate::refine::Refine>,
    /// Added by refinement (docs/studies.md, "Refinement"), not listed in the plan.
    pub refined: bool,
}

/// A stress axis of a study (its key in plans is the snake-case name, [`Axis::name`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
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
    /// Scale of the registration biases' typical σ's (docs/model.md §5.5).
    BiasScale,
    /// Every ship's link delay (s, docs/model.md §5.6).
    LinkDelayS,
}

impl Axis {
    /// Every axis, in the order of paths and columns.
    pub const ALL: [Axis; 8] = [
        Axis::RcsOffsetDb,
        Axis::Pfa,
        Axis::FormationSpacingScale,
        Axis::PeakPowerOffsetDb,
        Axis::SearchPulses,
        Axis::RaidTargets,
        Axis::BiasScale,
        Axis::LinkDelayS,
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
            Axis::BiasScale => "bias_scale",
            Axis::LinkDelayS => "link_delay_s",
        }
    }

    /// The value that leaves a scenario as it is (`pfa`: the standard radars' 1e-6).
    pub fn baseline(self) -> f64 {
        match self {
            Axis::RcsOffsetDb | Axis::PeakPowerOffsetDb | Axis::RaidTargets => 0.0,
            Axis::BiasScale | Axis::LinkDelayS => 0.0,
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
            Axis::BiasScale => "registration-bias scale (× typical σ)",
            Axis::LinkDelayS => "link delay of every ship (s)",
        }
    }

    /// Whether a larger value stresses a tracker more (more false alarms, more raid aircraft,
    /// larger biases, longer links);
    /// for every other axis a smaller value does (weaker echoes, closer targets, fewer pulses).
    pub fn harder_when_larger(self) -> bool {
        matches!(self, Axis::Pfa | Axis::RaidTargets | Axis::BiasScale | Axis::LinkDelayS)
    }

    /// Whether values are compared, drawn and interpolated on log10 of the value.
    pub fn log_scale(self) -> bool {
        matches!(self, Axis::Pfa)
    }

    /// Values ordered from the least to the most stressing.
    pub fn by_stress(self, values: &[f64]) -> Vec<f64> {
        let mut v = values.to_vec();
        v.sort_by(|a, b| if self.harder_when_larger() { a.total_cmp(b) } else { b.total_cmp(a) });
        v
    }

    pub(crate) fn check(self, v: f64) -> Result<(), String> {
        let r = |b| {
            check(self.name(), v, b)
                .map_err(|e: StressError| format!("expected a value in [{}, {}], got {v}", e.lo, e.hi))
        };
        match self {
            Axis::RcsOffsetDb => r(bounds::RCS_OFFSET_DB),
            Axis::Pfa => r(bounds::PFA),
            Axis::FormationSpacingScale => r(bounds::FORMATION_SPACING_SCALE),
            Axis::PeakPowerOffsetDb => r(bounds::PEAK_POWER_OFFSET_DB),
            Axis::BiasScale => r(bounds::BIAS_SCALE),
            Axis::LinkDelayS => r(bounds::LINK_DELAY_S),
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
    /// Keep every run's tables in its cell directory; by default a completed run's tables are
    /// deleted once it is scored (docs/studies.md, "What a study writes").
    pub keep_runs: bool,
    /// Failure limits.
    pub limits: Limits,
    /// The most refinement rounds of any family (0: the plan refines nothing).
    pub refine_rounds: u32,
    /// The energy the families' efficient frontiers are built on (`frontier_energy`).
    pub frontier_energy: crate::frontier_energy::FrontierEnergy,
}

pub(crate) struct Ctx<'a> {
    pub(crate) file: &'a str,
}

impl Ctx<'_> {
    pub(crate) fn err(&self, key: impl Into<String>, expected: impl Into<String>) -> PlanError {
        PlanError { file: self.file.to_string(), key: key.into(), expected: expected.into(), at: None }
    }

    pub(crate) fn number(&self, key: &str, v: &Toml) -> Result<f64, PlanError> {
        match v {
            Toml::Float(x) if x.is_finite() => Ok(*x),
            Toml::Integer(i) => Ok(*i as f64),
            _ => Err(self.err(key, format!("expected a finite number, got {v}"))),
        }
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

impl Plan {
    /// Read and check a plan file.
    pub fn read(path: &Path) -> Result<Plan, PlanError> {
        let file = path.display().to_string();
        let ctx = Ctx { file: &file };
        let text = std::fs::read_to_string(path).map_err(|e| ctx.err("(file)", format!("cannot read it: {e}")))?;
        Plan::parse(&text, path)
    }

    /// Check a plan's text (`path` names it and anchors relative scenario files): its keys and
    /// their types by serde (module `plan_toml`), then its values (module `plan_check`).
    pub fn parse(text: &str, path: &Path) -> Result<Plan, PlanError> {
        let file = path.display().to_string();
        let ctx = Ctx { file: &file };
        crate::plan_toml::read(text, &file)?.validate(&ctx, path)
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
        assert_eq!(p.frontier_energy, crate::frontier_energy::FrontierEnergy::Total);
        let ta = parse(&GOOD.replacen("duration_s = 60", "duration_s = 60\nfrontier_energy = \"test_article\"", 1));
        assert_eq!(ta.expect("plan").frontier_energy, crate::frontier_energy::FrontierEnergy::TestArticle);
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
            ("duration_s = 60", "duration_s = 60\nfrontier_energy = \"ta\"", "frontier_energy"),
            ("duration_s = 60", "duration_s = 60\nfrontier_energy = 1", "frontier_energy"),
        ];
        for (from, to, key) in cases {
            let text = GOOD.replacen(from, to, 1);
            assert_ne!(text, GOOD, "case {key}: replacement did not apply");
            let e = parse(&text).expect_err(key);
            assert_eq!(e.key, *key, "{e}");
            // A TOML error (an unknown key, a wrong type) also gives the line and column.
            let at = e.at.map(|(l, c)| format!(":{l}:{c}")).unwrap_or_default();
            assert!(e.to_string().starts_with(&format!("studies/x.toml{at}: {key}: ")), "{e}");
        }
        let e = parse("runs = [").expect_err("toml");
        assert!(e.expected.contains("not valid TOML"), "{e}");
        assert_eq!(e.at, Some((1, 9)), "{e}");
    }

    #[test]
    fn toml_type_errors_name_the_line_the_key_path_and_the_expectation() {
        let cases: &[(&str, &str, &str)] = &[
            (
                "runs = 2",
                "runs = \"2\"",
                "studies/x.toml:4:8: runs: expected a whole number of runs from 1 to 10000, got \"2\"",
            ),
            (
                "runs = 2",
                "runs = 2.5",
                "studies/x.toml:4:8: runs: expected a whole number of runs from 1 to 10000, got 2.5",
            ),
            (
                "config = { resource_manager = { mimo = false } }",
                "config = 3",
                "studies/x.toml:12:10: methods[1].config: expected a table of the test article's configuration, got 3",
            ),
            (
                "name = \"conv\"",
                "name = \"conv\"\ntracker = \"x\"",
                "studies/x.toml:11:1: methods[1].tracker: unknown key (expected one of: name, ta, ta_cmd, config, sweep, \
                 architecture, refine)",
            ),
            (
                "pfa = [1e-6, 1e-5]",
                "pfa = [1e-6, \"x\"]",
                "studies/x.toml:17:14: axes.pfa[1]: expected a number, got \"x\"",
            ),
            (
                "pfa = [1e-6, 1e-5]",
                "pfa = 1e-6",
                "studies/x.toml:17:7: axes.pfa: expected a non-empty list of numbers, got 1e-6",
            ),
            (
                "runs = 2",
                "runs = 2\nkeep_runs = \"yes\"",
                "studies/x.toml:5:13: keep_runs: expected true or false, got \"yes\"",
            ),
            (
                "search_pulses = [1, 2]",
                "search_pulses = [1, 2]\n[limits]\nmax_tracks = 1.5",
                "studies/x.toml:20:14: limits.max_tracks: expected a whole number >= 1, got 1.5",
            ),
            (
                "scenarios = [7, \"mine.toml\"]",
                "scenarios = 7",
                "studies/x.toml:3:13: scenarios: expected a non-empty list of scenario numbers or paths, got 7",
            ),
        ];
        for (from, to, want) in cases {
            let text = GOOD.replacen(from, to, 1);
            assert_ne!(text, GOOD, "{want}: replacement did not apply");
            assert_eq!(parse(&text).expect_err(want).to_string(), *want);
        }
        assert!(parse(&GOOD.replacen("runs = 2", "runs = 2\nkeep_runs = true", 1)).expect("plan").keep_runs);
        assert!(!parse(GOOD).expect("plan").keep_runs, "deleted once scored by default");
    }
}
