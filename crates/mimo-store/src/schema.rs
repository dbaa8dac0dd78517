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

/// How a column is stored beyond its type (a column's `as` tags in its table's declaration,
/// `mimo_core::table_decl`): the Parquet writer's settings for it ([`crate::writer_props`]).
/// They change a file's bytes, never its columns or values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    /// Ids that count up row by row: delta-encoded, a byte or two per row.
    Delta,
    /// Floats whose values are nearly all distinct (times, aim points): the byte-stream split,
    /// so that the compressor sees their slowly varying high bytes together.
    Split,
    /// Values zstd cannot shrink (measured: their compressed pages were as large as the plain
    /// ones): written uncompressed, which costs the writer nothing and the file a few bytes of
    /// frame headers less.
    Uncompressed,
    /// A float column a reader may filter on (times): min/max statistics per page, which every
    /// integer column has anyway.
    PageStats,
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
    /// How it is stored beyond its type (none: the table's defaults).
    pub storage: &'static [Storage],
}

/// A column that is none yet: what [`flatten`] fills its output with before it writes it.
const NO_COLUMN: ColumnSpec =
    ColumnSpec { name: "", ty: ColType::U8, nullable: false, unit: "", description: "", rule: Rule::Any, storage: &[] };

/// The columns of a declaration's fields, in order, as one list of `N` columns (a compile error
/// when `N` is not their count): each field's own column, or the columns of its group when its
/// type stands for several (`crate::cell::ColumnKind::GROUP`).
pub const fn flatten<const N: usize>(fields: &[(Option<&'static [ColumnSpec]>, ColumnSpec)]) -> [ColumnSpec; N] {
    let mut out = [NO_COLUMN; N];
    let (mut n, mut f) = (0, 0);
    while f < fields.len() {
        match fields[f].0 {
            Some(group) => {
                let mut i = 0;
                while i < group.len() {
                    out[n] = group[i];
                    (n, i) = (n + 1, i + 1);
                }
            }
            None => {
                out[n] = fields[f].1;
                n += 1;
            }
        }
        f += 1;
    }
    assert!(n == N, "flatten: the fields do not hold N columns");
    out
}

/// The names of `columns`, in order, as `N` names (a compile error when `N` is not their count).
pub const fn column_names<const N: usize>(columns: &[ColumnSpec]) -> [&'static str; N] {
    assert!(columns.len() == N, "column_names: not N columns");
    let mut out = [""; N];
    let mut i = 0;
    while i < N {
        out[i] = columns[i].name;
        i += 1;
    }
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

pub use crate::run_tables::{BIASES, DWELLS, MEASUREMENTS, PRIMITIVES, REGISTRATION, TRACKS, TRUTH, VOLTAGES};
pub use crate::study_schema::{STUDY_COSTS, STUDY_METRICS, STUDY_RESULTS, STUDY_SUMMARY};

/// Every table, in pipeline order.
pub const ALL_TABLES: [TableSpec; 8] =
    [TRUTH, DWELLS, VOLTAGES, PRIMITIVES, MEASUREMENTS, TRACKS, BIASES, REGISTRATION];

/// The tables a study writes.
pub const STUDY_TABLES: [TableSpec; 7] = [
    STUDY_RESULTS,
    STUDY_COSTS,
    STUDY_SUMMARY,
    crate::challenge_schema::STUDY_CHALLENGE,
    crate::challenge_schema::STUDY_CHALLENGE_RATIOS,
    crate::failure_point_schema::STUDY_FAILURE_POINTS,
    crate::challenge_schema::STUDY_FRONTIER,
];

/// Every table: run tables, study tables, score tables.
pub fn every_table() -> impl Iterator<Item = &'static TableSpec> {
    ALL_TABLES
        .iter()
        .chain(STUDY_TABLES.iter())
        .chain(crate::score_schema::SCORE_TABLES.iter())
        .chain(crate::score_schema::SCORE_OPTIONAL_TABLES.iter())
}

/// Look up a table (run, study or score table) by name.
pub fn table(name: &str) -> Option<&'static TableSpec> {
    every_table().find(|t| t.name == name)
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
    let mut out: Vec<(String, String)> = every_table()
        .map(|t| (format!("{}.json", t.name), serde_json::to_string_pretty(&t.to_json()).unwrap_or_default() + "\n"))
        .collect();
    out.push(("manifest.json".into(), serde_json::to_string_pretty(&manifest_json()).unwrap_or_default() + "\n"));
    out
}
