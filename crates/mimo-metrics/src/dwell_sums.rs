//! The dwells table reduced to the usage sums (docs/design.md §6) in one pass over its rows: each
//! row's radar, role, kind and requester mapped to a small index once per distinct string, the
//! checks of the dwells columns and table rule (docs/design.md §3, §7) made on the way, and the
//! transmit dwells' duration and energy added to their (run, radar, interval) group.
//!
//! The sums are the very additions of the polars group-by this replaces (`usage::transmit_sums`
//! per slice of [`DWELL_SLICE_ROWS`] rows, slices and files summed again by key), see [`Sum`]:
//! within a slice, a group's rows in row order; the slices' sums of a group in slice order; the
//! files' sums in file order. Groups come out in order of first appearance. Any check
//! that fails makes the pass give up (`None`): the caller then reads the file the polars way,
//! which names the file, column, row and rule exactly as before. The columns are read by
//! `crate::dwell_read`.

use crate::MetricsError;
use crate::load::{KINDS, REQUESTERS, ROLES};
use mimo_core::ids::RadarId;
use polars::prelude::*;
use std::collections::{BTreeSet, HashMap};

/// Rows of a dwells file read at a time: the file is reduced slice by slice, so that memory
/// follows this many rows, not a run's duration (a 1000-s scenario-7 run has ~600 k dwell rows).
/// The slices also set how the sums are split (see the module docs).
pub(crate) const DWELL_SLICE_ROWS: usize = 1 << 18;

/// No group yet / no partial sum yet.
const NONE: usize = usize::MAX;

/// A sum of the four usage figures as polars' grouped `sum` of a float column adds (in-memory
/// group-by, `agg_sum` of polars-core 0.55): a group of one value is that value, a group of more
/// a compensated (Kahan) sum from 0 over the values in row order, with the error term kept only
/// while finite.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Sum {
    n: u32,
    first: [f64; 4],
    sum: [f64; 4],
    err: [f64; 4],
}

impl Sum {
    /// One more row's values.
    fn add(&mut self, v: [f64; 4]) {
        if self.n == 0 {
            self.first = v;
        }
        self.n = self.n.saturating_add(1);
        for ((v, sum), err) in v.iter().zip(&mut self.sum).zip(&mut self.err) {
            let y = v - *err;
            let new_sum = *sum + y;
            let new_err = (new_sum - *sum) - y;
            *sum = new_sum;
            if new_err.is_finite() {
                *err = new_err;
            }
        }
    }

    /// The group's sums (0 for no value).
    fn value(&self) -> [f64; 4] {
        if self.n == 1 { self.first } else { self.sum }
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

    /// The sums of a `usage::transmit_sums` frame (groups in its row order) and the radars named.
    pub(crate) fn from_frame(df: &DataFrame, radars: BTreeSet<String>) -> Result<DwellSums, MetricsError> {
        let bug = || crate::error::internal("usage sums");
        let radar_names: Vec<String> = radars.into_iter().collect();
        let radar_map: HashMap<&str, usize> = radar_names.iter().enumerate().map(|(i, r)| (r.as_str(), i)).collect();
        let run = df.column("run").map_err(bug())?.u32().map_err(bug())?;
        let radar = df.column("radar").map_err(bug())?.str().map_err(bug())?;
        let interval = df.column("interval").map_err(bug())?.i64().map_err(bug())?;
        let mut groups = Vec::with_capacity(df.height());
        for ((r, name), k) in run.iter().zip(radar.iter()).zip(interval.iter()) {
            let (Some(r), Some(name), Some(k)) = (r, name, k) else {
                return Err(MetricsError::Internal { context: "usage sums", detail: "a null key".into() });
            };
            let i = radar_map.get(name).copied().ok_or_else(|| MetricsError::Internal {
                context: "usage sums",
                detail: format!("radar {name} not among the radars named"),
            })?;
            groups.push((r, i, k));
        }
        let mut values = vec![[0.0; 4]; groups.len()];
        for (q, name) in crate::usage::SUMS.iter().enumerate() {
            let c = df.column(name).map_err(bug())?.f64().map_err(bug())?;
            for (s, v) in values.iter_mut().zip(c.iter()) {
                s[q] = v.unwrap_or(0.0);
            }
        }
        let sums = values
            .into_iter()
            .map(|v| {
                let mut s = Sum::default();
                s.add(v);
                s
            })
            .collect();
        Ok(DwellSums { radar_names, groups, sums })
    }

    /// The groups as the frame `usage::usage` takes: `run`, `radar`, `interval` and the sums.
    pub(crate) fn into_frame(self) -> Result<DataFrame, MetricsError> {
        let run: Vec<u32> = self.groups.iter().map(|g| g.0).collect();
        let radar: Vec<&str> = self.groups.iter().map(|g| self.radar_names[g.1].as_str()).collect();
        let interval: Vec<i64> = self.groups.iter().map(|g| g.2).collect();
        let mut columns = vec![
            Column::new("run".into(), run),
            Column::new("radar".into(), radar),
            Column::new("interval".into(), interval),
        ];
        for (q, name) in crate::usage::SUMS.iter().enumerate() {
            let v: Vec<f64> = self.sums.iter().map(|s| s.value()[q]).collect();
            columns.push(Column::new((*name).into(), v));
        }
        DataFrame::new_infer_height(columns).map_err(crate::error::internal("usage sums"))
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

/// A utf8 column's distinct strings, each mapped to a small index once. A string is recognised
/// by its polars view when short enough to sit inline in it (12 bytes: the view is then its
/// length and bytes), else by comparison with the strings seen.
pub(crate) struct Labels {
    names: Vec<String>,
    views: Vec<(u128, u8)>,
    accept: fn(&str) -> bool,
}

/// The key of a string of at most 12 bytes: its length and bytes laid out as a polars inline
/// string view (`View::as_u128`), so that a view and the bytes it holds give the same key.
#[inline]
pub(crate) fn short_key(bytes: &[u8]) -> Option<u128> {
    let len = u32::try_from(bytes.len()).ok().filter(|&l| l <= 12)?;
    let mut b = [0u8; 16];
    b[..4].copy_from_slice(&len.to_le_bytes());
    for (d, s) in b[4..].iter_mut().zip(bytes) {
        *d = *s;
    }
    Some(u128::from_le_bytes(b))
}

/// Inline views remembered per column (more distinct short strings are compared as strings).
const MAX_VIEWS: usize = 64;

impl Labels {
    /// Labels that grow with every string `accept` takes (at most 255).
    pub(crate) fn open(accept: fn(&str) -> bool) -> Labels {
        Labels { names: Vec::new(), views: Vec::new(), accept }
    }

    /// Labels of a fixed list: any other string is refused.
    pub(crate) fn fixed(list: &[&str]) -> Labels {
        Labels { names: list.iter().map(|s| s.to_string()).collect(), views: Vec::new(), accept: |_| false }
    }

    /// The index of the string whose inline view is `view`, if seen before.
    #[inline]
    pub(crate) fn by_view(&self, view: u128) -> Option<u8> {
        self.views.iter().find(|(v, _)| *v == view).map(|(_, index)| *index)
    }

    /// The index of `s`, remembered under its inline view `view` if any; `None` when refused or
    /// beyond 255 strings.
    pub(crate) fn index(&mut self, s: &str, view: Option<u128>) -> Option<u8> {
        let index = match self.names.iter().position(|n| n == s) {
            Some(index) => index,
            None if (self.accept)(s) && self.names.len() < 255 => {
                self.names.push(s.to_string());
                self.names.len() - 1
            }
            None => return None,
        };
        let index = u8::try_from(index).ok()?;
        if let Some(view) = view
            && self.views.len() < MAX_VIEWS
        {
            self.views.push((view, index));
        }
        Some(index)
    }

    /// The index of a string of the list (never refused for `fixed` labels of that list).
    fn of(&mut self, s: &str) -> u8 {
        self.index(s, None).unwrap_or(u8::MAX)
    }
}

/// One slice of rows of a dwells file, its labels already mapped by [`Labels`].
pub(crate) struct Rows<'a> {
    pub run: &'a [u32],
    pub radar: &'a [u8],
    pub role: &'a [u8],
    pub requested_by: &'a [u8],
    pub t_s: &'a [f64],
    pub duration_s: &'a [f64],
    pub energy_j: &'a [f64],
}

/// The one pass over the rows of a dwells file: the labels, the checks and the sums.
pub(crate) struct FilePass<'r> {
    runs: &'r BTreeSet<u32>,
    interval_s: f64,
    slice_rows: usize,
    rows_done: usize,
    pub(crate) radar: Labels,
    pub(crate) role: Labels,
    pub(crate) kind: Labels,
    pub(crate) requested_by: Labels,
    out: DwellSums,
    keys: Vec<KeyState>,
    partials: Vec<(usize, Sum)>,
    rx: u8,
    ta: u8,
}

impl<'r> FilePass<'r> {
    /// A pass whose sums are split every `slice_rows` rows (at least one) of the file, as the
    /// polars read in slices of that many rows split them.
    pub(crate) fn new(runs: &'r BTreeSet<u32>, interval_s: f64, slice_rows: usize) -> FilePass<'r> {
        let mut role = Labels::fixed(ROLES);
        let mut requested_by = Labels::fixed(REQUESTERS);
        let (rx, ta) = (role.of("rx"), requested_by.of("ta"));
        FilePass {
            runs,
            interval_s,
            slice_rows: slice_rows.max(1),
            rows_done: 0,
            radar: Labels::open(|s| RadarId::parse(s).is_some()),
            role,
            kind: Labels::fixed(KINDS),
            requested_by,
            out: DwellSums::default(),
            keys: Vec::new(),
            partials: Vec::new(),
            rx,
            ta,
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
            if self.rows_done > 0 && self.rows_done.is_multiple_of(self.slice_rows) {
                self.end_slice();
            }
            self.rows_done += 1;
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
            if rows.role[i] == self.rx {
                continue;
            }
            // `(t_s / interval_s).cast(Int64) + 1` of `usage::transmit_sums`; beyond i64 the
            // polars read decides.
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
            let is_ta = rows.requested_by[i] == self.ta;
            self.partials[key.partial].1.add([d, e, if is_ta { d } else { 0.0 }, if is_ta { e } else { 0.0 }]);
        }
        Some(())
    }

    /// The file's sums and radars.
    pub(crate) fn finish(mut self) -> DwellSums {
        self.end_slice();
        self.out.radar_names = self.radar.names;
        self.out
    }
}
