//! The checks of a table file, one implementation for every reader (the typed rows of
//! [`crate::read_table`], the dwell keys of `mimo track`, the scorer's column reads in
//! `mimo-metrics`): what a file must be before any of its values is used (docs/design.md §3, §7).
//!
//! * [`open`]: the file is Parquet, its metadata names the table asked for and this mimo's schema
//!   version, and every column of the table's spec is there with exactly its type (`t_s` as
//!   float32 or `run` as int64 is refused; columns beyond the spec are welcome);
//! * [`check_array`]: a column's values keep the spec's [`Rule`] (no null where none is allowed,
//!   finite numbers, positive variances, labels of the enumeration, covariances that are ones);
//! * [`check_file_run`]: every row of `run-K.parquet` is run K;
//! * [`repaired_covariances`]: how many rows of a file hold a covariance accepted only after its
//!   repair (`mimo_core::covariance`: slightly indefinite, within the bound), for the count
//!   `mimo score` reports and the warning every command prints;
//! * every `t_s` within the run: from 0 on (the column rule) and up to its manifest's
//!   `duration_s` ([`crate::run_window`]).
//!
//! Each refusal is a [`StoreError`] naming the file and the column (and the row).

use crate::StoreError;
use crate::schema::{self, ColType, ColumnSpec, Rule, TableSpec};
use arrow::array::{Array, AsArray};
use arrow::datatypes::{DataType, Float64Type, UInt32Type};
use mimo_core::ids::RadarId;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::fs::File;
use std::path::Path;

fn bad(file: &Path, column: &str, why: String) -> StoreError {
    StoreError::BadColumn { file: file.to_path_buf(), column: column.to_string(), why }
}

/// Open one file of table `spec` for reading after checking its metadata (table name, schema
/// version), its column chunks and the type of every column of the spec.
pub fn open(path: &Path, spec: &TableSpec) -> Result<ParquetRecordBatchReaderBuilder<File>, StoreError> {
    let file = File::open(path).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            StoreError::Missing { path: path.to_path_buf() }
        } else {
            StoreError::Io { path: path.to_path_buf(), source: e }
        }
    })?;
    let builder = ParquetRecordBatchReaderBuilder::try_new(file)
        .map_err(|e| StoreError::Parquet { path: path.to_path_buf(), why: e.to_string() })?;
    check_metadata(path, builder.schema().metadata(), spec)?;
    crate::check_chunk_ranges(builder.metadata(), path)?;
    check_types(path, builder.schema(), spec)?;
    Ok(builder)
}

/// The table name and schema version of a file's key-value metadata.
fn check_metadata(path: &Path, md: &arrow::datatypes::Metadata, spec: &TableSpec) -> Result<(), StoreError> {
    let table_err = |why: String| StoreError::BadTable { file: path.into(), why };
    match md.get(schema::META_TABLE) {
        Some(t) if t == spec.name => {}
        Some(t) => {
            return Err(table_err(format!("holds table {}, expected '{}'", mimo_core::quote::quoted(t), spec.name)));
        }
        None => {
            return Err(table_err(format!("has no '{}' metadata: not written by mimo", schema::META_TABLE)));
        }
    }
    let want = schema::SCHEMA_VERSION.to_string();
    match md.get(schema::META_SCHEMA_VERSION) {
        Some(v) if *v == want => Ok(()),
        v => Err(table_err(format!(
            "schema version {} does not match this mimo's {want}",
            v.map(String::as_str).unwrap_or("(none)")
        ))),
    }
}

/// Every column of the spec present with exactly its type.
pub(crate) fn check_types(path: &Path, schema: &arrow::datatypes::Schema, spec: &TableSpec) -> Result<(), StoreError> {
    for c in spec.columns {
        let field = schema
            .field_with_name(c.name)
            .map_err(|_| bad(path, c.name, format!("missing (expected {})", c.ty.name())))?;
        let ok = match (c.ty, field.data_type()) {
            (ColType::Cov21, DataType::FixedSizeList(inner, 21)) => *inner.data_type() == DataType::Float64,
            (t, d) => t.arrow() == *d,
        };
        if !ok {
            return Err(bad(path, c.name, format!("has type {}, expected {}", field.data_type(), c.ty.name())));
        }
    }
    Ok(())
}

/// Check the values of one column (of the type its spec gives: [`open`] checked it) against
/// the spec's nullability and [`Rule`]; `first_row` is the file row of the array's first value,
/// so that errors name the row in the file.
pub fn check_array(path: &Path, c: &ColumnSpec, array: &dyn Array, first_row: usize) -> Result<(), StoreError> {
    let at = |i: usize| first_row + i;
    if !c.nullable
        && array.null_count() > 0
        && let Some(i) = (0..array.len()).find(|&i| array.is_null(i))
    {
        return Err(bad(path, c.name, format!("is null at row {}", at(i))));
    }
    if c.name == "t_s" {
        check_run_end(path, array, first_row)?;
    }
    match c.rule {
        Rule::Any => Ok(()),
        Rule::Finite | Rule::NonNegative | Rule::Positive => check_numbers(path, c, array, first_row),
        Rule::OneOf(labels) => check_labels(path, c, array, first_row, |s| labels.contains(&s), &labels.join(", ")),
        Rule::RadarId => {
            check_labels(path, c, array, first_row, |s| RadarId::parse(s).is_some(), "a radar id R1, R2, …")
        }
        Rule::Covariance => check_covariances(path, c, array, first_row),
    }
}

fn check_numbers(path: &Path, c: &ColumnSpec, array: &dyn Array, first_row: usize) -> Result<(), StoreError> {
    let Some(a) = array.as_primitive_opt::<Float64Type>() else {
        return Err(bad(path, c.name, format!("is not {}", c.ty.name())));
    };
    let (min, what) = match c.rule {
        Rule::NonNegative => (0.0, "a finite number >= 0"),
        Rule::Positive => (f64::MIN_POSITIVE, "a finite number > 0"),
        _ => (f64::NEG_INFINITY, "a finite number"),
    };
    let values = a.values();
    let broken = |i: usize| !values[i].is_finite() || values[i] < min;
    // Nulls (in a nullable column) are skipped.
    if let Some(i) = (0..values.len()).find(|&i| broken(i) && a.is_valid(i)) {
        return Err(bad(path, c.name, format!("is {} at row {} (expected {what})", values[i], first_row + i)));
    }
    Ok(())
}

/// No time after the end of the run the file belongs to ([`crate::run_window`]).
fn check_run_end(path: &Path, array: &dyn Array, first_row: usize) -> Result<(), StoreError> {
    let (Some(t), Some(end_s)) = (array.as_primitive_opt::<Float64Type>(), crate::run_window::run_end_s(path)) else {
        return Ok(());
    };
    match crate::run_window::first_after_end(t.values(), end_s, first_row) {
        None => Ok(()),
        Some((row, t_s)) => Err(bad(path, "t_s", format!("is {t_s} at row {row}, after the run's end at {end_s} s"))),
    }
}

/// Every non-null string accepted by `ok`, called once per run of equal values.
fn check_labels(
    path: &Path,
    c: &ColumnSpec,
    array: &dyn Array,
    first_row: usize,
    ok: impl Fn(&str) -> bool,
    what: &str,
) -> Result<(), StoreError> {
    let Some(strings) = array.as_string_opt::<i32>() else {
        return Err(bad(path, c.name, format!("is not {}", c.ty.name())));
    };
    let mut last: Option<&str> = None;
    for (i, v) in strings.iter().enumerate() {
        let Some(v) = v else { continue };
        if last == Some(v) {
            continue;
        }
        if !ok(v) {
            let v = mimo_core::quote::quoted(v);
            return Err(bad(path, c.name, format!("is {v} at row {} (expected one of {what})", first_row + i)));
        }
        last = Some(v);
    }
    Ok(())
}

fn check_covariances(path: &Path, c: &ColumnSpec, array: &dyn Array, first_row: usize) -> Result<(), StoreError> {
    let Some(list) = array.as_fixed_size_list_opt() else {
        return Err(bad(path, c.name, format!("is not {}", c.ty.name())));
    };
    let Some(values) = list.values().as_primitive_opt::<Float64Type>() else {
        return Err(bad(path, c.name, format!("is not {}", c.ty.name())));
    };
    let values = values.values();
    for i in 0..list.len() {
        if list.is_null(i) {
            continue;
        }
        let at = list.value_offset_at(i);
        let packed: &[f64; 21] = values
            .get(at..at + 21)
            .and_then(|s| s.try_into().ok())
            .ok_or_else(|| bad(path, c.name, format!("row {} does not hold 21 values", first_row + i)))?;
        mimo_core::table_rules::covariance_ok(packed)
            .map_err(|why| bad(path, c.name, format!("at row {}: {why}", first_row + i)))?;
    }
    Ok(())
}

/// The rows of a file whose covariance was repaired ([`repaired_covariances`]): how many, and
/// the most negative smallest-to-largest eigenvalue ratio among them.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Repairs {
    /// Rows repaired.
    pub rows: u64,
    /// The most negative ratio of smallest to largest eigenvalue found (0 when none).
    pub worst_ratio: f64,
}

impl Repairs {
    /// Add another file's repairs.
    pub fn add(&mut self, o: Repairs) {
        self.rows += o.rows;
        self.worst_ratio = self.worst_ratio.min(o.worst_ratio);
    }

    /// Count one covariance (already checked) if it needed a repair.
    pub fn note(&mut self, c: &[f64; 21]) {
        if let Ok(mimo_core::covariance::Accepted::Repaired { min_eigenvalue, max_eigenvalue, .. }) =
            mimo_core::covariance::check(c)
        {
            self.rows += 1;
            self.worst_ratio = self.worst_ratio.min(min_eigenvalue / max_eigenvalue);
        }
    }

    /// The one warning line for `what` (a file or a table), or `None` when nothing was repaired.
    pub fn warning(&self, what: &str) -> Option<String> {
        (self.rows > 0).then(|| {
            format!(
                "warning: {what}: {} covariance(s) slightly not positive semi-definite (smallest eigenvalue down to \
                 {:.2e} of the largest, within the bound -{:e}) were repaired to the nearest positive definite matrix \
                 (docs/design.md §7)",
                self.rows,
                self.worst_ratio,
                mimo_core::covariance::NEGATIVE_EIGENVALUE_BOUND
            )
        })
    }
}

/// The rows of table file `path` (of table `spec`) whose covariance is accepted only after a
/// repair: slightly indefinite within the bound of `mimo_core::covariance`. The file is opened
/// with the checks of [`open`]; a table without a covariance column has none. Call it on a file
/// its reader has already checked: a covariance beyond the bound is not counted here.
pub fn repaired_covariances(path: &Path, spec: &TableSpec) -> Result<Repairs, StoreError> {
    let builder = open(path, spec)?;
    let names: Vec<&str> = spec.columns.iter().filter(|c| c.rule == Rule::Covariance).map(|c| c.name).collect();
    let mut out = Repairs::default();
    if names.is_empty() {
        return Ok(out);
    }
    let schema = builder.schema().clone();
    let roots: Vec<usize> = names.iter().filter_map(|n| schema.index_of(n).ok()).collect();
    let mask = parquet::arrow::ProjectionMask::roots(builder.parquet_schema(), roots);
    let parquet_err =
        |e: parquet::errors::ParquetError| StoreError::Parquet { path: path.to_path_buf(), why: e.to_string() };
    let reader = builder.with_projection(mask).build().map_err(parquet_err)?;
    for batch in reader {
        let batch = batch.map_err(|e| StoreError::Parquet { path: path.to_path_buf(), why: e.to_string() })?;
        for name in &names {
            let Some(list) = batch.column_by_name(name).and_then(|a| a.as_fixed_size_list_opt()) else { continue };
            let Some(values) = list.values().as_primitive_opt::<Float64Type>() else { continue };
            let values = values.values();
            for i in (0..list.len()).filter(|&i| list.is_valid(i)) {
                let at = list.value_offset_at(i);
                if let Some(c) = values.get(at..at + 21).and_then(|s| <&[f64; 21]>::try_from(s).ok()) {
                    out.note(c);
                }
            }
        }
    }
    Ok(out)
}

/// Every row of a file named `run-K.parquet` is run K (`run` values of the rows from
/// `first_row` on).
pub fn check_file_run(path: &Path, run: &dyn Array, first_row: usize) -> Result<(), StoreError> {
    let Some(k) = crate::invariants::file_run(path) else { return Ok(()) };
    let Some(run) = run.as_primitive_opt::<UInt32Type>() else {
        return Err(bad(path, "run", "is not uint32".into()));
    };
    match run.values().iter().position(|&r| r != k) {
        None => Ok(()),
        Some(i) => Err(StoreError::BadRow {
            file: path.to_path_buf(),
            column: "run",
            row: first_row + i,
            why: format!("{} in the file of run {k} (each file holds one run)", run.value(i)),
        }),
    }
}

/// The spec of table `name` (a run, score or study table).
pub fn spec(name: &str) -> Result<&'static TableSpec, StoreError> {
    schema::table(name).ok_or_else(|| StoreError::Arrow(format!("unknown table {name}")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use arrow::array::{Float64Array, StringArray, UInt32Array};

    #[test]
    fn rules_name_the_file_column_and_row() {
        let p = Path::new("x/run-0003.parquet");
        let var = schema::MEASUREMENTS.columns.iter().find(|c| c.name == "var_u").expect("var_u");
        let e = check_array(p, var, &Float64Array::from(vec![1e-6, 0.0]), 10).expect_err("zero variance");
        assert_eq!(e.to_string(), "x/run-0003.parquet: column 'var_u' is 0 at row 11 (expected a finite number > 0)");
        assert!(check_array(p, var, &Float64Array::from(vec![1e-6, 2e-6]), 0).is_ok());
        let kind = schema::DWELLS.columns.iter().find(|c| c.name == "kind").expect("kind");
        let e = check_array(p, kind, &StringArray::from(vec!["search", "scan"]), 0).expect_err("label");
        assert!(e.to_string().contains("'scan' at row 1 (expected one of search, confirm, track, mimo)"), "{e}");
        let e = check_file_run(p, &UInt32Array::from(vec![3, 3, 0]), 0).expect_err("run");
        assert!(e.to_string().contains("column 'run' row 2: 0 in the file of run 3"), "{e}");
        assert!(check_file_run(Path::new("x/other.parquet"), &UInt32Array::from(vec![7]), 0).is_ok());
    }
}
