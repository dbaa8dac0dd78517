//! `manifest.json`: what made a run (docs/design.md §2).
//!
//! The manifest is written last, so a directory without one is not a finished run. Tables are
//! byte-identical for the same inputs and seed; the manifest is not quite (it holds wall-clock
//! timings), which is why timings live here and not in the tables.

use crate::StoreError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// File name of the manifest inside a run directory.
pub const MANIFEST_FILE: &str = "manifest.json";

/// One file of a table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TableFile {
    /// Path relative to the run directory, e.g. `truth/run-0000.parquet`.
    pub file: String,
    /// Number of rows in the file.
    pub rows: u64,
}

/// The scenario that made a run: its name and the full resolved scenario, so that the run can be
/// repeated from the manifest alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScenarioInfo {
    /// The scenario's short name, e.g. `scenario-7`.
    pub name: String,
    /// The full resolved scenario (`mimo_scenario::Scenario`: duration, fidelity, ships with their
    /// radars, targets), as JSON.
    pub resolved: serde_json::Value,
}

/// The tracker (test article) used, with its configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrackerInfo {
    /// The test article's name (`default`, `imm`, `cued`, `none`, …).
    pub name: String,
    /// Its full configuration, as JSON.
    pub config: serde_json::Value,
}

/// What a `mimo track` output recorded of its parent when it was made (crate::lineage): the
/// parent must still hold the same scenario and seed, and the same `manifest.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParentCheck {
    /// The parent's scenario name ([`ScenarioInfo::name`]).
    pub scenario: String,
    /// The parent's master seed ([`Manifest::seed`]).
    pub seed: u64,
    /// FNV-1a (64-bit) of the parent's `manifest.json`, hex.
    pub manifest_fnv1a64: String,
}

/// Most Monte Carlo runs a manifest may list (docs/decisions/0035-bounds-and-exit-statuses.md): far above any
/// study, far below what would exhaust a file system's directory entries.
pub const MAX_RUNS: u32 = 100_000;

/// The run manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// Version of the mimo that wrote the run.
    pub mimo_version: String,
    /// Table layout version ([`crate::schema::SCHEMA_VERSION`]); a reader refuses another.
    pub schema_version: u32,
    /// The scenario, fully resolved.
    pub scenario: ScenarioInfo,
    /// Master seed; every random stream is keyed by it (docs/design.md §7).
    pub seed: u64,
    /// Number of Monte Carlo runs (files `run-0000` … in each table).
    pub runs: u32,
    /// Simulated time per run, s.
    pub duration_s: f64,
    /// Every modelling switch in force.
    pub fidelity: serde_json::Value,
    /// The test article and its configuration; `None` (null) when none was recorded (a study
    /// cell none of whose runs reported one).
    pub tracker: Option<TrackerInfo>,
    /// How the dwell schedule was produced (e.g. closed loop with a TA, or a fixed schedule).
    pub schedule: String,
    /// For `mimo track` outputs: the run directory this one was derived from, relative to this
    /// run's own directory (crate::lineage).
    pub parent: Option<String>,
    /// For `mimo track` outputs: what the parent held when this run was made.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parent_check: Option<ParentCheck>,
    /// Table name → files and row counts.
    pub tables: BTreeMap<String, Vec<TableFile>>,
    /// Wall seconds per stage.
    pub timing_s: BTreeMap<String, f64>,
}

impl Manifest {
    /// Read and check `DIR/manifest.json`.
    pub fn read(run_dir: &Path) -> Result<Manifest, StoreError> {
        let path = run_dir.join(MANIFEST_FILE);
        if !run_dir.is_dir() {
            return Err(StoreError::Missing { path: run_dir.to_path_buf() });
        }
        let text = std::fs::read_to_string(&path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                StoreError::BadManifest {
                    file: path.clone(),
                    field: "(file)".into(),
                    why: "missing: not a finished mimo run directory".into(),
                }
            } else {
                StoreError::Io { path: path.clone(), source: e }
            }
        })?;
        let m: Manifest = serde_json::from_str(&text).map_err(|e| StoreError::BadManifest {
            file: path.clone(),
            field: field_of(&e.to_string()),
            why: format!("{e}"),
        })?;
        if m.schema_version != crate::schema::SCHEMA_VERSION {
            return Err(StoreError::BadManifest {
                file: path,
                field: "schema_version".into(),
                why: format!("{} does not match this mimo's {}", m.schema_version, crate::schema::SCHEMA_VERSION),
            });
        }
        m.check_runs(&path)?;
        Ok(m)
    }

    /// `runs` is at least 1 (and at most [`MAX_RUNS`]), and every table lists files
    /// `TABLE/run-K.parquet` of runs K < runs, each at most once (a study cell lists only the
    /// runs that succeeded).
    fn check_runs(&self, path: &Path) -> Result<(), StoreError> {
        let bad = |field: String, why: String| StoreError::BadManifest { file: path.to_path_buf(), field, why };
        if self.runs == 0 || self.runs > MAX_RUNS {
            return Err(bad("runs".into(), format!("{} is outside 1..={MAX_RUNS}", self.runs)));
        }
        for (table, files) in &self.tables {
            let mut seen = std::collections::BTreeSet::new();
            for f in files {
                let run = f
                    .file
                    .strip_prefix(&format!("{table}/"))
                    .and_then(|n| crate::invariants::file_run(Path::new(n)))
                    .filter(|&k| k < self.runs);
                match run {
                    Some(k) if seen.insert(k) => {}
                    _ => {
                        return Err(bad(
                            format!("tables.{table}"),
                            format!(
                                "file '{}' is not one of {table}/run-0000.parquet … of runs 0..{} listed once",
                                f.file, self.runs
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// Pretty JSON text.
    pub fn to_json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_default() + "\n"
    }
}

fn field_of(msg: &str) -> String {
    // serde_json messages read "missing field `x`" or "unknown field `x`"; pull the name out.
    msg.split('`').nth(1).unwrap_or("(json)").to_string()
}
