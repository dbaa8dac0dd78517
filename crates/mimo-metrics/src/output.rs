//! Writing `score/`: each score table through its spec in `mimo_store::score_schema` (units in
//! the Parquet metadata, mirrored to `schemas/score_*.json`), and `summary.json`.

use crate::error::MetricsError;
use crate::{
    AssignmentRow, RadarUsage, Score, TrackMetricsMeanRow, TrackMetricsRow, UsageByPurposeRow, UsageRow, UsageTotalRow,
};
use mimo_store::columns::{Column, write_columns};
use mimo_store::layout::ScoreDir;
use mimo_store::schema::TableSpec;
use mimo_store::score_schema::{
    SCORE_ASSIGNMENTS, SCORE_TRACK_METRICS, SCORE_TRACK_METRICS_MEAN, SCORE_USAGE, SCORE_USAGE_BY_PURPOSE,
    SCORE_USAGE_RADAR, SCORE_USAGE_TOTAL,
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

/// Each score table's values as store columns, in the order of its spec in
/// `mimo_store::score_schema`; `write_columns` refuses any mismatch of name count, type or
/// nullability, and a test checks the frames' names against the specs.
macro_rules! columns {
    ($rows:expr; $($kind:ident $f:ident),* $(,)?) => {
        vec![$(columns!(@one $kind, $rows, $f)),*]
    };
    (@one u32, $rows:expr, $f:ident) => { Column::U32($rows.iter().map(|r| r.$f).collect()) };
    (@one ou32, $rows:expr, $f:ident) => { Column::OptU32($rows.iter().map(|r| r.$f).collect()) };
    (@one ou64, $rows:expr, $f:ident) => { Column::OptU64($rows.iter().map(|r| r.$f).collect()) };
    (@one f64, $rows:expr, $f:ident) => { Column::F64($rows.iter().map(|r| Some(r.$f)).collect()) };
    (@one of64, $rows:expr, $f:ident) => { Column::F64($rows.iter().map(|r| r.$f).collect()) };
    (@one str, $rows:expr, $f:ident) => { Column::Utf8($rows.iter().map(|r| Some(r.$f.clone())).collect()) };
}

/// `track_metrics`: one row per run and scoring time.
pub(crate) fn track_metrics_columns(rows: &[TrackMetricsRow]) -> Vec<Column> {
    columns![rows;
        u32 run, u32 k, f64 t_s, u32 n_truths, u32 n_scorable, u32 n_tracks, u32 n_assigned, u32 n_redundant,
        u32 n_spurious, of64 completeness, of64 redundant_ratio, of64 spurious_ratio, u32 breaks, u32 switches,
        u32 cum_breaks, u32 cum_switches, f64 position_sq_sum_m2, f64 velocity_sq_sum_m2ps2, of64 position_rmse_m,
        of64 velocity_rmse_mps, of64 ospa_m, of64 gospa_m, of64 gospa_localisation_m, ou32 gospa_missed,
        ou32 gospa_false,
    ]
}

fn track_metrics_mean_columns(rows: &[TrackMetricsMeanRow]) -> Vec<Column> {
    columns![rows;
        u32 k, f64 t_s, u32 runs, f64 n_scorable_mean, f64 n_tracks_mean, of64 completeness, of64 redundant_ratio,
        of64 spurious_ratio, f64 cum_breaks_mean, f64 cum_switches_mean, of64 position_rmse_m,
        of64 velocity_rmse_mps, of64 ospa_m, of64 gospa_m,
    ]
}

fn assignments_columns(rows: &[AssignmentRow]) -> Vec<Column> {
    columns![rows; u32 run, f64 t_s, str target, ou64 track_id, of64 position_error_m, of64 velocity_error_mps]
}

fn usage_columns(rows: &[UsageRow]) -> Vec<Column> {
    columns![rows;
        str radar, u32 interval, f64 t_start_s, f64 t_end_s, u32 runs, f64 n_scorable_mean, f64 dwell_time_s,
        f64 energy_j, f64 ta_dwell_time_s, f64 ta_energy_j, of64 dwell_time_per_object_s, of64 energy_per_object_j,
        of64 ta_dwell_time_per_object_s, of64 ta_energy_per_object_j, f64 cum_dwell_time_s, f64 cum_energy_j,
        f64 cum_ta_dwell_time_s, f64 cum_ta_energy_j,
    ]
}

fn usage_total_columns(rows: &[UsageTotalRow]) -> Vec<Column> {
    columns![rows;
        u32 interval, f64 t_start_s, f64 t_end_s, u32 runs, f64 n_scorable_mean, f64 dwell_time_s, f64 energy_j,
        f64 ta_dwell_time_s, f64 ta_energy_j, of64 dwell_time_per_object_s, of64 energy_per_object_j,
        of64 ta_dwell_time_per_object_s, of64 ta_energy_per_object_j, f64 cum_dwell_time_s, f64 cum_energy_j,
        f64 cum_ta_dwell_time_s, f64 cum_ta_energy_j,
    ]
}

fn usage_radar_columns(rows: &[RadarUsage]) -> Vec<Column> {
    columns![rows; str radar, f64 dwell_time_s, f64 energy_j, f64 ta_dwell_time_s, f64 ta_energy_j]
}

fn usage_by_purpose_columns(rows: &[UsageByPurposeRow]) -> Vec<Column> {
    columns![rows;
        u32 run, u32 interval, f64 t_start_s, f64 t_end_s, str radar, str purpose, u32 dwells, f64 dwell_time_s,
        f64 energy_j,
    ]
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
/// `usage_total.parquet`, `usage_radar.parquet`, `usage_by_purpose.parquet` and `summary.json`
/// (written last). Each file is
/// written under a temporary name and renamed. Files already there are replaced; other files are
/// left alone (the caller clears a stale `score/` first if it wants).
pub fn write_outputs(score: &Score, score_dir: &Path) -> Result<(), MetricsError> {
    std::fs::create_dir_all(score_dir)
        .map_err(|e| MetricsError::Write { path: score_dir.to_path_buf(), detail: e.to_string() })?;
    write_table(score_dir, &SCORE_TRACK_METRICS, track_metrics_columns(&score.track_metrics))?;
    write_table(score_dir, &SCORE_TRACK_METRICS_MEAN, track_metrics_mean_columns(&score.track_metrics_mean))?;
    write_table(score_dir, &SCORE_ASSIGNMENTS, assignments_columns(&score.assignments))?;
    write_table(score_dir, &SCORE_USAGE, usage_columns(&score.usage))?;
    write_table(score_dir, &SCORE_USAGE_TOTAL, usage_total_columns(&score.usage_total))?;
    write_table(score_dir, &SCORE_USAGE_RADAR, usage_radar_columns(&score.usage_radar))?;
    write_table(score_dir, &SCORE_USAGE_BY_PURPOSE, usage_by_purpose_columns(&score.usage_by_purpose))?;
    let json = score.summary_json()?;
    write_atomic(&ScoreDir::new(score_dir).summary(), format!("{json}\n").as_bytes())
}
