//! How a value of each Rust type a table declaration may use is stored: its column type,
//! nullability and default rule, its Arrow array, and its decoding (with the checks of
//! [`Batch`]). The table generator ([`crate::run_tables`]) picks these by a field's type, so a
//! declaration names only the type.

use crate::StoreError;
use crate::rows::Batch;
use crate::schema::{ColType, ColumnSpec, Rule};
use arrow::array::{
    ArrayRef, BooleanArray, FixedSizeListArray, Float64Array, Int64Array, StringArray, UInt8Array, UInt32Array,
    UInt64Array,
};
use arrow::datatypes::{DataType, Field};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, Requester, Role, TrackStatus};
use std::sync::Arc;

/// A Rust type a table declaration may give a column: what its spec says of it.
pub trait ColumnKind {
    /// The column's type.
    const TY: ColType;
    /// Whether the column may hold nulls (`Option` types).
    const NULLABLE: bool = false;
    /// What every value must be unless the declaration says more.
    const RULE: Rule = Rule::Any;
    /// For a type that stands for several columns (the study tables' metrics), those columns:
    /// the field's own name, unit and description give way to theirs.
    const GROUP: Option<&'static [ColumnSpec]> = None;
    /// How many columns a field of the type is.
    const WIDTH: usize = match Self::GROUP {
        Some(group) => group.len(),
        None => 1,
    };
}

/// A Rust type stored as one column of a run table: its Arrow array and its checked decoding.
pub trait Cell: ColumnKind + Sized {
    /// The Arrow array of the values `get` picks from `rows`.
    fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef;
    /// The values of column `name` of a checked batch.
    fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError>;
}

/// Numbers and flags: one Arrow primitive array each, read by the [`Batch`] accessor of the
/// same name.
macro_rules! plain_cells {
    ($($t:ty => $ty:ident, $array:ty, $read:ident, $rule:expr;)*) => {$(
        impl ColumnKind for $t {
            const TY: ColType = ColType::$ty;
            const RULE: Rule = $rule;
        }
        impl Cell for $t {
            fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef {
                Arc::new(<$array>::from_iter_values(rows.iter().map(|r| *get(r))))
            }
            fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError> {
                b.$read(name)
            }
        }
    )*};
}

plain_cells! {
    u8 => U8, UInt8Array, u8, Rule::Any;
    u32 => U32, UInt32Array, u32, Rule::Any;
    u64 => U64, UInt64Array, u64, Rule::Any;
    i64 => I64, Int64Array, i64, Rule::Any;
    f64 => F64, Float64Array, f64, Rule::Finite;
}

impl ColumnKind for bool {
    const TY: ColType = ColType::Bool;
}
impl Cell for bool {
    fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef {
        Arc::new(BooleanArray::from_iter(rows.iter().map(|r| Some(*get(r)))))
    }
    fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError> {
        b.bool(name)
    }
}

impl ColumnKind for String {
    const TY: ColType = ColType::Utf8;
}
impl Cell for String {
    fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef {
        Arc::new(StringArray::from_iter_values(rows.iter().map(|r| get(r).as_str())))
    }
    fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError> {
        b.str(name)
    }
}

impl ColumnKind for Option<String> {
    const TY: ColType = ColType::Utf8;
    const NULLABLE: bool = true;
}
impl Cell for Option<String> {
    fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef {
        Arc::new(StringArray::from_iter(rows.iter().map(|r| get(r).as_deref())))
    }
    fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError> {
        b.opt_str(name)
    }
}

impl ColumnKind for Option<u64> {
    const TY: ColType = ColType::U64;
    const NULLABLE: bool = true;
}
impl Cell for Option<u64> {
    fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef {
        Arc::new(UInt64Array::from_iter(rows.iter().map(|r| *get(r))))
    }
    fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError> {
        b.opt_u64(name)
    }
}

/// A radar id, `R1`, `R2`, … on disk; each id's text is made once per column.
impl ColumnKind for RadarId {
    const TY: ColType = ColType::Utf8;
    const RULE: Rule = Rule::RadarId;
}
impl Cell for RadarId {
    fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef {
        let mut names: Vec<Option<String>> = Vec::new();
        for r in rows {
            let i = get(r).index();
            if names.len() <= i {
                names.resize(i + 1, None);
            }
            names[i].get_or_insert_with(|| get(r).to_string());
        }
        Arc::new(StringArray::from_iter_values(
            rows.iter().map(|r| names[get(r).index()].as_deref().unwrap_or_default()),
        ))
    }
    fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError> {
        b.radar(name)
    }
}

/// The upper triangle of a 6×6 covariance, row-major: a fixed-size list of 21 float64.
impl ColumnKind for [f64; 21] {
    const TY: ColType = ColType::Cov21;
    const RULE: Rule = Rule::Covariance;
}
impl Cell for [f64; 21] {
    fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef {
        let values = Float64Array::from_iter_values(rows.iter().flat_map(|r| *get(r)));
        let item = Arc::new(Field::new("item", DataType::Float64, false));
        Arc::new(FixedSizeListArray::new(item, 21, Arc::new(values), None))
    }
    /// Slightly indefinite covariances (accepted by the column's check) are read repaired
    /// (`mimo_core::covariance::repair`, docs/design.md §7); valid ones bit for bit.
    fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError> {
        Ok(b.cov21(name)?.iter().map(mimo_core::covariance::repair).collect())
    }
}

/// Enumerations of `mimo-core` declared by `label_enum!`: their labels, one of `LABELS`.
macro_rules! label_cells {
    ($($t:ty),*) => {$(
        impl ColumnKind for $t {
            const TY: ColType = ColType::Utf8;
            const RULE: Rule = Rule::OneOf(&<$t>::LABELS);
        }
        impl Cell for $t {
            fn column<R>(rows: &[R], get: impl Fn(&R) -> &Self) -> ArrayRef {
                Arc::new(StringArray::from_iter_values(rows.iter().map(|r| get(r).as_str())))
            }
            fn read(b: &Batch<'_>, name: &str) -> Result<Vec<Self>, StoreError> {
                b.parsed(name, <$t>::parse, &<$t>::LABELS.join(", "))
            }
        }
    )*};
}

label_cells!(Role, DwellKind, Requester, TrackStatus);

/// Nullable numbers, which only the score and study tables hold (written column by column,
/// [`crate::columns`]).
impl ColumnKind for Option<f64> {
    const TY: ColType = ColType::F64;
    const NULLABLE: bool = true;
    const RULE: Rule = Rule::Finite;
}
impl ColumnKind for Option<u32> {
    const TY: ColType = ColType::U32;
    const NULLABLE: bool = true;
}
