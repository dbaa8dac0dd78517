//! The columns the usage by purpose reads from the dwells table, and the truth's `run` column
//! ([`crate::purpose`]), with the `arrow` and `parquet` crates: only the columns named, batch by
//! batch, each checked for its type, nulls and (floats) finiteness, errors naming the file, the
//! column and the row.

use crate::MetricsError;
use arrow::array::{Array, ArrayRef, AsArray, Float64Array, StringArray, UInt8Array, UInt32Array, UInt64Array};
use arrow::compute::{CastOptions, cast_with_options};
use arrow::datatypes::{DataType, Float64Type, UInt8Type, UInt32Type, UInt64Type};
use arrow::record_batch::RecordBatch;
use parquet::arrow::ProjectionMask;
use std::path::Path;

/// Rows decoded at a time.
const BATCH_ROWS: usize = 8192;

/// One batch of a table with the file it came from and the index of its first row in the file.
pub(crate) struct Batch<'a> {
    table: &'static str,
    path: &'a Path,
    batch: RecordBatch,
    /// Index of the batch's first row in the file (0-based).
    pub first_row: usize,
}

fn read_err(table: &'static str, path: &Path, detail: String) -> MetricsError {
    MetricsError::Read { table, path: path.to_path_buf(), detail }
}

/// Read `columns` of the Parquet file `path` of `table` batch by batch, handing each to `each`.
pub(crate) fn for_batches(
    table: &'static str,
    path: &Path,
    columns: &[&'static str],
    mut each: impl FnMut(&Batch<'_>) -> Result<(), MetricsError>,
) -> Result<(), MetricsError> {
    let builder = crate::read::open_checked(table, path)?;
    let spec = crate::read::spec_of(table)?;
    let mut roots = Vec::with_capacity(columns.len());
    for &name in columns {
        let i = builder.schema().index_of(name).map_err(|_| MetricsError::MissingColumn {
            table,
            path: path.to_path_buf(),
            column: name,
            expected: "a column of the table's schema (schemas/)",
        })?;
        roots.push(i);
    }
    let mask = ProjectionMask::roots(builder.parquet_schema(), roots);
    let reader = builder
        .with_projection(mask)
        .with_batch_size(BATCH_ROWS)
        .build()
        .map_err(|e| read_err(table, path, e.to_string()))?;
    let mut first_row = 0;
    for batch in reader {
        let batch = batch.map_err(|e| read_err(table, path, e.to_string()))?;
        // The spec's rules and the file's run, on the columns read.
        mimo_store::rows::Batch::check_values(&batch, path, spec, first_row)?;
        let b = Batch { table, path, batch, first_row };
        each(&b)?;
        first_row += b.batch.num_rows();
    }
    Ok(())
}

impl Batch<'_> {
    /// Rows in the batch.
    pub(crate) fn len(&self) -> usize {
        self.batch.num_rows()
    }

    /// Column `name` as `want`: integer columns of another integer type and strings of another
    /// string layout are converted (as other writers, polars among them, store them); anything
    /// else, or a value the conversion cannot hold, is an input error.
    fn column(&self, name: &'static str, want: DataType, expected: &'static str) -> Result<ArrayRef, MetricsError> {
        let c: &ArrayRef = self.batch.column_by_name(name).ok_or_else(|| MetricsError::MissingColumn {
            table: self.table,
            path: self.path.to_path_buf(),
            column: name,
            expected,
        })?;
        let wrong_type = || MetricsError::ColumnType {
            table: self.table,
            path: self.path.to_path_buf(),
            column: name,
            expected,
            found: c.data_type().to_string(),
        };
        let found = c.data_type();
        let convertible = (found.is_integer() && want.is_integer())
            || (matches!(found, DataType::LargeUtf8 | DataType::Utf8View) && want == DataType::Utf8);
        let a = if *found == want {
            c.clone()
        } else if convertible {
            let opts = CastOptions { safe: false, ..CastOptions::default() };
            cast_with_options(c, &want, &opts).map_err(|_| wrong_type())?
        } else {
            return Err(wrong_type());
        };
        if a.null_count() > 0 {
            let row = (0..a.len()).find(|&i| a.is_null(i)).unwrap_or(0);
            return Err(MetricsError::Null {
                table: self.table,
                path: self.path.to_path_buf(),
                column: name,
                row: self.first_row + row,
            });
        }
        Ok(a)
    }

    /// A uint32 column.
    pub(crate) fn u32(&self, name: &'static str) -> Result<UInt32Array, MetricsError> {
        Ok(self.column(name, DataType::UInt32, "uint32")?.as_primitive::<UInt32Type>().clone())
    }

    /// A uint64 column.
    pub(crate) fn u64(&self, name: &'static str) -> Result<UInt64Array, MetricsError> {
        Ok(self.column(name, DataType::UInt64, "uint64")?.as_primitive::<UInt64Type>().clone())
    }

    /// A uint8 column.
    pub(crate) fn u8(&self, name: &'static str) -> Result<UInt8Array, MetricsError> {
        Ok(self.column(name, DataType::UInt8, "uint8")?.as_primitive::<UInt8Type>().clone())
    }

    /// A utf8 column.
    pub(crate) fn utf8(&self, name: &'static str) -> Result<StringArray, MetricsError> {
        Ok(self.column(name, DataType::Utf8, "utf8")?.as_string::<i32>().clone())
    }

    /// A float64 column whose every value is finite.
    pub(crate) fn f64(&self, name: &'static str) -> Result<Float64Array, MetricsError> {
        let a = self.column(name, DataType::Float64, "float64")?.as_primitive::<Float64Type>().clone();
        if let Some(row) = a.values().iter().position(|x| !x.is_finite()) {
            return Err(MetricsError::NonFinite {
                table: self.table,
                path: self.path.to_path_buf(),
                column: name,
                row: self.first_row + row,
                value: a.value(row),
            });
        }
        Ok(a)
    }

    /// An input error for `column` at row `row` of the batch.
    pub(crate) fn invalid(&self, column: &'static str, row: usize, value: String, expected: &str) -> MetricsError {
        MetricsError::InvalidValue {
            table: self.table,
            path: self.path.to_path_buf(),
            column,
            row: self.first_row + row,
            value,
            expected: expected.to_string(),
        }
    }
}
