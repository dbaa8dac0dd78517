//! The rules a well-formed run table keeps beyond its schema (docs/design.md §3, §7): who may
//! repeat, and which times may not run backwards. Both readers of the tables — `mimo-store`'s
//! typed reader and the metrics engine's own Parquet reader — check the same rules with these
//! functions, so a table that breaks one is refused the same way wherever it is read.
//!
//! * tracks: no row of a track earlier than the track's latest earlier row by more than
//!   [`TRACK_OUT_OF_SEQUENCE_S`]. A test article hears of a dwell when it ends, while its
//!   measurements are stamped at the dwell's middle, so a short dwell that ends first can put a
//!   track at a later time than a longer dwell processed next (an out-of-sequence update, a few
//!   milliseconds back); a table whose times run backwards beyond that is refused;
//! * truth: one row per (run, `target`, `t_s`), and times increasing within each target;
//! * dwells: `dwell_id` unique within a run, and start times non-decreasing per (run, `radar`)
//!   (a radar executes one dwell at a time, docs/model.md §7);
//! * measurements: `meas_id` unique within a run;
//! * tracks, at one time: rows of one track that share `t_s` (sequential updates from one dwell)
//!   are ordered by `n_updates`, the `deleted` row last ([`track_row_order`]); rows the table
//!   cannot order that way are refused ([`track_rows_orderable`]), so that no result depends on
//!   the order rows are stored in;
//! * covariances: symmetric 6×6 upper triangles with positive variances that are positive
//!   semi-definite to rounding, or slightly indefinite within the bound of a repair
//!   ([`covariance_ok`], [`crate::covariance`]).
//!
//! Each check returns the first offending row (0-based, within the file checked) and a reason.
//! The checks over a whole file are the streaming rules ([`TimeRule`], [`UniqueRule`],
//! [`OrderableRule`]) fed the file at once, so a reader that checks rows chunk by chunk as they
//! stream by names the same row, whatever its chunks.

use std::collections::HashMap;
use std::hash::Hash;

/// A row that breaks a rule: the column to blame, the row (0-based) and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Violation {
    /// The column whose value breaks the rule.
    pub column: &'static str,
    /// The row, 0-based within the file.
    pub row: usize,
    /// What is wrong, in words (names the earlier row it conflicts with).
    pub why: String,
}

/// How far back in time (s) a track's row may lie behind the latest earlier row of the same
/// track: half the longest dwell a test article may report out of sequence. A 16-pulse dwell at
/// the default 300 Hz lasts 53 ms; 1 s allows any dwell up to 2 s long.
pub const TRACK_OUT_OF_SEQUENCE_S: f64 = 1.0;

/// Track times: no row more than `tolerance_s` before the latest earlier time of its key (the
/// running maximum, so a table read backwards is caught however small its steps are).
pub fn times_nearly_ordered_per_key<K: Hash + Eq + Clone + std::fmt::Display>(
    keys: impl IntoIterator<Item = K>,
    t_s: &[f64],
    tolerance_s: f64,
    what: &str,
) -> Result<(), Violation> {
    check_times(keys, t_s, tolerance_s, false, what)
}

/// Times within each key: strictly increasing (`strict`, no repeated time) or non-decreasing.
/// `what` names the key in messages ("track", "target", "radar").
pub fn times_ordered_per_key<K: Hash + Eq + Clone + std::fmt::Display>(
    keys: impl IntoIterator<Item = K>,
    t_s: &[f64],
    strict: bool,
    what: &str,
) -> Result<(), Violation> {
    check_times(keys, t_s, 0.0, strict, what)
}

/// The one time rule: each row against the latest time of its key so far (for a table in order
/// that is the previous row of the key); a row more than `tolerance_s` before it, or (`strict`)
/// at it, breaks the rule.
fn check_times<K: Hash + Eq + Clone + std::fmt::Display>(
    keys: impl IntoIterator<Item = K>,
    t_s: &[f64],
    tolerance_s: f64,
    strict: bool,
    what: &str,
) -> Result<(), Violation> {
    let mut rule = TimeRule { latest: Latest::default(), tolerance_s, strict, what };
    for (row, (key, &t)) in keys.into_iter().zip(t_s).enumerate() {
        rule.check(row, key, t)?;
    }
    Ok(())
}

/// The time rule ([`times_ordered_per_key`], [`times_nearly_ordered_per_key`]) row by row, for a
/// reader that checks rows as they stream by: [`TimeRule::check`] takes the file's rows in order.
/// It holds the latest time of each key, so its memory is the keys', not the rows'.
pub struct TimeRule<'w, K> {
    latest: Latest<K>,
    tolerance_s: f64,
    strict: bool,
    what: &'w str,
}

impl<'w, K: Hash + Eq + Clone + std::fmt::Display> TimeRule<'w, K> {
    /// Times strictly increasing (`strict`) or non-decreasing within each key; `what` names the
    /// key in messages ("target", "radar").
    pub fn ordered(strict: bool, what: &'w str) -> Self {
        TimeRule { latest: Latest::default(), tolerance_s: 0.0, strict, what }
    }

    /// No time more than `tolerance_s` before its key's latest earlier time.
    pub fn nearly_ordered(tolerance_s: f64, what: &'w str) -> Self {
        TimeRule { latest: Latest::default(), tolerance_s, strict: false, what }
    }

    /// Row `row` of the file (after every earlier row), of key `key` at time `t`.
    pub fn check(&mut self, row: usize, key: K, t: f64) -> Result<(), Violation> {
        let (tolerance_s, strict, what) = (self.tolerance_s, self.strict, self.what);
        let (key, slot) = match self.latest.slot(key) {
            Slot::New(slot) => {
                *slot = (t, row);
                return Ok(());
            }
            Slot::Seen((key, slot)) => (&*key, slot),
        };
        let (max, max_row) = *slot;
        let back = t < max - tolerance_s;
        if back || (strict && t == max) {
            let why = match (back, tolerance_s > 0.0, strict) {
                (true, true, _) => format!(
                    "{t} is more than {tolerance_s} s before {max} at row {max_row} for {what} {key} (times must not run backwards within each {what})"
                ),
                (true, false, s) => format!(
                    "{t} is before {max} at row {max_row} for {what} {key} (times must {} within each {what})",
                    if s { "increase" } else { "not decrease" }
                ),
                (false, ..) => format!(
                    "{t} repeats {max} at row {max_row} for {what} {key} (times must increase within each {what})"
                ),
            };
            return Err(Violation { column: "t_s", row, why });
        }
        if t > max {
            *slot = (t, row);
        }
        Ok(())
    }
}

/// The latest time and row of each key: a short list while the keys are few (a file's radars or
/// targets: a few comparisons a row instead of a hash), indexed by a hash map beyond.
struct Latest<K> {
    entries: Vec<(K, (f64, usize))>,
    index: HashMap<K, usize>,
}

impl<K> Default for Latest<K> {
    fn default() -> Self {
        Latest { entries: Vec::new(), index: HashMap::new() }
    }
}

/// A key's entry in [`Latest`]: new (its time and row to be set), or seen (the key as first
/// stored, for messages, with its latest time and row).
enum Slot<'a, K> {
    New(&'a mut (f64, usize)),
    Seen(&'a mut (K, (f64, usize))),
}

impl<K: Hash + Eq + Clone> Latest<K> {
    const FEW: usize = 16;

    /// The entry of `key`, found in one look-up.
    fn slot(&mut self, key: K) -> Slot<'_, K> {
        let found = if self.entries.len() <= Self::FEW {
            self.entries.iter().position(|(k, _)| *k == key)
        } else {
            self.index.get(&key).copied()
        };
        if let Some(i) = found {
            return Slot::Seen(&mut self.entries[i]);
        }
        self.entries.push((key, (0.0, 0)));
        let n = self.entries.len();
        if n == Self::FEW + 1 {
            self.index = self.entries.iter().enumerate().map(|(i, (k, _))| (k.clone(), i)).collect();
        } else if n > Self::FEW + 1 {
            self.index.insert(self.entries[n - 1].0.clone(), n - 1);
        }
        Slot::New(&mut self.entries[n - 1].1)
    }
}

/// Keys that must be unique (e.g. `(run, dwell_id)`): the first repeat ([`UniqueRule`] over the
/// whole file at once).
pub fn unique<K: Hash + Eq + Ord + std::fmt::Display>(
    keys: impl IntoIterator<Item = K>,
    column: &'static str,
) -> Result<(), Violation> {
    UniqueRule::new(column).check(0, keys)
}

/// The rule that keys are unique, checked chunk by chunk as a reader streams a file's rows: the
/// first repeat in the file is found in the chunk that holds its second row, whatever the chunks.
///
/// It keeps every key read, sorted with its row. Tables are written nearly in key order (ids
/// count in the order dwells start, rows come in the order they end), so a chunk's keys go in
/// after the earlier ones with an insertion sort from the first earlier key they reach
/// ([`crate::nearly_sorted`]): a chunk costs its length plus its keys' displacement.
pub struct UniqueRule<K> {
    column: &'static str,
    /// Every key read, with its row, sorted by (key, row).
    sorted: Vec<(K, usize)>,
}

impl<K: Ord + std::fmt::Display> UniqueRule<K> {
    /// Keys of `column` must be unique.
    pub fn new(column: &'static str) -> Self {
        UniqueRule { column, sorted: Vec::new() }
    }

    /// The keys of the next rows, the first of them row `first_row` of the file (rows follow
    /// the earlier chunks').
    pub fn check(&mut self, first_row: usize, keys: impl IntoIterator<Item = K>) -> Result<(), Violation> {
        let start = self.sorted.len();
        self.sorted.extend(keys.into_iter().zip(first_row..));
        let Some(smallest) = self.sorted[start..].iter().map(|(k, _)| k).min() else {
            return Ok(());
        };
        // Earlier keys below the chunk's smallest key stay where they are; every key equal to a
        // new one is at or after `from`.
        let from = self.sorted[..start].partition_point(|(k, _)| k < smallest);
        crate::nearly_sorted::sort_nearly_sorted(&mut self.sorted[from..]);
        // Sorted by (key, row), each key's rows are together in file order; the first repeat in
        // the file is the smallest second row of any key, and it repeats that key's first row.
        // Earlier chunks held no repeat, so every second row found here is in this chunk.
        let part = &self.sorted[from..];
        let mut first: Option<usize> = None;
        for i in 1..part.len() {
            let starts_group = i == 1 || part[i - 2].0 != part[i - 1].0;
            if starts_group && part[i].0 == part[i - 1].0 && first.is_none_or(|f| part[i].1 < part[f].1) {
                first = Some(i);
            }
        }
        match first {
            None => Ok(()),
            Some(i) => {
                let (column, (key, row), was) = (self.column, &part[i], part[i - 1].1);
                Err(Violation {
                    column,
                    row: *row,
                    why: format!("{key} repeats row {was} ({column} must be unique within a run)"),
                })
            }
        }
    }
}

/// Every row's run is the file's run (files are `run-K.parquet`, one run each).
pub fn runs_match(runs: &[u32], file_run: u32) -> Result<(), Violation> {
    match runs.iter().position(|&r| r != file_run) {
        None => Ok(()),
        Some(row) => Err(Violation {
            column: "run",
            row,
            why: format!("{} in the file of run {file_run} (each file holds one run)", runs[row]),
        }),
    }
}

/// The run of a file named `run-K.parquet` (docs/design.md §2), if it is named so.
pub fn run_of_file_name(name: &str) -> Option<u32> {
    name.strip_prefix("run-")?.strip_suffix(".parquet")?.parse().ok()
}

/// The rank of a tracks row among the rows of its track at the same time: `n_updates`, then the
/// `deleted` row after the others (docs/decisions/0258-checked-table-readers.md).
pub fn track_row_order(n_updates: u32, deleted: bool) -> u64 {
    (u64::from(n_updates) << 1) | u64::from(deleted)
}

/// Rows of one track at one time must differ in their [`track_row_order`]: the first row that
/// repeats an earlier row's (key, `t_s`, rank) cannot be ordered by the table and breaks the rule
/// ([`OrderableRule`] over the whole file at once).
pub fn track_rows_orderable<K: Hash + Eq + std::fmt::Display>(
    keys: impl IntoIterator<Item = K>,
    t_s: &[f64],
    rank: &[u64],
) -> Result<(), Violation> {
    let mut rule = OrderableRule::default();
    for (row, ((key, &t), &r)) in keys.into_iter().zip(t_s).zip(rank).enumerate() {
        rule.check(row, key, t, r)?;
    }
    Ok(())
}

/// [`track_rows_orderable`] row by row, for a reader that checks rows as they stream by.
pub struct OrderableRule<K> {
    seen: HashMap<(K, u64, u64), usize>,
}

impl<K> Default for OrderableRule<K> {
    fn default() -> Self {
        OrderableRule { seen: HashMap::new() }
    }
}

impl<K: Hash + Eq + std::fmt::Display> OrderableRule<K> {
    /// Row `row` of the file (after every earlier row): its key, time and rank.
    pub fn check(&mut self, row: usize, key: K, t: f64, rank: u64) -> Result<(), Violation> {
        // -0.0 and 0.0 are one time.
        let bits = if t == 0.0 { 0 } else { t.to_bits() };
        match self.seen.entry((key, bits, rank)) {
            std::collections::hash_map::Entry::Vacant(v) => {
                v.insert(row);
                Ok(())
            }
            std::collections::hash_map::Entry::Occupied(o) => {
                let was = *o.get();
                let key = &o.key().0;
                Err(Violation {
                    column: "n_updates",
                    row,
                    why: format!(
                        "repeats row {was}: track {key} has two rows at t_s {t} with n_updates {} (rows of one track at one time are ordered by n_updates, the deleted row last; these cannot be)",
                        rank >> 1
                    ),
                })
            }
        }
    }
}

/// Whether a packed covariance can be one: finite values, positive variances, and positive
/// semi-definite to rounding or within the bound of a repair (`crate::covariance`, whose rule
/// this is). `Err` says what is wrong.
pub use crate::covariance::covariance_ok;

/// A key of two parts shown as `a/b` in messages (run and id).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Key2<A, B>(pub A, pub B);

impl<A: std::fmt::Display, B: std::fmt::Display> std::fmt::Display for Key2<A, B> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} of run {}", self.1, self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_and_uniqueness() {
        let keys = [Key2(0u32, 1u64), Key2(0, 2), Key2(0, 1), Key2(0, 1)];
        assert!(times_ordered_per_key(keys.iter().cloned(), &[0.0, 0.0, 1.0, 2.0], true, "track").is_ok());
        let e = times_ordered_per_key(keys.iter().cloned(), &[0.0, 0.0, 1.0, 1.0], true, "track").expect_err("repeat");
        assert_eq!((e.column, e.row), ("t_s", 3));
        assert!(e.why.contains("repeats"), "{}", e.why);
        assert!(times_ordered_per_key(keys.iter().cloned(), &[0.0, 0.0, 1.0, 1.0], false, "radar").is_ok());
        let e = times_ordered_per_key(keys.iter().cloned(), &[5.0, 0.0, 1.0, 2.0], false, "track").expect_err("back");
        assert_eq!(e.row, 2);
        assert!(e.why.contains("is before 5"), "{}", e.why);
        // Tracks: an out-of-sequence update a few ms back passes; a table read backwards does not,
        // even in steps smaller than the tolerance (the running maximum is the reference).
        let one = || (0..4).map(|_| Key2(0u32, 36u64));
        assert!(times_nearly_ordered_per_key(one(), &[844.0, 844.0601, 844.0588, 845.0], 1.0, "track").is_ok());
        let e = times_nearly_ordered_per_key(one(), &[3.0, 2.5, 2.0, 1.5], 1.0, "track").expect_err("reversed");
        assert_eq!((e.column, e.row), ("t_s", 3));
        let e = unique([Key2(0u32, 7u64), Key2(1, 7), Key2(0, 7)], "dwell_id").expect_err("dup");
        assert_eq!((e.column, e.row), ("dwell_id", 2));
        assert!(unique([Key2(0u32, 7u64), Key2(1, 7)], "dwell_id").is_ok());
        assert_eq!(runs_match(&[3, 3, 4], 3).expect_err("run").row, 2);
    }

    /// Chunk by chunk, the streaming rules name the row the whole-file checks name, wherever the
    /// chunks are cut (here: keys a few rows out of place, as dwell ids are, and one repeat).
    #[test]
    fn streamed_rules_name_the_whole_files_row() {
        let mut keys: Vec<Key2<u32, u64>> = (0..200u64).map(|i| Key2(0, i)).collect();
        for i in (0..196).step_by(7) {
            keys.swap(i, i + 3);
        }
        let t: Vec<f64> = (0..200).map(|i| f64::from(i / 3)).collect();
        for repeat in [None, Some((150usize, 40usize)), Some((41, 40)), Some((199, 0))] {
            let mut k = keys.clone();
            if let Some((at, of)) = repeat {
                k[at] = k[of].clone();
            }
            let whole = unique(k.iter().cloned(), "dwell_id");
            assert_eq!(whole.is_err(), repeat.is_some());
            for chunk in [1, 2, 7, 16, 64, 200] {
                let mut rule = UniqueRule::new("dwell_id");
                let streamed =
                    k.chunks(chunk).enumerate().try_for_each(|(c, part)| rule.check(c * chunk, part.iter().cloned()));
                assert_eq!(streamed, whole, "chunks of {chunk}, repeat {repeat:?}");
            }
            let radars = || k.iter().map(|k| Key2(0u32, k.1 % 3));
            let whole_t = times_ordered_per_key(radars(), &t, true, "radar");
            let mut rule = TimeRule::ordered(true, "radar");
            let streamed = radars().zip(&t).enumerate().try_for_each(|(row, (key, &t))| rule.check(row, key, t));
            assert_eq!(streamed, whole_t);
        }
    }

    #[test]
    fn track_rows_at_one_time_need_distinct_ranks() {
        let keys = || [Key2(0u32, 5u64), Key2(0, 5), Key2(0, 5), Key2(0, 6)].into_iter();
        let t = [1.0, 1.0, 1.0, 1.0];
        let ok = [track_row_order(3, false), track_row_order(4, false), track_row_order(4, true), 0];
        assert!(track_rows_orderable(keys(), &t, &ok).is_ok());
        let tie = [track_row_order(3, false), track_row_order(4, false), track_row_order(4, false), 0];
        let e = track_rows_orderable(keys(), &t, &tie).expect_err("tie");
        assert_eq!((e.column, e.row), ("n_updates", 2));
        // The same rank at another time, or for another track, is no tie.
        assert!(track_rows_orderable(keys(), &[1.0, 2.0, 3.0, 1.0], &tie).is_ok());
        assert!(track_row_order(4, false) > track_row_order(3, true));
    }

    #[test]
    fn covariance_checks() {
        let mut m = [[0.0; 6]; 6];
        for (i, row) in m.iter_mut().enumerate() {
            row[i] = 1.0 + i as f64;
        }
        m[0][3] = 0.9;
        m[3][0] = 0.9;
        assert!(covariance_ok(&crate::records::pack_cov(&m)).is_ok());
        // A correlation above 1 is not a covariance.
        m[0][3] = 3.0;
        m[3][0] = 3.0;
        assert!(covariance_ok(&crate::records::pack_cov(&m)).expect_err("not psd").contains("smallest eigenvalue"));
        // A rank-deficient (perfectly correlated) pair is semi-definite and passes.
        m[0][3] = (1.0f64 * 4.0).sqrt();
        m[3][0] = m[0][3];
        assert!(covariance_ok(&crate::records::pack_cov(&m)).is_ok());
        let mut c = crate::records::pack_cov(&m);
        c[0] = -1.0;
        assert!(covariance_ok(&c).expect_err("negative").contains("variance 0"));
        c[0] = f64::NAN;
        assert!(covariance_ok(&c).expect_err("nan").contains("finite"));
    }
}
