//! Conversion between the row records of `mimo-core` and Arrow record batches.
//!
//! Every run table implements [`TableRow`], generated from its declaration
//! ([`crate::run_tables`]). Writing builds one Arrow array per column in the order of
//! the table's [`TableSpec`]; reading checks that every column exists with the expected type and
//! that floating-point values are finite, naming the file and column when they are not.

use crate::StoreError;
use crate::schema::TableSpec;
use arrow::array::{
    Array, ArrayRef, BooleanArray, FixedSizeListArray, Float64Array, Int64Array, RecordBatch, StringArray, UInt8Array,
    UInt32Array, UInt64Array,
};
use arrow::datatypes::SchemaRef;
use mimo_core::ids::RadarId;
use std::path::Path;
use std::sync::Arc;

/// A record type stored as one table.
pub trait TableRow: Sized + crate::invariants::RowInvariants {
    /// The table's schema spec.
    const SPEC: TableSpec;
    /// One Arrow array per column, in spec order.
    fn to_columns(rows: &[Self]) -> Vec<ArrayRef>;
    /// Rows from a batch already checked against the spec.
    fn from_batch(b: &Batch<'_>) -> Result<Vec<Self>, StoreError>;
}

/// Build a record batch of rows.
pub fn to_batch<R: TableRow>(rows: &[R]) -> Result<RecordBatch, StoreError> {
    let schema: SchemaRef = Arc::new(R::SPEC.arrow_schema());
    RecordBatch::try_new(schema, R::to_columns(rows)).map_err(|e| StoreError::Arrow(e.to_string()))
}

/// A record batch being read, with the file it came from for error messages.
pub struct Batch<'a> {
    /// The record batch read.
    pub batch: &'a RecordBatch,
    /// The file it was read from, named in errors.
    pub file: &'a Path,
    /// The table the batch was checked against.
    pub spec: &'static TableSpec,
}

impl<'a> Batch<'a> {
    /// Check every spec column is present with the right type and keeps its rule
    /// ([`crate::checked`]), and every row is the file's run; rows are numbered from 0.
    pub fn check(batch: &'a RecordBatch, file: &'a Path, spec: &'static TableSpec) -> Result<Batch<'a>, StoreError> {
        Self::check_from(batch, file, spec, 0)
    }

    /// [`Batch::check`] of a batch whose first row is row `first_row` of the file.
    pub fn check_from(
        batch: &'a RecordBatch,
        file: &'a Path,
        spec: &'static TableSpec,
        first_row: usize,
    ) -> Result<Batch<'a>, StoreError> {
        crate::checked::check_types(file, &batch.schema(), spec)?;
        Self::check_values(batch, file, spec, first_row)
    }

    /// The values of the spec's columns the batch holds (a projection: types already checked
    /// when the file was opened) checked against their rules, and `run` against the file's run;
    /// the batch's first row is row `first_row` of the file.
    pub fn check_values(
        batch: &'a RecordBatch,
        file: &'a Path,
        spec: &'static TableSpec,
        first_row: usize,
    ) -> Result<Batch<'a>, StoreError> {
        check_values_of(batch, file, spec, first_row)?;
        Ok(Batch { batch, file, spec })
    }

    /// [`Batch::check_values`] of a batch of rows picked from the file: batch row `i` is file
    /// row `file_rows[i]`, named in the error.
    pub fn check_values_at(
        batch: &'a RecordBatch,
        file: &'a Path,
        spec: &'static TableSpec,
        file_rows: &[usize],
    ) -> Result<Batch<'a>, StoreError> {
        if check_values_of(batch, file, spec, 0).is_err() {
            // Row by row, to name the file row of the first value that breaks a rule.
            for (i, &row) in file_rows.iter().enumerate().take(batch.num_rows()) {
                check_values_of(&batch.slice(i, 1), file, spec, row)?;
            }
            check_values_of(batch, file, spec, 0)?;
        }
        Ok(Batch { batch, file, spec })
    }

    fn col_ref(&self, name: &str) -> &'a ArrayRef {
        let batch: &'a RecordBatch = self.batch;
        // Presence was checked in `check`; a spec column name is always there.
        let idx = batch.schema().index_of(name).unwrap_or(0);
        batch.column(idx)
    }

    fn col(&self, name: &str) -> &ArrayRef {
        // Presence was checked in `check`; a spec column name is always there.
        let idx = self.batch.schema().index_of(name).unwrap_or(0);
        self.batch.column(idx)
    }

    fn bad(&self, column: &str, why: impl Into<String>) -> StoreError {
        StoreError::BadColumn { file: self.file.to_path_buf(), column: column.to_string(), why: why.into() }
    }

    fn nonnull<T>(&self, name: &str, arr: &dyn Array, f: impl Fn(usize) -> T) -> Result<Vec<T>, StoreError> {
        if arr.null_count() > 0 {
            return Err(self.bad(name, "has null values"));
        }
        Ok((0..arr.len()).map(f).collect())
    }

    /// A checked float64 column's values, borrowed (no copy; its nulls and rule were checked by
    /// [`Batch::check_values`]). Errors ([`StoreError::BadColumn`]) when it is not float64.
    pub fn f64_values(&self, name: &str) -> Result<&'a [f64], StoreError> {
        let a = self.col_ref(name);
        Ok(a.as_any().downcast_ref::<Float64Array>().ok_or_else(|| self.bad(name, "is not float64"))?.values())
    }

    /// A checked uint32 column's values, borrowed.
    pub fn u32_values(&self, name: &str) -> Result<&'a [u32], StoreError> {
        let a = self.col_ref(name);
        Ok(a.as_any().downcast_ref::<UInt32Array>().ok_or_else(|| self.bad(name, "is not uint32"))?.values())
    }

    /// A checked uint64 column's values, borrowed.
    pub fn u64_values(&self, name: &str) -> Result<&'a [u64], StoreError> {
        let a = self.col_ref(name);
        Ok(a.as_any().downcast_ref::<UInt64Array>().ok_or_else(|| self.bad(name, "is not uint64"))?.values())
    }

    /// A checked utf8 column, borrowed (its strings are not copied).
    pub fn utf8(&self, name: &str) -> Result<&'a StringArray, StoreError> {
        let a = self.col_ref(name);
        a.as_any().downcast_ref::<StringArray>().ok_or_else(|| self.bad(name, "is not utf8"))
    }

    /// The number of rows.
    pub fn num_rows(&self) -> usize {
        self.batch.num_rows()
    }

    /// The values of a non-nullable float64 column. Errors ([`StoreError::BadColumn`]) when it is
    /// not float64, holds a null or a NaN or ∞.
    pub fn f64(&self, name: &str) -> Result<Vec<f64>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<Float64Array>().ok_or_else(|| self.bad(name, "is not float64"))?;
        let v = self.nonnull(name, a, |i| a.value(i))?;
        if let Some(i) = v.iter().position(|x| !x.is_finite()) {
            return Err(self.bad(name, format!("has a non-finite value ({}) at row {i}", v[i])));
        }
        Ok(v)
    }

    /// The values of a non-nullable uint32 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// uint32 or holds a null.
    pub fn u32(&self, name: &str) -> Result<Vec<u32>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<UInt32Array>().ok_or_else(|| self.bad(name, "is not uint32"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a non-nullable uint64 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// uint64 or holds a null.
    pub fn u64(&self, name: &str) -> Result<Vec<u64>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<UInt64Array>().ok_or_else(|| self.bad(name, "is not uint64"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a nullable uint64 column, `None` for a null. Errors ([`StoreError::BadColumn`])
    /// when it is not uint64.
    pub fn opt_u64(&self, name: &str) -> Result<Vec<Option<u64>>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<UInt64Array>().ok_or_else(|| self.bad(name, "is not uint64"))?;
        Ok((0..a.len()).map(|i| if a.is_null(i) { None } else { Some(a.value(i)) }).collect())
    }

    /// The values of a non-nullable int64 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// int64 or holds a null.
    pub fn i64(&self, name: &str) -> Result<Vec<i64>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<Int64Array>().ok_or_else(|| self.bad(name, "is not int64"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a non-nullable uint8 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// uint8 or holds a null.
    pub fn u8(&self, name: &str) -> Result<Vec<u8>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<UInt8Array>().ok_or_else(|| self.bad(name, "is not uint8"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a non-nullable boolean column. Errors ([`StoreError::BadColumn`]) when it is not
    /// boolean or holds a null.
    pub fn bool(&self, name: &str) -> Result<Vec<bool>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<BooleanArray>().ok_or_else(|| self.bad(name, "is not bool"))?;
        self.nonnull(name, a, |i| a.value(i))
    }

    /// The values of a non-nullable utf8 column. Errors ([`StoreError::BadColumn`]) when it is not
    /// utf8 or holds a null.
    pub fn str(&self, name: &str) -> Result<Vec<String>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<StringArray>().ok_or_else(|| self.bad(name, "is not utf8"))?;
        self.nonnull(name, a, |i| a.value(i).to_string())
    }

    /// The values of a nullable utf8 column, `None` for a null. Errors ([`StoreError::BadColumn`])
    /// when it is not utf8.
    pub fn opt_str(&self, name: &str) -> Result<Vec<Option<String>>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<StringArray>().ok_or_else(|| self.bad(name, "is not utf8"))?;
        Ok((0..a.len()).map(|i| if a.is_null(i) { None } else { Some(a.value(i).to_string()) }).collect())
    }

    /// A utf8 column of radar ids (`R1`…), parsed. Errors ([`StoreError::BadColumn`]) on a null or
    /// a value that is not a radar id, naming the row.
    pub fn radar(&self, name: &str) -> Result<Vec<RadarId>, StoreError> {
        self.parse_each(name, RadarId::parse, "a radar id like R1")
    }

    /// A utf8 column of categories parsed by `parse`; `what` lists the accepted values for the
    /// error ([`StoreError::BadColumn`], naming the row) raised on a null or any other value.
    pub fn parsed<T>(&self, name: &str, parse: fn(&str) -> Option<T>, what: &str) -> Result<Vec<T>, StoreError> {
        self.parse_each(name, parse, &format!("one of {what}"))
    }

    /// Parse every value of a non-nullable utf8 column in place (no string is copied); `what`
    /// completes "row i: 'x' is not …".
    fn parse_each<T>(&self, name: &str, parse: impl Fn(&str) -> Option<T>, what: &str) -> Result<Vec<T>, StoreError> {
        let a = self.col(name);
        let a = a.as_any().downcast_ref::<StringArray>().ok_or_else(|| self.bad(name, "is not utf8"))?;
        if a.null_count() > 0 {
            return Err(self.bad(name, "has null values"));
        }
        (0..a.len())
            .map(|i| {
                let s = a.value(i);
                parse(s)
                    .ok_or_else(|| self.bad(name, format!("row {i}: {} is not {what}", mimo_core::quote::quoted(s))))
            })
            .collect()
    }

    /// A non-nullable `fixed_size_list<float64, 21>` column: per row, the upper triangle of the
    /// 6×6 covariance, row-major. Errors ([`StoreError::BadColumn`]) when it has another type,
    /// holds a null or a NaN or ∞.
    pub fn cov21(&self, name: &str) -> Result<Vec<[f64; 21]>, StoreError> {
        let a = self.col(name);
        let a = a
            .as_any()
            .downcast_ref::<FixedSizeListArray>()
            .ok_or_else(|| self.bad(name, "is not a fixed-size list"))?;
        if a.null_count() > 0 {
            return Err(self.bad(name, "has null values"));
        }
        let vals = a.values();
        let vals =
            vals.as_any().downcast_ref::<Float64Array>().ok_or_else(|| self.bad(name, "items are not float64"))?;
        let mut out = Vec::with_capacity(a.len());
        for i in 0..a.len() {
            let mut c = [0.0; 21];
            for (k, ck) in c.iter_mut().enumerate() {
                *ck = vals.value(i * 21 + k);
                if !ck.is_finite() {
                    return Err(self.bad(name, format!("has a non-finite value at row {i}")));
                }
            }
            out.push(c);
        }
        Ok(out)
    }
}

/// The values of the spec's columns that `batch` holds against their rules, and `run` against the
/// file's run.
fn check_values_of(batch: &RecordBatch, file: &Path, spec: &TableSpec, first_row: usize) -> Result<(), StoreError> {
    for c in spec.columns {
        if let Some(array) = batch.column_by_name(c.name) {
            crate::checked::check_array(file, c, array.as_ref(), first_row)?;
            if c.name == "run" {
                crate::checked::check_file_run(file, array.as_ref(), first_row)?;
            }
        }
    }
    Ok(())
}
