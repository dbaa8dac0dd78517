//! Table rules checked on read (docs/design.md §7): what a table keeps beyond its schema — unique
//! ids, ordered times, one run per file — as defined once in `mimo_core::table_rules`. Every
//! typed read ([`crate::read_table`]) checks them, so `mimo track`, `mimo plot` and studies refuse
//! an inconsistent table with the file, column and row, before using a value of it.

use crate::StoreError;
use mimo_core::records::*;
use mimo_core::table_rules::{
    Key2, TRACK_OUT_OF_SEQUENCE_S, Violation, runs_match, times_nearly_ordered_per_key, times_ordered_per_key,
    track_row_order, track_rows_orderable, unique,
};
use std::path::Path;

/// The rules of one table's rows (the rows of one file).
pub trait RowInvariants: Sized {
    /// The first rule a file's rows break, if any.
    fn check_rows(rows: &[Self]) -> Result<(), Violation>;
    /// Each row's run.
    fn run_of(row: &Self) -> u32;
}

impl RowInvariants for TruthRow {
    fn check_rows(rows: &[Self]) -> Result<(), Violation> {
        let t: Vec<f64> = rows.iter().map(|r| r.t_s).collect();
        times_ordered_per_key(rows.iter().map(|r| Key2(r.run, r.target.as_str())), &t, true, TruthRow::COLUMNS.target)
    }
    fn run_of(row: &Self) -> u32 {
        row.run
    }
}

impl RowInvariants for DwellRow {
    fn check_rows(rows: &[Self]) -> Result<(), Violation> {
        unique(rows.iter().map(|r| Key2(r.run, r.dwell_id)), DwellRow::COLUMNS.dwell_id)?;
        let t: Vec<f64> = rows.iter().map(|r| r.t_s).collect();
        times_ordered_per_key(rows.iter().map(|r| Key2(r.run, r.radar)), &t, false, DwellRow::COLUMNS.radar)
    }
    fn run_of(row: &Self) -> u32 {
        row.run
    }
}

impl RowInvariants for VoltageRow {
    fn check_rows(_: &[Self]) -> Result<(), Violation> {
        Ok(())
    }
    fn run_of(row: &Self) -> u32 {
        row.run
    }
}

impl RowInvariants for PrimitiveRow {
    fn check_rows(_: &[Self]) -> Result<(), Violation> {
        Ok(())
    }
    fn run_of(row: &Self) -> u32 {
        row.run
    }
}

impl RowInvariants for BiasRow {
    fn check_rows(rows: &[Self]) -> Result<(), Violation> {
        unique(rows.iter().map(|r| Key2(r.run, r.radar)), BiasRow::COLUMNS.radar)
    }
    fn run_of(row: &Self) -> u32 {
        row.run
    }
}

impl RowInvariants for RegistrationRow {
    fn check_rows(_rows: &[Self]) -> Result<(), Violation> {
        // A test article may report its estimate as often as it likes: no key is unique.
        Ok(())
    }
    fn run_of(row: &Self) -> u32 {
        row.run
    }
}

impl RowInvariants for MeasurementRow {
    fn check_rows(rows: &[Self]) -> Result<(), Violation> {
        unique(rows.iter().map(|r| Key2(r.run, r.meas_id)), MeasurementRow::COLUMNS.meas_id)
    }
    fn run_of(row: &Self) -> u32 {
        row.run
    }
}

impl RowInvariants for TrackRow {
    fn check_rows(rows: &[Self]) -> Result<(), Violation> {
        let t: Vec<f64> = rows.iter().map(|r| r.t_s).collect();
        let keys = || rows.iter().map(|r| Key2(r.run, r.track_id));
        times_nearly_ordered_per_key(keys(), &t, TRACK_OUT_OF_SEQUENCE_S, "track")?;
        let rank: Vec<u64> =
            rows.iter().map(|r| track_row_order(r.n_updates, r.status == TrackStatus::Deleted)).collect();
        track_rows_orderable(keys(), &t, &rank)
    }
    fn run_of(row: &Self) -> u32 {
        row.run
    }
}

/// The run of a file named `run-K.parquet`, if it is named so.
pub fn file_run(path: &Path) -> Option<u32> {
    mimo_core::table_rules::run_of_file_name(path.file_name()?.to_str()?)
}

/// Check a file's rows: the table's rules, and (for `run-K.parquet`) that every row is run K.
pub fn check<R: RowInvariants>(path: &Path, rows: &[R]) -> Result<(), StoreError> {
    let to_err =
        |v: Violation| StoreError::BadRow { file: path.to_path_buf(), column: v.column, row: v.row, why: v.why };
    if let Some(k) = file_run(path) {
        let runs: Vec<u32> = rows.iter().map(R::run_of).collect();
        runs_match(&runs, k).map_err(to_err)?;
    }
    R::check_rows(rows).map_err(to_err)
}
