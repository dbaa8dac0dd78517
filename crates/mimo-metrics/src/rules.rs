//! The table rules of `mimo_core::table_rules` (docs/design.md §7), checked on each file this
//! crate reads before its rows are sorted and stacked: a tracks table whose times run backwards
//! would otherwise be re-sorted into a different (and wrong) track history, silently.

use crate::MetricsError;
use crate::load::{f64s, u32s, u64s};
use mimo_core::table_rules::{
    Key2, TRACK_OUT_OF_SEQUENCE_S, Violation, times_nearly_ordered_per_key, times_ordered_per_key,
};
use polars::prelude::DataFrame;
use std::path::Path;

fn to_err<'a>(table: &'static str, path: &'a Path) -> impl FnOnce(Violation) -> MetricsError + 'a {
    move |v| MetricsError::BrokenRule { table, path: path.to_path_buf(), column: v.column, row: v.row, why: v.why }
}

fn strs(df: &DataFrame, name: &str) -> Result<Vec<String>, MetricsError> {
    let c = df.column(name).map_err(crate::error::internal("column"))?;
    Ok(c.str().map_err(crate::error::internal("column"))?.no_null_iter().map(str::to_string).collect())
}

/// Tracks: no row more than `TRACK_OUT_OF_SEQUENCE_S` before its track's latest earlier row.
pub(crate) fn check_tracks(path: &Path, df: &DataFrame) -> Result<(), MetricsError> {
    let (run, id, t) = (u32s(df, "run")?, u64s(df, "track_id")?, f64s(df, "t_s")?);
    let keys = run.iter().zip(&id).map(|(r, i)| Key2(*r, *i));
    times_nearly_ordered_per_key(keys, &t, TRACK_OUT_OF_SEQUENCE_S, "track").map_err(to_err("tracks", path))
}

/// Truth: one row per (run, target, t_s), times increasing within each target.
pub(crate) fn check_truth(path: &Path, df: &DataFrame) -> Result<(), MetricsError> {
    let (run, target, t) = (u32s(df, "run")?, strs(df, "target")?, f64s(df, "t_s")?);
    times_ordered_per_key(run.iter().zip(&target).map(|(r, s)| Key2(*r, s.as_str())), &t, true, "target")
        .map_err(to_err("truth", path))
}

/// Dwells: start times non-decreasing per (run, radar).
pub(crate) fn check_dwells(path: &Path, df: &DataFrame) -> Result<(), MetricsError> {
    let (run, radar, t) = (u32s(df, "run")?, strs(df, "radar")?, f64s(df, "t_s")?);
    times_ordered_per_key(run.iter().zip(&radar).map(|(r, s)| Key2(*r, s.as_str())), &t, false, "radar")
        .map_err(to_err("dwells", path))
}
