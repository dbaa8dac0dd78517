//! What a score holds: the rows of the score tables (per run and scoring time, per radar and
//! interval) and the summary written to `summary.json` (see the crate docs for each definition).

use crate::{NamedList, ScoreOptions};
use serde::Serialize;

/// Track metrics of one run at one scoring time (see the crate docs for each definition).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackMetricsRow {
    pub run: u32,
    /// Scoring time index k (1-based); `t_s = k · interval_s`.
    pub k: u32,
    pub t_s: f64,
    /// Truths present (inside their sampled span), scorable or not.
    pub n_truths: u32,
    pub n_scorable: u32,
    /// Live (confirmed, not deleted) tracks.
    pub n_tracks: u32,
    pub n_assigned: u32,
    pub n_redundant: u32,
    pub n_spurious: u32,
    pub completeness: Option<f64>,
    pub redundant_ratio: Option<f64>,
    pub spurious_ratio: Option<f64>,
    pub breaks: u32,
    pub switches: u32,
    pub cum_breaks: u32,
    pub cum_switches: u32,
    pub position_sq_sum_m2: f64,
    pub velocity_sq_sum_m2ps2: f64,
    pub position_rmse_m: Option<f64>,
    pub velocity_rmse_mps: Option<f64>,
    pub ospa_m: Option<f64>,
    pub gospa_m: Option<f64>,
    /// GOSPA's parts (see [`crate::ospa::OspaGospa`]); null with `gospa_m`.
    pub gospa_localisation_m: Option<f64>,
    pub gospa_missed: Option<u32>,
    pub gospa_false: Option<u32>,
}

/// Track metrics at one scoring time averaged over runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackMetricsMeanRow {
    pub k: u32,
    pub t_s: f64,
    /// Runs that reach this scoring time.
    pub runs: u32,
    pub n_scorable_mean: f64,
    pub n_tracks_mean: f64,
    pub completeness: Option<f64>,
    pub redundant_ratio: Option<f64>,
    pub spurious_ratio: Option<f64>,
    pub cum_breaks_mean: f64,
    pub cum_switches_mean: f64,
    /// Pooled over the assigned pairs of every run at this time.
    pub position_rmse_m: Option<f64>,
    pub velocity_rmse_mps: Option<f64>,
    pub ospa_m: Option<f64>,
    pub gospa_m: Option<f64>,
}

/// One scorable truth at one scoring time and the track assigned to it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AssignmentRow {
    pub run: u32,
    pub t_s: f64,
    pub target: String,
    /// `None` when the truth is unassigned.
    pub track_id: Option<u64>,
    pub position_error_m: Option<f64>,
    pub velocity_error_mps: Option<f64>,
}

/// Usage of one radar in one scoring interval, averaged over runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UsageRow {
    pub radar: String,
    /// Interval index j (1-based), covering `[t_start_s, t_end_s)`.
    pub interval: u32,
    pub t_start_s: f64,
    pub t_end_s: f64,
    /// Runs that reach this interval.
    pub runs: u32,
    /// Scorable objects at the interval's scoring time, averaged over runs.
    pub n_scorable_mean: f64,
    /// Σ τ_dwell of transmit dwells starting in the interval (s), mean over runs.
    pub dwell_time_s: f64,
    /// Σ emitted energy (J), mean over runs.
    pub energy_j: f64,
    pub ta_dwell_time_s: f64,
    pub ta_energy_j: f64,
    /// `T[m,j]`: dwell time per scorable object (s); null when no run has a scorable object.
    pub dwell_time_per_object_s: Option<f64>,
    /// `E[m,j]`: energy per scorable object (J).
    pub energy_per_object_j: Option<f64>,
    pub ta_dwell_time_per_object_s: Option<f64>,
    pub ta_energy_per_object_j: Option<f64>,
    /// Cumulative raw sums up to and including this interval.
    pub cum_dwell_time_s: f64,
    pub cum_energy_j: f64,
    pub cum_ta_dwell_time_s: f64,
    pub cum_ta_energy_j: f64,
}

/// Usage of all radars in one scoring interval (the sums over radars of [`UsageRow`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct UsageTotalRow {
    pub interval: u32,
    pub t_start_s: f64,
    pub t_end_s: f64,
    pub runs: u32,
    pub n_scorable_mean: f64,
    pub dwell_time_s: f64,
    pub energy_j: f64,
    pub ta_dwell_time_s: f64,
    pub ta_energy_j: f64,
    pub dwell_time_per_object_s: Option<f64>,
    pub energy_per_object_j: Option<f64>,
    pub ta_dwell_time_per_object_s: Option<f64>,
    pub ta_energy_per_object_j: Option<f64>,
    pub cum_dwell_time_s: f64,
    pub cum_energy_j: f64,
    pub cum_ta_dwell_time_s: f64,
    pub cum_ta_energy_j: f64,
}

/// Sensor totals of one radar over a whole run, averaged over runs (`T[m]`, `E[m]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RadarUsage {
    pub radar: String,
    pub dwell_time_s: f64,
    pub energy_j: f64,
    pub ta_dwell_time_s: f64,
    pub ta_energy_j: f64,
}

/// Sensor totals of one radar in one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunRadarUsage {
    pub run: u32,
    pub radar: String,
    pub dwell_time_s: f64,
    pub energy_j: f64,
    pub ta_dwell_time_s: f64,
    pub ta_energy_j: f64,
}

/// `summary.json` `track`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackSummary {
    pub completeness: Option<f64>,
    pub redundant_ratio: Option<f64>,
    pub spurious_ratio: Option<f64>,
    /// Track breaks per run (total over the run, mean over runs).
    pub breaks: f64,
    /// Track switches per run (total over the run, mean over runs).
    pub switches: f64,
    pub position_rmse_m: Option<f64>,
    pub velocity_rmse_mps: Option<f64>,
}

/// `summary.json` `usage.per_radar.Rn`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RadarUsageSummary {
    pub dwell_time_s: f64,
    pub energy_j: f64,
    pub ta_dwell_time_s: f64,
    pub ta_energy_j: f64,
}

/// `summary.json` `usage`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UsageSummary {
    pub per_radar: NamedList<RadarUsageSummary>,
    pub total_dwell_time_s: f64,
    pub total_energy_j: f64,
    pub ta_dwell_time_s: f64,
    pub ta_energy_j: f64,
}

/// `summary.json` `challenge`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Challenge {
    pub completeness_required: f64,
    pub met: bool,
}

/// `summary.json` `ospa` / `gospa` (extras).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DistanceSummary {
    pub c_m: f64,
    pub p: f64,
    /// Only for GOSPA: 2.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alpha: Option<f64>,
    /// Mean over (run, scoring time) where defined (m).
    pub mean_m: Option<f64>,
}

/// One run's figures (extra `per_run` list in `summary.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunSummary {
    pub run: u32,
    pub scoring_times: u32,
    pub completeness: Option<f64>,
    pub redundant_ratio: Option<f64>,
    pub spurious_ratio: Option<f64>,
    pub breaks: u32,
    pub switches: u32,
    pub position_rmse_m: Option<f64>,
    pub velocity_rmse_mps: Option<f64>,
    pub ospa_m: Option<f64>,
    pub gospa_m: Option<f64>,
    /// Means over the run's scoring times of GOSPA's localisation part (m), missed truths and
    /// false tracks.
    pub gospa_localisation_m: Option<f64>,
    pub gospa_missed: Option<f64>,
    pub gospa_false: Option<f64>,
    pub total_dwell_time_s: f64,
    pub total_energy_j: f64,
    pub ta_dwell_time_s: f64,
    pub ta_energy_j: f64,
}

/// One target's figures over all runs (extra `per_target` map in `summary.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TargetSummary {
    /// (run, scoring time) pairs at which the target was scorable.
    pub scorable_times: u64,
    /// Assigned ÷ scorable over those pairs; null if never scorable.
    pub completeness: Option<f64>,
    /// Breaks and switches of this target per run (mean over runs).
    pub breaks: f64,
    pub switches: f64,
}

/// How the score was computed (extra `scoring` object in `summary.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScoringInfo {
    pub run_ids: Vec<u32>,
    /// Scoring times per run (the largest over runs).
    pub scoring_times: u32,
    pub assignment: &'static str,
    pub undefined_values: &'static str,
}

/// `summary.json`: the docs/design.md §6 keys first, then extras.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    pub scenario: String,
    pub runs: u32,
    pub interval_s: f64,
    pub gate_m: f64,
    pub track: TrackSummary,
    pub usage: UsageSummary,
    pub challenge: Challenge,
    pub ospa: DistanceSummary,
    pub gospa: DistanceSummary,
    pub scoring: ScoringInfo,
    pub per_run: Vec<RunSummary>,
    pub per_target: NamedList<TargetSummary>,
}

/// The result of [`score`].
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    pub options: ScoreOptions,
    /// Run ids (from the truth table), ascending.
    pub runs: Vec<u32>,
    /// Radars reported, in id order.
    pub radars: Vec<String>,
    /// Per run and scoring time.
    pub track_metrics: Vec<TrackMetricsRow>,
    /// Per scoring time, averaged over runs.
    pub track_metrics_mean: Vec<TrackMetricsMeanRow>,
    /// Per run, scoring time and scorable truth.
    pub assignments: Vec<AssignmentRow>,
    /// Per radar and interval, averaged over runs.
    pub usage: Vec<UsageRow>,
    /// Per interval, summed over radars.
    pub usage_total: Vec<UsageTotalRow>,
    /// Per radar over the whole run, averaged over runs.
    pub usage_radar: Vec<RadarUsage>,
    /// Per run and radar over the whole run.
    pub usage_run: Vec<RunRadarUsage>,
    pub summary: Summary,
}
