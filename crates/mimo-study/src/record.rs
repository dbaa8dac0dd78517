//! The record of one finished (cell, run) item: `runs/<cell>/.items/run-0000.json`, written
//! atomically after the run's tables, so that its presence means the item is done. Resuming
//! skips items with a record; merging reads every record. The study tables are always built from
//! these files, whichever machine or shard wrote them, which keeps `results.parquet` identical
//! for any split.

use mimo_store::manifest::TableFile;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Costs of one item (machine-dependent).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ItemCosts {
    /// CPU (or, for a process, wall) seconds inside the test article.
    pub ta_cpu_s: f64,
    /// CPU seconds of the rest of the item on its thread.
    pub sim_cpu_s: f64,
    /// Wall seconds of the item.
    pub wall_s: f64,
    /// CPU seconds of one reference Kalman-filter cycle on the machine that ran the item
    /// ([`crate::kfu`]); absent from records written before it was measured.
    #[serde(default)]
    pub kf_cycle_s: Option<f64>,
}

impl ItemCosts {
    /// The test article's CPU time in reference Kalman-filter cycles (`None` without a
    /// reference measurement).
    pub fn ta_cpu_kfu(&self) -> Option<f64> {
        self.kf_cycle_s.filter(|k| *k > 0.0).map(|k| self.ta_cpu_s / k)
    }
}

/// One finished item.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ItemRecord {
    /// Monte Carlo run.
    pub run: u32,
    /// Master seed.
    pub seed: u64,
    /// Simulated seconds.
    pub duration_s: f64,
    /// Why it failed; `None` when it completed.
    pub failure: Option<String>,
    /// Every metric of `mimo_store::schema::STUDY_METRICS` (null when failed or undefined).
    pub metrics: BTreeMap<String, Option<f64>>,
    /// Costs.
    pub costs: ItemCosts,
    /// The test article's name and configuration, as it reported them.
    pub ta: Option<(String, serde_json::Value)>,
    /// The table files written, by table.
    pub tables: BTreeMap<String, TableFile>,
}

/// Errors reading or writing records.
#[derive(Debug, thiserror::Error)]
pub enum RecordError {
    /// The file system failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A record is not what this version writes.
    #[error("{}: not an item record ({why}); remove it to run the item again", path.display())]
    Bad {
        /// The file.
        path: PathBuf,
        /// The cause.
        why: String,
    },
}

/// The record's path for run `run` of the cell directory `cell_dir`.
pub fn record_path(cell_dir: &Path, run: u32) -> PathBuf {
    mimo_store::layout::RunDir::new(cell_dir).item_record(run)
}

impl ItemRecord {
    /// Write atomically (temporary file, then rename).
    pub fn write(&self, path: &Path) -> Result<(), RecordError> {
        let io = |source| RecordError::Io { path: path.to_path_buf(), source };
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
        let text = serde_json::to_string_pretty(self)
            .map_err(|e| RecordError::Bad { path: path.to_path_buf(), why: e.to_string() })?;
        let tmp = path.with_extension(format!("json.tmp-{}", std::process::id()));
        std::fs::write(&tmp, text + "\n").map_err(|source| RecordError::Io { path: tmp.clone(), source })?;
        std::fs::rename(&tmp, path).map_err(|source| RecordError::Io { path: path.to_path_buf(), source })
    }

    /// Read a record; `Ok(None)` when the item has none yet.
    pub fn read(path: &Path) -> Result<Option<ItemRecord>, RecordError> {
        match std::fs::read_to_string(path) {
            Ok(text) => serde_json::from_str(&text)
                .map(Some)
                .map_err(|e| RecordError::Bad { path: path.to_path_buf(), why: e.to_string() }),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
            Err(source) => Err(RecordError::Io { path: path.to_path_buf(), source }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_round_trips_exactly() {
        let dir = tempfile::tempdir().expect("tmp");
        let mut metrics = BTreeMap::new();
        metrics.insert("completeness".to_string(), Some(0.987_654_321_012_345_6));
        metrics.insert("position_rmse_m".to_string(), Some(1.0 / 3.0));
        metrics.insert("ospa_m".to_string(), None);
        let mut tables = BTreeMap::new();
        tables.insert("tracks".to_string(), TableFile { file: "tracks/run-0002.parquet".into(), rows: 17 });
        let r = ItemRecord {
            run: 2,
            seed: 7,
            duration_s: 30.0,
            failure: None,
            metrics,
            costs: ItemCosts { ta_cpu_s: 0.1, sim_cpu_s: 0.2, wall_s: 0.3, kf_cycle_s: Some(2e-6) },
            ta: Some(("default".into(), serde_json::json!({"a": 1}))),
            tables,
        };
        let path = record_path(dir.path(), 2);
        assert_eq!(ItemRecord::read(&path).expect("read"), None);
        r.write(&path).expect("write");
        assert_eq!(ItemRecord::read(&path).expect("read"), Some(r));
        std::fs::write(&path, "{").expect("write");
        assert!(matches!(ItemRecord::read(&path), Err(RecordError::Bad { .. })));
    }
}
