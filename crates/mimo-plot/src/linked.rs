//! The linked metrics: completeness at each scoring time, the truth each track was assigned to,
//! and the energy spent per scoring interval, for one run (docs/design.md §6).
//!
//! Completeness and assignments come from `RUN/score/` when `mimo score` has been run (its
//! `track_metrics.parquet`, `assignments.parquet` and the interval of `summary.json`), so the
//! page agrees with the charts; otherwise the run is scored in memory with `mimo score`'s
//! defaults and nothing is written. Energy per interval is summed from the run's own
//! dwells ([`crate::dwell_digest::DwellDigest::energy_per_interval`]: the raw sums of docs/design.md §6: transmit parts, interval `⌊t/Δ⌋ + 1`), because
//! the `usage` tables average over the Monte Carlo runs.

use crate::PlotError;
use crate::source::{RunSource, RunTables};
use arrow::array::{ArrayRef, AsArray, RecordBatch};
use arrow::compute::cast;
use arrow::datatypes::{DataType, Float64Type, UInt64Type};
use mimo_metrics::{AssignmentRow, ScorablePredicate, ScoreInput, ScoreOptions, TrackMetricsRow};
use mimo_store::layout::ScoreDir;
use mimo_store::schema::TableSpec;
use mimo_store::score_schema::{self, SCORE_ASSIGNMENTS, SCORE_TRACK_METRICS};
use std::collections::BTreeMap;
use std::path::Path;

/// Scoring results of one run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunScore {
    /// Scoring interval Δ (s).
    pub interval_s: f64,
    /// Where the figures come from (for the page).
    pub source: String,
    /// Scoring times `t_k` (s), ascending.
    pub t_s: Vec<f64>,
    /// Completeness at each scoring time (None when nothing was scorable).
    pub completeness: Vec<Option<f64>>,
    /// Scorable truths at each scoring time.
    pub n_scorable: Vec<u32>,
    /// (scoring time index k ≥ 1, track id) → the truth assigned to that track at `t_k`.
    pub assigned: BTreeMap<(u64, u64), String>,
}

impl RunScore {
    /// Index k (1-based) of the scoring time at or after `t_s`: the first scoring time at which
    /// a track state of time `t_s` counts.
    pub fn k_at_or_after(&self, t_s: f64) -> u64 {
        (t_s / self.interval_s - 1e-9).ceil().max(1.0) as u64
    }
}

fn bad(file: &Path, why: impl std::fmt::Display) -> PlotError {
    PlotError::BadScore { file: file.to_path_buf(), why: why.to_string() }
}

/// A score table's batches (the whole file; score tables are small), read through the store's
/// checks of table `spec` (`mimo_store::checked`: metadata, column types, value rules).
fn read_frame(file: &Path, spec: &'static TableSpec) -> Result<Vec<RecordBatch>, PlotError> {
    let reader = mimo_store::checked::open(file, spec)?;
    let unreadable = |e: &dyn std::fmt::Display| bad(file, format!("not a readable score table ({e})"));
    let reader = reader.build().map_err(|e| unreadable(&e))?;
    let batches = reader.collect::<Result<Vec<_>, _>>().map_err(|e| unreadable(&e))?;
    let mut first_row = 0;
    for b in &batches {
        mimo_store::rows::Batch::check_values(b, file, spec, first_row)?;
        first_row += b.num_rows();
    }
    Ok(batches)
}

/// Column `name` of every batch, cast to `want`.
fn column(batches: &[RecordBatch], file: &Path, name: &str, want: &DataType) -> Result<Vec<ArrayRef>, PlotError> {
    let mut out = Vec::with_capacity(batches.len());
    for b in batches {
        let c = b.column_by_name(name).ok_or_else(|| bad(file, format!("no column `{name}`")))?;
        out.push(cast(c, want).map_err(|e| bad(file, format!("column `{name}`: {e}")))?);
    }
    if batches.is_empty() {
        return Err(bad(file, format!("no column `{name}`")));
    }
    Ok(out)
}

fn col_f64(df: &[RecordBatch], file: &Path, name: &str) -> Result<Vec<Option<f64>>, PlotError> {
    let parts = column(df, file, name, &DataType::Float64)?;
    Ok(parts.iter().flat_map(|a| a.as_primitive::<Float64Type>().iter().collect::<Vec<_>>()).collect())
}

fn col_u64(df: &[RecordBatch], file: &Path, name: &str) -> Result<Vec<Option<u64>>, PlotError> {
    let parts = column(df, file, name, &DataType::UInt64)?;
    Ok(parts.iter().flat_map(|a| a.as_primitive::<UInt64Type>().iter().collect::<Vec<_>>()).collect())
}

fn col_str(df: &[RecordBatch], file: &Path, name: &str) -> Result<Vec<Option<String>>, PlotError> {
    let parts = column(df, file, name, &DataType::Utf8)?;
    Ok(parts
        .iter()
        .flat_map(|a| a.as_string::<i32>().iter().map(|x| x.map(str::to_string)).collect::<Vec<_>>())
        .collect())
}

/// Read run `run`'s figures from a `mimo score` output directory.
pub fn from_score_dir(dir: &Path, run: u32) -> Result<RunScore, PlotError> {
    let score = ScoreDir::new(dir);
    let summary_f = score.summary();
    let text = std::fs::read_to_string(&summary_f).map_err(|e| bad(&summary_f, e))?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| bad(&summary_f, e))?;
    let interval_s = v["interval_s"].as_f64().filter(|x| x.is_finite() && *x > 0.0);
    let interval_s = interval_s.ok_or_else(|| bad(&summary_f, "field 'interval_s': expected a positive number"))?;

    let tm_f = score.table(&SCORE_TRACK_METRICS);
    let df = read_frame(&tm_f, &score_schema::SCORE_TRACK_METRICS)?;
    let c = TrackMetricsRow::COLUMNS;
    let runs = col_u64(&df, &tm_f, c.run)?;
    let t = col_f64(&df, &tm_f, c.t_s)?;
    let comp = col_f64(&df, &tm_f, c.completeness)?;
    let ns = col_u64(&df, &tm_f, c.n_scorable)?;
    let mut rows: Vec<(f64, Option<f64>, u32)> = Vec::new();
    for i in 0..runs.len() {
        if runs[i] == Some(u64::from(run)) {
            let ti = t[i].ok_or_else(|| bad(&tm_f, format!("column `{}` is null at row {i}", c.t_s)))?;
            rows.push((ti, comp[i], ns[i].unwrap_or(0) as u32));
        }
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = RunScore { interval_s, source: format!("{}", dir.display()), ..RunScore::default() };
    for (ti, c, n) in rows {
        out.t_s.push(ti);
        out.completeness.push(c);
        out.n_scorable.push(n);
    }

    let as_f = score.table(&SCORE_ASSIGNMENTS);
    let df = read_frame(&as_f, &score_schema::SCORE_ASSIGNMENTS)?;
    let c = AssignmentRow::COLUMNS;
    let runs = col_u64(&df, &as_f, c.run)?;
    let t = col_f64(&df, &as_f, c.t_s)?;
    let target = col_str(&df, &as_f, c.target)?;
    let track = col_u64(&df, &as_f, c.track_id)?;
    for i in 0..runs.len() {
        if let (Some(r), Some(ti), Some(tg), Some(tr)) = (runs[i], t[i], &target[i], track[i])
            && r == u64::from(run)
        {
            out.assigned.insert(((ti / interval_s).round() as u64, tr), tg.clone());
        }
    }
    Ok(out)
}

/// Score run `run` in memory with `mimo score`'s defaults (nothing is written).
pub fn computed(src: &RunSource, tables: &RunTables) -> Result<RunScore, PlotError> {
    let ships = src.scenario.ships.clone();
    let scorable: ScorablePredicate = Box::new(move |t, pos, alt| ships.iter().any(|s| s.sees(t, pos, alt)));
    let input = ScoreInput {
        truth: vec![tables.files[0].clone()],
        dwells: vec![tables.files[1].clone()],
        // A run without a tracks file (search only) is scored as a run without tracks.
        tracks: if tables.files[3].is_file() { vec![tables.files[3].clone()] } else { Vec::new() },
        scorable,
        // The page shows completeness only: the usage by purpose is not needed.
        beams: mimo_metrics::BeamGeometry::none(),
    };
    let opts = ScoreOptions {
        scenario: src.scenario.name.clone(),
        radars: src.scenario.ships.iter().map(|s| s.id.to_string()).collect(),
        threads: 1,
        ..ScoreOptions::default()
    };
    let score = mimo_metrics::score(&input, &opts)?;
    let mut out = RunScore {
        interval_s: opts.interval_s,
        source: "computed in memory (mimo score defaults; RUN/score absent)".into(),
        ..RunScore::default()
    };
    for r in &score.track_metrics {
        out.t_s.push(r.t_s);
        out.completeness.push(r.completeness);
        out.n_scorable.push(r.n_scorable);
    }
    for a in &score.assignments {
        if let Some(tr) = a.track_id {
            out.assigned.insert(((a.t_s / opts.interval_s).round() as u64, tr), a.target.clone());
        }
    }
    Ok(out)
}
