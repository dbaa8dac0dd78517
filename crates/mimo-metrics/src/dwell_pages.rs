//! The usage columns of a dwells file decoded straight from its Parquet pages, for the one-pass
//! usage sums ([`crate::dwell_sums`]), by the store's page decoder
//! ([`mimo_store::page_columns`], which lives beside the writer settings it depends on and is
//! checked against them). Each label is mapped to its index as its bytes are read, so no string
//! array is built. A file of another layout gives `None`, and it is read with the Arrow reader
//! instead ([`crate::dwell_read`]), as is a file whose values break a check.

use crate::dwell_sums::{DwellSums, FilePass, Labels, Rows};
use mimo_core::records::{DwellColumns, DwellRow};
use mimo_store::page_columns::{PageFile, PageRowGroup};
use std::collections::BTreeSet;
use std::path::Path;

/// The dwells table's column names (from its declaration).
const D: DwellColumns = DwellRow::COLUMNS;

/// The columns read, in this order.
const COLUMNS: [&str; 8] = [D.run, D.radar, D.role, D.kind, D.requested_by, D.t_s, D.duration_s, D.energy_j];

/// A utf8 column mapped to label indices; `None` on a string `labels` refuses (or that is not
/// UTF-8).
fn labels(rg: &PageRowGroup<'_>, col: usize, labels: &mut Labels, out: &mut Vec<u8>) -> Option<()> {
    out.clear();
    rg.strs(col, |bytes| {
        let key = crate::dwell_sums::short_key(bytes);
        let index = match key.and_then(|k| labels.by_view(k)) {
            Some(index) => index,
            None => labels.index(std::str::from_utf8(bytes).ok()?, key)?,
        };
        out.push(index);
        Some(())
    })
}

/// One dwells file checked and reduced to its usage sums from its pages, the sums split every
/// `slice_rows` rows as [`crate::dwell_read`] splits them; `None` when the file has another
/// layout or a check fails.
pub(crate) fn file_sums(path: &Path, runs: &BTreeSet<u32>, interval_s: f64, slice_rows: usize) -> Option<DwellSums> {
    let file = PageFile::open(path, &COLUMNS)?;
    let end_s = mimo_store::run_window::run_end_s(path);
    let mut pass = FilePass::new(runs, interval_s, slice_rows);
    let (mut radar, mut role, mut kind, mut by) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut run, mut t_s, mut duration_s, mut energy_j) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for g in 0..file.num_row_groups() {
        let rg = file.row_group(g)?;
        rg.u32s(0, &mut run)?;
        labels(&rg, 1, &mut pass.radar, &mut radar)?;
        labels(&rg, 2, &mut pass.role, &mut role)?;
        labels(&rg, 3, &mut pass.kind, &mut kind)?;
        labels(&rg, 4, &mut pass.requested_by, &mut by)?;
        rg.f64s(5, &mut t_s)?;
        // A time after the run's end is a check failing: the Arrow reader reports it.
        if end_s.is_some_and(|end| mimo_store::run_window::first_after_end(&t_s, end, 0).is_some()) {
            return None;
        }
        rg.f64s(6, &mut duration_s)?;
        rg.f64s(7, &mut energy_j)?;
        let n = rg.num_rows()?;
        if run.len() != n || kind.len() != n {
            return None;
        }
        pass.rows(&Rows {
            run: &run,
            radar: &radar,
            role: &role,
            requested_by: &by,
            t_s: &t_s,
            duration_s: &duration_s,
            energy_j: &energy_j,
        })?;
    }
    Some(pass.finish())
}
