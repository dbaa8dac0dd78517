//! Table schemas, defined once.
//!
//! Each table of docs/design.md §3 is a [`TableSpec`]: an ordered list of [`ColumnSpec`]s giving the
//! column name, type, unit and meaning. The Arrow schema (with the unit and description in each
//! field's metadata), the files under `schemas/` and the readers' validation are all derived from
//! these specs, so they cannot drift apart; a test fails when `schemas/` and the code disagree.

use arrow::datatypes::{DataType, Field, Schema};
use std::collections::HashMap;
use std::sync::Arc;

/// Version of the table layouts. Bump it whenever a column is added, removed or changes type.
pub const SCHEMA_VERSION: u32 = 1;

/// Parquet key-value metadata key holding the table name.
pub const META_TABLE: &str = "mimo.table";
/// Parquet key-value metadata key holding [`SCHEMA_VERSION`].
pub const META_SCHEMA_VERSION: &str = "mimo.schema_version";

/// Column types used by the tables.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ColType {
    /// Unsigned 8-bit integer (Arrow `UInt8`, `uint8` in `schemas/`): face indices.
    U8,
    /// Unsigned 32-bit integer (Arrow `UInt32`, `uint32`): `run`, counts, indices such as `waveform`.
    U32,
    /// Unsigned 64-bit integer (Arrow `UInt64`, `uint64`): dwell, group, measurement and track ids; seeds.
    U64,
    /// Signed 64-bit integer (Arrow `Int64`, `int64`): range cell indices.
    I64,
    /// 64-bit float (Arrow `Float64`, `float64`): times, positions, powers and other physical
    /// quantities; always finite in a valid file.
    F64,
    /// Boolean (Arrow `Boolean`, `bool`): flags such as `merged`.
    Bool,
    /// UTF-8 string (Arrow `Utf8`, `utf8`): ids (`radar`, `target`) and categories (`kind`,
    /// `role`, `status`).
    Utf8,
    /// Fixed-size list of 21 f64: the upper triangle of a 6×6 covariance, row-major.
    Cov21,
}

impl ColType {
    /// The Arrow data type.
    pub fn arrow(self) -> DataType {
        match self {
            ColType::U8 => DataType::UInt8,
            ColType::U32 => DataType::UInt32,
            ColType::U64 => DataType::UInt64,
            ColType::I64 => DataType::Int64,
            ColType::F64 => DataType::Float64,
            ColType::Bool => DataType::Boolean,
            ColType::Utf8 => DataType::Utf8,
            ColType::Cov21 => DataType::FixedSizeList(Arc::new(Field::new("item", DataType::Float64, false)), 21),
        }
    }

    /// Name used in `schemas/`.
    pub fn name(self) -> &'static str {
        match self {
            ColType::U8 => "uint8",
            ColType::U32 => "uint32",
            ColType::U64 => "uint64",
            ColType::I64 => "int64",
            ColType::F64 => "float64",
            ColType::Bool => "bool",
            ColType::Utf8 => "utf8",
            ColType::Cov21 => "fixed_size_list<float64, 21>",
        }
    }
}

/// What every value of a column must be, beyond its type (checked on every read,
/// [`crate::checked`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// Any value of the type.
    Any,
    /// A finite number (every `float64` column unless it says more).
    Finite,
    /// A finite number `>= 0`.
    NonNegative,
    /// A finite number `> 0` (variances).
    Positive,
    /// One of these labels (an enumeration of `mimo-core`, e.g. `Role::LABELS`).
    OneOf(&'static [&'static str]),
    /// A radar id `R1`, `R2`, ….
    RadarId,
    /// A covariance: finite, positive variances, positive semi-definite
    /// (`mimo_core::table_rules::covariance_ok`).
    Covariance,
}

/// One column.
#[derive(Debug, Clone, Copy)]
pub struct ColumnSpec {
    /// Column name; it ends in its unit (`_s`, `_m`, `_mps`, …; docs/design.md §3).
    pub name: &'static str,
    /// Column type.
    pub ty: ColType,
    /// Whether the column may hold nulls (an undefined or absent value).
    pub nullable: bool,
    /// SI unit, or "" for dimensionless / categorical.
    pub unit: &'static str,
    /// Meaning of the column, written to the field metadata and to `schemas/`.
    pub description: &'static str,
    /// What every (non-null) value must be.
    pub rule: Rule,
}

/// The rule a column of type `ty` has unless it says more.
const fn default_rule(ty: ColType) -> Rule {
    match ty {
        ColType::F64 => Rule::Finite,
        ColType::Cov21 => Rule::Covariance,
        _ => Rule::Any,
    }
}

pub(crate) const fn col(name: &'static str, ty: ColType, unit: &'static str, description: &'static str) -> ColumnSpec {
    ColumnSpec { name, ty, nullable: false, unit, description, rule: default_rule(ty) }
}

pub(crate) const fn opt(name: &'static str, ty: ColType, unit: &'static str, description: &'static str) -> ColumnSpec {
    ColumnSpec { name, ty, nullable: true, unit, description, rule: default_rule(ty) }
}

/// The columns of `parts`, in order, as one list of `N` columns (a compile error when `N` is not
/// their count): a table whose columns open with shared ones (the study tables' identifying
/// columns) lists them once.
pub(crate) const fn join<const N: usize>(parts: &[&[ColumnSpec]]) -> [ColumnSpec; N] {
    let mut out = [RUN; N];
    let (mut n, mut p) = (0, 0);
    while p < parts.len() {
        let mut i = 0;
        while i < parts[p].len() {
            out[n] = parts[p][i];
            (n, i) = (n + 1, i + 1);
        }
        p += 1;
    }
    assert!(n == N, "join: the parts do not hold N columns");
    out
}

/// One table.
#[derive(Debug, Clone, Copy)]
pub struct TableSpec {
    /// Table name: the directory of its files in a run directory and the `mimo.table` metadata.
    pub name: &'static str,
    /// What the table holds: what one of its rows is.
    pub description: &'static str,
    /// The columns, in file order.
    pub columns: &'static [ColumnSpec],
}

impl TableSpec {
    /// The Arrow schema, with unit and description in each field's metadata and the table name
    /// and schema version in the schema metadata.
    pub fn arrow_schema(&self) -> Schema {
        let fields: Vec<Field> = self
            .columns
            .iter()
            .map(|c| {
                let mut md = HashMap::new();
                md.insert("unit".to_string(), c.unit.to_string());
                md.insert("description".to_string(), c.description.to_string());
                Field::new(c.name, c.ty.arrow(), c.nullable).with_metadata(md)
            })
            .collect();
        let mut md = HashMap::new();
        md.insert(META_TABLE.to_string(), self.name.to_string());
        md.insert(META_SCHEMA_VERSION.to_string(), SCHEMA_VERSION.to_string());
        Schema::new(fields).with_metadata(md)
    }

    /// The JSON document written to `schemas/<table>.json`.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "table": self.name,
            "schema_version": SCHEMA_VERSION,
            "description": self.description,
            "columns": self.columns.iter().map(|c| serde_json::json!({
                "name": c.name,
                "type": c.ty.name(),
                "nullable": c.nullable,
                "unit": c.unit,
                "description": c.description,
            })).collect::<Vec<_>>(),
        })
    }
}

use ColType::*;

const RUN: ColumnSpec = col("run", U32, "", "Monte Carlo run index");

pub use crate::run_tables::{DWELLS, MEASUREMENTS, PRIMITIVES, TRACKS, TRUTH, VOLTAGES};

// ---- Study tables (docs/studies.md): per cell and Monte Carlo run, or per cell. ----

/// The identifying columns of every study table (a macro: they open three column lists).
macro_rules! study_ids {
    () => {
        [
            col("method", Utf8, "", "the method's name in the plan; a swept method's points are named family@value"),
            col("family", Utf8, "", "the [[methods]] entry the method comes from (its name)"),
            opt("knob", Utf8, "", "the configuration key path a swept method varies; null when not swept"),
            opt("knob_value", F64, "", "the knob's value at this method; null when not swept"),
            col("scenario", Utf8, "", "standard scenario number, or the scenario file's stem"),
            opt("swept", Utf8, "", "with sweep = \"each\": the axis this cell varies; null in a grid"),
            opt("rcs_offset_db", F64, "dB", "added to every target's RCS; null when the plan has no such axis"),
            opt("pfa", F64, "", "every radar's false-alarm probability; null when the plan has no such axis"),
            opt(
                "formation_spacing_scale",
                F64,
                "",
                "multiplies formation spacing; null when the plan has no such axis",
            ),
            opt(
                "peak_power_offset_db",
                F64,
                "dB",
                "added to every radar's peak power; null when the plan has no such axis",
            ),
            opt("search_pulses", F64, "", "pulses of the low search band; null when the plan has no such axis"),
            opt("raid_targets", F64, "", "raid aircraft added to the scenario; null when the plan has no such axis"),
        ]
    };
}

/// Number of identifying columns opening every study table.
pub const STUDY_ID_COLUMNS: usize = 12;

macro_rules! study_tables {
    ($( ($name:literal, $unit:literal, $desc:literal) ),* $(,)?) => {
        /// The per-run metrics of a study, (name, unit, meaning) in column order. Each is null
        /// when the run failed or the figure is undefined (docs/design.md §6).
        pub const STUDY_METRICS: &[(&str, &str, &str)] = &[$(($name, $unit, $desc)),*];

        /// The identifying columns opening every study table.
        pub(crate) const STUDY_IDS: [ColumnSpec; STUDY_ID_COLUMNS] = study_ids!();

        const STUDY_RESULTS_COLUMNS: [ColumnSpec; STUDY_ID_COLUMNS + 3 + STUDY_METRICS.len()] = join(&[
            &STUDY_IDS,
            &[RUN, col("seed", U64, "", "master seed of the run")],
            &[$(opt($name, F64, $unit, $desc)),*],
            &[opt("failure", Utf8, "", "why the run failed; null when it completed")],
        ]);

        const STUDY_SUMMARY_COLUMNS: [ColumnSpec; STUDY_ID_COLUMNS + 3 + 3 * STUDY_METRICS.len()] = join(&[
            &STUDY_IDS,
            &[
                col("runs", U32, "", "Monte Carlo runs of the cell"),
                col("failed", U32, "", "runs that failed"),
                opt("failure", Utf8, "", "the first failed run's reason; null when none failed"),
            ],
            &[$(
                opt(concat!($name, "_mean"), F64, $unit, concat!("mean over completed runs where defined: ", $desc)),
                opt(concat!($name, "_ci_lo"), F64, $unit, "lower end of the 95 % confidence interval of the mean (Student t, clipped to the metric's range); null with fewer than 2 values"),
                opt(concat!($name, "_ci_hi"), F64, $unit, "upper end of the 95 % confidence interval of the mean (Student t, clipped to the metric's range)"),
            )*],
        ]);
    };
}

study_tables![
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
];

/// `DIR/results.parquet` of a study.
pub const STUDY_RESULTS: TableSpec = TableSpec {
    name: "study_results",
    description: "A study's results: one row per cell (method, scenario, stress point) and Monte Carlo run; \
                  byte-deterministic for a plan and seed.",
    columns: &STUDY_RESULTS_COLUMNS,
};

/// `DIR/costs.parquet` of a study: timings, which differ from machine to machine.
pub const STUDY_COSTS: TableSpec = TableSpec {
    name: "study_costs",
    description: "A study's computing costs: one row per cell and Monte Carlo run (machine-dependent).",
    columns: &join::<20>(&[
        &STUDY_IDS,
        &[
            RUN,
            col("seed", U64, "", "master seed of the run"),
            col("duration_s", F64, "s", "simulated seconds of the run"),
            col("ta_cpu_s", F64, "s", "CPU time inside the test article (wall time for a child process)"),
            col("sim_cpu_s", F64, "s", "CPU time of the rest of the run on its thread: simulation, writing, scoring"),
            col("wall_s", F64, "s", "wall time of the run, simulation to score"),
            opt(
                "kf_cycle_s",
                F64,
                "s",
                "CPU time of one reference EKF predict + update cycle (6-state, 3-D measurement) on the machine \
             that ran the item, the median of repeats measured when the study started; null in a record without one",
            ),
            opt(
                "ta_cpu_kfu",
                F64,
                "",
                "ta_cpu_s / kf_cycle_s: the test article's compute in reference Kalman-filter cycles",
            ),
        ],
    ]),
};

/// `DIR/summary.parquet` of a study: one row per cell, the Monte Carlo mean and 95 % confidence
/// interval of every metric of [`STUDY_RESULTS`].
pub const STUDY_SUMMARY: TableSpec = TableSpec {
    name: "study_summary",
    description: "A study's summary: one row per cell with the mean and 95 % confidence interval of each metric.",
    columns: &STUDY_SUMMARY_COLUMNS,
};

/// Every table, in pipeline order.
pub const ALL_TABLES: [TableSpec; 6] = [TRUTH, DWELLS, VOLTAGES, PRIMITIVES, MEASUREMENTS, TRACKS];

/// The tables a study writes.
pub const STUDY_TABLES: [TableSpec; 6] = [
    STUDY_RESULTS,
    STUDY_COSTS,
    STUDY_SUMMARY,
    crate::challenge_schema::STUDY_CHALLENGE,
    crate::challenge_schema::STUDY_CHALLENGE_RATIOS,
    crate::failure_point_schema::STUDY_FAILURE_POINTS,
];

/// Look up a table (run, study or score table) by name.
pub fn table(name: &str) -> Option<&'static TableSpec> {
    ALL_TABLES
        .iter()
        .chain(STUDY_TABLES.iter())
        .chain(crate::score_schema::SCORE_TABLES.iter())
        .find(|t| t.name == name)
}

/// The manifest's keys and meanings, written to `schemas/manifest.json`.
pub const MANIFEST_KEYS: &[(&str, &str, &str)] = &[
    ("mimo_version", "string", "version of mimo that wrote the run"),
    ("schema_version", "uint32", "table layout version (SCHEMA_VERSION)"),
    ("scenario", "object {name, resolved}", "scenario name and the full resolved scenario"),
    ("seed", "uint64", "master random seed"),
    ("runs", "uint32", "number of Monte Carlo runs"),
    ("duration_s", "float64 (s)", "simulated duration of each run"),
    ("fidelity", "object", "every modelling switch in force"),
    ("tracker", "object {name, config} or null", "the test article / tracker and its configuration"),
    ("schedule", "string", "how the dwell schedule was produced"),
    (
        "parent",
        "string or null",
        "for mimo track outputs, the run directory re-tracked, relative to this run's directory",
    ),
    (
        "parent_check",
        "object {scenario, seed, manifest_fnv1a64} (absent if no parent)",
        "for mimo track outputs, what the parent held when this run was made",
    ),
    ("tables", "object table -> [{file, rows}]", "files of each table and their row counts"),
    ("timing_s", "object stage -> float64 (s)", "wall-clock seconds per stage"),
];

/// The JSON document written to `schemas/manifest.json`.
pub fn manifest_json() -> serde_json::Value {
    serde_json::json!({
        "file": "manifest.json",
        "schema_version": SCHEMA_VERSION,
        "keys": MANIFEST_KEYS.iter().map(|(k, t, d)| serde_json::json!({"name": k, "type": t, "description": d})).collect::<Vec<_>>(),
    })
}

/// Every file of `schemas/` as (file name, pretty JSON text).
pub fn schema_files() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = ALL_TABLES
        .iter()
        .chain(STUDY_TABLES.iter())
        .chain(crate::score_schema::SCORE_TABLES.iter())
        .map(|t| (format!("{}.json", t.name), serde_json::to_string_pretty(&t.to_json()).unwrap_or_default() + "\n"))
        .collect();
    out.push(("manifest.json".into(), serde_json::to_string_pretty(&manifest_json()).unwrap_or_default() + "\n"));
    out
}
