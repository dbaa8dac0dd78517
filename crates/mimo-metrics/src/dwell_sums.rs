//! The dwells table reduced to the usage sums (docs/design.md §6) in one pass over its rows (as
//! the dwells reader gives them, `mimo_store::dwell_chunks`, labels parsed): the checks of the
//! dwells columns and table rule (docs/design.md §3, §7) made on the way, and the transmit
//! dwells' duration and energy added to their (run, radar, interval) group.
//!
//! The additions are fixed, so that the same dwells give the same bits on every machine (see
//! [`Sum`]): within a slice of [`DWELL_SLICE_ROWS`] rows, a group's rows in row order; the
//! slices' sums of a group in slice order; the files' sums in file order. Groups come out in
//! order of first appearance. Any check that fails makes the pass give up (`None`): the caller
//! then reads the file with every check (`crate::read`), which names the file, column, row and
//! rule. The columns are read by `crate::dwell_file`.

use crate::mean::KahanSum;
use mimo_core::records::{Requester, Role};
use std::collections::{BTreeSet, HashMap};

/// Rows of a dwells file read at a time: the file is reduced slice by slice, so that memory
/// follows this many rows, not a run's duration (a 1000-s scenario-7 run has ~600 k dwell rows).
/// The slices also set how the sums are split (see the module docs).
pub(crate) const DWELL_SLICE_ROWS: usize = 1 << 18;

/// No group yet / no partial sum yet.
const NONE: usize = usize::MAX;

/// A sum of the four usage figures: a group of one value is that value, a group of more a
/// compensated (Kahan) sum from 0 over the values in row order, with the error term kept only
/// while finite (the additions of a grouped float sum in polars 0.55, which scored these tables
/// before; the score files are bit for bit those it wrote).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Sum {
    n: u32,
    first: [f64; 4],
    sum: [KahanSum; 4],
}

impl Sum {
    /// One more row's values.
    fn add(&mut self, v: [f64; 4]) {
        if self.n == 0 {
            self.first = v;
        }
        self.n = self.n.saturating_add(1);
        for (v, sum) in v.iter().zip(&mut self.sum) {
            sum.add(*v);
        }
    }

    /// The group's sums (0 for no value).
    pub(crate) fn value(&self) -> [f64; 4] {
        if self.n == 1 { self.first } else { self.sum.map(|s| s.value()) }
    }
}

/// The usage sums of one or more dwells files: groups (run, radar, interval) in order of first
/// appearance with the four sums of `usage::SUMS`, and every radar named (any role).
#[derive(Debug, Default)]
pub(crate) struct DwellSums {
    /// Distinct radar names, in order of first appearance.
    pub radar_names: Vec<String>,
    /// (run, index in `radar_names`, interval) of each group.
    pub groups: Vec<(u32, usize, i64)>,
    /// dwell time, energy, TA dwell time, TA energy of each group.
    pub sums: Vec<Sum>,
}

impl DwellSums {
    /// Every radar named.
    pub(crate) fn radars(&self) -> BTreeSet<String> {
        self.radar_names.iter().cloned().collect()
    }

    /// The sums of `sums` added to these by key (a new key appended, its sum added to 0).
    pub(crate) fn add(&mut self, sums: DwellSums) {
        let mut radar_map: HashMap<String, usize> =
            self.radar_names.iter().enumerate().map(|(i, r)| (r.clone(), i)).collect();
        let mut radar_index = Vec::with_capacity(sums.radar_names.len());
        for name in sums.radar_names {
            let next = self.radar_names.len();
            let i = *radar_map.entry(name.clone()).or_insert(next);
            if i == next {
                self.radar_names.push(name);
            }
            radar_index.push(i);
        }
        let mut group_map: HashMap<(u32, usize, i64), usize> =
            self.groups.iter().enumerate().map(|(i, g)| (*g, i)).collect();
        for ((run, radar, interval), s) in sums.groups.into_iter().zip(sums.sums) {
            let key = (run, radar_index[radar], interval);
            let next = self.groups.len();
            let g = *group_map.entry(key).or_insert(next);
            if g == next {
                self.groups.push(key);
                self.sums.push(Sum::default());
            }
            self.sums[g].add(s.value());
        }
    }
}

/// The latest state of one (run, radar) of a file.
struct KeyState {
    run: u32,
    radar: usize,
    latest_t_s: f64,
    interval: i64,
    group: usize,
    partial: usize,
}

/// One slice of rows of a dwells file, its labels parsed (radars as indices among the file's
/// radars, in order of first appearance).
pub(crate) struct Rows<'a> {
    pub run: &'a [u32],
    pub radar: &'a [u8],
    pub role: &'a [Role],
    pub requested_by: &'a [Requester],
    pub t_s: &'a [f64],
    pub duration_s: &'a [f64],
    pub energy_j: &'a [f64],
}

/// The one pass over the rows of a dwells file: the checks between rows and the sums.
pub(crate) struct FilePass<'r> {
    /// The runs a row may be of (borrowed from the score's, or owned by a pass over rows in
    /// memory, [`crate::dwell_rows`]).
    runs: std::borrow::Cow<'r, BTreeSet<u32>>,
    interval_s: f64,
    slice_rows: usize,
    /// Rows left before the current slice ends (a count down, not a division per row).
    rows_left_in_slice: usize,
    out: DwellSums,
    keys: Vec<KeyState>,
    partials: Vec<(usize, Sum)>,
}

impl<'r> FilePass<'r> {
    /// A pass whose sums are split every `slice_rows` rows (at least one) of the file.
    pub(crate) fn new(runs: &'r BTreeSet<u32>, interval_s: f64, slice_rows: usize) -> FilePass<'r> {
        FilePass::with_runs(std::borrow::Cow::Borrowed(runs), interval_s, slice_rows)
    }

    /// [`FilePass::new`] with the runs given as borrowed or owned.
    pub(crate) fn with_runs(
        runs: std::borrow::Cow<'r, BTreeSet<u32>>,
        interval_s: f64,
        slice_rows: usize,
    ) -> FilePass<'r> {
        FilePass {
            runs,
            interval_s,
            slice_rows: slice_rows.max(1),
            rows_left_in_slice: slice_rows.max(1),
            out: DwellSums::default(),
            keys: Vec::new(),
            partials: Vec::new(),
        }
    }

    /// The partial sums of the slice so far added to the file's.
    fn end_slice(&mut self) {
        for (g, p) in &self.partials {
            self.out.sums[*g].add(p.value());
        }
        self.partials.clear();
        for k in &mut self.keys {
            k.partial = NONE;
        }
    }

    /// The next rows of the file checked and added; `None` when a check fails.
    pub(crate) fn rows(&mut self, rows: &Rows<'_>) -> Option<()> {
        let n = rows.run.len();
        let lens = [rows.radar.len(), rows.role.len(), rows.requested_by.len()];
        if lens.iter().chain(&[rows.t_s.len(), rows.duration_s.len(), rows.energy_j.len()]).any(|&l| l != n) {
            return None;
        }
        // Finite and >= 0 (NaN fails both comparisons); folded without a branch per value.
        let bad = |v: &[f64]| {
            let mut bad = false;
            for x in v {
                bad |= !((*x >= 0.0) & (*x < f64::INFINITY));
            }
            bad
        };
        if bad(rows.t_s) || bad(rows.duration_s) || bad(rows.energy_j) {
            return None;
        }
        let mut last_run = None;
        let mut last_key = 0;
        for i in 0..n {
            if self.rows_left_in_slice == 0 {
                self.end_slice();
                self.rows_left_in_slice = self.slice_rows;
            }
            self.rows_left_in_slice -= 1;
            let (r, rad, t) = (rows.run[i], usize::from(rows.radar[i]), rows.t_s[i]);
            if last_run != Some(r) {
                if !self.runs.contains(&r) {
                    return None;
                }
                last_run = Some(r);
            }
            let k = match self.keys.get(last_key) {
                Some(k) if k.run == r && k.radar == rad => last_key,
                _ => match self.keys.iter().position(|k| k.run == r && k.radar == rad) {
                    Some(k) => k,
                    None => {
                        let state =
                            KeyState { run: r, radar: rad, latest_t_s: t, interval: 0, group: NONE, partial: NONE };
                        self.keys.push(state);
                        self.keys.len() - 1
                    }
                },
            };
            last_key = k;
            let key = &mut self.keys[k];
            if t < key.latest_t_s {
                return None;
            }
            key.latest_t_s = t;
            if rows.role[i] == Role::Rx {
                continue;
            }
            // `floor(t_s / interval_s) + 1` (docs/design.md §6) as an i64; beyond that the
            // checked read decides.
            let q = t / self.interval_s;
            if q.is_nan() || q >= 9.0e18 {
                return None;
            }
            let interval = q as i64 + 1;
            if key.group == NONE || key.interval != interval {
                // Times never decrease within a key, so a new interval is a new group.
                self.out.groups.push((r, rad, interval));
                self.out.sums.push(Sum::default());
                key.group = self.out.groups.len() - 1;
                key.interval = interval;
                key.partial = NONE;
            }
            if key.partial == NONE {
                self.partials.push((key.group, Sum::default()));
                key.partial = self.partials.len() - 1;
            }
            let (d, e) = (rows.duration_s[i], rows.energy_j[i]);
            let is_ta = rows.requested_by[i] == Requester::Ta;
            self.partials[key.partial].1.add([d, e, if is_ta { d } else { 0.0 }, if is_ta { e } else { 0.0 }]);
        }
        Some(())
    }

    /// The file's sums, its radars named by `radar_names` (a row's radar index into them).
    pub(crate) fn finish(mut self, radar_names: Vec<String>) -> DwellSums {
        self.end_slice();
        self.out.radar_names = radar_names;
        self.out
    }
}
