//! Radar usage: dwell time and emitted energy per radar and scoring interval (seed paper eqs.
//! 1–6, docs/design.md §6), from the dwells' sums per run, radar and interval, which
//! `crate::dwell_sums` adds up in one pass. Means over runs are [`GroupMean`]s, taken over the
//! runs in the order of the truth table's runs.

use crate::dwell_sums::DwellSums;
use crate::error::MetricsError;
use crate::mean::GroupMean;
use crate::{RadarUsage, RunRadarUsage, SensorTotals, UsageRow, UsageTotalRow};
use mimo_core::ids::RadarId;
use std::collections::{BTreeMap, HashMap};

/// Sort radar names by their index (`R2` before `R10`), unknown spellings last.
pub(crate) fn sort_radars(radars: &mut [String]) {
    radars.sort_by_key(|r| (RadarId::parse(r).map_or(u16::MAX, |id| u16::from(id.0)), r.clone()));
}

/// Everything the usage figures need besides the dwells.
pub(crate) struct UsageInput<'a> {
    pub interval_s: f64,
    pub runs: &'a [u32],
    pub radars: &'a [String],
    /// Scorable object count at each scoring time `k = 1..=K_run`, per run (index 0 is `k = 1`).
    pub n_scorable: &'a BTreeMap<u32, Vec<u32>>,
}

pub(crate) struct UsageOutput {
    pub per_interval: Vec<UsageRow>,
    pub total: Vec<UsageTotalRow>,
    pub per_radar: Vec<RadarUsage>,
    pub per_run: Vec<RunRadarUsage>,
    /// Per run, the per-object figures summed over scoring intervals ([`per_object_by_run`]).
    pub per_object: BTreeMap<u32, [Option<f64>; 4]>,
}

/// The usage sums by (run, radar name, scoring interval).
fn sums_by_key(sums: &DwellSums) -> HashMap<(u32, &str, i64), [f64; 4]> {
    sums.groups
        .iter()
        .zip(&sums.sums)
        .map(|(&(run, radar, k), s)| ((run, sums.radar_names[radar].as_str(), k), s.value()))
        .collect()
}

/// Per run, Σ over scoring times `k` with `N_k > 0` of the run's usage sums in interval `k`
/// (every radar) ÷ `N_k`: dwell time, energy, TA dwell time, TA energy per scorable object
/// (equations 5 and 6 of docs/design.md §6 summed over the run); `None` when nothing is ever
/// scorable. Added interval by interval, radar by radar, in order.
fn per_object_by_run(sums: &DwellSums, input: &UsageInput<'_>) -> BTreeMap<u32, [Option<f64>; 4]> {
    let by_key = sums_by_key(sums);
    let mut out = BTreeMap::new();
    for &run in input.runs {
        let counts = input.n_scorable.get(&run).map(Vec::as_slice).unwrap_or(&[]);
        let mut acc: [Option<f64>; 4] = [None; 4];
        for (i, &n) in counts.iter().enumerate().filter(|(_, n)| **n > 0) {
            let k = i64::try_from(i).unwrap_or(i64::MAX - 1) + 1;
            let mut slot = [0.0; 4];
            for radar in input.radars {
                let s = by_key.get(&(run, radar.as_str(), k)).copied().unwrap_or([0.0; 4]);
                for (a, v) in slot.iter_mut().zip(s) {
                    *a += v;
                }
            }
            for (a, v) in acc.iter_mut().zip(slot) {
                *a = Some(a.unwrap_or(0.0) + v / f64::from(n));
            }
        }
        out.insert(run, acc);
    }
    out
}

/// Per radar and interval, the means over the runs that reach that scoring time (in the runs'
/// order): the raw sums (0 where a run has no dwell there), the normalized sums (null where
/// nothing is scorable) and the scorable count.
#[derive(Default)]
struct Cell {
    sums: [GroupMean; 4],
    norms: [GroupMean; 4],
    n_scorable: GroupMean,
}

fn cells<'a>(sums: &'a DwellSums, input: &UsageInput<'a>) -> BTreeMap<(&'a str, u32), Cell> {
    let by_key = sums_by_key(sums);
    let mut cells: BTreeMap<(&str, u32), Cell> = BTreeMap::new();
    for &run in input.runs {
        let counts = input.n_scorable.get(&run).map(Vec::as_slice).unwrap_or(&[]);
        for radar in input.radars {
            for (i, &n) in counts.iter().enumerate() {
                let k = i as u32 + 1;
                let s = by_key.get(&(run, radar.as_str(), i64::from(k))).copied().unwrap_or([0.0; 4]);
                let cell = cells.entry((radar.as_str(), k)).or_default();
                let objects = (n > 0).then_some(f64::from(n));
                for ((sum, norm), v) in cell.sums.iter_mut().zip(&mut cell.norms).zip(s) {
                    sum.push(Some(v));
                    norm.push(objects.map(|n| v / n));
                }
                cell.n_scorable.push(Some(f64::from(n)));
            }
        }
    }
    cells
}

/// The per-interval rows of each radar, in radar then interval order, with cumulative sums.
fn interval_rows(cells: &BTreeMap<(&str, u32), Cell>, radars: &[String], dt: f64) -> Vec<UsageRow> {
    let mut per_interval = Vec::new();
    for radar in radars {
        let mut acc = [0.0; 4];
        for ((_, k), cell) in cells.range((radar.as_str(), 0)..=(radar.as_str(), u32::MAX)) {
            let s = |q: usize| cell.sums[q].value().unwrap_or(0.0);
            let (dwell_time_s, energy_j, ta_dwell_time_s, ta_energy_j) = (s(0), s(1), s(2), s(3));
            for (a, v) in acc.iter_mut().zip([dwell_time_s, energy_j, ta_dwell_time_s, ta_energy_j]) {
                *a += v;
            }
            let figures = UsageTotalRow {
                interval: *k,
                t_start_s: f64::from(k - 1) * dt,
                t_end_s: f64::from(*k) * dt,
                runs: cell.n_scorable.count(),
                n_scorable_mean: cell.n_scorable.value().unwrap_or(0.0),
                dwell_time_s,
                energy_j,
                ta_dwell_time_s,
                ta_energy_j,
                dwell_time_per_object_s: cell.norms[0].value(),
                energy_per_object_j: cell.norms[1].value(),
                ta_dwell_time_per_object_s: cell.norms[2].value(),
                ta_energy_per_object_j: cell.norms[3].value(),
                cum_dwell_time_s: acc[0],
                cum_energy_j: acc[1],
                cum_ta_dwell_time_s: acc[2],
                cum_ta_energy_j: acc[3],
            };
            per_interval.push(UsageRow { radar: radar.clone(), figures });
        }
    }
    per_interval
}

/// Sensor totals over the whole run (every dwell, also those after the last scoring time),
/// summed over the interval groups in their order, so the same rows give the same bits; runs
/// sorted and each once.
fn run_rows(sums: &DwellSums, input: &UsageInput<'_>) -> (Vec<RunRadarUsage>, usize) {
    let totals_by_key = run_totals(sums);
    let mut per_run = Vec::with_capacity(input.runs.len() * input.radars.len());
    let mut runs_sorted = input.runs.to_vec();
    runs_sorted.sort_unstable();
    runs_sorted.dedup();
    for &run in &runs_sorted {
        for radar in input.radars {
            let s = totals_by_key.get(&(run, radar.as_str())).copied().unwrap_or([0.0; 4]);
            let totals = SensorTotals { dwell_time_s: s[0], energy_j: s[1], ta_dwell_time_s: s[2], ta_energy_j: s[3] };
            per_run.push(RunRadarUsage { run, radar: radar.clone(), totals });
        }
    }
    (per_run, runs_sorted.len())
}

/// Means over `n_runs` runs of the per-run totals, radars in id order.
fn radar_means(per_run: &[RunRadarUsage], radars: &[String], n_runs: usize) -> Vec<RadarUsage> {
    if n_runs == 0 {
        return Vec::new();
    }
    let n_runs = n_runs as f64;
    radars
        .iter()
        .map(|radar| {
            let mut acc = [0.0; 4];
            for r in per_run.iter().filter(|r| r.radar == *radar) {
                let t = &r.totals;
                for (a, v) in acc.iter_mut().zip([t.dwell_time_s, t.energy_j, t.ta_dwell_time_s, t.ta_energy_j]) {
                    *a += v;
                }
            }
            RadarUsage {
                radar: radar.clone(),
                dwell_time_s: acc[0] / n_runs,
                energy_j: acc[1] / n_runs,
                ta_dwell_time_s: acc[2] / n_runs,
                ta_energy_j: acc[3] / n_runs,
            }
        })
        .collect()
}

pub(crate) fn usage(sums: &DwellSums, input: &UsageInput<'_>) -> Result<UsageOutput, MetricsError> {
    let per_interval = interval_rows(&cells(sums, input), input.radars, input.interval_s);
    let total = totals(&per_interval, input.interval_s);
    let (per_run, n_runs) = run_rows(sums, input);
    let per_radar = radar_means(&per_run, input.radars, n_runs);
    let per_object = per_object_by_run(sums, input);
    Ok(UsageOutput { per_interval, total, per_radar, per_run, per_object })
}

/// The four usage sums over every interval group of each (run, radar), added in group order.
fn run_totals(sums: &DwellSums) -> BTreeMap<(u32, &str), [f64; 4]> {
    let mut out: BTreeMap<(u32, &str), [f64; 4]> = BTreeMap::new();
    for (&(run, radar, _), s) in sums.groups.iter().zip(&sums.sums) {
        let acc = out.entry((run, sums.radar_names[radar].as_str())).or_insert([0.0; 4]);
        for (a, v) in acc.iter_mut().zip(s.value()) {
            *a += v;
        }
    }
    out
}

/// Sum the per-radar interval rows over radars.
fn totals(rows: &[UsageRow], dt: f64) -> Vec<UsageTotalRow> {
    let mut by_k: BTreeMap<u32, UsageTotalRow> = BTreeMap::new();
    let add = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(x), Some(y)) => Some(x + y),
        (x, None) => x,
        (None, y) => y,
    };
    for r in rows {
        let e = by_k.entry(r.interval).or_insert_with(|| UsageTotalRow {
            interval: r.interval,
            t_start_s: f64::from(r.interval - 1) * dt,
            t_end_s: f64::from(r.interval) * dt,
            runs: r.runs,
            n_scorable_mean: r.n_scorable_mean,
            ..UsageTotalRow::default()
        });
        e.dwell_time_s += r.dwell_time_s;
        e.energy_j += r.energy_j;
        e.ta_dwell_time_s += r.ta_dwell_time_s;
        e.ta_energy_j += r.ta_energy_j;
        e.dwell_time_per_object_s = add(e.dwell_time_per_object_s, r.dwell_time_per_object_s);
        e.energy_per_object_j = add(e.energy_per_object_j, r.energy_per_object_j);
        e.ta_dwell_time_per_object_s = add(e.ta_dwell_time_per_object_s, r.ta_dwell_time_per_object_s);
        e.ta_energy_per_object_j = add(e.ta_energy_per_object_j, r.ta_energy_per_object_j);
        e.cum_dwell_time_s += r.cum_dwell_time_s;
        e.cum_energy_j += r.cum_energy_j;
        e.cum_ta_dwell_time_s += r.cum_ta_dwell_time_s;
        e.cum_ta_energy_j += r.cum_ta_energy_j;
    }
    by_k.into_values().collect()
}
