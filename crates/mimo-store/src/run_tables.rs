//! The run tables (docs/design.md §3), each expanded from its one declaration in
//! `mimo_core::records` (see `mimo_core::table_decl`): the [`TableSpec`](crate::schema::TableSpec)
//! (names, types, nullability, units, rules, descriptions) and the [`TableRow`](crate::rows::TableRow)
//! conversions to record batches and back.

use mimo_core::records::{
    BiasRow, DwellRow, MeasurementRow, PrimitiveRow, RegistrationRow, TrackRow, TruthRow, VoltageRow,
};

/// A column's rule: the declaration's, else its type's default.
#[macro_export]
#[doc(hidden)]
macro_rules! column_rule {
    ($ty:ty) => {
        <$ty as $crate::cell::ColumnKind>::RULE
    };
    ($ty:ty, $rule:ident) => {
        $crate::schema::Rule::$rule
    };
}

/// The columns of a declaration's fields (see `mimo_core::table_decl`), as an array expression:
/// each field's column ([`ColumnSpec`](crate::schema::ColumnSpec): type, nullability and default
/// rule from its Rust type, [`crate::cell::ColumnKind`]), or its type's group of columns.
#[macro_export]
#[doc(hidden)]
macro_rules! declared_columns {
    ([$([$(#[$fmeta:meta])*] $field:ident ($ty:ty) ($unit:literal, $desc:literal $(, $rule:ident)?) [$($tag:ident)*])*]) => {
        $crate::schema::flatten::<{ 0 $(+ <$ty as $crate::cell::ColumnKind>::WIDTH)* }>(&[$((
            <$ty as $crate::cell::ColumnKind>::GROUP,
            $crate::schema::ColumnSpec {
                name: stringify!($field),
                ty: <$ty as $crate::cell::ColumnKind>::TY,
                nullable: <$ty as $crate::cell::ColumnKind>::NULLABLE,
                unit: $unit,
                description: $desc,
                rule: $crate::column_rule!($ty $(, $rule)?),
                storage: &[$($crate::schema::Storage::$tag),*],
            },
        )),*])
    };
}

/// The spec of a table declaration (see `mimo_core::table_decl`): a `pub const` named by the
/// declaration.
#[macro_export]
macro_rules! table_spec {
    (
        [$(#[$smeta:meta])*] $row:ident $cols:ident $spec:ident $table:literal $tdesc:literal
        [$($fields:tt)*]
    ) => {
        #[doc = concat!("`", $table, "`: ", $tdesc)]
        pub const $spec: $crate::schema::TableSpec = $crate::schema::TableSpec {
            name: $table,
            description: $tdesc,
            columns: &$crate::declared_columns!([$($fields)*]),
        };
    };
}

/// The spec and the Arrow conversions of a run table declaration: [`table_spec!`] and
/// [`TableRow`](crate::rows::TableRow) for its record struct.
macro_rules! run_table {
    (
        [$(#[$smeta:meta])*] $row:ident $cols:ident $spec:ident $table:literal $tdesc:literal
        [$([$(#[$fmeta:meta])*] $field:ident ($ty:ty) ($unit:literal, $desc:literal $(, $rule:ident)?) [$($tag:ident)*])*]
    ) => {
        $crate::table_spec! {
            [$(#[$smeta])*] $row $cols $spec $table $tdesc
            [$([$(#[$fmeta])*] $field ($ty) ($unit, $desc $(, $rule)?) [$($tag)*])*]
        }

        impl $crate::rows::TableRow for $row {
            const SPEC: $crate::schema::TableSpec = $spec;
            fn to_columns(rows: &[Self]) -> Vec<arrow::array::ArrayRef> {
                vec![$(<$ty as $crate::cell::Cell>::column(rows, |r| &r.$field)),*]
            }
            fn from_batch(b: &$crate::rows::Batch<'_>) -> Result<Vec<Self>, $crate::StoreError> {
                $(let mut $field = <$ty as $crate::cell::Cell>::read(b, stringify!($field))?.into_iter();)*
                Ok((0..b.batch.num_rows()).map_while(|_| Some($row { $($field: $field.next()?),* })).collect())
            }
        }
    };
}

mimo_core::truth_table!(run_table);
mimo_core::dwells_table!(run_table);
mimo_core::voltages_table!(run_table);
mimo_core::primitives_table!(run_table);
mimo_core::measurements_table!(run_table);
mimo_core::tracks_table!(run_table);
mimo_core::biases_table!(run_table);
mimo_core::registration_table!(run_table);
