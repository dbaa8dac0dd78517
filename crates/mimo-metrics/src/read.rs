//! Reading and validating the input tables.
//!
//! Each file is read on its own (only the columns the metrics need), its schema checked against
//! what the column means, and its values checked (nulls, NaN/∞, enumerations, runs) before the
//! files of a table are stacked. Errors therefore always name the file, the column, the row and
//! what was expected. Compatible physical types are accepted and converted (any integer type for an
//! integer column, f32 for f64, large/view/dictionary strings for utf8), so tables written by other
//! tools (pyarrow, DuckDB, polars) score too. Files are read with the parquet crate's Arrow
//! reader into a [`Frame`] of Arrow arrays.

use crate::error::MetricsError;
use crate::frame::Frame;
use arrow::array::{Array, ArrayRef, AsArray};
use arrow::compute::{CastOptions, cast_with_options};
use arrow::datatypes::{DataType as ArrowDataType, UInt32Type};
use arrow::util::display::array_value_to_string;
use mimo_core::ids::RadarId;
use parquet::arrow::ProjectionMask;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
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

    pub(crate) fn arrow(self) -> ArrowDataType {
        match self {
            Want::U32 => ArrowDataType::UInt32,
            Want::U64 => ArrowDataType::UInt64,
            Want::F64 => ArrowDataType::Float64,
            Want::Utf8 => ArrowDataType::Utf8,
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
            Want::Utf8 => is_str(dt) || matches!(dt, A::Dictionary(_, inner) if is_str(inner)),
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
pub(crate) type FileCheck<'a> = &'a dyn Fn(&Path, &Frame) -> Result<(), MetricsError>;

/// Read and stack the files of a table, with `check` run on each file's frame (row numbers are then the file's).
pub(crate) fn read_table_checked(
    table: &'static str,
    paths: &[PathBuf],
    cols: &[Col<'_>],
    check: FileCheck<'_>,
) -> Result<Frame, MetricsError> {
    if paths.is_empty() {
        return Err(MetricsError::MissingTable {
            table,
            path: PathBuf::from(table),
            detail: "no Parquet files given".into(),
        });
    }
    let mut frames = Vec::with_capacity(paths.len());
    for path in paths {
        let frame = read_file(table, path, cols)?;
        check(path, &frame)?;
        frames.push(frame);
    }
    Frame::stack(frames)
}

/// Read one file of `table` with the given columns (in that order), validated.
pub(crate) fn read_file(table: &'static str, path: &Path, cols: &[Col<'_>]) -> Result<Frame, MetricsError> {
    read_file_slice(table, path, cols, None)
}

fn open(table: &'static str, path: &Path) -> Result<File, MetricsError> {
    File::open(path).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            MetricsError::MissingTable { table, path: path.to_path_buf(), detail: "file does not exist".into() }
        } else {
            MetricsError::Read { table, path: path.to_path_buf(), detail: e.to_string() }
        }
    })
}

fn read_error<'a>(table: &'static str, path: &'a Path) -> impl Fn(parquet::errors::ParquetError) -> MetricsError + 'a {
    move |e| MetricsError::Read { table, path: path.to_path_buf(), detail: e.to_string() }
}

/// The number of rows of one file of `table` (from its footer).
pub(crate) fn file_rows(table: &'static str, path: &Path) -> Result<usize, MetricsError> {
    let builder = ParquetRecordBatchReaderBuilder::try_new(open(table, path)?).map_err(read_error(table, path))?;
    let rows = builder.metadata().file_metadata().num_rows();
    usize::try_from(rows).map_err(|_| MetricsError::Read {
        table,
        path: path.to_path_buf(),
        detail: format!("the footer gives {rows} rows"),
    })
}

/// [`read_file`] of the rows `slice` = (first row, count) only (all rows for `None`); row
/// numbers in its errors are then the slice's.
pub(crate) fn read_file_slice(
    table: &'static str,
    path: &Path,
    cols: &[Col<'_>],
    slice: Option<(usize, usize)>,
) -> Result<Frame, MetricsError> {
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
) -> Result<Frame, MetricsError> {
    read_file_slice_checking(table, path, cols, slice, false)
}

/// Rows decoded per Arrow batch.
const BATCH_ROWS: usize = 1 << 16;

fn read_file_slice_checking(
    table: &'static str,
    path: &Path,
    cols: &[Col<'_>],
    slice: Option<(usize, usize)>,
    check: bool,
) -> Result<Frame, MetricsError> {
    let read_err = read_error(table, path);
    let builder = ParquetRecordBatchReaderBuilder::try_new(open(table, path)?).map_err(&read_err)?;
    let schema = builder.schema().clone();
    let mut roots = Vec::with_capacity(cols.len());
    for c in cols {
        let (index, field) = schema.column_with_name(c.name).ok_or_else(|| MetricsError::MissingColumn {
            table,
            path: path.to_path_buf(),
            column: c.name,
            expected: c.want.name(),
        })?;
        if !c.want.accepts(field.data_type()) {
            return Err(MetricsError::ColumnType {
                table,
                path: path.to_path_buf(),
                column: c.name,
                expected: c.want.name(),
                found: type_name(field.data_type()),
            });
        }
        roots.push(index);
    }
    let mask = ProjectionMask::roots(builder.parquet_schema(), roots);
    let mut builder = builder.with_projection(mask).with_batch_size(BATCH_ROWS);
    if let Some((first, len)) = slice {
        builder = builder.with_offset(first).with_limit(len);
    }
    let reader = builder.build().map_err(&read_err)?;
    let mut parts: Vec<Vec<ArrayRef>> = vec![Vec::new(); cols.len()];
    for batch in reader {
        let batch = batch.map_err(|e| MetricsError::Read { table, path: path.to_path_buf(), detail: e.to_string() })?;
        for (c, part) in cols.iter().zip(&mut parts) {
            let array = batch.column_by_name(c.name).ok_or_else(|| MetricsError::Internal {
                context: "reading a column",
                detail: format!("{} missing from a batch", c.name),
            })?;
            part.push(array.clone());
        }
    }
    let mut columns = Vec::with_capacity(cols.len());
    for (c, part) in cols.iter().zip(parts) {
        let column = crate::frame::concat(part, c.want)?;
        let column = convert(table, path, c, column)?;
        if check {
            check_values(table, path, c, &column)?;
        }
        columns.push((c.name, column));
    }
    Frame::new(columns)
}

/// Cast to the wanted type; a value that does not fit (e.g. a negative id) is an input error.
fn convert(table: &'static str, path: &Path, c: &Col<'_>, column: ArrayRef) -> Result<ArrayRef, MetricsError> {
    let want = c.want.arrow();
    if column.data_type() == &want {
        return Ok(column);
    }
    let options = CastOptions { safe: true, ..Default::default() };
    let cast = cast_with_options(&column, &want, &options).map_err(|e| MetricsError::Read {
        table,
        path: path.to_path_buf(),
        detail: e.to_string(),
    })?;
    if cast.null_count() > column.null_count() {
        // The first value that did not survive the cast.
        if let Some(row) = (0..column.len()).find(|&i| column.is_valid(i) && cast.is_null(i)) {
            let value = array_value_to_string(&column, row).unwrap_or_else(|_| "?".into());
            return Err(MetricsError::InvalidValue {
                table,
                path: path.to_path_buf(),
                column: c.name,
                row,
                value,
                expected: format!("a value that fits {}", c.want.name()),
            });
        }
    }
    Ok(cast)
}

fn check_values(table: &'static str, path: &Path, c: &Col<'_>, column: &ArrayRef) -> Result<(), MetricsError> {
    if column.null_count() > 0
        && let Some(row) = (0..column.len()).find(|&i| column.is_null(i))
    {
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
    match c.check {
        Check::Any => {}
        Check::Finite | Check::FiniteNonNeg => {
            let values = crate::frame::f64_values(column)?;
            let non_neg = matches!(c.check, Check::FiniteNonNeg);
            if let Some(row) = values.iter().position(|v| !v.is_finite() || (non_neg && *v < 0.0)) {
                let v = values[row];
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
        }
        Check::OneOf(allowed) => check_strings(column, |s| allowed.contains(&s))
            .map_err(|(row, value)| invalid(row, value, format!("one of {}", allowed.join(", "))))?,
        Check::Radar => check_strings(column, |s| RadarId::parse(s).is_some())
            .map_err(|(row, value)| invalid(row, value, "a radar id R1, R2, …".into()))?,
        Check::RunIn(runs) => {
            let values = column.as_primitive::<UInt32Type>().values();
            if let Some(row) = values.iter().position(|v| !runs.contains(v)) {
                let list: Vec<String> = runs.iter().take(8).map(|r| r.to_string()).collect();
                let more = if runs.len() > 8 { ", …" } else { "" };
                return Err(invalid(
                    row,
                    values[row].to_string(),
                    format!("a run present in the truth table ({}{more})", list.join(", ")),
                ));
            }
        }
    }
    Ok(())
}

/// Check every value in one pass, calling `ok` only when a value differs from the previous one
/// (the label columns hold long runs of one value); the first offending row and its value.
fn check_strings(column: &ArrayRef, ok: impl Fn(&str) -> bool) -> Result<(), (usize, String)> {
    let Some(strings) = column.as_string_opt::<i32>() else {
        return Err((0, "<not a string>".into()));
    };
    let mut last: Option<&str> = None;
    for (row, v) in strings.iter().enumerate() {
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
