//! The failure-point table of a study (docs/studies.md, "Where each method fails"): per method,
//! scenario and stress axis, the axis value where the method's mean track completeness falls
//! through the requirement, interpolated between the grid values, with a bootstrap interval over
//! the Monte Carlo runs.

use crate::schema::ColType::{Bool, F64, U32, Utf8};
use crate::schema::{STUDY_IDS, TableSpec, col, join, opt};

/// `DIR/failure_points.parquet`: one row per method × scenario × stress axis.
pub const STUDY_FAILURE_POINTS: TableSpec = TableSpec {
    name: "study_failure_points",
    description: "A study's failure points: one row per method, scenario and stress axis; walking the axis's sweep \
                  from the least to the most stressing value, the value where the mean completeness (a failed run \
                  counting as 0) first falls below the requirement or a run fails, interpolated linearly between \
                  the last grid value that holds and the first that does not (on log10 of the value for a log \
                  axis), with a 95 % percentile interval from a bootstrap over Monte Carlo runs (one resample of \
                  run indices for every grid value when their runs share random draws).",
    columns: &join::<21>(&[
        STUDY_IDS.split_at(5).0,
        &[
            col("axis", Utf8, "", "the stress axis swept (rcs_offset_db, pfa, …)"),
            col("log_scale", Bool, "", "interpolated on log10 of the axis value (pfa)"),
            col(
                "least_stress_value",
                F64,
                "",
                "the sweep's least stressing value (the baseline in a plan that starts there)",
            ),
            col("most_stress_value", F64, "", "the sweep's most stressing value"),
            col("points", U32, "", "grid values of the sweep"),
            col("runs", U32, "", "Monte Carlo runs per grid value"),
            col("completeness_required", F64, "", "the mean completeness a grid value must reach (0.98)"),
            col(
                "paired",
                Bool,
                "",
                "run k of every grid value shares its random draws: one resample serves every value",
            ),
            col(
                "status",
                Utf8,
                "",
                "crosses (the failure point lies inside the sweep); holds (holds over the whole range: the failure point \
             lies beyond the most stressing value); fails_at_baseline (fails already at the least stressing value)",
            ),
            col(
                "crossings",
                U32,
                "",
                "times the sweep changes between holding and not, from the least stressing value",
            ),
            opt(
                "failure_point",
                F64,
                "",
                "the interpolated axis value where the method fails; null unless status is crosses",
            ),
            opt(
                "ci_lo",
                F64,
                "",
                "numerically lower end of the 95 % bootstrap interval; null where it runs off the grid",
            ),
            opt(
                "ci_hi",
                F64,
                "",
                "numerically upper end of the 95 % bootstrap interval; null where it runs off the grid",
            ),
            col(
                "interval",
                Utf8,
                "",
                "closed; open_below or open_above (that end runs off the grid); open_both; below_grid or above_grid (the \
             whole interval lies off the grid on that side); none (no resample)",
            ),
            col("resamples", U32, "", "bootstrap resamples of the run indices"),
            col("resamples_crossing", U32, "", "resamples whose failure point lies inside the sweep"),
        ],
    ]),
};
