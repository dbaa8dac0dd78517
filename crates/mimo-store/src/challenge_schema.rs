//! The challenge tables of a study (docs/studies.md, "The challenge"): per family and scenario
//! (and stress point), the energy, dwell time and power at which the family's mean-completeness
//! curve crosses the required 98 %, with bootstrap intervals over the Monte Carlo runs; and per
//! scenario the paired ratio of a MIMO family's energy at 98 % to a conventional family's. Each
//! is declared once in the grammar of `mimo_core::table_decl`, its scenario and stress-point
//! columns declared once with the other study tables' ([`crate::study_schema`]).

crate::core_crate::table_decl! { crate::column_table;
    /// One row of `DIR/challenge.parquet`: a family × scenario × stress point.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyChallengeRow / StudyChallengeColumns in STUDY_CHALLENGE = "study_challenge":
        "A study's challenge figures: one row per family (a [[methods]] entry, swept or not), scenario and stress \
         point; where the family's mean-completeness curve, its points ordered by knob value, first crosses the \
         required completeness upwards, interpolated linearly between the two points around the crossing, with 95 % \
         percentile intervals from a bootstrap over Monte Carlo runs (the same run resample for every point)." {
        family: String => ("", "the [[methods]] entry's name"),
        architecture: String => ("", "mimo or conventional"),
        knob: Option<String> => ("", "the configuration key path the family sweeps; null when not swept"),
        ..crate::study_schema::study_scenario_column,
        point: crate::study_schema::StudyPoint => ("", "the stress-point columns"),
        points: u32 => ("", "points of the family (knob values)"),
        runs: u32 => ("", "Monte Carlo runs per point"),
        completeness_required: f64 => ("", "the completeness the challenge requires (0.98)"),
        holds: bool => ("", "some point of the family reaches the required mean completeness with no failed run"),
        crossings: u32 => ("", "times the mean-completeness curve crosses the requirement (either way) along the knob"),
        reason: Option<String> => (
            "",
            "why the figures at 98 % are null (not swept; holds nowhere; holds already at the lowest knob value; a \
             bracketing point without completed runs); null when they are defined"
        ),
        knob_at_98: Option<f64> => ("", "the knob value at the crossing (interpolated)"),
        energy_at_98_j: Option<f64> => ("J", "TA energy per scorable object at the crossing (ta_energy_per_object_j)"),
        energy_at_98_ci_lo_j: Option<f64> => (
            "J",
            "lower end of its 95 % bootstrap interval; null when outside the sweep"
        ),
        energy_at_98_ci_hi_j: Option<f64> => (
            "J",
            "upper end of its 95 % bootstrap interval; null when outside the sweep"
        ),
        dwell_time_at_98_s: Option<f64> => ("s", "TA dwell time per scorable object at the crossing"),
        dwell_time_at_98_ci_lo_s: Option<f64> => ("s", "lower end of its 95 % bootstrap interval"),
        dwell_time_at_98_ci_hi_s: Option<f64> => ("s", "upper end of its 95 % bootstrap interval"),
        power_at_98_w: Option<f64> => ("W", "TA energy per scorable object at the crossing ÷ simulated duration"),
        power_at_98_ci_lo_w: Option<f64> => ("W", "lower end of its 95 % bootstrap interval"),
        power_at_98_ci_hi_w: Option<f64> => ("W", "upper end of its 95 % bootstrap interval"),
        resamples: u32 => ("", "bootstrap resamples of the run indices"),
        resamples_crossing: u32 => ("", "resamples in which the crossing lies inside the sweep"),
    }
}

crate::core_crate::table_decl! { crate::column_table;
    /// One row of `DIR/challenge_ratios.parquet`: a scenario × stress point × (MIMO,
    /// conventional) family pair.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyChallengeRatiosRow / StudyChallengeRatiosColumns in STUDY_CHALLENGE_RATIOS =
        "study_challenge_ratios":
        "A study's paired comparison: per scenario and stress point, each MIMO family's energy at the required \
         completeness divided by each conventional family's, with a paired bootstrap interval (one resample of run \
         indices applied to both families)." {
        ..crate::study_schema::study_scenario_column,
        point: crate::study_schema::StudyPoint => ("", "the stress-point columns"),
        mimo_family: String => ("", "the MIMO family (numerator)"),
        conventional_family: String => ("", "the conventional family (denominator)"),
        energy_ratio: Option<f64> => ("", "energy_at_98_j of the MIMO family ÷ that of the conventional family"),
        energy_ratio_ci_lo: Option<f64> => ("", "lower end of the paired 95 % bootstrap interval; null when unbounded"),
        energy_ratio_ci_hi: Option<f64> => ("", "upper end of the paired 95 % bootstrap interval; null when unbounded"),
        reason: Option<String> => ("", "why the ratio is null; null when it is defined"),
        resamples: u32 => ("", "bootstrap resamples of the run indices"),
        resamples_defined: u32 => ("", "resamples in which both crossings lie inside their sweeps"),
    }
}
