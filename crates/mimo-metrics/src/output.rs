//! Output tables (polars frames of the [`Score`] rows) and `score/` writing.

use crate::error::{MetricsError, internal};
use crate::{AssignmentRow, RadarUsage, Score, TrackMetricsRow, UsageRow, UsageTotalRow};
use polars::prelude::*;
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

fn c<T, P>(name: &str, values: Vec<T>) -> Column
where
    Series: NamedFrom<Vec<T>, P>,
    P: ?Sized,
{
    Column::from(Series::new(name.into(), values))
}

fn frame(columns: Vec<Column>) -> Result<DataFrame, MetricsError> {
    DataFrame::new_infer_height(columns).map_err(internal("building an output frame"))
}

/// `track_metrics`: one row per run and scoring time.
pub(crate) fn track_metrics_frame(rows: &[TrackMetricsRow]) -> Result<DataFrame, MetricsError> {
    macro_rules! col_of {
        ($f:ident) => {
            c(stringify!($f), rows.iter().map(|r| r.$f).collect::<Vec<_>>())
        };
    }
    frame(vec![
        col_of!(run),
        col_of!(k),
        col_of!(t_s),
        col_of!(n_truths),
        col_of!(n_scorable),
        col_of!(n_tracks),
        col_of!(n_assigned),
        col_of!(n_redundant),
        col_of!(n_spurious),
        col_of!(completeness),
        col_of!(redundant_ratio),
        col_of!(spurious_ratio),
        col_of!(breaks),
        col_of!(switches),
        col_of!(cum_breaks),
        col_of!(cum_switches),
        col_of!(position_sq_sum_m2),
        col_of!(velocity_sq_sum_m2ps2),
        col_of!(position_rmse_m),
        col_of!(velocity_rmse_mps),
        col_of!(ospa_m),
        col_of!(gospa_m),
    ])
}

impl Score {
    /// Per run and scoring time (`score/track_metrics.parquet`).
    pub fn track_metrics_frame(&self) -> Result<DataFrame, MetricsError> {
        track_metrics_frame(&self.track_metrics)
    }

    /// Per scoring time averaged over runs (`score/track_metrics_mean.parquet`).
    pub fn track_metrics_mean_frame(&self) -> Result<DataFrame, MetricsError> {
        let rows = &self.track_metrics_mean;
        macro_rules! col_of {
            ($f:ident) => {
                c(stringify!($f), rows.iter().map(|r| r.$f).collect::<Vec<_>>())
            };
        }
        frame(vec![
            col_of!(k),
            col_of!(t_s),
            col_of!(runs),
            col_of!(n_scorable_mean),
            col_of!(n_tracks_mean),
            col_of!(completeness),
            col_of!(redundant_ratio),
            col_of!(spurious_ratio),
            col_of!(cum_breaks_mean),
            col_of!(cum_switches_mean),
            col_of!(position_rmse_m),
            col_of!(velocity_rmse_mps),
            col_of!(ospa_m),
            col_of!(gospa_m),
        ])
    }

    /// Per run, scoring time and scorable truth (`score/assignments.parquet`).
    pub fn assignments_frame(&self) -> Result<DataFrame, MetricsError> {
        let rows: &[AssignmentRow] = &self.assignments;
        frame(vec![
            c("run", rows.iter().map(|r| r.run).collect::<Vec<_>>()),
            c("t_s", rows.iter().map(|r| r.t_s).collect::<Vec<_>>()),
            c("target", rows.iter().map(|r| r.target.clone()).collect::<Vec<_>>()),
            c("track_id", rows.iter().map(|r| r.track_id).collect::<Vec<_>>()),
            c("position_error_m", rows.iter().map(|r| r.position_error_m).collect::<Vec<_>>()),
            c("velocity_error_mps", rows.iter().map(|r| r.velocity_error_mps).collect::<Vec<_>>()),
        ])
    }

    /// Per radar and interval averaged over runs (`score/usage.parquet`).
    pub fn usage_frame(&self) -> Result<DataFrame, MetricsError> {
        let rows: &[UsageRow] = &self.usage;
        macro_rules! col_of {
            ($f:ident) => {
                c(stringify!($f), rows.iter().map(|r| r.$f.clone()).collect::<Vec<_>>())
            };
        }
        frame(vec![
            col_of!(radar),
            col_of!(interval),
            col_of!(t_start_s),
            col_of!(t_end_s),
            col_of!(runs),
            col_of!(n_scorable_mean),
            col_of!(dwell_time_s),
            col_of!(energy_j),
            col_of!(ta_dwell_time_s),
            col_of!(ta_energy_j),
            col_of!(dwell_time_per_object_s),
            col_of!(energy_per_object_j),
            col_of!(ta_dwell_time_per_object_s),
            col_of!(ta_energy_per_object_j),
            col_of!(cum_dwell_time_s),
            col_of!(cum_energy_j),
            col_of!(cum_ta_dwell_time_s),
            col_of!(cum_ta_energy_j),
        ])
    }

    /// Per interval summed over radars (`score/usage_total.parquet`).
    pub fn usage_total_frame(&self) -> Result<DataFrame, MetricsError> {
        let rows: &[UsageTotalRow] = &self.usage_total;
        macro_rules! col_of {
            ($f:ident) => {
                c(stringify!($f), rows.iter().map(|r| r.$f).collect::<Vec<_>>())
            };
        }
        frame(vec![
            col_of!(interval),
            col_of!(t_start_s),
            col_of!(t_end_s),
            col_of!(runs),
            col_of!(n_scorable_mean),
            col_of!(dwell_time_s),
            col_of!(energy_j),
            col_of!(ta_dwell_time_s),
            col_of!(ta_energy_j),
            col_of!(dwell_time_per_object_s),
            col_of!(energy_per_object_j),
            col_of!(ta_dwell_time_per_object_s),
            col_of!(ta_energy_per_object_j),
            col_of!(cum_dwell_time_s),
            col_of!(cum_energy_j),
            col_of!(cum_ta_dwell_time_s),
            col_of!(cum_ta_energy_j),
        ])
    }

    /// Sensor totals per radar, averaged over runs (`score/usage_radar.parquet`).
    pub fn usage_radar_frame(&self) -> Result<DataFrame, MetricsError> {
        let rows: &[RadarUsage] = &self.usage_radar;
        frame(vec![
            c("radar", rows.iter().map(|r| r.radar.clone()).collect::<Vec<_>>()),
            c("dwell_time_s", rows.iter().map(|r| r.dwell_time_s).collect::<Vec<_>>()),
            c("energy_j", rows.iter().map(|r| r.energy_j).collect::<Vec<_>>()),
            c("ta_dwell_time_s", rows.iter().map(|r| r.ta_dwell_time_s).collect::<Vec<_>>()),
            c("ta_energy_j", rows.iter().map(|r| r.ta_energy_j).collect::<Vec<_>>()),
        ])
    }

    /// `summary.json` text (pretty-printed, docs/design.md §6 keys first).
    pub fn summary_json(&self) -> Result<String, MetricsError> {
        serde_json::to_string_pretty(&self.summary)
            .map_err(|e| MetricsError::Internal { context: "summary JSON", detail: e.to_string() })
    }
}

/// Write `bytes` to `path` atomically (temporary name, then rename).
fn write_atomic(path: &Path, write: impl FnOnce(&mut File) -> Result<(), String>) -> Result<(), MetricsError> {
    let err = |detail: String| MetricsError::Write { path: path.to_path_buf(), detail };
    let mut tmp_name = path.file_name().map(|n| n.to_os_string()).unwrap_or_default();
    tmp_name.push(".tmp");
    let tmp = path.with_file_name(tmp_name);
    let mut f = File::create(&tmp).map_err(|e| err(e.to_string()))?;
    write(&mut f).map_err(err)?;
    f.sync_all().map_err(|e| err(e.to_string()))?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(|e| err(e.to_string()))
}

fn write_parquet(path: &Path, mut df: DataFrame) -> Result<(), MetricsError> {
    write_atomic(path, |f| ParquetWriter::new(f).finish(&mut df).map(|_| ()).map_err(|e| e.to_string()))
}

/// Write the score tables and `summary.json` into `score_dir` (created if needed):
/// `track_metrics.parquet`, `track_metrics_mean.parquet`, `assignments.parquet`, `usage.parquet`,
/// `usage_total.parquet`, `usage_radar.parquet` and `summary.json` (written last). Each file is
/// written under a temporary name and renamed. Files already there are replaced; other files are
/// left alone (the caller clears a stale `score/` first if it wants).
pub fn write_outputs(score: &Score, score_dir: &Path) -> Result<(), MetricsError> {
    std::fs::create_dir_all(score_dir)
        .map_err(|e| MetricsError::Write { path: score_dir.to_path_buf(), detail: e.to_string() })?;
    write_parquet(&score_dir.join("track_metrics.parquet"), score.track_metrics_frame()?)?;
    write_parquet(&score_dir.join("track_metrics_mean.parquet"), score.track_metrics_mean_frame()?)?;
    write_parquet(&score_dir.join("assignments.parquet"), score.assignments_frame()?)?;
    write_parquet(&score_dir.join("usage.parquet"), score.usage_frame()?)?;
    write_parquet(&score_dir.join("usage_total.parquet"), score.usage_total_frame()?)?;
    write_parquet(&score_dir.join("usage_radar.parquet"), score.usage_radar_frame()?)?;
    let json = score.summary_json()?;
    write_atomic(&score_dir.join("summary.json"), |f| {
        f.write_all(json.as_bytes()).and_then(|_| f.write_all(b"\n")).map_err(|e| e.to_string())
    })
}
