//! The failure-point table of a study (docs/studies.md, "Where each method fails"): per method,
//! scenario and stress axis, the axis value where the method's mean track completeness falls
//! through the requirement, interpolated between the grid values, with a bootstrap interval over
//! the Monte Carlo runs. Declared once in the grammar of `mimo_core::table_decl`, its method and
//! scenario columns declared once with the other study tables' ([`crate::study_schema`]).

crate::core_crate::table_decl! { crate::column_table;
    /// One row of `DIR/failure_points.parquet`: a method × scenario × stress axis.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyFailurePointRow / StudyFailurePointColumns in STUDY_FAILURE_POINTS = "study_failure_points":
        "A study's failure points: one row per method, scenario and stress axis; walking the axis's sweep from the \
         least to the most stressing value, the value where the mean completeness (a failed run counting as 0) first \
         falls below the requirement or a run fails, interpolated linearly between the last grid value that holds \
         and the first that does not (on log10 of the value for a log axis), with a 95 % percentile interval from a \
         bootstrap over Monte Carlo runs (one resample of run indices for every grid value when their runs share \
         random draws)." {
        method: crate::study_schema::StudyMethod => ("", "the method columns"),
        ..crate::study_schema::study_scenario_column,
        axis: String => ("", "the stress axis swept (rcs_offset_db, pfa, …)"),
        log_scale: bool => ("", "interpolated on log10 of the axis value (pfa)"),
        least_stress_value: f64 => ("", "the sweep's least stressing value (the baseline in a plan that starts there)"),
        most_stress_value: f64 => ("", "the sweep's most stressing value"),
        points: u32 => ("", "grid values of the sweep"),
        runs: u32 => ("", "Monte Carlo runs per grid value"),
        completeness_required: f64 => ("", "the mean completeness a grid value must reach (0.98)"),
        paired: bool => ("", "run k of every grid value shares its random draws: one resample serves every value"),
        status: String => (
            "",
            "crosses (the failure point lies inside the sweep); holds (holds over the whole range: the failure point \
             lies beyond the most stressing value); fails_at_baseline (fails already at the least stressing value)"
        ),
        crossings: u32 => ("", "times the sweep changes between holding and not, from the least stressing value"),
        failure_point: Option<f64> => (
            "",
            "the interpolated axis value where the method fails; null unless status is crosses"
        ),
        ci_lo: Option<f64> => (
            "",
            "numerically lower end of the 95 % bootstrap interval; null where it runs off the grid"
        ),
        ci_hi: Option<f64> => (
            "",
            "numerically upper end of the 95 % bootstrap interval; null where it runs off the grid"
        ),
        interval: String => (
            "",
            "closed; open_below or open_above (that end runs off the grid); open_both; below_grid or above_grid (the \
             whole interval lies off the grid on that side); none (no resample)"
        ),
        resamples: u32 => ("", "bootstrap resamples of the run indices"),
        resamples_crossing: u32 => ("", "resamples whose failure point lies inside the sweep"),
    }
}
