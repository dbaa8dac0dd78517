//! The study tables (`results.parquet`, `costs.parquet`, `summary.parquet`), built from the item
//! records of every cell, each reduced to a [`ResultRow`] as it is read. Their columns are declared once in `mimo_store::schema`
//! (`STUDY_RESULTS`, `STUDY_COSTS`, `STUDY_SUMMARY`); rows follow the grid order (methods ×
//! scenarios × stress points, then runs), so the tables are the same however the items were
//! split over machines.

use crate::estimate::{bounded_mean_ci, mean_ci, metric_range};
use crate::grid::Cell;
use crate::plan::{Axis, Plan};
use crate::record::{ItemCosts, ItemRecord};
use mimo_store::StoreError;
use mimo_store::columns::{Column, write_columns};
use mimo_store::layout::StudyDir;
use mimo_store::schema::{STUDY_COSTS, STUDY_METRICS, STUDY_RESULTS, STUDY_SUMMARY};
use std::path::Path;

/// One cell's Monte Carlo summary.
#[derive(Debug, Clone, PartialEq)]
pub struct CellSummary {
    /// Runs of the cell.
    pub runs: u32,
    /// Runs that failed.
    pub failed: u32,
    /// The first failed run's reason.
    pub failure: Option<String>,
    /// Per metric of `STUDY_METRICS`, (mean, lo, hi) over the completed runs.
    pub estimates: Vec<(Option<f64>, Option<f64>, Option<f64>)>,
    /// Mean TA CPU seconds per simulated second (from the costs).
    pub ta_cpu_per_sim_s: Option<f64>,
    /// Mean TA compute in reference Kalman-filter cycles per simulated second (`None` when a
    /// record has no reference measurement).
    pub ta_kfu_per_sim_s: Option<f64>,
}

/// One row of the results and costs tables: an item record less its table files and the test
/// article's configuration (a cell's manifest keeps those), so that merging a study holds a few
/// hundred bytes per item however large the records are.
#[derive(Debug, Clone, PartialEq)]
pub struct ResultRow {
    /// Monte Carlo run.
    pub run: u32,
    /// Master seed.
    pub seed: u64,
    /// Simulated seconds.
    pub duration_s: f64,
    /// Why it failed; `None` when it completed.
    pub failure: Option<String>,
    /// The metrics, in `STUDY_METRICS` order.
    pub metrics: Vec<Option<f64>>,
    /// Costs.
    pub costs: ItemCosts,
}

impl ResultRow {
    /// The metric `name` of `STUDY_METRICS` (`None` when undefined or not a study metric).
    pub fn metric(&self, name: &str) -> Option<f64> {
        let k = STUDY_METRICS.iter().position(|(n, _, _)| *n == name)?;
        self.metrics.get(k).copied().flatten()
    }

    /// The row of a record.
    pub fn of(r: &ItemRecord) -> ResultRow {
        ResultRow {
            run: r.run,
            seed: r.seed,
            duration_s: r.duration_s,
            failure: r.failure.clone(),
            metrics: STUDY_METRICS.iter().map(|(name, _, _)| r.metrics.get(*name).copied().flatten()).collect(),
            costs: r.costs,
        }
    }
}

/// Summarise each cell's rows.
pub fn summarize(rows: &[Vec<ResultRow>]) -> Vec<CellSummary> {
    rows.iter()
        .map(|recs| {
            let failed = recs.iter().filter(|r| r.failure.is_some()).count() as u32;
            let estimates = STUDY_METRICS
                .iter()
                .enumerate()
                .map(|(k, (name, _, _))| {
                    let v: Vec<f64> =
                        recs.iter().filter(|r| r.failure.is_none()).filter_map(|r| r.metrics[k]).collect();
                    bounded_mean_ci(&v, metric_range(name))
                })
                .collect();
            let cpu: Vec<f64> =
                recs.iter().filter(|r| r.duration_s > 0.0).map(|r| r.costs.ta_cpu_s / r.duration_s).collect();
            let kfu: Option<Vec<f64>> = recs
                .iter()
                .filter(|r| r.duration_s > 0.0)
                .map(|r| Some(r.costs.ta_cpu_kfu()? / r.duration_s))
                .collect();
            CellSummary {
                runs: recs.len() as u32,
                failed,
                failure: recs.iter().find_map(|r| r.failure.clone()),
                estimates,
                ta_cpu_per_sim_s: mean_ci(&cpu).0,
                ta_kfu_per_sim_s: kfu.and_then(|v| mean_ci(&v).0),
            }
        })
        .collect()
}

/// The identifying columns for rows of `cells` (a cell index per row).
fn id_columns(plan: &Plan, cells: &[Cell], rows: &[usize]) -> Vec<Column> {
    let m = |c: usize| &plan.methods[cells[c].method];
    let mut out = vec![
        Column::Utf8(rows.iter().map(|&c| Some(m(c).name.clone())).collect()),
        Column::Utf8(rows.iter().map(|&c| Some(m(c).family.clone())).collect()),
        Column::Utf8(rows.iter().map(|&c| m(c).knob.clone()).collect()),
        Column::F64(rows.iter().map(|&c| m(c).knob_value).collect()),
        Column::Utf8(rows.iter().map(|&c| Some(plan.scenarios[cells[c].scenario].label())).collect()),
        Column::Utf8(rows.iter().map(|&c| cells[c].swept.map(|a| a.name().to_string())).collect()),
    ];
    for axis in Axis::ALL {
        out.push(Column::F64(rows.iter().map(|&c| cells[c].value(axis)).collect()));
    }
    out
}

/// Write `results.parquet` and `costs.parquet` into `dir`.
pub fn write_results(plan: &Plan, cells: &[Cell], records: &[Vec<ResultRow>], dir: &Path) -> Result<(), StoreError> {
    let rows: Vec<(usize, &ResultRow)> =
        records.iter().enumerate().flat_map(|(c, recs)| recs.iter().map(move |r| (c, r))).collect();
    let cell_of: Vec<usize> = rows.iter().map(|(c, _)| *c).collect();
    let run = Column::U32(rows.iter().map(|(_, r)| r.run).collect());
    let seed = Column::U64(rows.iter().map(|(_, r)| r.seed).collect());

    let mut results = id_columns(plan, cells, &cell_of);
    results.push(run.clone());
    results.push(seed.clone());
    for k in 0..STUDY_METRICS.len() {
        results.push(Column::F64(rows.iter().map(|(_, r)| r.metrics[k]).collect()));
    }
    results.push(Column::Utf8(rows.iter().map(|(_, r)| r.failure.clone()).collect()));
    write_columns(&StudyDir::new(dir).table(&STUDY_RESULTS), &STUDY_RESULTS, results)?;

    let mut costs = id_columns(plan, cells, &cell_of);
    costs.push(run);
    costs.push(seed);
    let f = |g: fn(&ResultRow) -> f64| Column::F64(rows.iter().map(|(_, r)| Some(g(r))).collect());
    costs.push(f(|r| r.duration_s));
    costs.push(f(|r| r.costs.ta_cpu_s));
    costs.push(f(|r| r.costs.sim_cpu_s));
    costs.push(f(|r| r.costs.wall_s));
    costs.push(Column::F64(rows.iter().map(|(_, r)| r.costs.kf_cycle_s).collect()));
    costs.push(Column::F64(rows.iter().map(|(_, r)| r.costs.ta_cpu_kfu()).collect()));
    write_columns(&StudyDir::new(dir).table(&STUDY_COSTS), &STUDY_COSTS, costs)?;
    Ok(())
}

/// Write `summary.parquet` into `dir`.
pub fn write_summary(plan: &Plan, cells: &[Cell], summaries: &[CellSummary], dir: &Path) -> Result<(), StoreError> {
    let idx: Vec<usize> = (0..cells.len()).collect();
    let mut cols = id_columns(plan, cells, &idx);
    cols.push(Column::U32(summaries.iter().map(|s| s.runs).collect()));
    cols.push(Column::U32(summaries.iter().map(|s| s.failed).collect()));
    cols.push(Column::Utf8(summaries.iter().map(|s| s.failure.clone()).collect()));
    for k in 0..STUDY_METRICS.len() {
        cols.push(Column::F64(summaries.iter().map(|s| s.estimates[k].0).collect()));
        cols.push(Column::F64(summaries.iter().map(|s| s.estimates[k].1).collect()));
        cols.push(Column::F64(summaries.iter().map(|s| s.estimates[k].2).collect()));
    }
    write_columns(&StudyDir::new(dir).table(&STUDY_SUMMARY), &STUDY_SUMMARY, cols)?;
    Ok(())
}
