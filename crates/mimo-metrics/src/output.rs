//! Writing `score/`: each score table through its spec in `mimo_store::score_schema` (units in
//! the Parquet metadata, mirrored to `schemas/score_*.json`), and `summary.json`.

use crate::error::MetricsError;
use crate::{
    AssignmentRow, FirstTrackRow, RadarUsage, RegistrationErrorRow, Score, TrackMetricsMeanRow, TrackMetricsRow,
    UsageByPurposeRow, UsageRow, UsageTotalRow,
};
use mimo_store::columns::{Column, ColumnRows, write_columns};
use mimo_store::layout::ScoreDir;
use mimo_store::schema::TableSpec;
use mimo_store::score_schema::{
    SCORE_ASSIGNMENTS, SCORE_FIRST_TRACK, SCORE_REGISTRATION, SCORE_TRACK_METRICS, SCORE_TRACK_METRICS_MEAN,
    SCORE_USAGE, SCORE_USAGE_BY_PURPOSE, SCORE_USAGE_RADAR, SCORE_USAGE_TOTAL,
};
use serde::ser::{Serialize, SerializeMap, Serializer};
use std::fs::File;
use std::io::Write;
use std::path::Path;

/// A JSON object whose keys keep the order of the list (e.g. radars `R1`, `R2`, … `R10`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NamedList<T>(pub Vec<(String, T)>);

impl<T> NamedList<T> {
    /// The value of `name`.
    pub fn get(&self, name: &str) -> Option<&T> {
        self.0.iter().find(|(n, _)| n == name).map(|(_, v)| v)
    }
}

impl<T: Serialize> Serialize for NamedList<T> {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

impl Score {
    /// `summary.json` text (pretty-printed, docs/design.md §6 keys first).
    pub fn summary_json(&self) -> Result<String, MetricsError> {
        serde_json::to_string_pretty(&self.summary)
            .map_err(|e| MetricsError::Internal { context: "summary JSON", detail: e.to_string() })
    }
}

/// Write `bytes` to `path` atomically (temporary name, then rename).
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), MetricsError> {
    let err = |e: std::io::Error| MetricsError::Write { path: path.to_path_buf(), detail: e.to_string() };
    let mut tmp_name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    tmp_name.push(".tmp");
    let tmp = path.with_file_name(tmp_name);
    let mut f = File::create(&tmp).map_err(err)?;
    f.write_all(bytes).map_err(err)?;
    f.sync_all().map_err(err)?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(err)
}

/// Write one score table through its spec (units in the Parquet metadata, atomically).
fn write_table(score_dir: &Path, spec: &TableSpec, columns: Vec<Column>) -> Result<(), MetricsError> {
    let path = ScoreDir::new(score_dir).table(spec);
    write_columns(&path, spec, columns).map(|_| ()).map_err(|e| MetricsError::Write { path, detail: e.to_string() })
}

/// Write the score tables and `summary.json` into `score_dir` (created if needed):
/// `track_metrics.parquet`, `track_metrics_mean.parquet`, `assignments.parquet`, `usage.parquet`,
/// `usage_total.parquet`, `usage_radar.parquet`, `usage_by_purpose.parquet`, `first_track.parquet`, `registration.parquet` (only with
/// registration errors) and `summary.json`
/// (written last). Each file is
/// written under a temporary name and renamed. Files already there are replaced; other files are
/// left alone (the caller clears a stale `score/` first if it wants).
pub fn write_outputs(score: &Score, score_dir: &Path) -> Result<(), MetricsError> {
    std::fs::create_dir_all(score_dir)
        .map_err(|e| MetricsError::Write { path: score_dir.to_path_buf(), detail: e.to_string() })?;
    write_table(score_dir, &SCORE_TRACK_METRICS, TrackMetricsRow::columns(&score.track_metrics))?;
    write_table(score_dir, &SCORE_TRACK_METRICS_MEAN, TrackMetricsMeanRow::columns(&score.track_metrics_mean))?;
    write_table(score_dir, &SCORE_ASSIGNMENTS, AssignmentRow::columns(&score.assignments))?;
    write_table(score_dir, &SCORE_USAGE, UsageRow::columns(&score.usage))?;
    write_table(score_dir, &SCORE_USAGE_TOTAL, UsageTotalRow::columns(&score.usage_total))?;
    write_table(score_dir, &SCORE_USAGE_RADAR, RadarUsage::columns(&score.usage_radar))?;
    write_table(score_dir, &SCORE_USAGE_BY_PURPOSE, UsageByPurposeRow::columns(&score.usage_by_purpose))?;
    write_table(score_dir, &SCORE_FIRST_TRACK, FirstTrackRow::columns(&score.first_track))?;
    if !score.registration.is_empty() {
        write_table(score_dir, &SCORE_REGISTRATION, RegistrationErrorRow::columns(&score.registration))?;
    }
    let json = score.summary_json()?;
    write_atomic(&ScoreDir::new(score_dir).summary(), format!("{json}\n").as_bytes())
}
