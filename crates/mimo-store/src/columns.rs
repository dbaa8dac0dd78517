//! Tables written column by column, for tables whose rows are assembled at run time (the study
//! and score tables): each column is a [`Column`] of values, checked against the table's [`TableSpec`]
//! (names, order, types and nullability) before anything is written.

use crate::cell::ColumnKind;
use crate::schema::{ColType, TableSpec};
use crate::{StoreError, write_batch};
use arrow::array::{Array, RecordBatch};
use arrow::array::{ArrayRef, BooleanArray, Float64Array, StringArray, UInt32Array, UInt64Array};
use std::path::Path;
use std::sync::Arc;

/// The values of one column.
#[derive(Debug, Clone, PartialEq)]
pub enum Column {
    /// `uint32`.
    U32(Vec<u32>),
    /// `uint64`.
    U64(Vec<u64>),
    /// `uint32`, null where `None`.
    OptU32(Vec<Option<u32>>),
    /// `uint64`, null where `None`.
    OptU64(Vec<Option<u64>>),
    /// `float64`, null where `None`.
    F64(Vec<Option<f64>>),
    /// `utf8`, null where `None`.
    Utf8(Vec<Option<String>>),
    /// `bool`.
    Bool(Vec<bool>),
}

impl Column {
    fn len(&self) -> usize {
        match self {
            Column::U32(v) => v.len(),
            Column::U64(v) => v.len(),
            Column::OptU32(v) => v.len(),
            Column::OptU64(v) => v.len(),
            Column::F64(v) => v.len(),
            Column::Utf8(v) => v.len(),
            Column::Bool(v) => v.len(),
        }
    }

    fn ty(&self) -> ColType {
        match self {
            Column::U32(_) | Column::OptU32(_) => ColType::U32,
            Column::U64(_) | Column::OptU64(_) => ColType::U64,
            Column::F64(_) => ColType::F64,
            Column::Utf8(_) => ColType::Utf8,
            Column::Bool(_) => ColType::Bool,
        }
    }

    fn array(self) -> ArrayRef {
        match self {
            Column::U32(v) => Arc::new(UInt32Array::from(v)),
            Column::U64(v) => Arc::new(UInt64Array::from(v)),
            Column::OptU32(v) => Arc::new(UInt32Array::from(v)),
            Column::OptU64(v) => Arc::new(UInt64Array::from(v)),
            Column::F64(v) => Arc::new(Float64Array::from(v)),
            Column::Utf8(v) => Arc::new(StringArray::from(v)),
            Column::Bool(v) => Arc::new(BooleanArray::from(v)),
        }
    }
}

/// Write `columns` (one per column of `spec`, in order) as one Parquet file, atomically.
/// Returns the number of rows.
pub fn write_columns(path: &Path, spec: &TableSpec, columns: Vec<Column>) -> Result<u64, StoreError> {
    if columns.len() != spec.columns.len() {
        return Err(StoreError::Arrow(format!(
            "table {}: {} columns given, the schema has {}",
            spec.name,
            columns.len(),
            spec.columns.len()
        )));
    }
    let rows = columns.first().map_or(0, Column::len);
    for (c, s) in columns.iter().zip(spec.columns) {
        if c.ty() != s.ty || c.len() != rows {
            return Err(StoreError::Arrow(format!(
                "table {}: column '{}' given as {} × {}, expected {} × {rows}",
                spec.name,
                s.name,
                c.len(),
                c.ty().name(),
                s.ty.name()
            )));
        }
    }
    let arrays: Vec<ArrayRef> = columns.into_iter().map(Column::array).collect();
    for (a, s) in arrays.iter().zip(spec.columns) {
        if !s.nullable && a.null_count() > 0 {
            return Err(StoreError::Arrow(format!("table {}: column '{}' holds nulls", spec.name, s.name)));
        }
    }
    let schema = Arc::new(spec.arrow_schema());
    let batch = RecordBatch::try_new(schema, arrays).map_err(|e| StoreError::Arrow(e.to_string()))?;
    write_batch(path, &batch)?;
    Ok(rows as u64)
}

/// A Rust type a declared table (score or study) gives a column written column by column: its
/// [`Column`] of the values `get` picks from `rows`.
pub trait IntoColumn: ColumnKind {
    /// The column of the values `get` picks from `rows`.
    fn column_of<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> Column;
}

/// A Rust type a declared table gives a field: its column ([`IntoColumn`]) or, for a group
/// type ([`ColumnKind::GROUP`]), its columns.
pub trait IntoColumns: ColumnKind {
    /// Append the column(s) of the values `get` picks from `rows` to `out`.
    fn push_columns<R>(rows: &[R], get: impl Fn(&R) -> &Self, out: &mut Vec<Column>);
}

impl<T: IntoColumn> IntoColumns for T {
    fn push_columns<R>(rows: &[R], get: impl Fn(&R) -> &Self, out: &mut Vec<Column>) {
        out.push(T::column_of(rows, get));
    }
}

macro_rules! into_columns {
    ($($t:ty => |$v:ident| $variant:ident($e:expr);)*) => {$(
        impl IntoColumn for $t {
            fn column_of<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> Column {
                Column::$variant(rows.iter().map(|r| { let $v = get(r); $e }).collect())
            }
        }
    )*};
}

into_columns! {
    u32 => |v| U32(*v);
    u64 => |v| U64(*v);
    bool => |v| Bool(*v);
    Option<u32> => |v| OptU32(*v);
    Option<u64> => |v| OptU64(*v);
    f64 => |v| F64(Some(*v));
    Option<f64> => |v| F64(*v);
    String => |v| Utf8(Some(v.clone()));
    Option<String> => |v| Utf8(v.clone());
}

/// Rows of a declared table written column by column: the columns of its spec, in order.
pub trait ColumnRows: Sized {
    /// The columns of the rows `get` picks from `rows`, in the order of the table's spec.
    fn columns_of<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> Vec<Column>;
    /// The columns of `rows`.
    fn columns(rows: &[Self]) -> Vec<Column> {
        Self::columns_of(rows, |r| r)
    }
}

/// Rows of a declared table whose spec is known where the rows are (the study tables).
pub trait ColumnTable: ColumnRows {
    /// The table's spec.
    const SPEC: TableSpec;
}

/// Write `rows` of a declared table as one Parquet file, atomically ([`write_columns`]).
/// Returns the number of rows.
pub fn write_rows<R: ColumnTable>(path: &Path, rows: &[R]) -> Result<u64, StoreError> {
    write_columns(path, &R::SPEC, R::columns(rows))
}

/// The record struct of a declared table (see `mimo_core::table_decl`), its column names
/// (`COLUMN_NAMES`, a group field's columns included) and its [`ColumnRows`], for tables whose
/// rows are assembled at run time and written through [`write_columns`].
#[macro_export]
macro_rules! column_rows {
    (
        [$(#[$smeta:meta])*] $row:ident $cols:ident $spec:ident $table:literal $tdesc:literal
        [$([$(#[$fmeta:meta])*] $field:ident ($ty:ty) ($unit:literal, $desc:literal $(, $rule:ident)?) [$($tag:ident)*])*]
    ) => {
        $crate::core_crate::record_struct! {
            @struct [$(#[$smeta])*] $row $cols $spec $table $tdesc
            [$([$(#[$fmeta])*] $field ($ty) ($unit, $desc $(, $rule)?) [$($tag)*])*]
        }

        impl $row {
            /// The table's column names in file order.
            pub const COLUMN_NAMES: &'static [&'static str] = &$crate::schema::column_names::<
                { 0 $(+ <$ty as $crate::cell::ColumnKind>::WIDTH)* },
            >(&$crate::declared_columns!([$([$(#[$fmeta])*] $field ($ty) ($unit, $desc $(, $rule)?) [$($tag)*])*]));
        }

        impl $crate::columns::ColumnRows for $row {
            fn columns_of<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> Vec<$crate::columns::Column> {
                let mut out = Vec::new();
                $(<$ty as $crate::columns::IntoColumns>::push_columns(rows, |r| &get(r).$field, &mut out);)*
                out
            }
        }
    };
}

/// The spec, record struct, column names and columns of a declared group of columns several
/// study tables share (the identifying columns), which a table's row holds as one field: the
/// group's [`ColumnKind::GROUP`] is its spec's columns.
#[macro_export]
#[doc(hidden)]
macro_rules! column_group {
    ([$($smeta:tt)*] $row:ident $cols:ident $spec:ident $table:literal $tdesc:literal [$($fields:tt)*]) => {
        $crate::table_spec! { [$($smeta)*] $row $cols $spec $table $tdesc [$($fields)*] }
        $crate::column_rows! { [$($smeta)*] $row $cols $spec $table $tdesc [$($fields)*] }
        impl $crate::cell::ColumnKind for $row {
            const TY: $crate::schema::ColType = $crate::schema::ColType::Utf8;
            const GROUP: Option<&'static [$crate::schema::ColumnSpec]> = Some($spec.columns);
        }
        impl $crate::columns::IntoColumns for $row {
            fn push_columns<R>(rows: &[R], get: impl Fn(&R) -> &Self, out: &mut Vec<$crate::columns::Column>) {
                out.extend(<Self as $crate::columns::ColumnRows>::columns_of(rows, get));
            }
        }
    };
}

/// The spec, record struct, column names and [`ColumnTable`] of a declared table written column
/// by column whose declaration lives in this crate (the study tables).
#[macro_export]
#[doc(hidden)]
macro_rules! column_table {
    ([$($smeta:tt)*] $row:ident $cols:ident $spec:ident $table:literal $tdesc:literal [$($fields:tt)*]) => {
        $crate::table_spec! { [$($smeta)*] $row $cols $spec $table $tdesc [$($fields)*] }
        $crate::column_rows! { [$($smeta)*] $row $cols $spec $table $tdesc [$($fields)*] }
        impl $crate::columns::ColumnTable for $row {
            const SPEC: $crate::schema::TableSpec = $spec;
        }
    };
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::study_schema::{STUDY_COSTS, STUDY_ID_COLUMNS};
    use arrow::array::AsArray;

    /// The first record batch of the Parquet file at `path`.
    pub(crate) fn first_batch(path: &Path) -> RecordBatch {
        let f = std::fs::File::open(path).expect("open");
        parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(f)
            .expect("reader")
            .build()
            .expect("build")
            .next()
            .expect("a batch")
            .expect("batch")
    }

    fn ids(n: usize) -> Vec<Column> {
        // method, family, knob, knob_value, scenario, swept, then the five axes.
        let mut v = vec![
            Column::Utf8(vec![Some("m@2".into()); n]),
            Column::Utf8(vec![Some("m".into()); n]),
            Column::Utf8(vec![Some("resource_manager.max_ta_share".into()); n]),
            Column::F64(vec![Some(2.0); n]),
            Column::Utf8(vec![Some("7".into()); n]),
            Column::Utf8(vec![None; n]),
        ];
        v.extend((6..STUDY_ID_COLUMNS).map(|i| Column::F64(vec![(i == 6).then_some(-3.0); n])));
        v
    }

    #[test]
    fn columns_round_trip_and_mismatches_are_refused() {
        let dir = tempfile::tempdir().expect("tmp");
        let path = dir.path().join("costs.parquet");
        let mut cols = ids(2);
        cols.push(Column::U32(vec![0, 1]));
        cols.push(Column::U64(vec![9, 9]));
        for x in [100.0, 1.5, 2.5, 4.0, 1e-6, 1.5e6] {
            cols.push(Column::F64(vec![Some(x), Some(x + 1.0)]));
        }
        assert_eq!(write_columns(&path, &STUDY_COSTS, cols.clone()).expect("write"), 2);
        let batch = first_batch(&path);
        assert_eq!(batch.num_rows(), 2);
        let wall = batch.column_by_name("wall_s").expect("wall_s").as_primitive::<arrow::datatypes::Float64Type>();
        assert_eq!(wall.values().to_vec(), vec![4.0, 5.0]);
        let rcs = batch.column_by_name("rcs_offset_db").expect("rcs");
        assert_eq!(rcs.null_count(), 0);
        assert_eq!(batch.column_by_name("pfa").expect("pfa").null_count(), 2);
        // A missing column, a wrong type and a null in a non-null column are refused.
        assert!(write_columns(&path, &STUDY_COSTS, cols[..cols.len() - 1].to_vec()).is_err());
        let mut wrong = cols.clone();
        wrong[11] = Column::U64(vec![0, 1]);
        assert!(write_columns(&path, &STUDY_COSTS, wrong).is_err());
        let mut null = cols;
        null[0] = Column::Utf8(vec![None, Some("m".into())]);
        assert!(write_columns(&path, &STUDY_COSTS, null).is_err());
    }
}
