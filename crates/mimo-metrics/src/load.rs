//! Loading the scorer's inputs: the truth, tracks and dwells tables of a run, checked column by
//! column (see the crate docs, "Errors"), into the structures the per-run scoring walks.

use crate::MetricsError;
use crate::error;
use crate::read::{Check, Want, col as rcol, read_file, read_table_checked};
use crate::track_metrics::{TargetTruth, TrackLife, TrackState, TruthSample};
use glam::DVec3;
use mimo_core::records::TrackStatus;
use polars::prelude::*;
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

pub(crate) const TRACK_STATUSES: &[&str] = &["tentative", "confirmed", "deleted"];
pub(crate) const ROLES: &[&str] = &["tx", "rx", "txrx"];
pub(crate) const REQUESTERS: &[&str] = &["radar", "ta"];
pub(crate) const KINDS: &[&str] = &["search", "confirm", "track", "mimo"];

pub(crate) fn u32s(df: &DataFrame, name: &str) -> Result<Vec<u32>, MetricsError> {
    let c = df.column(name).map_err(error::internal("column"))?;
    Ok(c.u32().map_err(error::internal("column"))?.no_null_iter().collect())
}
pub(crate) fn u64s(df: &DataFrame, name: &str) -> Result<Vec<u64>, MetricsError> {
    let c = df.column(name).map_err(error::internal("column"))?;
    Ok(c.u64().map_err(error::internal("column"))?.no_null_iter().collect())
}
pub(crate) fn f64s(df: &DataFrame, name: &str) -> Result<Vec<f64>, MetricsError> {
    let c = df.column(name).map_err(error::internal("column"))?;
    Ok(c.f64().map_err(error::internal("column"))?.no_null_iter().collect())
}
pub(crate) fn vec3s(df: &DataFrame, names: [&str; 3]) -> Result<Vec<DVec3>, MetricsError> {
    let (x, y, z) = (f64s(df, names[0])?, f64s(df, names[1])?, f64s(df, names[2])?);
    Ok(x.iter().zip(&y).zip(&z).map(|((&x, &y), &z)| DVec3::new(x, y, z)).collect())
}

/// Truth grouped by run and target.
pub(crate) struct Truth {
    pub(crate) runs: Vec<u32>,
    pub(crate) target_names: Vec<String>,
    pub(crate) per_run: BTreeMap<u32, Vec<TargetTruth>>,
    pub(crate) t_end: BTreeMap<u32, f64>,
}

pub(crate) fn load_truth(paths: &[PathBuf]) -> Result<Truth, MetricsError> {
    use Check::*;
    use Want::*;
    let cols = [
        rcol("run", U32, Any),
        rcol("t_s", F64, Finite),
        rcol("target", Utf8, Any),
        rcol("x_m", F64, Finite),
        rcol("y_m", F64, Finite),
        rcol("z_m", F64, Finite),
        rcol("vx_mps", F64, Finite),
        rcol("vy_mps", F64, Finite),
        rcol("vz_mps", F64, Finite),
        rcol("alt_m", F64, Finite),
    ];
    let df = read_table_checked("truth", paths, &cols, &crate::rules::check_truth)?;
    let df = df
        .sort(["run", "target", "t_s"], SortMultipleOptions::default().with_maintain_order(true))
        .map_err(error::internal("sorting truth"))?;
    let run = u32s(&df, "run")?;
    let t = f64s(&df, "t_s")?;
    let p = vec3s(&df, ["x_m", "y_m", "z_m"])?;
    let v = vec3s(&df, ["vx_mps", "vy_mps", "vz_mps"])?;
    let alt = f64s(&df, "alt_m")?;
    let target_col = df.column("target").map_err(error::internal("truth target"))?;
    let targets = target_col.str().map_err(error::internal("truth target"))?;

    let mut names: BTreeSet<String> = BTreeSet::new();
    for s in targets.no_null_iter() {
        if !names.contains(s) {
            names.insert(s.to_string());
        }
    }
    let target_names: Vec<String> = names.into_iter().collect();
    let index: BTreeMap<&str, usize> = target_names.iter().enumerate().map(|(i, s)| (s.as_str(), i)).collect();

    let mut per_run: BTreeMap<u32, Vec<TargetTruth>> = BTreeMap::new();
    let mut t_end: BTreeMap<u32, f64> = BTreeMap::new();
    let mut current: Option<(u32, &str)> = None;
    for (i, name) in targets.no_null_iter().enumerate() {
        let key = (run[i], name);
        let list = per_run.entry(run[i]).or_default();
        if current != Some(key) {
            let target = index.get(name).copied().unwrap_or(0);
            list.push(TargetTruth { target, samples: Vec::new() });
            current = Some(key);
        }
        if let Some(tt) = list.last_mut() {
            tt.samples.push(TruthSample { t: t[i], p: p[i], v: v[i], alt: alt[i] });
        }
        let e = t_end.entry(run[i]).or_insert(f64::NEG_INFINITY);
        *e = e.max(t[i]);
    }
    Ok(Truth { runs: per_run.keys().copied().collect(), target_names, per_run, t_end })
}

pub(crate) fn load_tracks(
    paths: &[PathBuf],
    runs: &BTreeSet<u32>,
) -> Result<BTreeMap<u32, Vec<TrackLife>>, MetricsError> {
    use Check::*;
    use Want::*;
    let cols = [
        rcol("run", U32, RunIn(runs)),
        rcol("t_s", F64, Finite),
        rcol("track_id", U64, Any),
        rcol("status", Utf8, OneOf(TRACK_STATUSES)),
        rcol("x_m", F64, Finite),
        rcol("y_m", F64, Finite),
        rcol("z_m", F64, Finite),
        rcol("vx_mps", F64, Finite),
        rcol("vy_mps", F64, Finite),
        rcol("vz_mps", F64, Finite),
    ];
    let df = read_table_checked("tracks", paths, &cols, &crate::rules::check_tracks)?;
    let df = df
        .sort(["run", "track_id", "t_s"], SortMultipleOptions::default().with_maintain_order(true))
        .map_err(error::internal("sorting tracks"))?;
    let run = u32s(&df, "run")?;
    let id = u64s(&df, "track_id")?;
    let t = f64s(&df, "t_s")?;
    let p = vec3s(&df, ["x_m", "y_m", "z_m"])?;
    let v = vec3s(&df, ["vx_mps", "vy_mps", "vz_mps"])?;
    let status_col = df.column("status").map_err(error::internal("track status"))?;
    let status = status_col.str().map_err(error::internal("track status"))?;

    let mut out: BTreeMap<u32, Vec<TrackLife>> = BTreeMap::new();
    let mut current: Option<(u32, u64)> = None;
    let mut ended = false;
    for (i, s) in status.no_null_iter().enumerate() {
        let key = (run[i], id[i]);
        let list = out.entry(run[i]).or_default();
        if current != Some(key) {
            list.push(TrackLife { id: id[i], t_confirm: f64::INFINITY, t_delete: f64::INFINITY, states: Vec::new() });
            current = Some(key);
            ended = false;
        }
        let Some(tr) = list.last_mut() else { continue };
        if ended {
            continue;
        }
        match TrackStatus::parse(s) {
            Some(TrackStatus::Deleted) => {
                tr.t_delete = t[i];
                ended = true;
            }
            Some(TrackStatus::Confirmed) => {
                if !tr.t_confirm.is_finite() {
                    tr.t_confirm = t[i];
                }
                tr.states.push(TrackState { t: t[i], p: p[i], v: v[i] });
            }
            _ => tr.states.push(TrackState { t: t[i], p: p[i], v: v[i] }),
        }
    }
    Ok(out)
}

/// The dwells table reduced to what the usage figures need: the transmit sums per run, radar and
/// scoring interval (see [`crate::usage::transmit_sums`]), and every radar named in it (any role).
///
/// Files are read one at a time, only the columns of [`dwell_file_sums`], each validated and
/// reduced to its sums before the next is read, so memory follows one file (one run by
/// convention, docs/design.md §2) rather than the whole recording. (Reading two files at once on
/// two workers saved 3 % of the wall time of a 10-run score and raised its peak RSS from 377 to
/// 572 MB: not done.) The per-file sums are stacked and summed again by key, so a run
/// split over several files gives the same figures (to rounding). With one file per run the rows
/// come out in the order a single pass over all dwells would give (groups in order of first
/// appearance), so the figures are the very numbers of that pass, bit for bit.
pub(crate) fn load_dwell_sums(
    paths: &[PathBuf],
    runs: &BTreeSet<u32>,
    interval_s: f64,
) -> Result<(DataFrame, BTreeSet<String>), MetricsError> {
    if paths.is_empty() {
        return Err(MetricsError::MissingTable {
            table: "dwells",
            path: PathBuf::from("dwells"),
            detail: "no Parquet files given".into(),
        });
    }
    let mut radars = BTreeSet::new();
    let mut sums: Option<DataFrame> = None;
    for path in paths {
        let (part, part_radars) = dwell_file_sums(path, runs, interval_s)?;
        radars.extend(part_radars);
        match sums.as_mut() {
            None => sums = Some(part),
            Some(acc) => {
                acc.vstack_mut_owned(part).map_err(error::internal("stacking usage sums"))?;
            }
        }
    }
    let sums = sums.ok_or_else(|| MetricsError::Internal { context: "reading", detail: "no files".into() })?;
    let sums = if paths.len() > 1 { crate::usage::resum(sums)? } else { sums };
    Ok((sums, radars))
}

/// One dwells file read, checked and reduced to its usage sums and the radars it names.
fn dwell_file_sums(
    path: &std::path::Path,
    runs: &BTreeSet<u32>,
    interval_s: f64,
) -> Result<(DataFrame, BTreeSet<String>), MetricsError> {
    use Check::*;
    use Want::*;
    let cols = [
        rcol("run", U32, RunIn(runs)),
        rcol("radar", Utf8, Radar),
        rcol("role", Utf8, OneOf(ROLES)),
        rcol("kind", Utf8, OneOf(KINDS)),
        rcol("requested_by", Utf8, OneOf(REQUESTERS)),
        rcol("t_s", F64, FiniteNonNeg),
        rcol("duration_s", F64, FiniteNonNeg),
        rcol("energy_j", F64, FiniteNonNeg),
    ];
    let df = read_file("dwells", path, &cols)?;
    crate::rules::check_dwells(path, &df)?;
    let c = df.column("radar").map_err(error::internal("dwell radars"))?;
    let u = c.unique().map_err(error::internal("dwell radars"))?;
    let radars = u.str().map_err(error::internal("dwell radars"))?.no_null_iter().map(str::to_string).collect();
    let part = crate::usage::transmit_sums(&df, interval_s).collect().map_err(error::internal("usage sums"))?;
    Ok((part, radars))
}
