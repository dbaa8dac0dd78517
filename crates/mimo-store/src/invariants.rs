//! Table rules checked on read (docs/design.md §7): what a table keeps beyond its schema — unique
//! ids, ordered times, one run per file — as defined once in `mimo_core::table_rules`. Every
//! typed read ([`crate::table_chunks::TableChunks`], and [`crate::read_table`] through it) checks
//! them chunk by chunk as the rows stream by, so `mimo track`, `mimo plot`, `mimo score` and
//! studies refuse an inconsistent table with the file, column and row, before using a value of
//! it; the row named is the one a check of the whole file names (the rules' own tests).

use crate::StoreError;
use crate::rows::Batch;
use mimo_core::records::*;
use mimo_core::table_rules::{
    Key2, OrderableRule, TRACK_OUT_OF_SEQUENCE_S, TimeRule, UniqueRule, Violation, track_row_order,
};
use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

/// The rules of one table's rows (the rows of one file), checked as a reader streams them.
///
/// The rules read the key columns of each checked batch ([`Batch`]), not typed rows, so that
/// the reader of typed rows and the reader of columns ([`crate::table_chunks::TableChunks`]'s
/// `next_chunk` and `next_batch`) check them with the same code, the second without building a
/// row.
pub trait RowInvariants: Sized {
    /// What the rules keep of the rows read so far of one file (latest times, keys seen).
    type Rules: Default;
    /// The first rule the rows of `b` break, if any: they are rows `first_row..` of the file and
    /// follow the rows `rules` has seen; `b`'s values were checked ([`Batch::check_from`]).
    fn check_chunk(rules: &mut Self::Rules, first_row: usize, b: &Batch<'_>) -> Result<(), StoreError>;
}

/// A table without rules between rows.
#[derive(Default)]
pub struct NoRules;

/// A target name shared by the truth rule's keys: one allocation a target, not a row, and equal
/// keys are one pointer ([`Names`] gives each name once), so a key compares in one instruction.
#[derive(Clone)]
pub struct Name(Arc<str>);

impl PartialEq for Name {
    fn eq(&self, other: &Name) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Eq for Name {}

impl std::hash::Hash for Name {
    fn hash<H: std::hash::Hasher>(&self, h: &mut H) {
        std::ptr::hash(Arc::as_ptr(&self.0).cast::<u8>(), h);
    }
}

impl std::fmt::Display for Name {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Each target name once. The truth is written time by time, its targets in the same order each
/// time: the name after the previous row's is tried first, the names' map only when it fails.
#[derive(Default)]
struct Names {
    names: Vec<Name>,
    index: HashMap<Arc<str>, usize>,
    last: usize,
}

impl Names {
    fn of(&mut self, name: &str) -> Name {
        let n = self.names.len();
        let next = if n == 0 { 0 } else { (self.last + 1) % n };
        let i = match self.names.get(next) {
            Some(guess) if *guess.0 == *name => next,
            _ => match self.index.get(name) {
                Some(&i) => i,
                None => {
                    let s: Arc<str> = Arc::from(name);
                    self.index.insert(s.clone(), n);
                    self.names.push(Name(s));
                    n
                }
            },
        };
        self.last = i;
        self.names[i].clone()
    }
}

/// The truth's rule: times increasing within each (run, target).
pub struct TruthRules {
    names: Names,
    times: TimeRule<'static, Key2<u32, Name>>,
}

impl Default for TruthRules {
    fn default() -> Self {
        TruthRules { names: Names::default(), times: TimeRule::ordered(true, TruthRow::COLUMNS.target) }
    }
}

impl RowInvariants for TruthRow {
    type Rules = TruthRules;
    fn check_chunk(rules: &mut TruthRules, first_row: usize, b: &Batch<'_>) -> Result<(), StoreError> {
        let c = TruthRow::COLUMNS;
        let (run, target, t) = (b.u32_values(c.run)?, b.utf8(c.target)?, b.f64_values(c.t_s)?);
        for (i, (&run, &t)) in run.iter().zip(t).enumerate() {
            let name = rules.names.of(target.value(i));
            rules.times.check(first_row + i, Key2(run, name), t).map_err(|v| violation_error(b.file, v))?;
        }
        Ok(())
    }
}

/// The dwells' rules: `dwell_id` unique within a run, start times non-decreasing per radar.
pub struct DwellRules {
    radars: Names,
    ids: UniqueRule<Key2<u32, u64>>,
    times: TimeRule<'static, Key2<u32, Name>>,
}

impl Default for DwellRules {
    fn default() -> Self {
        DwellRules {
            radars: Names::default(),
            ids: UniqueRule::new(DwellRow::COLUMNS.dwell_id),
            times: TimeRule::ordered(false, DwellRow::COLUMNS.radar),
        }
    }
}

impl RowInvariants for DwellRow {
    type Rules = DwellRules;
    fn check_chunk(rules: &mut DwellRules, first_row: usize, b: &Batch<'_>) -> Result<(), StoreError> {
        let c = DwellRow::COLUMNS;
        let (run, id, radar, t) =
            (b.u32_values(c.run)?, b.u64_values(c.dwell_id)?, b.utf8(c.radar)?, b.f64_values(c.t_s)?);
        let err = |v| violation_error(b.file, v);
        rules.ids.check(first_row, run.iter().zip(id).map(|(&r, &d)| Key2(r, d))).map_err(err)?;
        for (i, (&run, &t)) in run.iter().zip(t).enumerate() {
            let name = rules.radars.of(radar.value(i));
            rules.times.check(first_row + i, Key2(run, name), t).map_err(err)?;
        }
        Ok(())
    }
}

impl RowInvariants for VoltageRow {
    type Rules = NoRules;
    fn check_chunk(_: &mut NoRules, _: usize, _: &Batch<'_>) -> Result<(), StoreError> {
        Ok(())
    }
}

impl RowInvariants for PrimitiveRow {
    type Rules = NoRules;
    fn check_chunk(_: &mut NoRules, _: usize, _: &Batch<'_>) -> Result<(), StoreError> {
        Ok(())
    }
}

/// The biases' rule: one row per (run, radar).
pub struct BiasRules(UniqueRule<Key2<u32, String>>);

impl Default for BiasRules {
    fn default() -> Self {
        BiasRules(UniqueRule::new(BiasRow::COLUMNS.radar))
    }
}

impl RowInvariants for BiasRow {
    type Rules = BiasRules;
    fn check_chunk(rules: &mut BiasRules, first_row: usize, b: &Batch<'_>) -> Result<(), StoreError> {
        let c = BiasRow::COLUMNS;
        let (run, radar) = (b.u32_values(c.run)?, b.utf8(c.radar)?);
        let keys = run.iter().enumerate().map(|(i, &r)| Key2(r, radar.value(i).to_string()));
        rules.0.check(first_row, keys).map_err(|v| violation_error(b.file, v))
    }
}

impl RowInvariants for RegistrationRow {
    // A test article may report its estimate as often as it likes: no key is unique.
    type Rules = NoRules;
    fn check_chunk(_: &mut NoRules, _: usize, _: &Batch<'_>) -> Result<(), StoreError> {
        Ok(())
    }
}

/// The measurements' rule: `meas_id` unique within a run.
pub struct MeasurementRules(UniqueRule<Key2<u32, u64>>);

impl Default for MeasurementRules {
    fn default() -> Self {
        MeasurementRules(UniqueRule::new(MeasurementRow::COLUMNS.meas_id))
    }
}

impl RowInvariants for MeasurementRow {
    type Rules = MeasurementRules;
    fn check_chunk(rules: &mut MeasurementRules, first_row: usize, b: &Batch<'_>) -> Result<(), StoreError> {
        let c = MeasurementRow::COLUMNS;
        let (run, id) = (b.u32_values(c.run)?, b.u64_values(c.meas_id)?);
        rules.0.check(first_row, run.iter().zip(id).map(|(&r, &m)| Key2(r, m))).map_err(|v| violation_error(b.file, v))
    }
}

/// The tracks' rules: no row far before its track's latest earlier row, and rows of one track at
/// one time that the table can order.
pub struct TrackRules {
    times: TimeRule<'static, Key2<u32, u64>>,
    orderable: OrderableRule<Key2<u32, u64>>,
}

impl Default for TrackRules {
    fn default() -> Self {
        TrackRules {
            times: TimeRule::nearly_ordered(TRACK_OUT_OF_SEQUENCE_S, "track"),
            orderable: OrderableRule::default(),
        }
    }
}

impl RowInvariants for TrackRow {
    type Rules = TrackRules;
    fn check_chunk(rules: &mut TrackRules, first_row: usize, b: &Batch<'_>) -> Result<(), StoreError> {
        let c = TrackRow::COLUMNS;
        let (run, id, t) = (b.u32_values(c.run)?, b.u64_values(c.track_id)?, b.f64_values(c.t_s)?);
        let (n_updates, status) = (b.u32_values(c.n_updates)?, b.utf8(c.status)?);
        let err = |v| violation_error(b.file, v);
        for (i, ((&run, &id), &t)) in run.iter().zip(id).zip(t).enumerate() {
            rules.times.check(first_row + i, Key2(run, id), t).map_err(err)?;
        }
        let deleted = TrackStatus::Deleted.as_str();
        for (i, ((&run, &id), &t)) in run.iter().zip(id).zip(t).enumerate() {
            let rank = track_row_order(n_updates[i], status.value(i) == deleted);
            rules.orderable.check(first_row + i, Key2(run, id), t, rank).map_err(err)?;
        }
        Ok(())
    }
}

/// The run of a file named `run-K.parquet`, if it is named so.
pub fn file_run(path: &Path) -> Option<u32> {
    mimo_core::table_rules::run_of_file_name(path.file_name()?.to_str()?)
}

/// A broken rule as the store's error, naming the file.
pub fn violation_error(path: &Path, v: Violation) -> StoreError {
    StoreError::BadRow { file: path.to_path_buf(), column: v.column, row: v.row, why: v.why }
}
