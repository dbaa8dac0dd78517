//! The tables `mimo score` writes into `RUN/score/` (docs/design.md §6), declared like the run
//! tables: names, types, nullability, units and meanings, mirrored to `schemas/score_*.json` and
//! checked by the schema test. `mimo-metrics` fills them through
//! [`write_columns`](crate::columns::write_columns), which refuses columns that do not match.
//!
//! Undefined figures (a ratio with nothing to divide by, an RMSE with no assigned pair) are null,
//! never a number.

use crate::schema::ColType::*;
use crate::schema::{ColumnSpec, TableSpec, col, opt};

const RUN: ColumnSpec = col("run", U32, "", "Monte Carlo run index");
const K: ColumnSpec = col("k", U32, "", "scoring time index, 1-based (t_s = k · interval_s)");
const T_S: ColumnSpec = col("t_s", F64, "s", "scoring time since scenario start");

/// `score/track_metrics.parquet`: one row per run and scoring time.
pub const SCORE_TRACK_METRICS: TableSpec = TableSpec {
    name: "score_track_metrics",
    description: "Track metrics per run and scoring time (docs/design.md §6)",
    columns: &[
        RUN,
        K,
        T_S,
        col("n_truths", U32, "", "truths present (inside their sampled span), scorable or not"),
        col("n_scorable", U32, "", "scorable truths N: present and seen by at least one radar (docs/design.md §6)"),
        col("n_tracks", U32, "", "live tracks M (confirmed, not deleted)"),
        col("n_assigned", U32, "", "scorable truths assigned a track A"),
        col("n_redundant", U32, "", "unassigned tracks inside the gate of some scorable truth"),
        col("n_spurious", U32, "", "tracks inside the gate of no present truth"),
        opt("completeness", F64, "", "A / N; null when N = 0"),
        opt("redundant_ratio", F64, "", "n_redundant / N; null when N = 0"),
        opt("spurious_ratio", F64, "", "n_spurious / M; null when M = 0"),
        col("breaks", U32, "", "truths assigned at the previous scoring time, scorable and unassigned now"),
        col("switches", U32, "", "truths assigned now to another track than the one they last had"),
        col("cum_breaks", U32, "", "breaks summed up to this time in the run"),
        col("cum_switches", U32, "", "switches summed up to this time in the run"),
        col("position_sq_sum_m2", F64, "m^2", "sum of squared position errors over assigned pairs"),
        col("velocity_sq_sum_m2ps2", F64, "m^2/s^2", "sum of squared velocity errors over assigned pairs"),
        opt("position_rmse_m", F64, "m", "RMS position error over assigned pairs; null without any"),
        opt("velocity_rmse_mps", F64, "m/s", "RMS velocity error over assigned pairs; null without any"),
        opt("ospa_m", F64, "m", "OSPA between scorable truths and live tracks; null when both sets are empty"),
        opt("gospa_m", F64, "m", "GOSPA (alpha = 2); null when both sets are empty"),
        opt("gospa_localisation_m", F64, "m", "GOSPA's localisation part: (sum of assigned d^p)^(1/p)"),
        opt("gospa_missed", U32, "", "GOSPA's missed truths (each costing c^p / 2)"),
        opt("gospa_false", U32, "", "GOSPA's false tracks (each costing c^p / 2)"),
    ],
};

/// `score/track_metrics_mean.parquet`: one row per scoring time, averaged over runs.
pub const SCORE_TRACK_METRICS_MEAN: TableSpec = TableSpec {
    name: "score_track_metrics_mean",
    description: "Track metrics per scoring time, averaged over runs where defined (docs/design.md §6)",
    columns: &[
        K,
        T_S,
        col("runs", U32, "", "runs averaged"),
        col("n_scorable_mean", F64, "", "mean scorable truths"),
        col("n_tracks_mean", F64, "", "mean live tracks"),
        opt("completeness", F64, "", "mean completeness over runs with N > 0"),
        opt("redundant_ratio", F64, "", "mean redundant ratio over runs with N > 0"),
        opt("spurious_ratio", F64, "", "mean spurious ratio over runs with M > 0"),
        col("cum_breaks_mean", F64, "", "mean cumulative breaks"),
        col("cum_switches_mean", F64, "", "mean cumulative switches"),
        opt("position_rmse_m", F64, "m", "position RMSE pooled over the runs' assigned pairs"),
        opt("velocity_rmse_mps", F64, "m/s", "velocity RMSE pooled over the runs' assigned pairs"),
        opt("ospa_m", F64, "m", "mean OSPA where defined"),
        opt("gospa_m", F64, "m", "mean GOSPA where defined"),
    ],
};

/// `score/assignments.parquet`: one row per run, scoring time and scorable truth.
pub const SCORE_ASSIGNMENTS: TableSpec = TableSpec {
    name: "score_assignments",
    description: "The track assigned to each scorable truth at each scoring time, with its errors",
    columns: &[
        RUN,
        T_S,
        col("target", Utf8, "", "truth name, as in the truth table"),
        opt("track_id", U64, "", "assigned track; null when the truth is unassigned"),
        opt("position_error_m", F64, "m", "‖track position − truth position‖; null when unassigned"),
        opt("velocity_error_mps", F64, "m/s", "‖track velocity − truth velocity‖; null when unassigned"),
    ],
};

/// The usage columns shared by `usage` and `usage_total` (equations (1), (2), (5), (6) of
/// docs/design.md §6, all dwells and TA-requested dwells alone).
macro_rules! usage_columns {
    ($($first:expr),*) => {
        &[
            $($first,)*
            col("interval", U32, "", "interval index j, 1-based; a dwell belongs to it by its start time"),
            col("t_start_s", F64, "s", "interval start"),
            col("t_end_s", F64, "s", "interval end"),
            col("runs", U32, "", "runs averaged"),
            col("n_scorable_mean", F64, "", "mean scorable truths at the interval's scoring time"),
            col("dwell_time_s", F64, "s", "transmit dwell time in the interval, mean over runs"),
            col("energy_j", F64, "J", "transmitted energy in the interval, mean over runs"),
            col("ta_dwell_time_s", F64, "s", "as dwell_time_s, TA-requested dwells only"),
            col("ta_energy_j", F64, "J", "as energy_j, TA-requested dwells only"),
            opt("dwell_time_per_object_s", F64, "s", "dwell time per scorable object (eq. 1 / 5); null where no run has one"),
            opt("energy_per_object_j", F64, "J", "energy per scorable object (eq. 2 / 6); null where no run has one"),
            opt("ta_dwell_time_per_object_s", F64, "s", "as dwell_time_per_object_s, TA-requested dwells only"),
            opt("ta_energy_per_object_j", F64, "J", "as energy_per_object_j, TA-requested dwells only"),
            col("cum_dwell_time_s", F64, "s", "dwell_time_s summed up to this interval"),
            col("cum_energy_j", F64, "J", "energy_j summed up to this interval"),
            col("cum_ta_dwell_time_s", F64, "s", "ta_dwell_time_s summed up to this interval"),
            col("cum_ta_energy_j", F64, "J", "ta_energy_j summed up to this interval"),
        ]
    };
}

/// `score/usage.parquet`: one row per radar and interval, averaged over runs.
pub const SCORE_USAGE: TableSpec = TableSpec {
    name: "score_usage",
    description: "Dwell time and energy per radar and interval, averaged over runs (equations 1-2)",
    columns: usage_columns!(col("radar", Utf8, "", "radar id R1…R4")),
};

/// `score/usage_total.parquet`: one row per interval, summed over radars.
pub const SCORE_USAGE_TOTAL: TableSpec = TableSpec {
    name: "score_usage_total",
    description: "Dwell time and energy per interval summed over radars, averaged over runs (equations 5-6)",
    columns: usage_columns!(),
};

/// `score/usage_radar.parquet`: one row per radar, the whole run.
pub const SCORE_USAGE_RADAR: TableSpec = TableSpec {
    name: "score_usage_radar",
    description: "Sensor totals per radar over the whole run, mean over runs, every dwell included (equations 3-4)",
    columns: &[
        col("radar", Utf8, "", "radar id R1…R4"),
        col("dwell_time_s", F64, "s", "transmit dwell time"),
        col("energy_j", F64, "J", "transmitted energy"),
        col("ta_dwell_time_s", F64, "s", "transmit dwell time of TA-requested dwells"),
        col("ta_energy_j", F64, "J", "transmitted energy of TA-requested dwells"),
    ],
};

/// `score/usage_by_purpose.parquet`: one row per run, radar, scoring interval and purpose.
pub const SCORE_USAGE_BY_PURPOSE: TableSpec = TableSpec {
    name: "score_usage_by_purpose",
    description: "Transmit dwell time and energy per run, radar, scoring interval and purpose (docs/design.md §6, \
                  \"Usage by purpose\"); every (run, radar, interval, purpose) of the scoring intervals has a row, \
                  zeros included",
    columns: &[
        RUN,
        col("interval", U32, "", "interval index j, 1-based; a dwell belongs to it by its start time"),
        col("t_start_s", F64, "s", "interval start"),
        col("t_end_s", F64, "s", "interval end"),
        col("radar", Utf8, "", "radar id R1…R4"),
        col(
            "purpose",
            Utf8,
            "",
            "search, confirm_true, confirm_false, track or track_false (docs/design.md §6, \"Usage by purpose\")",
        ),
        col("dwells", U32, "", "transmit dwell rows (role tx or txrx) of the radar starting in the interval"),
        col("dwell_time_s", F64, "s", "their transmit dwell time"),
        col("energy_j", F64, "J", "their transmitted energy"),
    ],
};

/// Every score table, in the order `mimo score` writes them.
pub const SCORE_TABLES: [TableSpec; 7] = [
    SCORE_TRACK_METRICS,
    SCORE_TRACK_METRICS_MEAN,
    SCORE_ASSIGNMENTS,
    SCORE_USAGE,
    SCORE_USAGE_TOTAL,
    SCORE_USAGE_RADAR,
    SCORE_USAGE_BY_PURPOSE,
];

/// The file a score table is written to inside `RUN/score/` (`score_usage` → `usage.parquet`).
pub fn score_file_name(spec: &TableSpec) -> String {
    format!("{}.parquet", spec.name.trim_start_matches("score_"))
}
