//! The dwells' rule of `mimo_core::table_rules` (docs/design.md §7) on the checked read of a
//! dwells file's usage columns ([`crate::load`]); the truth and tracks come checked, rules
//! included, from the store's reader (`mimo_store::table_chunks`).

use crate::MetricsError;
use crate::frame::Frame;
use mimo_core::records::{DwellColumns, DwellRow};
use mimo_core::table_rules::{Key2, Violation, times_ordered_per_key};
use std::path::Path;

/// The run tables' column names (from their declarations in `mimo_core::records`).
const D: DwellColumns = DwellRow::COLUMNS;

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

/// Dwells: start times non-decreasing per (run, radar).
pub(crate) fn check_dwells(path: &Path, df: &Frame) -> Result<(), MetricsError> {
    let (run, radar, t) = (df.u32s(D.run)?, strs(df, D.radar)?, df.f64s(D.t_s)?);
    let keys = || run.iter().zip(&radar).map(|(r, s)| Key2(*r, *s));
    if ordered_few_keys(keys(), t, false) {
        return Ok(());
    }
    times_ordered_per_key(keys(), t, false, D.radar).map_err(to_err(DwellRow::TABLE, path))
}
