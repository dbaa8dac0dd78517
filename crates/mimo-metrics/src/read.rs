//! Reading columns of the input tables, through the store's checks: the checked read of a dwells
//! file's usage columns when its one-pass reader gives up ([`crate::load`]), and the `run`
//! columns that split a score by run ([`crate::parts`]). Truth and tracks are read with the
//! store's reader of every run table (`mimo_store::table_chunks`, rules included).
//!
//! Each file is opened with `mimo_store::checked::open` (the table's name and schema version in
//! its metadata, every column of the table's spec with exactly its type) and read on its own,
//! only the columns named (a projection: names only; types, nullability and value rules come
//! from the table's spec in `mimo-store`), each column's values checked against its spec
//! ([`mimo_store::checked::check_array`]), `run` against the file's run and, for the dwells,
//! against the runs of the truth table. Errors therefore always name the file, the column, the
//! row and what was expected. Files are read with the parquet crate's Arrow reader into a
//! [`Frame`] of Arrow arrays.

use crate::error::MetricsError;
use crate::frame::Frame;
use arrow::array::{ArrayRef, AsArray};
use arrow::datatypes::UInt32Type;
use mimo_store::schema::{ColumnSpec, TableSpec};
use parquet::arrow::ProjectionMask;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::collections::BTreeSet;
use std::fs::File;
use std::path::{Path, PathBuf};

/// A check beyond the column's spec.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Check<'a> {
    /// The spec's rule only.
    Any,
    /// A run present in the truth table.
    RunIn(&'a BTreeSet<u32>),
}

/// One column read: its name in the table's spec, and any check beyond the spec.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Col<'a> {
    pub name: &'static str,
    pub check: Check<'a>,
}

pub(crate) const fn col<'a>(name: &'static str, check: Check<'a>) -> Col<'a> {
    Col { name, check }
}

/// The spec of `table`.
pub(crate) fn spec_of(table: &'static str) -> Result<&'static TableSpec, MetricsError> {
    Ok(mimo_store::checked::spec(table)?)
}

fn column_spec(spec: &'static TableSpec, name: &str) -> Result<&'static ColumnSpec, MetricsError> {
    spec.columns.iter().find(|c| c.name == name).ok_or_else(|| MetricsError::Internal {
        context: "reading a table",
        detail: format!("table {} has no column {name}", spec.name),
    })
}

/// One file of `table` opened for reading, checked (`mimo_store::checked::open`).
pub(crate) fn open_checked(
    table: &'static str,
    path: &Path,
) -> Result<ParquetRecordBatchReaderBuilder<File>, MetricsError> {
    match mimo_store::checked::open(path, spec_of(table)?) {
        Ok(builder) => Ok(builder),
        Err(mimo_store::StoreError::Missing { path }) => {
            Err(MetricsError::MissingTable { table, path, detail: "file does not exist".into() })
        }
        Err(e) => Err(e.into()),
    }
}

/// Rows decoded per Arrow batch.
const BATCH_ROWS: usize = 1 << 16;

/// Read one file of `table` with the given columns (in that order), every value checked.
pub(crate) fn read_file(table: &'static str, path: &Path, cols: &[Col<'_>]) -> Result<Frame, MetricsError> {
    let spec = spec_of(table)?;
    let builder = open_checked(table, path)?;
    let schema = builder.schema().clone();
    let mut roots = Vec::with_capacity(cols.len());
    let mut specs = Vec::with_capacity(cols.len());
    for c in cols {
        specs.push(column_spec(spec, c.name)?);
        // Present: `open_checked` found every column of the spec.
        roots.push(
            schema
                .index_of(c.name)
                .map_err(|e| MetricsError::Internal { context: "reading a table", detail: e.to_string() })?,
        );
    }
    let mask = ProjectionMask::roots(builder.parquet_schema(), roots);
    let builder = builder.with_projection(mask).with_batch_size(BATCH_ROWS);
    let reader = builder.build().map_err(read_error(table, path))?;
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
    for ((c, s), part) in cols.iter().zip(specs).zip(parts) {
        let column = crate::frame::concat(part, &s.ty.arrow())?;
        check_values(table, path, c, s, &column, 0)?;
        columns.push((c.name, column));
    }
    Frame::new(columns)
}
fn read_error<'a>(table: &'static str, path: &'a Path) -> impl Fn(parquet::errors::ParquetError) -> MetricsError + 'a {
    move |e| MetricsError::Read { table, path: path.to_path_buf(), detail: e.to_string() }
}

/// The number of rows of one file of `table` (from its footer), after the file's checks
/// ([`open_checked`]).
pub(crate) fn file_rows(table: &'static str, path: &Path) -> Result<usize, MetricsError> {
    let builder = open_checked(table, path)?;
    let rows = builder.metadata().file_metadata().num_rows();
    usize::try_from(rows).map_err(|_| MetricsError::Read {
        table,
        path: path.to_path_buf(),
        detail: format!("the footer gives {rows} rows"),
    })
}

/// A column's values against its spec ([`mimo_store::checked::check_array`]), the [`Check`]
/// beyond the spec, and `run` against the file's run.
fn check_values(
    table: &'static str,
    path: &Path,
    c: &Col<'_>,
    spec: &ColumnSpec,
    column: &ArrayRef,
    first_row: usize,
) -> Result<(), MetricsError> {
    mimo_store::checked::check_array(path, spec, column.as_ref(), first_row)?;
    if let Check::RunIn(runs) = c.check {
        let values = column.as_primitive::<UInt32Type>().values();
        if let Some(row) = values.iter().position(|v| !runs.contains(v)) {
            let list: Vec<String> = runs.iter().take(8).map(|r| r.to_string()).collect();
            let more = if runs.len() > 8 { ", …" } else { "" };
            return Err(MetricsError::InvalidValue {
                table,
                path: path.to_path_buf(),
                column: c.name,
                row: first_row + row,
                value: values[row].to_string(),
                expected: format!("a run present in the truth table ({}{more})", list.join(", ")),
            });
        }
    }
    if c.name == mimo_core::records::TruthRow::COLUMNS.run {
        mimo_store::checked::check_file_run(path, column.as_ref(), first_row)?;
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
