//! Reading and validating the input tables.
//!
//! Each file is read on its own (only the columns the metrics need), its schema checked against
//! what the column means, and its values checked (nulls, NaN/∞, enumerations, runs) before the
//! files of a table are stacked. Errors therefore always name the file, the column, the row and
//! what was expected. Compatible physical types are accepted and converted (any integer type for an
//! integer column, f32 for f64, large/view/dictionary strings for utf8), so tables written by other
//! tools (pyarrow, DuckDB) score too.

use crate::error::{MetricsError, internal};
use mimo_core::ids::RadarId;
use polars::prelude::*;
use std::collections::BTreeSet;
use std::fs::File;
use std::path::{Path, PathBuf};

/// The type a column must have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Want {
    U32,
    U64,
    F64,
    Utf8,
}

impl Want {
    pub(crate) fn name(self) -> &'static str {
        match self {
            Want::U32 => "uint32",
            Want::U64 => "uint64",
            Want::F64 => "float64",
            Want::Utf8 => "utf8",
        }
    }

    fn polars(self) -> DataType {
        match self {
            Want::U32 => DataType::UInt32,
            Want::U64 => DataType::UInt64,
            Want::F64 => DataType::Float64,
            Want::Utf8 => DataType::String,
        }
    }

    fn accepts(self, dt: &ArrowDataType) -> bool {
        use ArrowDataType as A;
        let is_int =
            matches!(dt, A::Int8 | A::Int16 | A::Int32 | A::Int64 | A::UInt8 | A::UInt16 | A::UInt32 | A::UInt64);
        let is_str = |d: &ArrowDataType| matches!(d, A::Utf8 | A::LargeUtf8 | A::Utf8View);
        match self {
            Want::U32 | Want::U64 => is_int,
            Want::F64 => matches!(dt, A::Float32 | A::Float64),
            Want::Utf8 => is_str(dt) || matches!(dt, A::Dictionary(_, inner, _) if is_str(inner)),
        }
    }
}

/// A readable name for an Arrow type in error messages.
fn type_name(dt: &ArrowDataType) -> String {
    use ArrowDataType as A;
    match dt {
        A::Null => "null".into(),
        A::Boolean => "bool".into(),
        A::Int8 => "int8".into(),
        A::Int16 => "int16".into(),
        A::Int32 => "int32".into(),
        A::Int64 => "int64".into(),
        A::UInt8 => "uint8".into(),
        A::UInt16 => "uint16".into(),
        A::UInt32 => "uint32".into(),
        A::UInt64 => "uint64".into(),
        A::Float16 => "float16".into(),
        A::Float32 => "float32".into(),
        A::Float64 => "float64".into(),
        A::Utf8 | A::LargeUtf8 | A::Utf8View => "utf8".into(),
        A::Binary | A::LargeBinary | A::BinaryView => "binary".into(),
        other => format!("{other:?}").to_lowercase(),
    }
}

/// A value check applied to a column.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Check<'a> {
    Any,
    /// Every value finite.
    Finite,
    /// Every value finite and `>= 0`.
    FiniteNonNeg,
    /// Every value one of these strings.
    OneOf(&'static [&'static str]),
    /// A radar id `R1`…`R255`.
    Radar,
    /// A run present in the truth table.
    RunIn(&'a BTreeSet<u32>),
}

/// One required column.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Col<'a> {
    pub name: &'static str,
    pub want: Want,
    pub check: Check<'a>,
}

pub(crate) const fn col<'a>(name: &'static str, want: Want, check: Check<'a>) -> Col<'a> {
    Col { name, want, check }
}

/// Read `paths` as one table with the given columns (in that order), validating every file.
/// A check of one file's frame (its table rules) before the files are stacked.
pub(crate) type FileCheck<'a> = &'a dyn Fn(&Path, &DataFrame) -> Result<(), MetricsError>;

/// Read and stack the files of a table, with `check` run on each file's frame (row numbers are then the file's).
pub(crate) fn read_table_checked(
    table: &'static str,
    paths: &[PathBuf],
    cols: &[Col<'_>],
    check: FileCheck<'_>,
) -> Result<DataFrame, MetricsError> {
    if paths.is_empty() {
        return Err(MetricsError::MissingTable {
            table,
            path: PathBuf::from(table),
            detail: "no Parquet files given".into(),
        });
    }
    let mut out: Option<DataFrame> = None;
    for path in paths {
        let df = read_file(table, path, cols)?;
        check(path, &df)?;
        match out.as_mut() {
            None => out = Some(df),
            Some(acc) => {
                acc.vstack_mut_owned(df).map_err(internal("stacking files"))?;
            }
        }
    }
    let mut df = out.ok_or_else(|| MetricsError::Internal { context: "reading", detail: "no files".into() })?;
    df.rechunk_mut();
    Ok(df)
}

/// Read one file of `table` with the given columns (in that order), validated.
pub(crate) fn read_file(table: &'static str, path: &Path, cols: &[Col<'_>]) -> Result<DataFrame, MetricsError> {
    read_file_slice(table, path, cols, None)
}

/// The number of rows of one file of `table` (from its footer).
pub(crate) fn file_rows(table: &'static str, path: &Path) -> Result<usize, MetricsError> {
    let file =
        File::open(path).map_err(|e| MetricsError::Read { table, path: path.to_path_buf(), detail: e.to_string() })?;
    ParquetReader::new(file).num_rows().map_err(|e| MetricsError::Read {
        table,
        path: path.to_path_buf(),
        detail: e.to_string(),
    })
}

/// [`read_file`] of the rows `slice` = (first row, count) only (all rows for `None`); row
/// numbers in its errors are then the slice's.
pub(crate) fn read_file_slice(
    table: &'static str,
    path: &Path,
    cols: &[Col<'_>],
    slice: Option<(usize, usize)>,
) -> Result<DataFrame, MetricsError> {
    read_file_slice_checking(table, path, cols, slice, true)
}

/// [`read_file_slice`] with the schema checked and the columns converted, but not the values
/// (nulls, [`Check`]s): for a caller that checks them itself and reads again with
/// [`read_file_slice`] to report what it found.
pub(crate) fn read_file_slice_unchecked(
    table: &'static str,
    path: &Path,
    cols: &[Col<'_>],
    slice: Option<(usize, usize)>,
) -> Result<DataFrame, MetricsError> {
    read_file_slice_checking(table, path, cols, slice, false)
}

fn read_file_slice_checking(
    table: &'static str,
    path: &Path,
    cols: &[Col<'_>],
    slice: Option<(usize, usize)>,
    check: bool,
) -> Result<DataFrame, MetricsError> {
    let file = File::open(path).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            MetricsError::MissingTable { table, path: path.to_path_buf(), detail: "file does not exist".into() }
        } else {
            MetricsError::Read { table, path: path.to_path_buf(), detail: e.to_string() }
        }
    })?;
    let read_err = |e: PolarsError| MetricsError::Read { table, path: path.to_path_buf(), detail: e.to_string() };
    let mut reader = ParquetReader::new(file);
    let schema = reader.schema().map_err(read_err)?;
    for c in cols {
        let field = schema.get(c.name).ok_or_else(|| MetricsError::MissingColumn {
            table,
            path: path.to_path_buf(),
            column: c.name,
            expected: c.want.name(),
        })?;
        if !c.want.accepts(&field.dtype) {
            return Err(MetricsError::ColumnType {
                table,
                path: path.to_path_buf(),
                column: c.name,
                expected: c.want.name(),
                found: type_name(&field.dtype),
            });
        }
    }
    let names: Vec<String> = cols.iter().map(|c| c.name.to_string()).collect();
    let df = reader.with_columns(Some(names.clone())).with_slice(slice).finish().map_err(read_err)?;
    let df = df.select(names).map_err(read_err)?;
    let mut columns = Vec::with_capacity(cols.len());
    for c in cols {
        let column = df.column(c.name).map_err(read_err)?;
        let column = convert(table, path, c, column)?;
        if check {
            check_values(table, path, c, &column)?;
        }
        columns.push(column);
    }
    DataFrame::new(df.height(), columns).map_err(internal("rebuilding a frame"))
}

/// Cast to the wanted type; a value that does not fit (e.g. a negative id) is an input error.
fn convert(table: &'static str, path: &Path, c: &Col<'_>, column: &Column) -> Result<Column, MetricsError> {
    let want = c.want.polars();
    if column.dtype() == &want {
        return Ok(column.clone());
    }
    let cast = column
        .cast_with_options(&want, polars::chunked_array::cast::CastOptions::NonStrict)
        .map_err(|e| MetricsError::Read { table, path: path.to_path_buf(), detail: e.to_string() })?;
    if cast.null_count() > column.null_count() {
        // Find the first value that did not survive the cast.
        let orig = column.as_materialized_series();
        let new = cast.as_materialized_series();
        for row in 0..column.len() {
            let o = orig.get(row).map_err(internal("reading a value"))?;
            let n = new.get(row).map_err(internal("reading a value"))?;
            if !o.is_null() && n.is_null() {
                return Err(MetricsError::InvalidValue {
                    table,
                    path: path.to_path_buf(),
                    column: c.name,
                    row,
                    value: o.to_string(),
                    expected: format!("a value that fits {}", c.want.name()),
                });
            }
        }
    }
    Ok(cast)
}

fn first_null(column: &Column) -> Option<usize> {
    if column.null_count() == 0 {
        return None;
    }
    let s = column.as_materialized_series();
    (0..s.len()).find(|&i| s.get(i).map(|v| v.is_null()).unwrap_or(true))
}

fn check_values(table: &'static str, path: &Path, c: &Col<'_>, column: &Column) -> Result<(), MetricsError> {
    if let Some(row) = first_null(column) {
        return Err(MetricsError::Null { table, path: path.to_path_buf(), column: c.name, row });
    }
    let invalid = |row: usize, value: String, expected: String| MetricsError::InvalidValue {
        table,
        path: path.to_path_buf(),
        column: c.name,
        row,
        value,
        expected,
    };
    let bug = internal("checking values");
    match c.check {
        Check::Any => {}
        Check::Finite | Check::FiniteNonNeg => {
            let ca = column.f64().map_err(bug)?;
            let mut offset = 0;
            for arr in ca.downcast_iter() {
                let values = arr.values().as_slice();
                let non_neg = matches!(c.check, Check::FiniteNonNeg);
                if let Some(i) = values.iter().position(|v| !v.is_finite() || (non_neg && *v < 0.0)) {
                    let (row, v) = (offset + i, values[i]);
                    if !v.is_finite() {
                        return Err(MetricsError::NonFinite {
                            table,
                            path: path.to_path_buf(),
                            column: c.name,
                            row,
                            value: v,
                        });
                    }
                    return Err(invalid(row, v.to_string(), "a value >= 0".into()));
                }
                offset += values.len();
            }
        }
        Check::OneOf(allowed) => check_one_of(column, allowed)
            .map_err(|(row, value)| invalid(row, value, format!("one of {}", allowed.join(", "))))?,
        Check::Radar => check_strings(column, |s| RadarId::parse(s).is_some())
            .map_err(|(row, value)| invalid(row, value, "a radar id R1, R2, …".into()))?,
        Check::RunIn(runs) => {
            let distinct = column.unique().map_err(internal("checking runs"))?;
            let distinct = distinct.u32().map_err(internal("checking runs"))?;
            if distinct.iter().flatten().any(|v| !runs.contains(&v)) {
                let ca = column.u32().map_err(bug)?;
                if let Some((row, v)) = ca.iter().enumerate().find(|(_, v)| v.is_some_and(|v| !runs.contains(&v))) {
                    let list: Vec<String> = runs.iter().take(8).map(|r| r.to_string()).collect();
                    let more = if runs.len() > 8 { ", …" } else { "" };
                    return Err(invalid(
                        row,
                        v.map(|v| v.to_string()).unwrap_or_default(),
                        format!("a run present in the truth table ({}{more})", list.join(", ")),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Vectorized membership test against a few allowed labels, then locate the first offender.
fn check_one_of(column: &Column, allowed: &[&str]) -> Result<(), (usize, String)> {
    let Ok(ca) = column.str() else {
        return Err((0, "<not a string>".into()));
    };
    let mut hits: usize = 0;
    for a in allowed {
        hits += ca.equal(*a).sum().unwrap_or(0) as usize;
    }
    if hits == ca.len() - ca.null_count() {
        return Ok(());
    }
    check_strings(column, |s| allowed.contains(&s))
}

/// Check every value in one pass, calling `ok` only when a value differs from the previous one
/// (the label columns hold long runs of one value); the first offending row and its value.
fn check_strings(column: &Column, ok: impl Fn(&str) -> bool) -> Result<(), (usize, String)> {
    let Ok(ca) = column.str() else {
        return Err((0, "<not a string>".into()));
    };
    let mut last: Option<&str> = None;
    for (row, v) in ca.iter().enumerate() {
        let Some(v) = v else { continue };
        if last == Some(v) {
            continue;
        }
        if !ok(v) {
            return Err((row, v.to_string()));
        }
        last = Some(v);
    }
    Ok(())
}

/// List the `*.parquet` files of a table directory, sorted by name.
pub(crate) fn list_parquet(table: &'static str, dir: &Path) -> Result<Vec<PathBuf>, MetricsError> {
    let entries = std::fs::read_dir(dir).map_err(|e| MetricsError::MissingTable {
        table,
        path: dir.to_path_buf(),
        detail: if e.kind() == std::io::ErrorKind::NotFound {
            "directory does not exist".into()
        } else {
            e.to_string()
        },
    })?;
    let mut files = Vec::new();
    for entry in entries {
        let entry =
            entry.map_err(|e| MetricsError::MissingTable { table, path: dir.to_path_buf(), detail: e.to_string() })?;
        let p = entry.path();
        let hidden = p.file_name().is_some_and(|n| n.to_string_lossy().starts_with('.'));
        if p.extension().is_some_and(|e| e == "parquet") && !hidden && p.is_file() {
            files.push(p);
        }
    }
    if files.is_empty() {
        return Err(MetricsError::MissingTable { table, path: dir.to_path_buf(), detail: "no *.parquet files".into() });
    }
    files.sort();
    Ok(files)
}
