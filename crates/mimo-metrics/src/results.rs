//! What a score holds: the rows of the score tables (per run and scoring time, per radar and
//! interval) and the summary written to `summary.json` (see the crate docs for each definition).

use crate::{NamedList, ScoreOptions};
use mimo_store::columns::{Column, ColumnRows, IntoColumn};
use serde::Serialize;

mimo_store::score_track_metrics_table!(mimo_store::column_rows);

mimo_store::score_track_metrics_mean_table!(mimo_store::column_rows);

mimo_store::score_assignments_table!(mimo_store::column_rows);

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

/// The columns of `score_usage` (`mimo_store::score_usage_table!`): the radar, then its figures.
impl ColumnRows for UsageRow {
    fn columns_of<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> Vec<Column> {
        let mut columns = vec![String::column_of(rows, |r| &get(r).radar)];
        columns.extend(UsageTotalRow::columns_of(rows, |r| &get(r).figures));
        columns
    }
}

mimo_store::score_usage_total_table!(mimo_store::column_rows);

mimo_store::score_usage_radar_table!(mimo_store::column_rows);

/// Sensor totals of one radar in one run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RunRadarUsage {
    /// Monte Carlo run index.
    pub run: u32,
    /// Radar id R1…R4.
    pub radar: String,
    /// The radar's totals over the run.
    #[serde(flatten)]
    pub totals: SensorTotals,
}

/// Sensor totals of one radar: over one run (in a [`RunRadarUsage`]), or their mean over runs
/// (`summary.json` `usage.per_radar.Rn`, equations 3 and 4).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct SensorTotals {
    /// Transmit dwell time over the run (s).
    pub dwell_time_s: f64,
    /// Transmitted energy over the run (J).
    pub energy_j: f64,
    /// As `dwell_time_s`, TA-requested dwells only (s).
    pub ta_dwell_time_s: f64,
    /// As `energy_j`, TA-requested dwells only (J).
    pub ta_energy_j: f64,
}

/// Transmit usage summed over radars: of one run (in a [`RunSummary`]), or its mean over runs
/// (`summary.json` `usage`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct UsageTotals {
    /// Transmit dwell time summed over radars (s).
    pub total_dwell_time_s: f64,
    /// Transmitted energy summed over radars (J).
    pub total_energy_j: f64,
    /// As `total_dwell_time_s`, TA-requested dwells only (s).
    pub ta_dwell_time_s: f64,
    /// As `total_energy_j`, TA-requested dwells only (J).
    pub ta_energy_j: f64,
    /// Σ over scoring intervals of the transmit dwell time of every radar ÷ the objects scorable
    /// then (s; docs/design.md §6, eq. 5 summed over the run); in `usage`, the mean over runs
    /// where defined. Null when nothing is ever scorable.
    pub dwell_time_per_object_s: Option<f64>,
    /// The same of the transmitted energy (J; eq. 6 summed).
    pub energy_per_object_j: Option<f64>,
    /// As `dwell_time_per_object_s`, TA-requested dwells only (s).
    pub ta_dwell_time_per_object_s: Option<f64>,
    /// As `energy_per_object_j`, TA-requested dwells only (J).
    pub ta_energy_per_object_j: Option<f64>,
    /// The totals over radars by purpose.
    pub by_purpose: PurposeUsage,
}

impl UsageTotals {
    /// The sums of the radars' sensor totals, in the order given (usage by purpose left at zero
    /// and the per-object figures null, for the caller to fill in).
    pub fn summed<'a>(radars: impl Iterator<Item = &'a SensorTotals> + Clone) -> UsageTotals {
        UsageTotals {
            total_dwell_time_s: radars.clone().map(|r| r.dwell_time_s).sum(),
            total_energy_j: radars.clone().map(|r| r.energy_j).sum(),
            ta_dwell_time_s: radars.clone().map(|r| r.ta_dwell_time_s).sum(),
            ta_energy_j: radars.map(|r| r.ta_energy_j).sum(),
            dwell_time_per_object_s: None,
            energy_per_object_j: None,
            ta_dwell_time_per_object_s: None,
            ta_energy_per_object_j: None,
            by_purpose: PurposeUsage::default(),
        }
    }
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

mimo_store::score_usage_by_purpose_table!(mimo_store::column_rows);

mimo_store::score_first_track_table!(mimo_store::column_rows);

mimo_store::score_registration_table!(mimo_store::column_rows);

/// The registration error over every (run, radar) scored (`summary.json` `registration`, only
/// with biases on and estimates reported; docs/design.md §6, "Registration error").
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RegistrationSummary {
    /// (run, radar) estimates scored.
    pub estimates: u32,
    /// RMS of the range-bias error (m).
    pub range_error_rms_m: f64,
    /// RMS of the u-bias error.
    pub u_error_rms: f64,
    /// RMS of the v-bias error.
    pub v_error_rms: f64,
    /// RMS of the heading-bias error (deg).
    pub heading_error_rms_deg: f64,
    /// Mean NEES of the estimates against the drawn biases (`null` if no covariance was usable).
    pub nees_mean: Option<f64>,
    /// Degrees of freedom of each NEES (4: a consistent estimate's mean NEES).
    pub nees_dof: u32,
}

/// Track figures over a set of (run, scoring time)s: every run's (`summary.json` `track`,
/// [`TrackSummary`], breaks and switches per run as means over runs) or one run's (in a
/// [`RunSummary`], breaks and switches as the run's totals, `Count` = `u32`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackFigures<Count> {
    /// Mean completeness over those times with N > 0; null if none.
    pub completeness: Option<f64>,
    /// Mean redundant ratio over those times with N > 0; null if none.
    pub redundant_ratio: Option<f64>,
    /// Mean spurious ratio over those times with M > 0; null if none.
    pub spurious_ratio: Option<f64>,
    /// Track breaks (a run's total; in `track`, its mean over runs).
    pub breaks: Count,
    /// Track switches (a run's total; in `track`, its mean over runs).
    pub switches: Count,
    /// Position RMSE pooled over every truth–track pair assigned at those times (m); null without any.
    pub position_rmse_m: Option<f64>,
    /// Velocity RMSE pooled over every truth–track pair assigned at those times (m/s); null without any.
    pub velocity_rmse_mps: Option<f64>,
}

/// `summary.json` `track`: over every run, breaks and switches per run (mean over runs).
pub type TrackSummary = TrackFigures<f64>;

/// `summary.json` `usage`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UsageSummary {
    /// Sensor totals per radar, mean over runs, in radar order.
    pub per_radar: NamedList<SensorTotals>,
    /// Per-run totals over radars (also by purpose), mean over runs.
    #[serde(flatten)]
    pub totals: UsageTotals,
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
    /// The track figures over the run's scoring times, breaks and switches in the run.
    #[serde(flatten)]
    pub track: TrackFigures<u32>,
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
    /// The run's totals over radars (also by purpose).
    #[serde(flatten)]
    pub usage: UsageTotals,
    /// How soon the run's targets were found.
    pub first_track: FirstTrackSummary,
}

/// How soon targets are first tracked (docs/design.md §6, "Time to first track"): over the
/// (run, target)s scorable at some scoring time, the time from the first scorable scoring time
/// to the first at which the target is assigned a confirmed track (`score/first_track.parquet`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct FirstTrackSummary {
    /// (run, target)s scorable at some scoring time.
    pub targets: u32,
    /// Mean time to first track over those that got a track (s); null if none did.
    pub mean_s: Option<f64>,
    /// The longest of those times (s); null if none got a track.
    pub max_s: Option<f64>,
    /// (run, target)s never assigned a confirmed track.
    pub never_tracked: u32,
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
    /// How soon targets are first tracked, over every run.
    pub first_track: FirstTrackSummary,
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
    /// The registration error (only with biases on and estimates reported, so the summary of
    /// a run without them is unchanged).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub registration: Option<RegistrationSummary>,
    /// Rows whose covariance was slightly indefinite and was repaired, per table (docs/design.md
    /// §7); written only when some row was, so the summary of valid input is unchanged.
    #[serde(skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub repaired_covariances: std::collections::BTreeMap<String, u64>,
}

/// The result of [`crate::score`].
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
    /// Per run and target scorable at some scoring time.
    pub first_track: Vec<FirstTrackRow>,
    /// Per run and radar with a drawn bias and an estimate (empty otherwise).
    pub registration: Vec<RegistrationErrorRow>,
    /// What `summary.json` holds.
    pub summary: Summary,
}
