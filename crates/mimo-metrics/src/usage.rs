//! Radar usage: dwell time and emitted energy per radar and scoring interval (seed paper eqs.
//! 1–6, docs/design.md §6), computed with polars from the dwells' sums per run, radar and
//! interval, which `crate::dwell_sums` adds up in one pass ([`transmit_sums`] is the polars
//! form of those sums: the reference it is tested against, and the way a file that breaks a
//! check is read).

use crate::error::{MetricsError, internal};
use crate::{RadarUsage, RunRadarUsage, UsageRow, UsageTotalRow};
use mimo_core::ids::RadarId;
use polars::prelude::*;
use std::collections::BTreeMap;

pub(crate) const SUMS: [&str; 4] = ["dwell_time_s", "energy_j", "ta_dwell_time_s", "ta_energy_j"];
const NORMS: [&str; 4] =
    ["dwell_time_per_object_s", "energy_per_object_j", "ta_dwell_time_per_object_s", "ta_energy_per_object_j"];

/// Sort radar names by their index (`R2` before `R10`), unknown spellings last.
pub(crate) fn sort_radars(radars: &mut [String]) {
    radars.sort_by_key(|r| (RadarId::parse(r).map_or(u16::MAX, |id| u16::from(id.0)), r.clone()));
}

/// Sums of the four usage figures over the transmit dwells of `dwells`, per run, radar and
/// interval (columns `run`, `radar`, `interval` and [`SUMS`]). The interval of a dwell starting at
/// `t_s >= 0` is `floor(t_s / interval_s) + 1`. Every interval is kept, also those after the last
/// scoring time, so that the sensor totals can be summed from these rows.
pub(crate) fn transmit_sums(dwells: &DataFrame, interval_s: f64) -> LazyFrame {
    let is_ta = col("requested_by").eq(lit("ta"));
    dwells
        .clone()
        .lazy()
        .filter(col("role").neq(lit("rx")))
        .select([
            col("run"),
            col("radar"),
            ((col("t_s") / lit(interval_s)).cast(DataType::Int64) + lit(1i64)).alias("interval"),
            col("duration_s"),
            col("energy_j"),
            when(is_ta.clone()).then(col("duration_s")).otherwise(lit(0.0)).alias("ta_duration_s"),
            when(is_ta).then(col("energy_j")).otherwise(lit(0.0)).alias("ta_energy_j_row"),
        ])
        .group_by_stable([col("run"), col("radar"), col("interval")])
        .agg([
            col("duration_s").sum().alias(SUMS[0]),
            col("energy_j").sum().alias(SUMS[1]),
            col("ta_duration_s").sum().alias(SUMS[2]),
            col("ta_energy_j_row").sum().alias(SUMS[3]),
        ])
}

/// Sum stacked [`transmit_sums`] rows of several files again by run, radar and interval (what
/// `crate::dwell_sums` does in Rust; kept to test it against).
#[cfg(test)]
pub(crate) fn resum(sums: DataFrame) -> Result<DataFrame, MetricsError> {
    sums.lazy()
        .group_by_stable([col("run"), col("radar"), col("interval")])
        .agg(SUMS.iter().map(|s| col(*s).sum()).collect::<Vec<_>>())
        .collect()
        .map_err(internal("usage sums"))
}

fn f64_col(df: &DataFrame, name: &str) -> Result<Vec<Option<f64>>, MetricsError> {
    let c = df.column(name).map_err(internal("usage column"))?;
    let c = c.cast(&DataType::Float64).map_err(internal("usage column"))?;
    Ok(c.f64().map_err(internal("usage column"))?.iter().collect())
}

fn str_col(df: &DataFrame, name: &str) -> Result<Vec<String>, MetricsError> {
    let c = df.column(name).map_err(internal("usage column"))?;
    Ok(c.str().map_err(internal("usage column"))?.iter().map(|s| s.unwrap_or_default().to_string()).collect())
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
}

pub(crate) fn usage(interval_sums: DataFrame, input: &UsageInput<'_>) -> Result<UsageOutput, MetricsError> {
    let dt = input.interval_s;
    // The full grid run × radar × interval, with the scorable count of the interval (its scoring
    // time closes it); `n_objects` is null where nothing is scorable.
    let (mut g_run, mut g_radar, mut g_interval, mut g_n, mut g_obj) = (vec![], vec![], vec![], vec![], vec![]);
    for &run in input.runs {
        let counts = input.n_scorable.get(&run).map(Vec::as_slice).unwrap_or(&[]);
        for radar in input.radars {
            for (i, &n) in counts.iter().enumerate() {
                g_run.push(run);
                g_radar.push(radar.clone());
                g_interval.push(i as i64 + 1);
                g_n.push(n);
                g_obj.push((n > 0).then_some(f64::from(n)));
            }
        }
    }
    let grid = DataFrame::new_infer_height(vec![
        Column::new("run".into(), g_run),
        Column::new("radar".into(), g_radar),
        Column::new("interval".into(), g_interval),
        Column::new("n_scorable".into(), g_n),
        Column::new("n_objects".into(), g_obj),
    ])
    .map_err(internal("usage grid"))?;

    // `interval_sums`: the dwells' sums per run, radar and interval (see `transmit_sums`).
    let keys = [col("run"), col("radar"), col("interval")];
    let mut norm_exprs: Vec<Expr> = SUMS.iter().map(|s| col(*s).fill_null(lit(0.0))).collect();
    norm_exprs.push(col("n_scorable").cast(DataType::Float64));
    let filled = grid
        .lazy()
        .join(interval_sums.clone().lazy(), keys.clone(), keys, JoinArgs::new(JoinType::Left))
        .with_columns(norm_exprs)
        .with_columns(SUMS.iter().zip(NORMS).map(|(s, n)| (col(*s) / col("n_objects")).alias(n)).collect::<Vec<_>>());
    let mut aggs: Vec<Expr> = SUMS.iter().chain(NORMS.iter()).map(|s| col(*s).mean()).collect();
    aggs.push(col("n_scorable").mean().alias("n_scorable_mean"));
    aggs.push(col("run").count().alias("runs"));
    let per = filled
        .group_by_stable([col("radar"), col("interval")])
        .agg(aggs)
        .sort(["radar", "interval"], SortMultipleOptions::default())
        .collect()
        .map_err(internal("usage per interval"))?;

    let radar = str_col(&per, "radar")?;
    let interval = f64_col(&per, "interval")?;
    let runs = f64_col(&per, "runs")?;
    let n_mean = f64_col(&per, "n_scorable_mean")?;
    let sums: Vec<Vec<Option<f64>>> = SUMS.iter().map(|s| f64_col(&per, s)).collect::<Result<_, _>>()?;
    let norms: Vec<Vec<Option<f64>>> = NORMS.iter().map(|s| f64_col(&per, s)).collect::<Result<_, _>>()?;

    let mut by_radar: BTreeMap<String, Vec<UsageRow>> = BTreeMap::new();
    for i in 0..per.height() {
        let k = interval[i].unwrap_or(0.0) as u32;
        let s = |q: usize| sums[q][i].unwrap_or(0.0);
        by_radar.entry(radar[i].clone()).or_default().push(UsageRow {
            radar: radar[i].clone(),
            interval: k,
            t_start_s: f64::from(k - 1) * dt,
            t_end_s: f64::from(k) * dt,
            runs: runs[i].unwrap_or(0.0) as u32,
            n_scorable_mean: n_mean[i].unwrap_or(0.0),
            dwell_time_s: s(0),
            energy_j: s(1),
            ta_dwell_time_s: s(2),
            ta_energy_j: s(3),
            dwell_time_per_object_s: norms[0][i],
            energy_per_object_j: norms[1][i],
            ta_dwell_time_per_object_s: norms[2][i],
            ta_energy_per_object_j: norms[3][i],
            cum_dwell_time_s: 0.0,
            cum_energy_j: 0.0,
            cum_ta_dwell_time_s: 0.0,
            cum_ta_energy_j: 0.0,
        });
    }
    // Cumulative sums over intervals (of the run-averaged sums), then the radars in id order.
    let mut per_interval = Vec::new();
    for radar in input.radars {
        let Some(mut rows) = by_radar.remove(radar) else { continue };
        rows.sort_by_key(|r| r.interval);
        let mut acc = [0.0; 4];
        for r in &mut rows {
            acc[0] += r.dwell_time_s;
            acc[1] += r.energy_j;
            acc[2] += r.ta_dwell_time_s;
            acc[3] += r.ta_energy_j;
            (r.cum_dwell_time_s, r.cum_energy_j, r.cum_ta_dwell_time_s, r.cum_ta_energy_j) =
                (acc[0], acc[1], acc[2], acc[3]);
        }
        per_interval.extend(rows);
    }
    let total = totals(&per_interval, dt);

    // Sensor totals over the whole run (every dwell, also those after the last scoring time),
    // summed over the interval rows in their order, so the same rows give the same bits (a polars
    // grouped sum of floats did not, run to run).
    let totals_by_key = run_totals(&interval_sums)?;
    let mut per_run = Vec::with_capacity(input.runs.len() * input.radars.len());
    let mut runs_sorted = input.runs.to_vec();
    runs_sorted.sort_unstable();
    runs_sorted.dedup();
    for &run in &runs_sorted {
        for radar in input.radars {
            let s = totals_by_key.get(&(run, radar.as_str())).copied().unwrap_or([0.0; 4]);
            per_run.push(RunRadarUsage {
                run,
                radar: radar.clone(),
                dwell_time_s: s[0],
                energy_j: s[1],
                ta_dwell_time_s: s[2],
                ta_energy_j: s[3],
            });
        }
    }
    // Means over runs, radars in id order.
    let n_runs = runs_sorted.len() as f64;
    let per_radar: Vec<RadarUsage> = if runs_sorted.is_empty() {
        Vec::new()
    } else {
        input
            .radars
            .iter()
            .map(|radar| {
                let mut acc = [0.0; 4];
                for r in per_run.iter().filter(|r| r.radar == *radar) {
                    for (a, v) in acc.iter_mut().zip([r.dwell_time_s, r.energy_j, r.ta_dwell_time_s, r.ta_energy_j]) {
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
    };

    Ok(UsageOutput { per_interval, total, per_radar, per_run })
}

/// The four sums of [`SUMS`] over every interval row of each (run, radar), added in row order.
fn run_totals(interval_sums: &DataFrame) -> Result<BTreeMap<(u32, &str), [f64; 4]>, MetricsError> {
    let run = interval_sums.column("run").map_err(internal("usage run"))?;
    let run = run.u32().map_err(internal("usage run"))?;
    let radar = interval_sums.column("radar").map_err(internal("usage radar"))?;
    let radar = radar.str().map_err(internal("usage radar"))?;
    let sums = SUMS
        .iter()
        .map(|s| {
            let c = interval_sums.column(s).map_err(internal("usage sums"))?;
            Ok(c.f64().map_err(internal("usage sums"))?.iter().map(|v| v.unwrap_or(0.0)).collect::<Vec<f64>>())
        })
        .collect::<Result<Vec<_>, MetricsError>>()?;
    let mut out: BTreeMap<(u32, &str), [f64; 4]> = BTreeMap::new();
    for (i, (run, radar)) in run.iter().zip(radar.iter()).enumerate() {
        let (Some(run), Some(radar)) = (run, radar) else { continue };
        let acc = out.entry((run, radar)).or_insert([0.0; 4]);
        for (a, s) in acc.iter_mut().zip(&sums) {
            *a += s[i];
        }
    }
    Ok(out)
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
