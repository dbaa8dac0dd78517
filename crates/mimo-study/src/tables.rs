//! The study tables (`results.parquet`, `costs.parquet`, `summary.parquet`), built from the item
//! records of every cell, each reduced to a [`ResultRow`] as it is read. Each table is declared
//! once in `mimo_store::study_schema` (`STUDY_RESULTS`, `STUDY_COSTS`, `STUDY_SUMMARY`), which
//! gives its row struct and columns; rows follow the grid order (methods × scenarios × stress
//! points, then runs), so the tables are the same however the items were split over machines.

use crate::estimate::{bounded_mean_ci, mean_ci, metric_range};
use crate::grid::Cell;
use crate::plan::{Axis, Plan};
use crate::record::{ItemCosts, ItemRecord};
use mimo_store::StoreError;
use mimo_store::columns::write_rows;
use mimo_store::layout::StudyDir;
use mimo_store::study_schema::{
    MetricEstimates, MetricValues, STUDY_COSTS, STUDY_METRICS, STUDY_RESULTS, STUDY_SUMMARY, StudyCostsRow, StudyIds,
    StudyMethod, StudyPoint, StudyResultsRow, StudySummaryRow,
};
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

/// The method columns of a method of the plan.
pub(crate) fn method_ids(m: &crate::plan::Method) -> StudyMethod {
    StudyMethod { method: m.name.clone(), family: m.family.clone(), knob: m.knob.clone(), knob_value: m.knob_value }
}

/// The stress-point columns of a cell.
pub(crate) fn point_ids(cell: &Cell) -> StudyPoint {
    StudyPoint {
        swept: cell.swept.map(|a| a.name().to_string()),
        rcs_offset_db: cell.value(Axis::RcsOffsetDb),
        pfa: cell.value(Axis::Pfa),
        formation_spacing_scale: cell.value(Axis::FormationSpacingScale),
        peak_power_offset_db: cell.value(Axis::PeakPowerOffsetDb),
        search_pulses: cell.value(Axis::SearchPulses),
        raid_targets: cell.value(Axis::RaidTargets),
        bias_scale: cell.value(Axis::BiasScale),
        link_delay_s: cell.value(Axis::LinkDelayS),
    }
}

/// The identifying columns of a cell.
fn cell_ids(plan: &Plan, cell: &Cell) -> StudyIds {
    StudyIds {
        method: method_ids(&plan.methods[cell.method]),
        scenario: plan.scenarios[cell.scenario].label(),
        point: point_ids(cell),
    }
}

/// Write `results.parquet` and `costs.parquet` into `dir`.
pub fn write_results(plan: &Plan, cells: &[Cell], records: &[Vec<ResultRow>], dir: &Path) -> Result<(), StoreError> {
    let ids: Vec<StudyIds> = cells.iter().map(|c| cell_ids(plan, c)).collect();
    let rows = || records.iter().zip(&ids).flat_map(|(recs, ids)| recs.iter().map(move |r| (ids, r)));
    let results: Vec<StudyResultsRow> = rows()
        .map(|(ids, r)| StudyResultsRow {
            ids: ids.clone(),
            run: r.run,
            seed: r.seed,
            metrics: MetricValues(r.metrics.clone()),
            failure: r.failure.clone(),
        })
        .collect();
    write_rows(&StudyDir::new(dir).table(&STUDY_RESULTS), &results)?;
    let costs: Vec<StudyCostsRow> = rows()
        .map(|(ids, r)| StudyCostsRow {
            ids: ids.clone(),
            run: r.run,
            seed: r.seed,
            duration_s: r.duration_s,
            ta_cpu_s: r.costs.ta_cpu_s,
            sim_cpu_s: r.costs.sim_cpu_s,
            wall_s: r.costs.wall_s,
            kf_cycle_s: r.costs.kf_cycle_s,
            ta_cpu_kfu: r.costs.ta_cpu_kfu(),
        })
        .collect();
    write_rows(&StudyDir::new(dir).table(&STUDY_COSTS), &costs)?;
    Ok(())
}

/// Write `summary.parquet` into `dir`.
pub fn write_summary(plan: &Plan, cells: &[Cell], summaries: &[CellSummary], dir: &Path) -> Result<(), StoreError> {
    let rows: Vec<StudySummaryRow> = cells
        .iter()
        .zip(summaries)
        .map(|(c, s)| StudySummaryRow {
            ids: cell_ids(plan, c),
            runs: s.runs,
            failed: s.failed,
            failure: s.failure.clone(),
            estimates: MetricEstimates(s.estimates.clone()),
        })
        .collect();
    write_rows(&StudyDir::new(dir).table(&STUDY_SUMMARY), &rows)?;
    Ok(())
}
