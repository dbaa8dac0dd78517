//! The columns of a dwells file read for the one-pass usage sums ([`crate::dwell_sums`]): from
//! its Parquet pages when it has mimo's layout ([`crate::dwell_pages`]), else with the Arrow
//! reader (`crate::read`), slice by slice, each label mapped to its index once per run of equal
//! strings.

use crate::dwell_sums::{DWELL_SLICE_ROWS, DwellSums, FilePass, Labels, Rows, short_key};
use crate::frame::Frame;
use crate::read::Col;
use arrow::array::Array;
use mimo_core::records::{DwellColumns, DwellRow};
use std::collections::BTreeSet;
use std::path::Path;

/// The dwells table's column names (from its declaration).
const D: DwellColumns = DwellRow::COLUMNS;

/// One dwells file checked and reduced to its usage sums in one pass, read in slices of
/// [`DWELL_SLICE_ROWS`] rows; `None` when a check fails or the file cannot be read (the checked
/// read then reports it).
pub(crate) fn file_sums(
    path: &Path,
    cols: &[Col<'_>],
    runs: &BTreeSet<u32>,
    interval_s: f64,
    n_rows: usize,
) -> Option<DwellSums> {
    crate::dwell_pages::file_sums(path, runs, interval_s, DWELL_SLICE_ROWS)
        .or_else(|| file_sums_in_slices(path, cols, runs, interval_s, n_rows, DWELL_SLICE_ROWS))
}

/// A utf8 column's labels into `out`; `None` on a null or a string `labels` refuses.
fn labels_of(df: &Frame, name: &str, labels: &mut Labels, out: &mut Vec<u8>) -> Option<()> {
    let strings = df.strs(name).ok()?;
    if strings.null_count() > 0 {
        return None;
    }
    out.clear();
    let mut last: Option<(&str, u8)> = None;
    for s in strings.iter().flatten() {
        let index = match last {
            Some((l, index)) if l == s => index,
            _ => {
                let key = short_key(s.as_bytes());
                match key.and_then(|k| labels.by_view(k)) {
                    Some(index) => index,
                    None => labels.index(s, key)?,
                }
            }
        };
        last = Some((s, index));
        out.push(index);
    }
    Some(())
}

/// A float column's values into `out`; `None` on a null.
fn f64s_of(df: &Frame, name: &str, out: &mut Vec<f64>) -> Option<()> {
    if df.column(name).ok()?.null_count() > 0 {
        return None;
    }
    out.clear();
    out.extend_from_slice(df.f64s(name).ok()?);
    Some(())
}

/// The rows of `df` (a slice of a dwells file, or all of it) checked and added to `pass`.
pub(crate) fn frame_rows(pass: &mut FilePass<'_>, df: &Frame, bufs: &mut Buffers) -> Option<()> {
    if df.column(D.run).ok()?.null_count() > 0 {
        return None;
    }
    bufs.run.clear();
    bufs.run.extend_from_slice(df.u32s(D.run).ok()?);
    labels_of(df, D.radar, &mut pass.radar, &mut bufs.radar)?;
    labels_of(df, D.role, &mut pass.role, &mut bufs.role)?;
    labels_of(df, D.kind, &mut pass.kind, &mut bufs.kind)?;
    labels_of(df, D.requested_by, &mut pass.requested_by, &mut bufs.by)?;
    f64s_of(df, D.t_s, &mut bufs.t_s)?;
    f64s_of(df, D.duration_s, &mut bufs.duration_s)?;
    f64s_of(df, D.energy_j, &mut bufs.energy_j)?;
    pass.rows(&Rows {
        run: &bufs.run,
        radar: &bufs.radar,
        role: &bufs.role,
        requested_by: &bufs.by,
        t_s: &bufs.t_s,
        duration_s: &bufs.duration_s,
        energy_j: &bufs.energy_j,
    })
}

/// The columns of one slice, reused from slice to slice.
#[derive(Default)]
pub(crate) struct Buffers {
    run: Vec<u32>,
    radar: Vec<u8>,
    role: Vec<u8>,
    kind: Vec<u8>,
    by: Vec<u8>,
    t_s: Vec<f64>,
    duration_s: Vec<f64>,
    energy_j: Vec<f64>,
}

/// [`file_sums`] in slices of `slice_rows` rows (the columns converted as `crate::read`
/// converts them).
pub(crate) fn file_sums_in_slices(
    path: &Path,
    cols: &[Col<'_>],
    runs: &BTreeSet<u32>,
    interval_s: f64,
    n_rows: usize,
    slice_rows: usize,
) -> Option<DwellSums> {
    let slice_rows = slice_rows.max(1);
    let mut pass = FilePass::new(runs, interval_s, slice_rows);
    let mut bufs = Buffers::default();
    for first in (0..n_rows).step_by(slice_rows) {
        let len = slice_rows.min(n_rows - first);
        let df = crate::read::read_file_slice_unchecked(DwellRow::TABLE, path, cols, Some((first, len))).ok()?;
        frame_rows(&mut pass, &df, &mut bufs)?;
    }
    Some(pass.finish())
}
