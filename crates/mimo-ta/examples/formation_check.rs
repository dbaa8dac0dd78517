//! Evaluation of a recorded run directory for the formation goals: fighter and airliner
//! track NEES against truth, and search starvation (the longest stretch without a search dwell,
//! per radar). Reads truth, so it is an evaluation tool, never part of a test article.
//!
//! `cargo run --example formation_check -- RUN_DIR`
//!
//! NEES: every confirmed-track row written after an update (n_updates ≥ 3) is paired with the
//! truth nearest in position at that time (same run, within 5 km); the truth is moved to the row
//! time along its sampled velocity. ε = (x̂ − x)ᵀ P⁻¹ (x̂ − x) over the 6-state [p; v] in ECEF,
//! χ²₆ when the filter is consistent (mean 6). Targets named `F-…` are fighters.
//!
//! The fighter rows are also split by the kind of the row's last measurement (`merged`; `split`:
//! another measurement of the same dwell and channel within 3 cells of range, a two-target
//! member or a close neighbour; `clean` otherwise) and by whether its dominant target
//! (`target_hint`) is the nearest truth; and ε is also given against the last measurement's
//! dominant target ("followed"), which differs from the nearest truth when a track sits on one
//! aircraft's range with another's cross-range
//! (docs/decisions/0045-fighter-nees-on-score-assignment.md), and against the truth
//! nearest in the track's own metric (the smallest ε over the truths sampled within 2 s).
//!
//! When the run has been scored, ε is also given against the truth the score's assignment
//! (docs/design.md §6, `score/assignments.parquet`) gives the track at the first scoring time
//! at or after the row (within one interval, 1 s): the pairing every track metric uses. Rows of
//! a track unassigned then are left out of that figure.

use mimo_core::records::{DwellKind, MeasurementRow, TrackRow, TrackStatus, TruthRow, unpack_cov};
use mimo_store::read_table_dir;
use mimo_track::linalg::{chol_mahalanobis, cholesky};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// (run, track id) -> (scoring time, assigned truth), by time, from `score/assignments.parquet`;
/// `None` when the run has not been scored.
type Assigned = BTreeMap<(u32, u64), Vec<(f64, String)>>;

fn assignments(dir: &Path) -> Option<Assigned> {
    use arrow::array::{Array, Float64Array, StringArray, UInt32Array, UInt64Array};
    let file = std::fs::File::open(dir.join("score").join("assignments.parquet")).ok()?;
    let reader = parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(file).ok()?.build().ok()?;
    let mut out: Assigned = BTreeMap::new();
    for batch in reader {
        let b = batch.ok()?;
        let run = b.column_by_name("run")?.as_any().downcast_ref::<UInt32Array>()?;
        let t = b.column_by_name("t_s")?.as_any().downcast_ref::<Float64Array>()?;
        let target = b.column_by_name("target")?.as_any().downcast_ref::<StringArray>()?;
        let track = b.column_by_name("track_id")?.as_any().downcast_ref::<UInt64Array>()?;
        for i in 0..b.num_rows() {
            if !track.is_null(i) {
                out.entry((run.value(i), track.value(i))).or_default().push((t.value(i), target.value(i).to_string()));
            }
        }
    }
    for v in out.values_mut() {
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
    }
    Some(out)
}

fn main() {
    let Some(dir) = std::env::args().nth(1).map(PathBuf::from) else {
        eprintln!("usage: formation_check RUN_DIR");
        std::process::exit(2);
    };
    if let Err(e) = run(&dir) {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

fn run(dir: &std::path::Path) -> Result<(), mimo_store::StoreError> {
    let truth: Vec<TruthRow> = read_table_dir(dir, "truth")?;
    let tracks: Vec<TrackRow> = read_table_dir(dir, "tracks")?;
    // (run, target) -> samples by time.
    let mut by_target: BTreeMap<(u32, String), Vec<&TruthRow>> = BTreeMap::new();
    for t in &truth {
        by_target.entry((t.run, t.target.clone())).or_default().push(t);
    }
    for v in by_target.values_mut() {
        v.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    }
    let measurements: Vec<MeasurementRow> = read_table_dir(dir, "measurements")?;
    // (run, meas_id) -> (kind, dominant target).
    let mut channel: BTreeMap<(u32, u64, String, String), Vec<&MeasurementRow>> = BTreeMap::new();
    for m in &measurements {
        channel.entry((m.run, m.dwell_id, m.rx.to_string(), m.tx.to_string())).or_default().push(m);
    }
    let mut kind_of: BTreeMap<(u32, u64), (&'static str, Option<&str>)> = BTreeMap::new();
    for ms in channel.values() {
        for m in ms {
            let close = ms.iter().any(|o| o.meas_id != m.meas_id && (o.range_m - m.range_m).abs() < 90.0);
            let kind = if m.merged {
                "merged"
            } else if close {
                "split"
            } else {
                "clean"
            };
            kind_of.insert((m.run, m.meas_id), (kind, m.target_hint.as_deref()));
        }
    }
    let mut nees: BTreeMap<&str, Vec<f64>> = BTreeMap::new();
    // (kind, hint is the nearest truth) -> fighter ε.
    let mut by_kind: BTreeMap<(&str, bool), Vec<f64>> = BTreeMap::new();
    let mut followed: Vec<f64> = Vec::new();
    // Fighter rows: (ε against the nearest truth in position, ε against the nearest in the track's
    // own metric, i.e. the smallest ε over the truths).
    let mut metric_nearest: Vec<(f64, f64)> = Vec::new();
    let assigned = assignments(dir);
    // Fighter rows' ε against the truth the score assigns the track; rows left unassigned.
    let (mut by_assignment, mut unassigned): (Vec<f64>, usize) = (Vec::new(), 0);
    for r in tracks.iter().filter(|r| r.status == TrackStatus::Confirmed && r.n_updates >= 3) {
        let last = r.last_meas_id.and_then(|id| kind_of.get(&(r.run, id))).copied();
        let mut at_hint: Option<[f64; 6]> = None;
        let assigned_to: Option<&str> = assigned.as_ref().and_then(|a| {
            let v = a.get(&(r.run, r.track_id))?;
            let k = v.partition_point(|(t, _)| *t < r.t_s);
            v.get(k).filter(|(t, _)| *t - r.t_s <= 1.0 + 1e-9).map(|(_, name)| name.as_str())
        });
        let mut at_assigned: Option<([f64; 6], bool)> = None;
        let mut candidates: Vec<[f64; 6]> = Vec::new();
        let mut best: Option<(f64, [f64; 6], bool, &str)> = None;
        for ((run, name), samples) in &by_target {
            if *run != r.run {
                continue;
            }
            let k = samples.partition_point(|s| s.t_s <= r.t_s);
            let s = match (k.checked_sub(1).map(|i| samples[i]), samples.get(k)) {
                (Some(a), Some(b)) => {
                    if r.t_s - a.t_s <= b.t_s - r.t_s {
                        a
                    } else {
                        *b
                    }
                }
                (Some(a), None) => a,
                (None, Some(b)) => *b,
                (None, None) => continue,
            };
            if (s.t_s - r.t_s).abs() > 2.0 {
                continue;
            }
            let dt = r.t_s - s.t_s;
            let x = [s.x_m + s.vx_mps * dt, s.y_m + s.vy_mps * dt, s.z_m + s.vz_mps * dt, s.vx_mps, s.vy_mps, s.vz_mps];
            let d2 = (x[0] - r.x_m).powi(2) + (x[1] - r.y_m).powi(2) + (x[2] - r.z_m).powi(2);
            candidates.push(x);
            if last.and_then(|k| k.1) == Some(name.as_str()) {
                at_hint = Some(x);
            }
            if assigned_to == Some(name.as_str()) {
                at_assigned = Some((x, name.starts_with("F-")));
            }
            if d2 < 5000.0f64.powi(2) && best.is_none_or(|b| d2 < b.0) {
                best = Some((d2, x, name.starts_with("F-"), name.as_str()));
            }
        }
        let Some((_, x, fighter, nearest)) = best else { continue };
        let err = |x: &[f64; 6]| {
            [r.x_m - x[0], r.y_m - x[1], r.z_m - x[2], r.vx_mps - x[3], r.vy_mps - x[4], r.vz_mps - x[5]]
        };
        let Some(l) = cholesky(&unpack_cov(&r.cov)) else { continue };
        let eps = chol_mahalanobis(&l, &err(&x));
        match at_assigned {
            Some((xa, true)) => by_assignment.push(chol_mahalanobis(&l, &err(&xa))),
            Some((_, false)) => {}
            None => unassigned += usize::from(fighter),
        }
        nees.entry(if fighter { "fighters" } else { "airliners" }).or_default().push(eps);
        if fighter {
            let (kind, hint) = last.unwrap_or(("none", None));
            by_kind.entry((kind, hint == Some(nearest))).or_default().push(eps);
            if let Some(xh) = at_hint {
                followed.push(chol_mahalanobis(&l, &err(&xh)));
            }
            let min = candidates.iter().map(|c| chol_mahalanobis(&l, &err(c))).fold(eps, f64::min);
            metric_nearest.push((eps, min));
        }
    }
    println!("track NEES (6-state, χ²₆ mean 6):");
    for (class, mut v) in nees {
        v.sort_by(f64::total_cmp);
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let q = |p: f64| v[((v.len() - 1) as f64 * p) as usize];
        let inside = v.iter().filter(|&&x| x <= 16.81).count() as f64 / v.len() as f64;
        println!(
            "  {class:9} rows {:7}  mean {mean:8.2}  median {:6.2}  p90 {:7.2}  within χ²₆ 99 % ({:.1} %)",
            v.len(),
            q(0.5),
            q(0.9),
            100.0 * inside
        );
    }
    println!("fighter NEES by the last measurement (kind, its dominant target is the nearest truth):");
    for ((kind, right), v) in &by_kind {
        let mean = v.iter().sum::<f64>() / v.len() as f64;
        let big = v.iter().filter(|&&x| x > 100.0).count();
        println!(
            "  {kind:6} {right:5}  rows {:6}  mean {mean:9.2}  sum {:11.0}  rows > 100: {big}",
            v.len(),
            mean * v.len() as f64
        );
    }
    if !followed.is_empty() {
        followed.sort_by(f64::total_cmp);
        let mean = followed.iter().sum::<f64>() / followed.len() as f64;
        println!(
            "fighter NEES against the last measurement's dominant target: rows {}  mean {mean:.2}  median {:.2}",
            followed.len(),
            followed[followed.len() / 2]
        );
    }
    if !metric_nearest.is_empty() {
        let n = metric_nearest.len() as f64;
        let total: f64 = metric_nearest.iter().map(|p| p.0).sum();
        let other: Vec<f64> = metric_nearest.iter().filter(|p| p.1 < p.0).map(|p| p.0).collect();
        let other_sum: f64 = other.iter().sum();
        let same_mean = (total - other_sum) / (n - other.len() as f64).max(1.0);
        println!(
            "fighter NEES against the truth nearest in the track's metric (smallest ε): mean {:.2}; rows whose \
             nearest truth in position is another: {} ({:.2} %), {:.1} % of the NEES sum; the other rows' mean {same_mean:.2}",
            metric_nearest.iter().map(|p| p.1).sum::<f64>() / n,
            other.len(),
            100.0 * other.len() as f64 / n,
            100.0 * other_sum / total.max(f64::MIN_POSITIVE),
        );
    }
    match (&assigned, by_assignment.len()) {
        (None, _) => {
            println!("fighter NEES against the score's assignment: run not scored (no score/assignments.parquet)")
        }
        (Some(_), 0) => println!("fighter NEES against the score's assignment: no assigned fighter rows"),
        (Some(_), n) => {
            by_assignment.sort_by(f64::total_cmp);
            println!(
                "fighter NEES against the truth the score assigns the track: rows {n}  mean {:.2}  median {:.2}  \
                 (fighter rows of tracks unassigned at the next scoring time: {unassigned})",
                by_assignment.iter().sum::<f64>() / n as f64,
                by_assignment[n / 2]
            );
        }
    }
    drop(tracks);
    drop(truth);
    drop(measurements);
    let dwells: Vec<mimo_core::records::DwellRow> = read_table_dir(dir, "dwells")?;
    // (radar, run) -> search start times.
    let mut search: BTreeMap<(String, u32), Vec<f64>> = BTreeMap::new();
    let mut t_end: BTreeMap<u32, f64> = BTreeMap::new();
    for d in &dwells {
        let end = t_end.entry(d.run).or_insert(0.0);
        *end = end.max(d.t_s + d.duration_s);
        if d.kind == DwellKind::Search {
            search.entry((d.radar.to_string(), d.run)).or_default().push(d.t_s);
        }
    }
    // FORMATION_DUMP="R1 0 208 212": that radar's dwells of one run in a time span.
    if let Ok(spec) = std::env::var("FORMATION_DUMP") {
        let f: Vec<&str> = spec.split_whitespace().collect();
        if let [radar, run, from, to] = f[..] {
            let (run, from, to): (u32, f64, f64) =
                (run.parse().unwrap_or(0), from.parse().unwrap_or(0.0), to.parse().unwrap_or(0.0));
            for d in
                dwells.iter().filter(|d| d.radar.to_string() == radar && d.run == run && d.t_s >= from && d.t_s < to)
            {
                println!(
                    "  {:9.4} {:7.4} s {:?} {:?} {:?} n={}",
                    d.t_s, d.duration_s, d.kind, d.role, d.requested_by, d.n_pulses
                );
            }
        }
    }
    let mut worst: BTreeMap<String, (f64, f64, u32)> = BTreeMap::new();
    for ((radar, run), mut ts) in search {
        ts.sort_by(f64::total_cmp);
        let mut gap_max = ts.first().copied().unwrap_or(0.0);
        let mut at = 0.0;
        for w in ts.windows(2) {
            if w[1] - w[0] > gap_max {
                gap_max = w[1] - w[0];
                at = w[0];
            }
        }
        let e = worst.entry(radar).or_insert((0.0, 0.0, 0));
        if gap_max > e.0 {
            *e = (gap_max, at, run);
        }
    }
    println!("longest search stop per radar (max over runs):");
    for (radar, (gap, at, run)) in worst {
        println!("  {radar}: {gap:7.2} s (run {run}, from t = {at:.1} s)");
    }
    Ok(())
}
