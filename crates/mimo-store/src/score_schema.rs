//! The tables `mimo score` writes into `RUN/score/` (docs/design.md §6), declared like the run
//! tables: names, types, nullability, units and meanings, mirrored to `schemas/score_*.json` and
//! checked by the schema test. `mimo-metrics` fills them through
//! [`write_columns`](crate::columns::write_columns), which refuses columns that do not match.
//!
//! Undefined figures (a ratio with nothing to divide by, an RMSE with no assigned pair) are null,
//! never a number.
//!
//! Each score table is declared once here, in the grammar of `mimo_core::table_decl`: expanded
//! here into its [`TableSpec`], and in `mimo-metrics` into its record struct and the columns it
//! writes.

/// The `score_track_metrics` table, declared once: hands its columns to `$gen`.
#[macro_export]
macro_rules! score_track_metrics_table {
    ($gen:path) => {
        $crate::core_crate::table_decl! { $gen;
            /// Track metrics of one run at one scoring time (see the `mimo-metrics` docs for each definition).
            #[derive(Debug, Clone, PartialEq, Serialize)]
            pub struct TrackMetricsRow / TrackMetricsColumns in SCORE_TRACK_METRICS = "score_track_metrics":
                "Track metrics per run and scoring time (docs/design.md §6)" {
                run: u32 => ("", "Monte Carlo run index"),
                k: u32 => ("", "scoring time index, 1-based (t_s = k · interval_s)"),
                t_s: f64 => ("s", "scoring time since scenario start") as Split + PageStats,
                n_truths: u32 => ("", "truths present (inside their sampled span), scorable or not"),
                n_scorable: u32 => ("", "scorable truths N: present and seen by at least one radar (docs/design.md §6)"),
                n_tracks: u32 => ("", "live tracks M (confirmed, not deleted)"),
                n_assigned: u32 => ("", "scorable truths assigned a track A"),
                n_redundant: u32 => ("", "unassigned tracks inside the gate of some scorable truth"),
                n_spurious: u32 => ("", "tracks inside the gate of no present truth"),
                completeness: Option<f64> => ("", "A / N; null when N = 0"),
                redundant_ratio: Option<f64> => ("", "n_redundant / N; null when N = 0"),
                spurious_ratio: Option<f64> => ("", "n_spurious / M; null when M = 0"),
                breaks: u32 => ("", "truths assigned at the previous scoring time, scorable and unassigned now"),
                switches: u32 => ("", "truths assigned now to another track than the one they last had"),
                cum_breaks: u32 => ("", "breaks summed up to this time in the run"),
                cum_switches: u32 => ("", "switches summed up to this time in the run"),
                position_sq_sum_m2: f64 => ("m^2", "sum of squared position errors over assigned pairs"),
                velocity_sq_sum_m2ps2: f64 => ("m^2/s^2", "sum of squared velocity errors over assigned pairs"),
                position_rmse_m: Option<f64> => ("m", "RMS position error over assigned pairs; null without any"),
                velocity_rmse_mps: Option<f64> => ("m/s", "RMS velocity error over assigned pairs; null without any"),
                ospa_m: Option<f64> => ("m", "OSPA between scorable truths and live tracks; null when both sets are empty"),
                gospa_m: Option<f64> => ("m", "GOSPA (alpha = 2); null when both sets are empty"),
                gospa_localisation_m: Option<f64> => ("m", "GOSPA's localisation part: (sum of assigned d^p)^(1/p)"),
                gospa_missed: Option<u32> => ("", "GOSPA's missed truths (each costing c^p / 2)"),
                gospa_false: Option<u32> => ("", "GOSPA's false tracks (each costing c^p / 2)"),
            }
        }
    };
}

/// The `score_track_metrics_mean` table, declared once: hands its columns to `$gen`.
#[macro_export]
macro_rules! score_track_metrics_mean_table {
    ($gen:path) => {
        $crate::core_crate::table_decl! { $gen;
            /// Track metrics at one scoring time averaged over runs.
            #[derive(Debug, Clone, PartialEq, Serialize)]
            pub struct TrackMetricsMeanRow / TrackMetricsMeanColumns in SCORE_TRACK_METRICS_MEAN =
                "score_track_metrics_mean":
                "Track metrics per scoring time, averaged over runs where defined (docs/design.md §6)" {
                k: u32 => ("", "scoring time index, 1-based (t_s = k · interval_s)"),
                t_s: f64 => ("s", "scoring time since scenario start") as Split + PageStats,
                runs: u32 => ("", "runs averaged"),
                n_scorable_mean: f64 => ("", "mean scorable truths"),
                n_tracks_mean: f64 => ("", "mean live tracks"),
                completeness: Option<f64> => ("", "mean completeness over runs with N > 0"),
                redundant_ratio: Option<f64> => ("", "mean redundant ratio over runs with N > 0"),
                spurious_ratio: Option<f64> => ("", "mean spurious ratio over runs with M > 0"),
                cum_breaks_mean: f64 => ("", "mean cumulative breaks"),
                cum_switches_mean: f64 => ("", "mean cumulative switches"),
                position_rmse_m: Option<f64> => ("m", "position RMSE pooled over the runs' assigned pairs"),
                velocity_rmse_mps: Option<f64> => ("m/s", "velocity RMSE pooled over the runs' assigned pairs"),
                ospa_m: Option<f64> => ("m", "mean OSPA where defined"),
                gospa_m: Option<f64> => ("m", "mean GOSPA where defined"),
            }
        }
    };
}

/// The `score_assignments` table, declared once: hands its columns to `$gen`.
#[macro_export]
macro_rules! score_assignments_table {
    ($gen:path) => {
        $crate::core_crate::table_decl! { $gen;
            /// One scorable truth at one scoring time and the track assigned to it.
            #[derive(Debug, Clone, PartialEq, Serialize)]
            pub struct AssignmentRow / AssignmentColumns in SCORE_ASSIGNMENTS = "score_assignments":
                "The track assigned to each scorable truth at each scoring time, with its errors" {
                run: u32 => ("", "Monte Carlo run index"),
                t_s: f64 => ("s", "scoring time since scenario start") as Split + PageStats,
                target: String => ("", "truth name, as in the truth table"),
                track_id: Option<u64> => ("", "assigned track; null when the truth is unassigned"),
                position_error_m: Option<f64> => ("m", "‖track position − truth position‖; null when unassigned"),
                velocity_error_mps: Option<f64> => ("m/s", "‖track velocity − truth velocity‖; null when unassigned"),
            }
        }
    };
}

/// The usage columns shared by `score_usage` and `score_usage_total` (equations (1), (2), (5),
/// (6) of docs/design.md §6, all dwells and TA-requested dwells alone), declared once: hands
/// `$gen` the declaration `$head { $prefix… usage columns }`.
#[macro_export]
#[doc(hidden)]
macro_rules! usage_figure_columns {
    ($gen:path; { $($head:tt)* } { $($prefix:tt)* }) => {
        $crate::core_crate::table_decl! { $gen;
            $($head)* {
                $($prefix)*
                interval: u32 => ("", "interval index j, 1-based; a dwell belongs to it by its start time"),
                t_start_s: f64 => ("s", "interval start"),
                t_end_s: f64 => ("s", "interval end"),
                runs: u32 => ("", "runs averaged"),
                n_scorable_mean: f64 => ("", "mean scorable truths at the interval's scoring time"),
                dwell_time_s: f64 => ("s", "transmit dwell time in the interval, mean over runs"),
                energy_j: f64 => ("J", "transmitted energy in the interval, mean over runs"),
                ta_dwell_time_s: f64 => ("s", "as dwell_time_s, TA-requested dwells only"),
                ta_energy_j: f64 => ("J", "as energy_j, TA-requested dwells only"),
                dwell_time_per_object_s: Option<f64> =>
                    ("s", "dwell time per scorable object (eq. 1 / 5); null where no run has one"),
                energy_per_object_j: Option<f64> =>
                    ("J", "energy per scorable object (eq. 2 / 6); null where no run has one"),
                ta_dwell_time_per_object_s: Option<f64> => ("s", "as dwell_time_per_object_s, TA-requested dwells only"),
                ta_energy_per_object_j: Option<f64> => ("J", "as energy_per_object_j, TA-requested dwells only"),
                cum_dwell_time_s: f64 => ("s", "dwell_time_s summed up to this interval"),
                cum_energy_j: f64 => ("J", "energy_j summed up to this interval"),
                cum_ta_dwell_time_s: f64 => ("s", "ta_dwell_time_s summed up to this interval"),
                cum_ta_energy_j: f64 => ("J", "ta_energy_j summed up to this interval"),
            }
        }
    };
}

/// The `score_usage` table, declared once: hands its columns to `$gen`. Its rows in
/// `mimo-metrics` are a radar and a [`score_usage_total_table!`] row (`UsageRow`).
#[macro_export]
macro_rules! score_usage_table {
    ($gen:path) => {
        $crate::usage_figure_columns! { $gen; {
            /// Usage of one radar in one scoring interval, averaged over runs.
            pub struct UsageRadarIntervalRow / UsageColumns in SCORE_USAGE = "score_usage":
                "Dwell time and energy per radar and interval, averaged over runs (equations 1-2)"
        } { radar: String => ("", "radar id R1…R4"), } }
    };
}

/// The `score_usage_total` table, declared once: hands its columns to `$gen`.
#[macro_export]
macro_rules! score_usage_total_table {
    ($gen:path) => {
        $crate::usage_figure_columns! { $gen; {
            /// Usage in one scoring interval, averaged over runs: of one radar (in a `UsageRow`) or
            /// of all radars (`usage_total`, the sums over radars of the `UsageRow`s).
            #[derive(Debug, Clone, Default, PartialEq, Serialize)]
            pub struct UsageTotalRow / UsageTotalColumns in SCORE_USAGE_TOTAL = "score_usage_total":
                "Dwell time and energy per interval summed over radars, averaged over runs (equations 5-6)"
        } {} }
    };
}

/// The `score_usage_radar` table, declared once: hands its columns to `$gen`.
#[macro_export]
macro_rules! score_usage_radar_table {
    ($gen:path) => {
        $crate::core_crate::table_decl! { $gen;
            /// Sensor totals of one radar over a whole run, averaged over runs (`T[m]`, `E[m]`).
            #[derive(Debug, Clone, PartialEq, Serialize)]
            pub struct RadarUsage / RadarUsageColumns in SCORE_USAGE_RADAR = "score_usage_radar":
                "Sensor totals per radar over the whole run, mean over runs, every dwell included (equations 3-4)" {
                radar: String => ("", "radar id R1…R4"),
                dwell_time_s: f64 => ("s", "transmit dwell time"),
                energy_j: f64 => ("J", "transmitted energy"),
                ta_dwell_time_s: f64 => ("s", "transmit dwell time of TA-requested dwells"),
                ta_energy_j: f64 => ("J", "transmitted energy of TA-requested dwells"),
            }
        }
    };
}

/// The `score_usage_by_purpose` table, declared once: hands its columns to `$gen`.
#[macro_export]
macro_rules! score_usage_by_purpose_table {
    ($gen:path) => {
        $crate::core_crate::table_decl! { $gen;
            /// Transmit usage of one radar in one scoring interval of one run for one purpose
            /// (`score/usage_by_purpose.parquet`).
            #[derive(Debug, Clone, PartialEq, Serialize)]
            pub struct UsageByPurposeRow / UsageByPurposeColumns in SCORE_USAGE_BY_PURPOSE = "score_usage_by_purpose":
                "Transmit dwell time and energy per run, radar, scoring interval and purpose (docs/design.md §6, \
                 \"Usage by purpose\"); every (run, radar, interval, purpose) of the scoring intervals has a row, \
                 zeros included" {
                run: u32 => ("", "Monte Carlo run index"),
                interval: u32 => ("", "interval index j, 1-based; a dwell belongs to it by its start time"),
                t_start_s: f64 => ("s", "interval start"),
                t_end_s: f64 => ("s", "interval end"),
                radar: String => ("", "radar id R1…R4"),
                purpose: String => (
                    "",
                    "search, confirm_true, confirm_false, track or track_false (docs/design.md §6, \"Usage by purpose\")"
                ),
                dwells: u32 => ("", "transmit dwell rows (role tx or txrx) of the radar starting in the interval"),
                dwell_time_s: f64 => ("s", "their transmit dwell time"),
                energy_j: f64 => ("J", "their transmitted energy"),
            }
        }
    };
}

/// The `score_first_track` table, declared once: hands its columns to `$gen`.
#[macro_export]
macro_rules! score_first_track_table {
    ($gen:path) => {
        $crate::core_crate::table_decl! { $gen;
            /// How soon one target was first tracked in one run (`score/first_track.parquet`).
            #[derive(Debug, Clone, PartialEq, Serialize)]
            pub struct FirstTrackRow / FirstTrackColumns in SCORE_FIRST_TRACK = "score_first_track":
                "Per run and target scorable at some scoring time: the first scoring time it is scorable, the first \
at which it is assigned a confirmed track, and the time between (docs/design.md §6, \"Time to \
first track\"); rows by run, then by first scorable time, then in truth-table order" {
                run: u32 => ("", "Monte Carlo run index"),
                target_id: String => ("", "truth name, as in the truth table"),
                scorable_from_s: f64 => ("s", "the first scoring time at which the target is scorable"),
                first_track_s: Option<f64> => (
                    "s",
                    "the first scoring time at which it is assigned a confirmed track; null if never"
                ),
                time_to_first_track_s: Option<f64> => ("s", "first_track_s − scorable_from_s; null if never tracked"),
            }
        }
    };
}

/// The `score_registration` table, declared once: hands its columns to `$gen`.
#[macro_export]
macro_rules! score_registration_table {
    ($gen:path) => {
        $crate::core_crate::table_decl! { $gen;
            /// How far a test article's last registration estimate of one radar is from the biases
            /// drawn for it (`score/registration.parquet`, only with biases on and estimates
            /// reported).
            #[derive(Debug, Clone, PartialEq, Serialize)]
            pub struct RegistrationErrorRow / RegistrationErrorColumns in SCORE_REGISTRATION = "score_registration":
                "Per run and radar: the test article's last registration estimate minus the biases drawn, and its \
NEES against them (docs/design.md §6, \"Registration error\"); rows by run, then radar" {
                run: u32 => ("", "Monte Carlo run index"),
                radar: String => ("", "radar id R1…R4"),
                t_s: f64 => ("s", "time of the estimate"),
                looks: u64 => ("", "looks the estimate had learnt from"),
                range_error_m: f64 => ("m", "estimated minus true range bias"),
                u_error: f64 => ("", "estimated minus true bias of u"),
                v_error: f64 => ("", "estimated minus true bias of v"),
                heading_error_deg: f64 => ("deg", "estimated minus true heading bias"),
                nees: Option<f64> => (
                    "",
                    "error' P⁻¹ error with the radar's 4 × 4 covariance block (χ² with 4 degrees of freedom if \
consistent); null if that block is singular"
                ),
            }
        }
    };
}

use crate::schema::TableSpec;

score_track_metrics_table!(crate::table_spec);
score_track_metrics_mean_table!(crate::table_spec);
score_assignments_table!(crate::table_spec);
score_usage_table!(crate::table_spec);
score_usage_total_table!(crate::table_spec);
score_usage_radar_table!(crate::table_spec);
score_usage_by_purpose_table!(crate::table_spec);
score_first_track_table!(crate::table_spec);
score_registration_table!(crate::table_spec);

/// Every score table, in the order `mimo score` writes them.
pub const SCORE_TABLES: [TableSpec; 8] = [
    SCORE_TRACK_METRICS,
    SCORE_TRACK_METRICS_MEAN,
    SCORE_ASSIGNMENTS,
    SCORE_USAGE,
    SCORE_USAGE_TOTAL,
    SCORE_USAGE_RADAR,
    SCORE_USAGE_BY_PURPOSE,
    SCORE_FIRST_TRACK,
];

/// Score tables written only when their input is there: `score_registration` with biases on and
/// a test article's estimates reported.
pub const SCORE_OPTIONAL_TABLES: [TableSpec; 1] = [SCORE_REGISTRATION];

/// The file a score table is written to inside `RUN/score/` (`score_usage` → `usage.parquet`).
pub fn score_file_name(spec: &TableSpec) -> String {
    format!("{}.parquet", spec.name.trim_start_matches("score_"))
}
