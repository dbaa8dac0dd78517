//! What a score holds: the rows of the score tables (per run and scoring time, per radar and
//! interval) and the summary written to `summary.json` (see the crate docs for each definition).

use crate::{NamedList, ScoreOptions};
use serde::Serialize;

/// Track metrics of one run at one scoring time (see the crate docs for each definition).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackMetricsRow {
    /// Monte Carlo run index.
    pub run: u32,
    /// Scoring time index k (1-based); `t_s = k · interval_s`.
    pub k: u32,
    /// Scoring time since scenario start (s).
    pub t_s: f64,
    /// Truths present (inside their sampled span), scorable or not.
    pub n_truths: u32,
    /// Scorable truths N: present and seen by at least one radar (docs/design.md §6).
    pub n_scorable: u32,
    /// Live (confirmed, not deleted) tracks.
    pub n_tracks: u32,
    /// Scorable truths assigned a track A.
    pub n_assigned: u32,
    /// Unassigned tracks inside the gate of some scorable truth.
    pub n_redundant: u32,
    /// Tracks inside the gate of no present truth.
    pub n_spurious: u32,
    /// A / N; null when N = 0.
    pub completeness: Option<f64>,
    /// n_redundant / N; null when N = 0.
    pub redundant_ratio: Option<f64>,
    /// n_spurious / M; null when M = 0.
    pub spurious_ratio: Option<f64>,
    /// Truths assigned at the previous scoring time, scorable and unassigned now.
    pub breaks: u32,
    /// Truths assigned now to another track than the one they last had.
    pub switches: u32,
    /// Breaks summed up to this time in the run.
    pub cum_breaks: u32,
    /// Switches summed up to this time in the run.
    pub cum_switches: u32,
    /// Sum of squared position errors over assigned pairs (m^2).
    pub position_sq_sum_m2: f64,
    /// Sum of squared velocity errors over assigned pairs (m^2/s^2).
    pub velocity_sq_sum_m2ps2: f64,
    /// RMS position error over assigned pairs; null without any (m).
    pub position_rmse_m: Option<f64>,
    /// RMS velocity error over assigned pairs; null without any (m/s).
    pub velocity_rmse_mps: Option<f64>,
    /// OSPA between scorable truths and live tracks; null when both sets are empty (m).
    pub ospa_m: Option<f64>,
    /// GOSPA (alpha = 2); null when both sets are empty (m).
    pub gospa_m: Option<f64>,
    /// GOSPA's parts (see [`crate::ospa::OspaGospa`]); null with `gospa_m`.
    pub gospa_localisation_m: Option<f64>,
    /// GOSPA's missed truths (each costing c^p / 2).
    pub gospa_missed: Option<u32>,
    /// GOSPA's false tracks (each costing c^p / 2).
    pub gospa_false: Option<u32>,
}

/// Track metrics at one scoring time averaged over runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackMetricsMeanRow {
    /// Scoring time index, 1-based (t_s = k · interval_s).
    pub k: u32,
    /// Scoring time since scenario start (s).
    pub t_s: f64,
    /// Runs that reach this scoring time.
    pub runs: u32,
    /// Mean scorable truths.
    pub n_scorable_mean: f64,
    /// Mean live tracks.
    pub n_tracks_mean: f64,
    /// Mean completeness over runs with N > 0.
    pub completeness: Option<f64>,
    /// Mean redundant ratio over runs with N > 0.
    pub redundant_ratio: Option<f64>,
    /// Mean spurious ratio over runs with M > 0.
    pub spurious_ratio: Option<f64>,
    /// Mean cumulative breaks.
    pub cum_breaks_mean: f64,
    /// Mean cumulative switches.
    pub cum_switches_mean: f64,
    /// Pooled over the assigned pairs of every run at this time.
    pub position_rmse_m: Option<f64>,
    /// Velocity RMSE pooled over the runs' assigned pairs (m/s).
    pub velocity_rmse_mps: Option<f64>,
    /// Mean OSPA where defined (m).
    pub ospa_m: Option<f64>,
    /// Mean GOSPA where defined (m).
    pub gospa_m: Option<f64>,
}

/// One scorable truth at one scoring time and the track assigned to it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AssignmentRow {
    /// Monte Carlo run index.
    pub run: u32,
    /// Scoring time since scenario start (s).
    pub t_s: f64,
    /// Truth name, as in the truth table.
    pub target: String,
    /// `None` when the truth is unassigned.
    pub track_id: Option<u64>,
    /// ‖track position − truth position‖; null when unassigned (m).
    pub position_error_m: Option<f64>,
    /// ‖track velocity − truth velocity‖; null when unassigned (m/s).
    pub velocity_error_mps: Option<f64>,
}

/// Usage of one radar in one scoring interval, averaged over runs: the radar and its figures,
/// which are those a [`UsageTotalRow`] holds for all radars (read them through `Deref`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UsageRow {
    /// Radar id R1…R4.
    pub radar: String,
    /// The radar's figures in the interval.
    #[serde(flatten)]
    pub figures: UsageTotalRow,
}

impl std::ops::Deref for UsageRow {
    type Target = UsageTotalRow;
    fn deref(&self) -> &UsageTotalRow {
        &self.figures
    }
}

/// Usage in one scoring interval, averaged over runs: of one radar (in a [`UsageRow`]) or of all
/// radars (`usage_total`, the sums over radars of the [`UsageRow`]s).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct UsageTotalRow {
    /// Interval index j, 1-based; a dwell belongs to it by its start time.
    pub interval: u32,
    /// Interval start (s).
    pub t_start_s: f64,
    /// Interval end (s).
    pub t_end_s: f64,
    /// Runs averaged.
    pub runs: u32,
    /// Mean scorable truths at the interval's scoring time.
    pub n_scorable_mean: f64,
    /// Transmit dwell time in the interval, mean over runs (s).
    pub dwell_time_s: f64,
    /// Transmitted energy in the interval, mean over runs (J).
    pub energy_j: f64,
    /// As dwell_time_s, TA-requested dwells only (s).
    pub ta_dwell_time_s: f64,
    /// As energy_j, TA-requested dwells only (J).
    pub ta_energy_j: f64,
    /// Dwell time per scorable object (eq. 1 / 5); null where no run has one (s).
    pub dwell_time_per_object_s: Option<f64>,
    /// Energy per scorable object (eq. 2 / 6); null where no run has one (J).
    pub energy_per_object_j: Option<f64>,
    /// As dwell_time_per_object_s, TA-requested dwells only (s).
    pub ta_dwell_time_per_object_s: Option<f64>,
    /// As energy_per_object_j, TA-requested dwells only (J).
    pub ta_energy_per_object_j: Option<f64>,
    /// Dwell_time_s summed up to this interval (s).
    pub cum_dwell_time_s: f64,
    /// Energy_j summed up to this interval (J).
    pub cum_energy_j: f64,
    /// Ta_dwell_time_s summed up to this interval (s).
    pub cum_ta_dwell_time_s: f64,
    /// Ta_energy_j summed up to this interval (J).
    pub cum_ta_energy_j: f64,
}

/// Sensor totals of one radar over a whole run, averaged over runs (`T[m]`, `E[m]`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RadarUsage {
    /// Radar id R1…R4.
    pub radar: String,
    /// Transmit dwell time (s).
    pub dwell_time_s: f64,
    /// Transmitted energy (J).
    pub energy_j: f64,
    /// Transmit dwell time of TA-requested dwells (s).
    pub ta_dwell_time_s: f64,
    /// Transmitted energy of TA-requested dwells (J).
    pub ta_energy_j: f64,
}

/// Sensor totals of one radar in one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunRadarUsage {
    /// Monte Carlo run index.
    pub run: u32,
    /// Radar id R1…R4.
    pub radar: String,
    /// Transmit dwell time of the radar over the run (s).
    pub dwell_time_s: f64,
    /// Transmitted energy of the radar over the run (J).
    pub energy_j: f64,
    /// As `dwell_time_s`, TA-requested dwells only (s).
    pub ta_dwell_time_s: f64,
    /// As `energy_j`, TA-requested dwells only (J).
    pub ta_energy_j: f64,
}

/// Transmit dwell time and energy of one purpose.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct UsagePair {
    /// Transmit dwell time (s).
    pub dwell_time_s: f64,
    /// Transmitted energy (J).
    pub energy_j: f64,
}

/// Transmit dwell time and energy by purpose (docs/design.md §6, "Usage by purpose").
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct PurposeUsage {
    /// Search dwells (kind `search`, whoever requested them).
    pub search: UsagePair,
    /// Confirmation looks with a truth in beam and range window.
    pub confirm_true: UsagePair,
    /// Confirmation looks with none (looks at false alarms).
    pub confirm_false: UsagePair,
    /// Track and MIMO looks with a truth in beam and range window.
    pub track: UsagePair,
    /// Track and MIMO looks with none (tracks following no object).
    pub track_false: UsagePair,
}

impl PurposeUsage {
    /// The figures of `purpose`.
    pub fn get(&self, purpose: crate::Purpose) -> UsagePair {
        match purpose {
            crate::Purpose::Search => self.search,
            crate::Purpose::ConfirmTrue => self.confirm_true,
            crate::Purpose::ConfirmFalse => self.confirm_false,
            crate::Purpose::Track => self.track,
            crate::Purpose::TrackFalse => self.track_false,
        }
    }
}

/// Transmit usage of one radar in one scoring interval of one run for one purpose
/// (`score/usage_by_purpose.parquet`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UsageByPurposeRow {
    /// Monte Carlo run index.
    pub run: u32,
    /// Interval index j (1-based), covering `[t_start_s, t_end_s)`.
    pub interval: u32,
    /// Interval start (s).
    pub t_start_s: f64,
    /// Interval end (s).
    pub t_end_s: f64,
    /// Radar id R1…R4.
    pub radar: String,
    /// `search`, `confirm_true`, `confirm_false`, `track` or `track_false`.
    pub purpose: String,
    /// Transmit dwell rows (role tx or txrx) starting in the interval.
    pub dwells: u32,
    /// Their dwell time (s).
    pub dwell_time_s: f64,
    /// Their energy (J).
    pub energy_j: f64,
}

/// `summary.json` `track`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackSummary {
    /// Mean completeness over all (run, scoring time) with N > 0; null if none.
    pub completeness: Option<f64>,
    /// Mean redundant ratio over all (run, scoring time) with N > 0; null if none.
    pub redundant_ratio: Option<f64>,
    /// Mean spurious ratio over all (run, scoring time) with M > 0; null if none.
    pub spurious_ratio: Option<f64>,
    /// Track breaks per run (total over the run, mean over runs).
    pub breaks: f64,
    /// Track switches per run (total over the run, mean over runs).
    pub switches: f64,
    /// Position RMSE pooled over every assigned pair of every time and run (m); null without any.
    pub position_rmse_m: Option<f64>,
    /// Velocity RMSE pooled over every assigned pair of every time and run (m/s); null without any.
    pub velocity_rmse_mps: Option<f64>,
}

/// `summary.json` `usage.per_radar.Rn`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RadarUsageSummary {
    /// Transmit dwell time over the run, mean over runs (equation 3) (s).
    pub dwell_time_s: f64,
    /// Transmitted energy over the run, mean over runs (equation 4) (J).
    pub energy_j: f64,
    /// As `dwell_time_s`, TA-requested dwells only (s).
    pub ta_dwell_time_s: f64,
    /// As `energy_j`, TA-requested dwells only (J).
    pub ta_energy_j: f64,
}

/// `summary.json` `usage`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UsageSummary {
    /// Sensor totals per radar, in radar order.
    pub per_radar: NamedList<RadarUsageSummary>,
    /// Transmit dwell time summed over radars, mean over runs (s).
    pub total_dwell_time_s: f64,
    /// Transmitted energy summed over radars, mean over runs (J).
    pub total_energy_j: f64,
    /// As `total_dwell_time_s`, TA-requested dwells only (s).
    pub ta_dwell_time_s: f64,
    /// As `total_energy_j`, TA-requested dwells only (J).
    pub ta_energy_j: f64,
    /// Per-run totals over radars by purpose, mean over runs.
    pub by_purpose: PurposeUsage,
}

/// `summary.json` `challenge`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Challenge {
    /// Completeness the challenge requires (0.98).
    pub completeness_required: f64,
    /// Whether the mean completeness reaches it.
    pub met: bool,
}

/// `summary.json` `ospa` / `gospa` (extras).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DistanceSummary {
    /// Cut-off distance c (m).
    pub c_m: f64,
    /// Order p.
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
    /// Monte Carlo run index.
    pub run: u32,
    /// Scoring times of the run.
    pub scoring_times: u32,
    /// Mean completeness over the run's scoring times with N > 0.
    pub completeness: Option<f64>,
    /// Mean redundant ratio over the run's scoring times with N > 0.
    pub redundant_ratio: Option<f64>,
    /// Mean spurious ratio over the run's scoring times with M > 0.
    pub spurious_ratio: Option<f64>,
    /// Track breaks in the run.
    pub breaks: u32,
    /// Track switches in the run.
    pub switches: u32,
    /// Position RMSE over the run's assigned pairs (m).
    pub position_rmse_m: Option<f64>,
    /// Velocity RMSE over the run's assigned pairs (m/s).
    pub velocity_rmse_mps: Option<f64>,
    /// Mean OSPA over the run's scoring times where defined (m).
    pub ospa_m: Option<f64>,
    /// Mean GOSPA over the run's scoring times where defined (m).
    pub gospa_m: Option<f64>,
    /// Means over the run's scoring times of GOSPA's localisation part (m), missed truths and
    /// false tracks.
    pub gospa_localisation_m: Option<f64>,
    /// Mean missed truths per scoring time (GOSPA).
    pub gospa_missed: Option<f64>,
    /// Mean false tracks per scoring time (GOSPA).
    pub gospa_false: Option<f64>,
    /// Transmit dwell time summed over radars (s).
    pub total_dwell_time_s: f64,
    /// Transmitted energy summed over radars (J).
    pub total_energy_j: f64,
    /// As `total_dwell_time_s`, TA-requested dwells only (s).
    pub ta_dwell_time_s: f64,
    /// As `total_energy_j`, TA-requested dwells only (J).
    pub ta_energy_j: f64,
    /// The run's totals over radars by purpose.
    pub by_purpose: PurposeUsage,
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
    /// Switches of this target per run (mean over runs).
    pub switches: f64,
}

/// How the score was computed (extra `scoring` object in `summary.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScoringInfo {
    /// Run ids scored, ascending.
    pub run_ids: Vec<u32>,
    /// Scoring times per run (the largest over runs).
    pub scoring_times: u32,
    /// How truths and tracks are paired (a description for readers of the summary).
    pub assignment: &'static str,
    /// How undefined figures are reported (null, left out of averages).
    pub undefined_values: &'static str,
}

/// `summary.json`: the docs/design.md §6 keys first, then extras.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Summary {
    /// Scenario name.
    pub scenario: String,
    /// Monte Carlo runs scored.
    pub runs: u32,
    /// Scoring interval Δ (s).
    pub interval_s: f64,
    /// Truth–track assignment gate (m).
    pub gate_m: f64,
    /// Track metrics (docs/design.md §6).
    pub track: TrackSummary,
    /// Usage metrics (equations 3–4).
    pub usage: UsageSummary,
    /// Whether the completeness challenge is met.
    pub challenge: Challenge,
    /// OSPA settings and mean.
    pub ospa: DistanceSummary,
    /// GOSPA settings and mean.
    pub gospa: DistanceSummary,
    /// How the score was computed.
    pub scoring: ScoringInfo,
    /// Each run's figures.
    pub per_run: Vec<RunSummary>,
    /// Each target's figures over all runs.
    pub per_target: NamedList<TargetSummary>,
}

/// The result of [`score`].
#[derive(Debug, Clone, PartialEq)]
pub struct Score {
    /// The options the score was computed with.
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
    /// Per run, radar, scoring interval and purpose.
    pub usage_by_purpose: Vec<UsageByPurposeRow>,
    /// What `summary.json` holds.
    pub summary: Summary,
}
