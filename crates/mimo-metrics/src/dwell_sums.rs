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
//! which names the file, column, row and rule exactly as before.

use crate::MetricsError;
use crate::load::{KINDS, REQUESTERS, ROLES};
use crate::read::Col;
use mimo_core::ids::RadarId;
use polars::prelude::*;
use std::borrow::Cow;
use std::collections::{BTreeSet, HashMap};
use std::path::Path;

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

/// One dwells file checked and reduced in one pass, slice by slice; `None` when a value or rule
/// check fails, or the file cannot be read (the polars read then reports it).
pub(crate) fn file_sums(
    path: &Path,
    cols: &[Col<'_>],
    runs: &BTreeSet<u32>,
    interval_s: f64,
    n_rows: usize,
) -> Option<DwellSums> {
    let slice_rows = if n_rows > DWELL_SLICE_ROWS { DWELL_SLICE_ROWS } else { n_rows.max(1) };
    file_sums_in_slices(path, cols, runs, interval_s, n_rows, slice_rows)
}

/// [`file_sums`] in slices of `slice_rows` rows (at least one).
pub(crate) fn file_sums_in_slices(
    path: &Path,
    cols: &[Col<'_>],
    runs: &BTreeSet<u32>,
    interval_s: f64,
    n_rows: usize,
    slice_rows: usize,
) -> Option<DwellSums> {
    let slice_rows = slice_rows.max(1);
    let mut out = DwellSums::default();
    let mut keys: Vec<KeyState> = Vec::new();
    let mut partials: Vec<(usize, Sum)> = Vec::new();
    for first in (0..n_rows).step_by(slice_rows) {
        let len = slice_rows.min(n_rows - first);
        let df = crate::read::read_file_slice_unchecked("dwells", path, cols, Some((first, len))).ok()?;
        partials.clear();
        for k in &mut keys {
            k.partial = NONE;
        }
        slice_sums(&df, runs, interval_s, &mut out, &mut keys, &mut partials)?;
        for (g, p) in &partials {
            out.sums[*g].add(p.value());
        }
    }
    Some(out)
}

/// A column's values without nulls, as one slice when it has one chunk.
fn f64_values<'a>(df: &'a DataFrame, name: &str) -> Option<Cow<'a, [f64]>> {
    let ca = df.column(name).ok()?.f64().ok()?;
    if ca.null_count() > 0 {
        return None;
    }
    Some(match ca.cont_slice() {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(ca.into_no_null_iter().collect()),
    })
}

/// A utf8 column mapped to indices into `names`: a string not yet there is appended when `accept`
/// takes it; `None` on a null, a string `accept` refuses, or more than 255 distinct strings.
fn label_indices(
    df: &DataFrame,
    name: &str,
    names: &mut Vec<String>,
    accept: impl Fn(&str) -> bool,
) -> Option<Vec<u8>> {
    let ca = df.column(name).ok()?.str().ok()?;
    if ca.null_count() > 0 {
        return None;
    }
    let mut out = Vec::with_capacity(ca.len());
    for arr in ca.downcast_iter() {
        let views = arr.views();
        // Equal views are equal strings (same length and bytes, inline or at the same place).
        let mut last: Option<(u128, u8)> = None;
        for (i, view) in views.iter().enumerate() {
            let view = view.as_u128();
            if let Some((v, index)) = last
                && v == view
            {
                out.push(index);
                continue;
            }
            let s = arr.value(i);
            let index = match names.iter().position(|n| n == s) {
                Some(index) => index,
                None if accept(s) && names.len() < 255 => {
                    names.push(s.to_string());
                    names.len() - 1
                }
                None => return None,
            };
            let index = u8::try_from(index).ok()?;
            last = Some((view, index));
            out.push(index);
        }
    }
    Some(out)
}

/// The rows of one slice checked and added to the slice's partial sums (`partials`), continuing
/// the per-(run, radar) state `keys` of the slices before.
fn slice_sums(
    df: &DataFrame,
    runs: &BTreeSet<u32>,
    interval_s: f64,
    out: &mut DwellSums,
    keys: &mut Vec<KeyState>,
    partials: &mut Vec<(usize, Sum)>,
) -> Option<()> {
    let run_ca = df.column("run").ok()?.u32().ok()?;
    if run_ca.null_count() > 0 {
        return None;
    }
    let run: Cow<'_, [u32]> = match run_ca.cont_slice() {
        Ok(s) => Cow::Borrowed(s),
        Err(_) => Cow::Owned(run_ca.into_no_null_iter().collect()),
    };
    let radar = label_indices(df, "radar", &mut out.radar_names, |s| RadarId::parse(s).is_some())?;
    let fixed = |list: &[&str]| list.iter().map(|s| s.to_string()).collect::<Vec<String>>();
    let role = label_indices(df, "role", &mut fixed(ROLES), |_| false)?;
    let _kind = label_indices(df, "kind", &mut fixed(KINDS), |_| false)?;
    let by = label_indices(df, "requested_by", &mut fixed(REQUESTERS), |_| false)?;
    let (t_s, duration_s, energy_j) =
        (f64_values(df, "t_s")?, f64_values(df, "duration_s")?, f64_values(df, "energy_j")?);
    let good = |v: &f64| v.is_finite() && *v >= 0.0;
    if !(t_s.iter().all(good) && duration_s.iter().all(good) && energy_j.iter().all(good)) {
        return None;
    }
    let rx = ROLES.iter().position(|r| *r == "rx").unwrap_or(usize::MAX);
    let ta = REQUESTERS.iter().position(|r| *r == "ta").unwrap_or(usize::MAX);
    let n = run.len();
    if [radar.len(), role.len(), by.len(), t_s.len(), duration_s.len(), energy_j.len()].iter().any(|&l| l != n) {
        return None;
    }
    let mut last_run = None;
    let mut last_key = 0;
    for i in 0..n {
        let (r, rad, t) = (run[i], usize::from(radar[i]), t_s[i]);
        if last_run != Some(r) {
            if !runs.contains(&r) {
                return None;
            }
            last_run = Some(r);
        }
        let k = match keys.get(last_key) {
            Some(k) if k.run == r && k.radar == rad => last_key,
            _ => match keys.iter().position(|k| k.run == r && k.radar == rad) {
                Some(k) => k,
                None => {
                    keys.push(KeyState { run: r, radar: rad, latest_t_s: t, interval: 0, group: NONE, partial: NONE });
                    keys.len() - 1
                }
            },
        };
        last_key = k;
        let key = &mut keys[k];
        if t < key.latest_t_s {
            return None;
        }
        key.latest_t_s = t;
        if usize::from(role[i]) == rx {
            continue;
        }
        // `(t_s / interval_s).cast(Int64) + 1` of `usage::transmit_sums`; beyond i64 the polars
        // read decides.
        let q = t / interval_s;
        if q.is_nan() || q >= 9.0e18 {
            return None;
        }
        let interval = q as i64 + 1;
        if key.group == NONE || key.interval != interval {
            // Times never decrease within a key, so a new interval is a new group.
            out.groups.push((r, rad, interval));
            out.sums.push(Sum::default());
            key.group = out.groups.len() - 1;
            key.interval = interval;
            key.partial = NONE;
        }
        if key.partial == NONE {
            partials.push((key.group, Sum::default()));
            key.partial = partials.len() - 1;
        }
        let (d, e) = (duration_s[i], energy_j[i]);
        let is_ta = usize::from(by[i]) == ta;
        partials[key.partial].1.add([d, e, if is_ta { d } else { 0.0 }, if is_ta { e } else { 0.0 }]);
    }
    Some(())
}
