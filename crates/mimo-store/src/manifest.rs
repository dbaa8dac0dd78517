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
    pub rows: u64,
}

/// The scenario that made a run: its name and the full resolved scenario, so that the run can be
/// repeated from the manifest alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ScenarioInfo {
    pub name: String,
    pub resolved: serde_json::Value,
}

/// The tracker (test article) used, with its configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrackerInfo {
    pub name: String,
    pub config: serde_json::Value,
}

/// The run manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub mimo_version: String,
    pub schema_version: u32,
    pub scenario: ScenarioInfo,
    pub seed: u64,
    /// Number of Monte Carlo runs (files `run-0000` … in each table).
    pub runs: u32,
    pub duration_s: f64,
    /// Every modelling switch in force.
    pub fidelity: serde_json::Value,
    pub tracker: Option<TrackerInfo>,
    /// How the dwell schedule was produced (e.g. closed loop with a TA, or a fixed schedule).
    pub schedule: String,
    /// For `mimo track` outputs: the run directory this one was derived from (as given).
    pub parent: Option<String>,
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
        Ok(m)
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
