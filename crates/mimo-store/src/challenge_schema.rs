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
         required completeness on the family's efficient frontier (its points' least mean energy for each mean \
         completeness: total energy, or the test article's part when the plan sets frontier_energy = \
         \"test_article\"), interpolated linearly in completeness between the two frontier points around the crossing, \
         with 95 % percentile intervals from a bootstrap over Monte Carlo runs (the same run resample for every \
         point; each resample rebuilds the frontier and re-reads the crossing on it)." {
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
        knob_at_98: Option<f64> => (
            "",
            "the knob value at the crossing (interpolated between the bracketing points); null for a family that \
             sweeps a grid of several keys"
        ),
        energy_at_98_j: Option<f64> => (
            "J",
            "total energy (search and TA) per scorable object at the crossing (energy_per_object_j)"
        ),
        energy_at_98_ci_lo_j: Option<f64> => (
            "J",
            "lower end of its 95 % bootstrap interval; null when outside the sweep"
        ),
        energy_at_98_ci_hi_j: Option<f64> => (
            "J",
            "upper end of its 95 % bootstrap interval; null when outside the sweep"
        ),
        dwell_time_at_98_s: Option<f64> => (
            "s",
            "total transmit dwell time per scorable object at the crossing (dwell_time_per_object_s)"
        ),
        dwell_time_at_98_ci_lo_s: Option<f64> => ("s", "lower end of its 95 % bootstrap interval"),
        dwell_time_at_98_ci_hi_s: Option<f64> => ("s", "upper end of its 95 % bootstrap interval"),
        power_at_98_w: Option<f64> => ("W", "energy_at_98_j ÷ simulated duration"),
        power_at_98_ci_lo_w: Option<f64> => ("W", "lower end of its 95 % bootstrap interval"),
        power_at_98_ci_hi_w: Option<f64> => ("W", "upper end of its 95 % bootstrap interval"),
        ta_energy_at_98_j: Option<f64> => (
            "J",
            "the test article's part: TA energy per scorable object at the crossing (ta_energy_per_object_j)"
        ),
        ta_energy_at_98_ci_lo_j: Option<f64> => ("J", "lower end of its 95 % bootstrap interval"),
        ta_energy_at_98_ci_hi_j: Option<f64> => ("J", "upper end of its 95 % bootstrap interval"),
        ta_dwell_time_at_98_s: Option<f64> => (
            "s",
            "TA dwell time per scorable object at the crossing (ta_dwell_time_per_object_s)"
        ),
        ta_dwell_time_at_98_ci_lo_s: Option<f64> => ("s", "lower end of its 95 % bootstrap interval"),
        ta_dwell_time_at_98_ci_hi_s: Option<f64> => ("s", "upper end of its 95 % bootstrap interval"),
        ta_power_at_98_w: Option<f64> => ("W", "ta_energy_at_98_j ÷ simulated duration"),
        ta_power_at_98_ci_lo_w: Option<f64> => ("W", "lower end of its 95 % bootstrap interval"),
        ta_power_at_98_ci_hi_w: Option<f64> => ("W", "upper end of its 95 % bootstrap interval"),
        first_track_max_at_98_s: Option<f64> => (
            "s",
            "time to first track of the run's worst target (first_track_max_s, mean over runs) at the crossing, \
             interpolated as the energy is"
        ),
        frontier_points: u32 => (
            "",
            "the family's points on its efficient frontier (least mean energy, on the plan's frontier_energy, for each \
             mean completeness)"
        ),
        bracket_lo_method: Option<String> => (
            "",
            "the frontier point below the 98 % crossing (a method name); null when the crossing is outside the sweep"
        ),
        bracket_hi_method: Option<String> => ("", "the frontier point at or above it; null when outside the sweep"),
        bracket_lo_energy_j: Option<f64> => (
            "J",
            "mean energy per scorable object of bracket_lo_method, on the frontier's energy (the plan's \
             frontier_energy: total by default, or the test article's part)"
        ),
        bracket_hi_energy_j: Option<f64> => ("J", "the same of bracket_hi_method"),
        bracket_gap: Option<f64> => (
            "",
            "(bracket_hi_energy_j − bracket_lo_energy_j) / the frontier's energy at the crossing (energy_at_98_j, or \
             ta_energy_at_98_j on the test article's part): how far apart the grid's points around the crossing are"
        ),
        refine_rounds: u32 => ("", "refinement rounds the study ran for this family and scenario"),
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
        energy_ratio: Option<f64> => (
            "",
            "energy_at_98_j (total) of the MIMO family ÷ that of the conventional family"
        ),
        energy_ratio_ci_lo: Option<f64> => ("", "lower end of the paired 95 % bootstrap interval; null when unbounded"),
        energy_ratio_ci_hi: Option<f64> => ("", "upper end of the paired 95 % bootstrap interval; null when unbounded"),
        ta_energy_ratio: Option<f64> => ("", "the same of ta_energy_at_98_j (the test article's part)"),
        ta_energy_ratio_ci_lo: Option<f64> => ("", "lower end of its paired 95 % bootstrap interval"),
        ta_energy_ratio_ci_hi: Option<f64> => ("", "upper end of its paired 95 % bootstrap interval"),
        reason: Option<String> => ("", "why the ratio is null; null when it is defined"),
        resamples: u32 => ("", "bootstrap resamples of the run indices"),
        resamples_defined: u32 => ("", "resamples in which both crossings lie inside their sweeps"),
    }
}

crate::core_crate::table_decl! { crate::column_table;
    /// One row of `DIR/frontier.parquet`: a method × scenario × stress point of a family, with
    /// its means and whether it lies on the family's efficient frontier.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyFrontierRow / StudyFrontierColumns in STUDY_FRONTIER = "study_frontier":
        "A study's efficient frontiers: one row per method (a point of a family), scenario and stress point, with \
         its mean total energy per scorable object and mean completeness over every run (a failed run counting as \
         0 completeness), and whether the point lies on its family's frontier (no other point of the family reaches \
         at least its completeness for at most its energy: total energy, or the test article's part when the plan \
         sets frontier_energy = \"test_article\")." {
        family: String => ("", "the [[methods]] entry's name"),
        method: String => ("", "the method's name (family@value, or family@key=value,… for a grid)"),
        ..crate::study_schema::study_scenario_column,
        point: crate::study_schema::StudyPoint => ("", "the stress-point columns"),
        energy_per_object_j: Option<f64> => (
            "J",
            "mean over completed runs of energy_per_object_j (total: search and TA)"
        ),
        completeness: Option<f64> => ("", "mean completeness over every run, a failed run counting as 0"),
        on_frontier: bool => (
            "",
            "the point lies on the family's efficient frontier (built on the plan's frontier_energy)"
        ),
    }
}
