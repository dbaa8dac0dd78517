//! How a table is declared once (docs/architecture.md, "Tables").
//!
//! A table's declaration is a `macro_rules!` macro that hands its one column list to a generator
//! macro (the "callback" style of arrow-rs' and rerun's schema code), through
//! [`table_decl!`](crate::table_decl), which parses the grammar below once. The declaration names the
//! record struct, the columns' field names (which are the column names), Rust types, units,
//! meanings and any rule stricter than the type's default. Each crate expands it with its own
//! generator:
//!
//! * here, [`record_struct!`](crate::record_struct) makes the record struct, its
//!   `COLUMNS` (a struct of the column names, one field per column, so readers name a column
//!   through the declaration) and `COLUMN_NAMES` (in file order);
//! * in `mimo-store`, the spec (`TableSpec`: names, types, nullability, units, rules,
//!   descriptions) and the Arrow conversions both ways.
//!
//! The declaration's grammar, which every generator accepts:
//!
//! ```text
//! /// docs of the record struct
//! #[derive(..)]
//! pub struct RowType / ColumnNamesType in SPEC_CONST = "table_name": "table description" {
//!     /// docs of the field
//!     field_name: RustType => ("unit", "description" [, RuleOverride]) [as Storage [+ Storage]…],
//!     ..$crate::fragment_macro,
//!     …
//! }
//! ```
//!
//! `as Storage` tags say how the column is stored, beyond its type: the variants of
//! `mimo_store::schema::Storage` (`Delta` for ids counting up row by row, `Split` for floats
//! whose values are nearly all distinct, `Uncompressed` for values the compressor cannot shrink,
//! `PageStats` for a float column a reader may filter on). They change the file's bytes, never
//! its columns or values; the record struct ignores them.
//!
//! A field's type may stand for several columns (in `mimo-store`, a type whose
//! `ColumnKind::GROUP` lists them: the study tables' identifying columns and metrics); its
//! columns then take the field's place, `COLUMNS` holds the field's name and `COLUMN_NAMES`
//! (made by `mimo_store::column_rows!` for such tables) the group's columns.
//!
//! `..path::to_fragment,` splices columns shared by several tables (the study tables' identifying
//! columns) in place: the fragment is a macro that takes `[head] [fields before] [fields after]`
//! and hands `table_decl!` back `head { before, its columns, after }`, so a shared column is
//! declared once, in its fragment. A fragment is a `#[macro_export]` macro of one rule:
//!
//! ```text
//! ([$($head:tt)*] [$($before:tt)*] [$($after:tt)*]) => {
//!     $crate::core_crate::table_decl! { $($head)* { $($before)* column: Type => ("unit", "description"), … $($after)* } }
//! };
//! ```
//!
//! Enumerations stored as labels are declared once by [`label_enum!`](crate::label_enum): the
//! variants with their on-disk labels, from which come `LABELS`, `as_str` and `parse`.

/// Parse a table declaration (the grammar of the [module docs](self)) and hand it to the
/// generator `$gen` in one normal form, which every generator matches:
///
/// ```text
/// [struct attributes] Row Columns SPEC "table" "description"
///     [[field attributes] field (Type) ("unit", "description" [, Rule]) [Storage…]…]
/// ```
#[macro_export]
macro_rules! table_decl {
    // A fragment marker: hand the fields before it and after it to the fragment.
    (@splice [$($head:tt)*] [$($done:tt)*] .. $frag:path , $($rest:tt)*) => {
        $frag! { [$($head)*] [$($done)*] [$($rest)*] }
    };
    // A field before the first marker: carry it over.
    (
        @splice [$($head:tt)*] [$($done:tt)*]
        $(#[$fmeta:meta])* $field:ident : $ty:ty => $spec:tt $(as $tag:ident $(+ $more:ident)*)? , $($rest:tt)*
    ) => {
        $crate::table_decl! {
            @splice [$($head)*] [$($done)* $(#[$fmeta])* $field : $ty => $spec $(as $tag $(+ $more)*)? ,] $($rest)*
        }
    };
    (
        $gen:path;
        $(#[$smeta:meta])*
        pub struct $row:ident / $cols:ident in $spec:ident = $table:literal : $tdesc:literal {
            $(
                $(#[$fmeta:meta])*
                $field:ident : $ty:ty => ($unit:literal, $desc:literal $(, $rule:ident)?) $(as $tag:ident $(+ $more:ident)*)?
            ),* $(,)?
        }
    ) => {
        $gen! {
            [$(#[$smeta])*] $row $cols $spec $table $tdesc
            [$([$(#[$fmeta])*] $field ($ty) ($unit, $desc $(, $rule)?) [$($tag $($more)*)?])*]
        }
    };
    // A declaration with fragment markers: splice them first.
    (
        $gen:path;
        $(#[$smeta:meta])*
        pub struct $row:ident / $cols:ident in $spec:ident = $table:literal : $tdesc:literal { $($body:tt)* }
    ) => {
        $crate::table_decl! {
            @splice [$gen; $(#[$smeta])* pub struct $row / $cols in $spec = $table : $tdesc] [] $($body)*
        }
    };
}

/// Make the record struct of a table declaration (see the [module docs](self)), with its
/// column names. `@struct` makes all but `COLUMN_NAMES`, for a generator whose fields may stand
/// for several columns (`mimo_store`'s study tables).
#[macro_export]
macro_rules! record_struct {
    (
        @struct [$(#[$smeta:meta])*] $row:ident $cols:ident $spec:ident $table:literal $tdesc:literal
        [$([$(#[$fmeta:meta])*] $field:ident ($ty:ty) ($unit:literal, $desc:literal $(, $rule:ident)?) [$($tag:ident)*])*]
    ) => {
        $(#[$smeta])*
        pub struct $row {
            $(
                $(#[$fmeta])*
                #[doc = concat!("\n\nColumn `", stringify!($field), "` (unit \"", $unit, "\"): ", $desc, ".")]
                pub $field: $ty,
            )*
        }

        #[doc = concat!("The column names of the `", $table, "` table, one field per column, in file order.")]
        #[derive(Debug, Clone, Copy, PartialEq, Eq)]
        pub struct $cols {
            $(
                #[doc = concat!("`", stringify!($field), "`: ", $desc)]
                pub $field: &'static str,
            )*
        }

        impl $row {
            /// The table's name: its directory in a run directory and its `mimo.table` metadata.
            pub const TABLE: &'static str = $table;
            /// The table's column names, one field per column.
            pub const COLUMNS: $cols = $cols { $($field: stringify!($field)),* };
        }
    };
    (
        [$(#[$smeta:meta])*] $row:ident $cols:ident $spec:ident $table:literal $tdesc:literal
        [$([$(#[$fmeta:meta])*] $field:ident ($ty:ty) ($unit:literal, $desc:literal $(, $rule:ident)?) [$($tag:ident)*])*]
    ) => {
        $crate::record_struct! {
            @struct [$(#[$smeta])*] $row $cols $spec $table $tdesc
            [$([$(#[$fmeta])*] $field ($ty) ($unit, $desc $(, $rule)?) [$($tag)*])*]
        }

        impl $row {
            /// The table's column names in file order.
            pub const COLUMN_NAMES: &'static [&'static str] = &[$(stringify!($field)),*];
        }
    };
}

/// Declare an enumeration stored as labels: the enum, its variants' on-disk labels in
/// declaration order (`LABELS`), `as_str` and `parse`.
#[macro_export]
macro_rules! label_enum {
    (
        $(#[$meta:meta])*
        pub enum $name:ident {
            $(
                $(#[$vmeta:meta])*
                $variant:ident = $label:literal
            ),* $(,)?
        }
    ) => {
        $(#[$meta])*
        pub enum $name {
            $(
                $(#[$vmeta])*
                $variant,
            )*
        }

        impl $name {
            /// Every on-disk label, in declaration order (the values the table's column may hold).
            pub const LABELS: [&'static str; [$($label),*].len()] = [$($label),*];
            /// Every variant, in declaration order (the order of [`Self::LABELS`]).
            pub const ALL: [$name; [$($label),*].len()] = [$($name::$variant),*];
            /// The on-disk label.
            pub fn as_str(self) -> &'static str {
                match self {
                    $($name::$variant => $label,)*
                }
            }
            /// The value whose label is `s`; `None` for any string not in [`Self::LABELS`].
            pub fn parse(s: &str) -> Option<$name> {
                match s {
                    $($label => Some($name::$variant),)*
                    _ => None,
                }
            }
        }
    };
}
