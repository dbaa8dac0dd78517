//! The columns of a dwells file read for the one-pass usage sums ([`crate::dwell_sums`]): from
//! its Parquet pages when it has mimo's layout ([`crate::dwell_pages`]), else with polars, slice
//! by slice, the labels mapped by their string views.
//!
//! (The parquet crate's arrow reader was measured for this and rejected: decoding the plain
//! strings into offset arrays and validating them took more instructions than polars' views,
//! 1 791 M against 1 691 M for the whole `mimo score` of a 1000-s scenario-7 run.)

use crate::dwell_sums::{DWELL_SLICE_ROWS, DwellSums, FilePass, Labels, Rows};
use crate::read::Col;
use polars::prelude::*;
use std::collections::BTreeSet;
use std::path::Path;

/// One dwells file checked and reduced to its usage sums in one pass, read in slices of
/// [`DWELL_SLICE_ROWS`] rows; `None` when a check fails or the file cannot be read (the polars
/// read with its checks then reports it).
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
fn labels_of(df: &DataFrame, name: &str, labels: &mut Labels, out: &mut Vec<u8>) -> Option<()> {
    let ca = df.column(name).ok()?.str().ok()?;
    if ca.null_count() > 0 {
        return None;
    }
    out.clear();
    for arr in ca.downcast_iter() {
        for (i, view) in arr.views().iter().enumerate() {
            let inline = view.is_inline().then(|| view.as_u128());
            let index = match inline.and_then(|v| labels.by_view(v)) {
                Some(index) => index,
                None => labels.index(arr.value(i), inline)?,
            };
            out.push(index);
        }
    }
    Some(())
}

/// A float column's values into `out`; `None` on a null.
fn f64s_of(df: &DataFrame, name: &str, out: &mut Vec<f64>) -> Option<()> {
    let ca = df.column(name).ok()?.f64().ok()?;
    if ca.null_count() > 0 {
        return None;
    }
    out.clear();
    for arr in ca.downcast_iter() {
        out.extend_from_slice(arr.values());
    }
    Some(())
}

/// [`file_sums`] in slices of `slice_rows` rows (the columns converted as the polars read
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
    let (mut radar, mut role, mut kind, mut by) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut run, mut t_s, mut duration_s, mut energy_j) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for first in (0..n_rows).step_by(slice_rows) {
        let len = slice_rows.min(n_rows - first);
        let df = crate::read::read_file_slice_unchecked("dwells", path, cols, Some((first, len))).ok()?;
        let run_ca = df.column("run").ok()?.u32().ok()?;
        if run_ca.null_count() > 0 {
            return None;
        }
        run.clear();
        for arr in run_ca.downcast_iter() {
            run.extend_from_slice(arr.values());
        }
        labels_of(&df, "radar", &mut pass.radar, &mut radar)?;
        labels_of(&df, "role", &mut pass.role, &mut role)?;
        labels_of(&df, "kind", &mut pass.kind, &mut kind)?;
        labels_of(&df, "requested_by", &mut pass.requested_by, &mut by)?;
        f64s_of(&df, "t_s", &mut t_s)?;
        f64s_of(&df, "duration_s", &mut duration_s)?;
        f64s_of(&df, "energy_j", &mut energy_j)?;
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
