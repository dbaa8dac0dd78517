//! Errors of the metrics engine. Each names the file, the column and what was expected, so the
//! CLI can print it on one `error:` line.

use std::path::PathBuf;
use thiserror::Error;

/// Everything that can go wrong while scoring.
#[derive(Debug, Error)]
pub enum MetricsError {
    /// A table has no Parquet file at all (directory missing or empty, or a listed file absent).
    #[error("missing {table} table: {}: {detail}", path.display())]
    MissingTable {
        /// Which table (`truth`, `tracks`, `dwells`).
        table: &'static str,
        /// The file or directory at fault.
        path: PathBuf,
        /// What the reader or the system reported.
        detail: String,
    },

    /// A file could not be opened or is not readable Parquet.
    #[error("{}: cannot read the {table} table as Parquet: {detail}", path.display())]
    Read {
        /// Which table (`truth`, `tracks`, `dwells`).
        table: &'static str,
        /// The file or directory at fault.
        path: PathBuf,
        /// What the reader or the system reported.
        detail: String,
    },

    /// A required column is absent.
    #[error("{}: {table} table has no column `{column}` (expected {expected})", path.display())]
    MissingColumn {
        /// Which table (`truth`, `tracks`, `dwells`).
        table: &'static str,
        /// The file or directory at fault.
        path: PathBuf,
        /// The column at fault.
        column: &'static str,
        /// What the column should hold.
        expected: &'static str,
    },

    /// A column has a type that cannot hold what the column means.
    #[error("{}: {table} column `{column}` has type {found}, expected {expected}", path.display())]
    ColumnType {
        /// Which table (`truth`, `tracks`, `dwells`).
        table: &'static str,
        /// The file or directory at fault.
        path: PathBuf,
        /// The column at fault.
        column: &'static str,
        /// What the column should hold.
        expected: &'static str,
        /// The type found.
        found: String,
    },

    /// A required value is null.
    #[error("{}: {table} column `{column}` is null at row {row}", path.display())]
    Null {
        /// Which table (`truth`, `tracks`, `dwells`).
        table: &'static str,
        /// The file or directory at fault.
        path: PathBuf,
        /// The column at fault.
        column: &'static str,
        /// Row index, 0-based, in the table as read (the files of the table in name order).
        row: usize,
    },

    /// A float is NaN or infinite where a finite number is required (positions, velocities, times).
    #[error("{}: {table} column `{column}` is {value} at row {row} (expected a finite number)", path.display())]
    NonFinite {
        /// Which table (`truth`, `tracks`, `dwells`).
        table: &'static str,
        /// The file or directory at fault.
        path: PathBuf,
        /// The column at fault.
        column: &'static str,
        /// Row index, 0-based, in the table as read (the files of the table in name order).
        row: usize,
        /// The value found.
        value: f64,
    },

    /// A value is out of its domain (unknown status, negative energy, run absent from truth, …).
    #[error("{}: {table} column `{column}` has the invalid value `{value}` at row {row} (expected {expected})", path.display())]
    InvalidValue {
        /// Which table (`truth`, `tracks`, `dwells`).
        table: &'static str,
        /// The file at fault.
        path: PathBuf,
        /// The column at fault.
        column: &'static str,
        /// Row index, 0-based, in the table as read (the files of the table in name order).
        row: usize,
        /// The value found.
        value: String,
        /// What the column should hold.
        expected: String,
    },

    /// A row breaks a table rule (`mimo_core::table_rules`): a repeated id, a time out of order,
    /// a run other than the file's.
    #[error("{}: {table} column `{column}` row {row}: {why}", path.display())]
    BrokenRule {
        /// Which table (`truth`, `tracks`, `dwells`).
        table: &'static str,
        /// The file at fault.
        path: PathBuf,
        /// The column at fault.
        column: &'static str,
        /// Row index, 0-based, in the file.
        row: usize,
        /// Which rule the row breaks.
        why: String,
    },

    /// A table file fails the store's checks (`mimo_store::checked`): not a table of this name
    /// and schema version, a column missing or of another type, a value breaking its column's
    /// rule, a row of another run than the file's.
    #[error(transparent)]
    Table(#[from] mimo_store::StoreError),

    /// A scoring option is out of range.
    #[error("invalid scoring option {option} = {value}: {expected}")]
    InvalidOption {
        /// The option as the user gives it.
        option: &'static str,
        /// The value given.
        value: String,
        /// The range or form allowed.
        expected: &'static str,
    },

    /// Writing an output failed.
    #[error("cannot write {}: {detail}", path.display())]
    Write {
        /// The file that could not be written.
        path: PathBuf,
        /// What the reader or the system reported.
        detail: String,
    },

    /// An internal table operation failed (a bug, not bad input).
    #[error("internal table operation failed ({context}): {detail}")]
    Internal {
        /// The operation that failed.
        context: &'static str,
        /// What the reader or the system reported.
        detail: String,
    },
}

impl MetricsError {
    /// Is this error caused by the input (exit status 2) rather than by the machine (exit status 1)?
    pub fn is_bad_input(&self) -> bool {
        match self {
            MetricsError::Table(e) => e.is_input_error(),
            MetricsError::Write { .. } | MetricsError::Internal { .. } => false,
            _ => true,
        }
    }
}
