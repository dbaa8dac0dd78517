//! The table rules of `mimo_core::table_rules` (docs/design.md §7), checked on each file this
//! crate reads before its rows are sorted and stacked: a tracks table whose times run backwards
//! would otherwise be re-sorted into a different (and wrong) track history, silently.

use crate::MetricsError;
use crate::frame::Frame;
use mimo_core::records::{DwellColumns, DwellRow, TrackColumns, TrackRow, TrackStatus, TruthColumns, TruthRow};
use mimo_core::table_rules::{
    Key2, TRACK_OUT_OF_SEQUENCE_S, Violation, times_nearly_ordered_per_key, times_ordered_per_key, track_row_order,
    track_rows_orderable,
};
use std::path::Path;

/// The run tables' column names (from their declarations in `mimo_core::records`).
const T: TruthColumns = TruthRow::COLUMNS;
const D: DwellColumns = DwellRow::COLUMNS;
const K: TrackColumns = TrackRow::COLUMNS;

fn to_err<'a>(table: &'static str, path: &'a Path) -> impl FnOnce(Violation) -> MetricsError + 'a {
    move |v| MetricsError::BrokenRule { table, path: path.to_path_buf(), column: v.column, row: v.row, why: v.why }
}

/// A utf8 column's values, borrowed from the frame (no string copied; checked columns hold no
/// null).
fn strs<'a>(df: &'a Frame, name: &str) -> Result<Vec<&'a str>, MetricsError> {
    Ok(df.strs(name)?.iter().map(|s| s.unwrap_or_default()).collect())
}

/// Keys beyond which [`ordered_few_keys`] gives up (tables hold a few radars or targets a file).
const FEW_KEYS: usize = 64;

/// Whether the times are certainly in order within each key (non-decreasing, or increasing with
/// `strict`): the rule of `mimo_core::table_rules` checked with the latest time of each key in a
/// short list instead of a hash map. `false` means "look closer": a row breaks the rule, or there
/// are more than [`FEW_KEYS`] keys; the caller then runs the full check, which names the row.
fn ordered_few_keys<K: PartialEq>(keys: impl IntoIterator<Item = K>, t_s: &[f64], strict: bool) -> bool {
    let mut latest: Vec<(K, f64)> = Vec::new();
    let mut last = 0;
    for (key, &t) in keys.into_iter().zip(t_s) {
        let slot = if latest.get(last).is_some_and(|(k, _)| *k == key) {
            Some(last)
        } else {
            latest.iter().position(|(k, _)| *k == key)
        };
        match slot {
            Some(i) => {
                let max = latest[i].1;
                if t < max || (strict && t == max) {
                    return false;
                }
                latest[i].1 = t;
                last = i;
            }
            None if latest.len() >= FEW_KEYS => return false,
            None => {
                last = latest.len();
                latest.push((key, t));
            }
        }
    }
    true
}

/// Tracks: no row more than `TRACK_OUT_OF_SEQUENCE_S` before its track's latest earlier row, and
/// rows of one track at one time that the table can order (`track_rows_orderable`).
pub(crate) fn check_tracks(path: &Path, df: &Frame) -> Result<(), MetricsError> {
    let (run, id, t) = (df.u32s(K.run)?, df.u64s(K.track_id)?, df.f64s(K.t_s)?);
    let keys = || run.iter().zip(id).map(|(r, i)| Key2(*r, *i));
    times_nearly_ordered_per_key(keys(), t, TRACK_OUT_OF_SEQUENCE_S, "track").map_err(to_err(TrackRow::TABLE, path))?;
    let rank = track_ranks(df, &track_statuses(df)?)?;
    track_rows_orderable(keys(), t, &rank).map_err(to_err(TrackRow::TABLE, path))
}

/// Each tracks row's status (`None` only for a label the checked read refused).
pub(crate) fn track_statuses(df: &Frame) -> Result<Vec<Option<TrackStatus>>, MetricsError> {
    let mut last: Option<(&str, Option<TrackStatus>)> = None;
    let mut status = Vec::with_capacity(df.height());
    for s in df.strs(K.status)?.iter() {
        let s = s.unwrap_or_default();
        let parsed = match last {
            Some((name, parsed)) if name == s => parsed,
            _ => TrackStatus::parse(s),
        };
        last = Some((s, parsed));
        status.push(parsed);
    }
    Ok(status)
}

/// Each tracks row's rank among its track's rows at its time (`track_row_order`).
pub(crate) fn track_ranks(df: &Frame, status: &[Option<TrackStatus>]) -> Result<Vec<u64>, MetricsError> {
    let n_updates = df.u32s(K.n_updates)?;
    Ok(n_updates.iter().zip(status).map(|(&n, s)| track_row_order(n, *s == Some(TrackStatus::Deleted))).collect())
}

/// Truth: one row per (run, target, t_s), times increasing within each target.
pub(crate) fn check_truth(path: &Path, df: &Frame) -> Result<(), MetricsError> {
    let (run, target, t) = (df.u32s(T.run)?, strs(df, T.target)?, df.f64s(T.t_s)?);
    let keys = || run.iter().zip(&target).map(|(r, s)| Key2(*r, *s));
    if ordered_few_keys(keys(), t, true) {
        return Ok(());
    }
    times_ordered_per_key(keys(), t, true, T.target).map_err(to_err(TruthRow::TABLE, path))
}

/// Dwells: start times non-decreasing per (run, radar).
pub(crate) fn check_dwells(path: &Path, df: &Frame) -> Result<(), MetricsError> {
    let (run, radar, t) = (df.u32s(D.run)?, strs(df, D.radar)?, df.f64s(D.t_s)?);
    let keys = || run.iter().zip(&radar).map(|(r, s)| Key2(*r, *s));
    if ordered_few_keys(keys(), t, false) {
        return Ok(());
    }
    times_ordered_per_key(keys(), t, false, D.radar).map_err(to_err(DwellRow::TABLE, path))
}
