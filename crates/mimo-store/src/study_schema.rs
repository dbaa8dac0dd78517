//! The study tables `results.parquet`, `costs.parquet` and `summary.parquet` (docs/studies.md,
//! "What a study writes"), each declared once in the grammar of `mimo_core::table_decl` and
//! expanded here ([`crate::column_table!`]) into its spec, its record struct with its column
//! names, and its columns. The identifying columns of the study tables are declared once, as
//! groups a row holds as one field ([`StudyMethod`], [`StudyPoint`], [`StudyIds`];
//! [`crate::column_group!`]) or a fragment a declaration splices (`..study_scenario_column,`),
//! and so are the per-run metrics ([`STUDY_METRICS`]), which stand as a group of columns in the results
//! ([`MetricValues`]) and, as mean and interval, in the summary ([`MetricEstimates`]).

use crate::cell::ColumnKind;
use crate::columns::{Column, IntoColumns};
use crate::schema::{ColType, ColumnSpec, Rule};

/// The scenario column of the study tables (a fragment: spliced as `..study_scenario_column,`).
macro_rules! study_scenario_column {
    ([$($head:tt)*] [$($before:tt)*] [$($after:tt)*]) => {
        $crate::core_crate::table_decl! { $($head)* { $($before)*
            scenario: String => ("", "standard scenario number, or the scenario file's stem"),
            $($after)*
        } }
    };
}
pub(crate) use study_scenario_column;

crate::core_crate::table_decl! { crate::column_group;
    /// The method columns of a study table: which method of the plan, and where a family sweeps
    /// a knob, its value.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyMethod / StudyMethodColumns in STUDY_METHOD = "study_method": "the method a row is of" {
        method: String => ("", "the method's name in the plan; a swept method's points are named family@value"),
        family: String => ("", "the [[methods]] entry the method comes from (its name)"),
        knob: Option<String> => ("", "the configuration key path a swept method varies; null when not swept"),
        knob_value: Option<f64> => ("", "the knob's value at this method; null when not swept"),
    }
}

crate::core_crate::table_decl! { crate::column_group;
    /// The stress-point columns of a study table: `swept` and one per stress axis.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyPoint / StudyPointColumns in STUDY_POINT = "study_point": "the stress point a row is at" {
        swept: Option<String> => ("", "with sweep = \"each\": the axis this cell varies; null in a grid"),
        rcs_offset_db: Option<f64> => ("dB", "added to every target's RCS; null when the plan has no such axis"),
        pfa: Option<f64> => ("", "every radar's false-alarm probability; null when the plan has no such axis"),
        formation_spacing_scale: Option<f64> => ("", "multiplies formation spacing; null when the plan has no such axis"),
        peak_power_offset_db: Option<f64> => (
            "dB",
            "added to every radar's peak power; null when the plan has no such axis"
        ),
        search_pulses: Option<f64> => ("", "pulses of the low search band; null when the plan has no such axis"),
        raid_targets: Option<f64> => ("", "raid aircraft added to the scenario; null when the plan has no such axis"),
        bias_scale: Option<f64> => ("", "scale of the registration biases' typical σ's; null when the plan has no such axis"),
        link_delay_s: Option<f64> => ("s", "every ship's link delay; null when the plan has no such axis"),
    }
}

crate::core_crate::table_decl! { crate::column_group;
    /// The identifying columns opening the results, costs and summary: method, scenario, stress
    /// point.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyIds / StudyIdsColumns in STUDY_IDS = "study_ids": "the cell a row is of" {
        method: StudyMethod => ("", "the method columns"),
        ..crate::study_schema::study_scenario_column,
        point: StudyPoint => ("", "the stress-point columns"),
    }
}

/// Number of identifying columns opening the results, costs and summary.
pub const STUDY_ID_COLUMNS: usize = STUDY_IDS.columns.len();

/// The per-run metrics of a study, declared once: (name, unit, meaning), and the columns they
/// are in the results and the summary.
macro_rules! study_metrics {
    ($( ($name:literal, $unit:literal, $desc:literal) ),* $(,)?) => {
        /// The per-run metrics of a study, (name, unit, meaning) in column order. Each is null
        /// when the run failed or the figure is undefined (docs/design.md §6).
        pub const STUDY_METRICS: &[(&str, &str, &str)] = &[$(($name, $unit, $desc)),*];

        /// The metrics' columns in the results: one per metric.
        const METRIC_VALUE_COLUMNS: &[ColumnSpec] = &[$(metric_column($name, $unit, $desc)),*];

        /// The metrics' columns in the summary: mean, lower and upper end of its interval, per
        /// metric.
        const METRIC_ESTIMATE_COLUMNS: &[ColumnSpec] = &[$(
            metric_column(concat!($name, "_mean"), $unit, concat!("mean over completed runs where defined: ", $desc)),
            metric_column(
                concat!($name, "_ci_lo"),
                $unit,
                "lower end of the 95 % confidence interval of the mean (Student t, clipped to the metric's range); \
                 null with fewer than 2 values",
            ),
            metric_column(
                concat!($name, "_ci_hi"),
                $unit,
                "upper end of the 95 % confidence interval of the mean (Student t, clipped to the metric's range)",
            ),
        )*];
    };
}

/// A metric's column: a float, null when undefined.
const fn metric_column(name: &'static str, unit: &'static str, description: &'static str) -> ColumnSpec {
    ColumnSpec { name, ty: ColType::F64, nullable: true, unit, description, rule: Rule::Finite, storage: &[] }
}

study_metrics![
    ("completeness", "", "track completeness, mean over scoring times with a scorable truth"),
    ("redundant_ratio", "", "redundant tracks per scorable truth, mean over scoring times"),
    ("spurious_ratio", "", "spurious tracks per live track, mean over scoring times"),
    ("breaks", "", "track breaks in the run"),
    ("switches", "", "track switches in the run"),
    ("position_rmse_m", "m", "position RMSE pooled over assigned pairs"),
    ("velocity_rmse_mps", "m/s", "velocity RMSE pooled over assigned pairs"),
    ("ospa_m", "m", "OSPA, mean over scoring times"),
    ("gospa_m", "m", "GOSPA (alpha = 2), mean over scoring times"),
    ("gospa_localisation_m", "m", "GOSPA's localisation part, mean over scoring times"),
    ("gospa_missed", "", "GOSPA's missed truths, mean over scoring times"),
    ("gospa_false", "", "GOSPA's false tracks, mean over scoring times"),
    ("energy_j", "J", "energy emitted by all radars in the run (search and TA)"),
    ("dwell_time_s", "s", "transmit dwell time of all radars in the run"),
    ("ta_energy_j", "J", "energy of the dwells the test article requested"),
    ("ta_dwell_time_s", "s", "transmit time of the dwells the test article requested"),
    ("energy_per_object_j", "J", "energy per scorable object: sum over scoring intervals of energy / scorable objects"),
    ("ta_energy_per_object_j", "J", "the same for the dwells the test article requested"),
    ("ta_dwell_time_per_object_s", "s", "sum over scoring intervals of TA dwell time / scorable objects"),
    ("energy_search_j", "J", "energy of search dwells in the run (docs/design.md §6, usage by purpose)"),
    ("energy_confirm_true_j", "J", "energy of confirmation looks with a truth in beam and range window"),
    ("energy_confirm_false_j", "J", "energy of confirmation looks with no truth in beam and range window"),
    ("energy_track_j", "J", "energy of track and MIMO looks with a truth in beam and range window"),
    ("energy_track_false_j", "J", "energy of track and MIMO looks with no truth in beam and range window"),
    ("dwell_time_search_s", "s", "transmit dwell time of search dwells in the run"),
    ("dwell_time_confirm_true_s", "s", "transmit dwell time of confirmation looks with a truth in them"),
    ("dwell_time_confirm_false_s", "s", "transmit dwell time of confirmation looks with no truth in them"),
    ("dwell_time_track_s", "s", "transmit dwell time of track and MIMO looks with a truth in them"),
    ("dwell_time_track_false_s", "s", "transmit dwell time of track and MIMO looks with no truth in them"),
    (
        "dwell_time_per_object_s",
        "s",
        "sum over scoring intervals of all transmit dwell time (search and TA) / scorable objects"
    ),
    (
        "first_track_mean_s",
        "s",
        "mean over the run's targets that got a track of the time from first scorable to first assignment to a \
         confirmed track"
    ),
    ("first_track_max_s", "s", "the same, of the worst such target"),
    ("never_tracked", "", "targets scorable at some scoring time of the run never assigned to a confirmed track"),
    (
        "registration_range_error_rms_m",
        "m",
        "RMS over radars of the test article's last range-bias estimate minus the drawn bias; null without biases or estimates"
    ),
    ("registration_heading_error_rms_deg", "deg", "the same, of the heading bias"),
    (
        "registration_nees",
        "",
        "mean over radars of the registration estimate's NEES against the drawn biases (4 if consistent); null without"
    ),
];

/// One value per metric of [`STUDY_METRICS`], in its order (null when the run failed or the
/// figure is undefined): the metric columns of a results row.
#[derive(Debug, Clone, PartialEq)]
pub struct MetricValues(pub Vec<Option<f64>>);

/// A figure with its 95 % interval: (mean or value, lower end, upper end), each null when
/// undefined; in the summary, a metric's Monte Carlo mean and confidence interval.
pub type Estimate = (Option<f64>, Option<f64>, Option<f64>);

/// One estimate per metric of [`STUDY_METRICS`], in its order: the metric columns of a summary
/// row.
#[derive(Debug, Clone, PartialEq)]
pub struct MetricEstimates(pub Vec<Estimate>);

impl ColumnKind for MetricValues {
    const TY: ColType = ColType::F64;
    const NULLABLE: bool = true;
    const GROUP: Option<&'static [ColumnSpec]> = Some(METRIC_VALUE_COLUMNS);
}

impl IntoColumns for MetricValues {
    fn push_columns<R>(rows: &[R], get: impl Fn(&R) -> &Self, out: &mut Vec<Column>) {
        for k in 0..STUDY_METRICS.len() {
            out.push(Column::F64(rows.iter().map(|r| get(r).0.get(k).copied().flatten()).collect()));
        }
    }
}

impl ColumnKind for MetricEstimates {
    const TY: ColType = ColType::F64;
    const NULLABLE: bool = true;
    const GROUP: Option<&'static [ColumnSpec]> = Some(METRIC_ESTIMATE_COLUMNS);
}

impl IntoColumns for MetricEstimates {
    fn push_columns<R>(rows: &[R], get: impl Fn(&R) -> &Self, out: &mut Vec<Column>) {
        let part = |k: usize, of: fn(&Estimate) -> Option<f64>| {
            Column::F64(rows.iter().map(|r| get(r).0.get(k).and_then(of)).collect())
        };
        for k in 0..STUDY_METRICS.len() {
            out.extend([part(k, |e| e.0), part(k, |e| e.1), part(k, |e| e.2)]);
        }
    }
}

crate::core_crate::table_decl! { crate::column_table;
    /// One row of `DIR/results.parquet`: a cell and Monte Carlo run.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyResultsRow / StudyResultsColumns in STUDY_RESULTS = "study_results":
        "A study's results: one row per cell (method, scenario, stress point) and Monte Carlo run; \
         byte-deterministic for a plan and seed." {
        ids: StudyIds => ("", "the cell: method, scenario, stress point"),
        run: u32 => ("", "Monte Carlo run index"),
        seed: u64 => ("", "master seed of the run"),
        metrics: MetricValues => ("", "every metric of STUDY_METRICS, a column each"),
        failure: Option<String> => ("", "why the run failed; null when it completed"),
    }
}

crate::core_crate::table_decl! { crate::column_table;
    /// One row of `DIR/costs.parquet`: a cell and Monte Carlo run's timings, which differ from
    /// machine to machine.
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudyCostsRow / StudyCostsColumns in STUDY_COSTS = "study_costs":
        "A study's computing costs: one row per cell and Monte Carlo run (machine-dependent)." {
        ids: StudyIds => ("", "the cell: method, scenario, stress point"),
        run: u32 => ("", "Monte Carlo run index"),
        seed: u64 => ("", "master seed of the run"),
        duration_s: f64 => ("s", "simulated seconds of the run"),
        ta_cpu_s: f64 => ("s", "CPU time inside the test article (wall time for a child process)"),
        sim_cpu_s: f64 => ("s", "CPU time of the rest of the run on its thread: simulation, writing, scoring"),
        wall_s: f64 => ("s", "wall time of the run, simulation to score"),
        kf_cycle_s: Option<f64> => (
            "s",
            "CPU time of one reference EKF predict + update cycle (6-state, 3-D measurement) on the machine \
             that ran the item, the median of repeats measured when the study started; null in a record without one"
        ),
        ta_cpu_kfu: Option<f64> => (
            "",
            "ta_cpu_s / kf_cycle_s: the test article's compute in reference Kalman-filter cycles"
        ),
    }
}

crate::core_crate::table_decl! { crate::column_table;
    /// One row of `DIR/summary.parquet`: a cell, with the Monte Carlo mean and 95 % confidence
    /// interval of every metric of [`STUDY_RESULTS`].
    #[derive(Debug, Clone, PartialEq)]
    pub struct StudySummaryRow / StudySummaryColumns in STUDY_SUMMARY = "study_summary":
        "A study's summary: one row per cell with the mean and 95 % confidence interval of each metric." {
        ids: StudyIds => ("", "the cell: method, scenario, stress point"),
        runs: u32 => ("", "Monte Carlo runs of the cell"),
        failed: u32 => ("", "runs that failed"),
        failure: Option<String> => ("", "the first failed run's reason; null when none failed"),
        estimates: MetricEstimates => ("", "every metric of STUDY_METRICS: its mean, ci_lo and ci_hi columns"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::challenge_schema::{STUDY_CHALLENGE, StudyChallengeRow};
    use crate::columns::write_rows;
    use crate::failure_point_schema::{STUDY_FAILURE_POINTS, StudyFailurePointRow};
    use arrow::array::{Array, AsArray};
    use arrow::datatypes::Float64Type;

    fn names(spec: &crate::schema::TableSpec) -> Vec<&'static str> {
        spec.columns.iter().map(|c| c.name).collect()
    }

    /// A group field stands for its columns, in order, in the spec and in `COLUMN_NAMES`.
    #[test]
    fn group_fields_expand_to_their_columns() {
        assert_eq!(StudyResultsRow::COLUMN_NAMES, names(&STUDY_RESULTS));
        assert_eq!(StudySummaryRow::COLUMN_NAMES, names(&STUDY_SUMMARY));
        assert_eq!(StudyChallengeRow::COLUMN_NAMES, names(&STUDY_CHALLENGE));
        assert_eq!(StudyFailurePointRow::COLUMN_NAMES, names(&STUDY_FAILURE_POINTS));
        let m = STUDY_METRICS.len();
        assert_eq!(STUDY_RESULTS.columns.len(), STUDY_ID_COLUMNS + 2 + m + 1);
        assert_eq!(STUDY_SUMMARY.columns.len(), STUDY_ID_COLUMNS + 3 + 3 * m);
        assert_eq!(&names(&STUDY_RESULTS)[..5], ["method", "family", "knob", "knob_value", "scenario"]);
        assert_eq!(names(&STUDY_RESULTS)[STUDY_ID_COLUMNS - 1], "link_delay_s");
        assert_eq!(names(&STUDY_RESULTS)[STUDY_ID_COLUMNS + 2], STUDY_METRICS[0].0);
        let last = STUDY_METRICS[m - 1].0;
        assert_eq!(names(&STUDY_SUMMARY)[STUDY_ID_COLUMNS + 3 * m + 2], format!("{last}_ci_hi"));
        assert_eq!(names(&STUDY_FAILURE_POINTS)[4..6], ["scenario", "axis"]);
        assert_eq!(names(&STUDY_CHALLENGE)[3..5], ["scenario", "swept"]);
    }

    /// Summary rows written through their declaration read back column by column.
    #[test]
    fn summary_rows_round_trip() {
        let row = |k: f64| StudySummaryRow {
            ids: StudyIds {
                method: StudyMethod {
                    method: "m@2".into(),
                    family: "m".into(),
                    knob: Some("x".into()),
                    knob_value: Some(k),
                },
                scenario: "7".into(),
                point: StudyPoint {
                    swept: None,
                    rcs_offset_db: None,
                    pfa: Some(1e-6 * k),
                    formation_spacing_scale: None,
                    peak_power_offset_db: None,
                    search_pulses: None,
                    raid_targets: None,
                    bias_scale: None,
                    link_delay_s: None,
                },
            },
            runs: 4,
            failed: 0,
            failure: None,
            estimates: MetricEstimates(
                (0..STUDY_METRICS.len()).map(|i| (Some(i as f64), None, Some(k + i as f64))).collect(),
            ),
        };
        let dir = tempfile::tempdir().expect("tmp");
        let path = dir.path().join("summary.parquet");
        assert_eq!(write_rows(&path, &[row(1.0), row(2.0)]).expect("write"), 2);
        let b = crate::columns::tests::first_batch(&path);
        let f64s = |name: &str| b.column_by_name(name).expect(name).as_primitive::<Float64Type>().clone();
        assert_eq!(f64s("pfa").values().to_vec(), vec![1e-6, 2e-6]);
        assert_eq!(f64s("switches_mean").values().to_vec(), vec![4.0, 4.0]);
        assert_eq!(f64s("switches_ci_hi").values().to_vec(), vec![5.0, 6.0]);
        assert_eq!(f64s("switches_ci_lo").null_count(), 2);
        assert_eq!(b.column_by_name("rcs_offset_db").expect("rcs").null_count(), 2);
    }
}
