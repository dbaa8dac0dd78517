//! The challenge tables of a study (docs/studies.md, "The challenge"): per family and scenario
//! (and stress point), the energy, dwell time and power at which the family's mean-completeness
//! curve crosses the required 98 %, with bootstrap intervals over the Monte Carlo runs; and per
//! scenario the paired ratio of a MIMO family's energy at 98 % to a conventional family's.

use crate::schema::ColType::{Bool, F64, U32, Utf8};
use crate::schema::{ColumnSpec, STUDY_IDS, TableSpec, col, join, opt};

/// The stress-point columns (`swept` and the six axes) of the study tables.
const POINT: &[ColumnSpec] = STUDY_IDS.split_at(5).1;

/// `DIR/challenge.parquet`: one row per family × scenario × stress point.
pub const STUDY_CHALLENGE: TableSpec = TableSpec {
    name: "study_challenge",
    description: "A study's challenge figures: one row per family (a [[methods]] entry, swept or not), scenario and \
                  stress point; where the family's mean-completeness curve, its points ordered by knob value, first \
                  crosses the required completeness upwards, interpolated linearly between the two points around \
                  the crossing, with 95 % percentile intervals from a bootstrap over Monte Carlo runs (the same run \
                  resample for every point).",
    columns: &join::<29>(&[
        &[
            col("family", Utf8, "", "the [[methods]] entry's name"),
            col("architecture", Utf8, "", "mimo or conventional"),
            opt("knob", Utf8, "", "the configuration key path the family sweeps; null when not swept"),
            STUDY_IDS[4],
        ],
        POINT,
        &[
            col("points", U32, "", "points of the family (knob values)"),
            col("runs", U32, "", "Monte Carlo runs per point"),
            col("completeness_required", F64, "", "the completeness the challenge requires (0.98)"),
            col(
                "holds",
                Bool,
                "",
                "some point of the family reaches the required mean completeness with no failed run",
            ),
            col(
                "crossings",
                U32,
                "",
                "times the mean-completeness curve crosses the requirement (either way) along the knob",
            ),
            opt(
                "reason",
                Utf8,
                "",
                "why the figures at 98 % are null (not swept; holds nowhere; holds already at the lowest knob value; a \
             bracketing point without completed runs); null when they are defined",
            ),
            opt("knob_at_98", F64, "", "the knob value at the crossing (interpolated)"),
            opt("energy_at_98_j", F64, "J", "TA energy per scorable object at the crossing (ta_energy_per_object_j)"),
            opt(
                "energy_at_98_ci_lo_j",
                F64,
                "J",
                "lower end of its 95 % bootstrap interval; null when outside the sweep",
            ),
            opt(
                "energy_at_98_ci_hi_j",
                F64,
                "J",
                "upper end of its 95 % bootstrap interval; null when outside the sweep",
            ),
            opt("dwell_time_at_98_s", F64, "s", "TA dwell time per scorable object at the crossing"),
            opt("dwell_time_at_98_ci_lo_s", F64, "s", "lower end of its 95 % bootstrap interval"),
            opt("dwell_time_at_98_ci_hi_s", F64, "s", "upper end of its 95 % bootstrap interval"),
            opt("power_at_98_w", F64, "W", "TA energy per scorable object at the crossing ÷ simulated duration"),
            opt("power_at_98_ci_lo_w", F64, "W", "lower end of its 95 % bootstrap interval"),
            opt("power_at_98_ci_hi_w", F64, "W", "upper end of its 95 % bootstrap interval"),
            col("resamples", U32, "", "bootstrap resamples of the run indices"),
            col("resamples_crossing", U32, "", "resamples in which the crossing lies inside the sweep"),
        ],
    ]),
};

/// `DIR/challenge_ratios.parquet`: one row per scenario × stress point × (MIMO, conventional)
/// family pair.
pub const STUDY_CHALLENGE_RATIOS: TableSpec = TableSpec {
    name: "study_challenge_ratios",
    description: "A study's paired comparison: per scenario and stress point, each MIMO family's energy at the \
                  required completeness divided by each conventional family's, with a paired bootstrap interval \
                  (one resample of run indices applied to both families).",
    columns: &join::<16>(&[
        &[STUDY_IDS[4]],
        POINT,
        &[
            col("mimo_family", Utf8, "", "the MIMO family (numerator)"),
            col("conventional_family", Utf8, "", "the conventional family (denominator)"),
            opt("energy_ratio", F64, "", "energy_at_98_j of the MIMO family ÷ that of the conventional family"),
            opt("energy_ratio_ci_lo", F64, "", "lower end of the paired 95 % bootstrap interval; null when unbounded"),
            opt("energy_ratio_ci_hi", F64, "", "upper end of the paired 95 % bootstrap interval; null when unbounded"),
            opt("reason", Utf8, "", "why the ratio is null; null when it is defined"),
            col("resamples", U32, "", "bootstrap resamples of the run indices"),
            col("resamples_defined", U32, "", "resamples in which both crossings lie inside their sweeps"),
        ],
    ]),
};
