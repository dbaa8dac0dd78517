//! `DIR/failure_points.parquet` (declared in `mimo_store::failure_point_schema`): the failure
//! point of every method on every scenario along every stress axis of the plan
//! ([`crate::failure_point`]), from the item records. Rows follow the plan: methods, then
//! scenarios, then axes, in plan order.

use crate::bootstrap::{RESAMPLES, resamples, resamples_keyed};
use crate::challenge::COMPLETENESS_REQUIRED;
use crate::failure_point::{FailurePoint, Resamples, SweepRuns, failure_point, numeric_interval};
use crate::grid::Cell;
use crate::plan::{Axis, Plan};
use crate::tables::ResultRow;
use crate::tables::method_ids;
use mimo_store::StoreError;
use mimo_store::columns::write_rows;
use mimo_store::failure_point_schema::{STUDY_FAILURE_POINTS, StudyFailurePointRow};
use mimo_store::layout::StudyDir;
use std::path::Path;

/// One method's sweep of one axis on one scenario, with its failure point.
#[derive(Debug, Clone)]
pub struct FailureRow {
    /// Index into the plan's methods.
    pub method: usize,
    /// Index into the plan's scenarios.
    pub scenario: usize,
    /// The axis.
    pub axis: Axis,
    /// The cells of the sweep, from the least to the most stressing value.
    pub cells: Vec<usize>,
    /// The sweep's values, in the same order.
    pub values: Vec<f64>,
    /// Runs per grid value.
    pub runs: u32,
    /// Whether run `k` of every grid value shares its random draws.
    pub paired: bool,
    /// The failure point and its interval.
    pub point: FailurePoint,
}

/// The cells of `axis`'s sweep for a method on a scenario, from the least to the most stressing
/// value: with `sweep = "each"` the cells that vary the axis; in a grid, those where every other
/// axis sits at its baseline.
pub fn sweep_cells(cells: &[Cell], method: usize, scenario: usize, axis: Axis) -> Vec<usize> {
    let mut of: Vec<usize> = (0..cells.len())
        .filter(|&c| {
            let cell = &cells[c];
            let on_axis = match cell.swept {
                Some(a) => a == axis,
                None => cell.point.iter().all(|(a, v)| *a == axis || *v == a.baseline()),
            };
            cell.method == method && cell.scenario == scenario && on_axis && cell.value(axis).is_some()
        })
        .collect();
    let rank = |c: &usize| cells[*c].value(axis).unwrap_or(f64::NAN);
    of.sort_by(|a, b| {
        let (x, y) = (rank(a), rank(b));
        if axis.harder_when_larger() { x.total_cmp(&y) } else { y.total_cmp(&x) }
    });
    of
}

/// Whether run `k` of every cell is the same run with the same seed (common random numbers).
fn shares_draws(records: &[&Vec<ResultRow>]) -> bool {
    let key = |r: &Vec<ResultRow>| r.iter().map(|x| (x.run, x.seed)).collect::<Vec<_>>();
    records.windows(2).all(|w| key(w[0]) == key(w[1]))
}

fn point_runs(recs: &[ResultRow]) -> crate::challenge::PointRuns {
    crate::challenge_table::point_runs(recs, "", None)
}

/// Every method × scenario × axis of the study with a sweep, in table order.
pub fn failure_rows(plan: &Plan, cells: &[Cell], records: &[Vec<ResultRow>]) -> Vec<FailureRow> {
    let paired_boot = resamples(plan.seed, plan.runs as usize, RESAMPLES);
    let mut out = Vec::new();
    for method in 0..plan.methods.len() {
        for scenario in 0..plan.scenarios.len() {
            for (axis, _) in &plan.axes {
                let of = sweep_cells(cells, method, scenario, *axis);
                if of.is_empty() {
                    continue;
                }
                let recs: Vec<&Vec<ResultRow>> = of.iter().map(|&c| &records[c]).collect();
                let paired = shares_draws(&recs);
                let sweep = SweepRuns {
                    values: of.iter().map(|&c| cells[c].value(*axis).unwrap_or(f64::NAN)).collect(),
                    log: axis.log_scale(),
                    points: recs.iter().map(|r| point_runs(r)).collect(),
                };
                let boot = if paired {
                    Resamples::Paired(paired_boot.clone())
                } else {
                    Resamples::Independent(
                        recs.iter()
                            .enumerate()
                            .map(|(i, r)| resamples_keyed(plan.seed, i as u64, r.len(), RESAMPLES))
                            .collect(),
                    )
                };
                out.push(FailureRow {
                    method,
                    scenario,
                    axis: *axis,
                    runs: recs.first().map_or(0, |r| r.len() as u32),
                    paired,
                    point: failure_point(&sweep, &boot),
                    values: sweep.values,
                    cells: of,
                });
            }
        }
    }
    out
}

/// Write `failure_points.parquet` into `dir`.
pub fn write_failure_points(plan: &Plan, rows: &[FailureRow], dir: &Path) -> Result<(), StoreError> {
    let out: Vec<StudyFailurePointRow> = rows
        .iter()
        .map(|r| {
            let (ci_lo, ci_hi, interval) = numeric_interval(r.point.interval, r.axis.harder_when_larger());
            StudyFailurePointRow {
                method: method_ids(&plan.methods[r.method]),
                scenario: plan.scenarios[r.scenario].label(),
                axis: r.axis.name().to_string(),
                log_scale: r.axis.log_scale(),
                // A sweep has a value at least (`failure_rows` skips empty ones).
                least_stress_value: r.values.first().copied().unwrap_or(f64::NAN),
                most_stress_value: r.values.last().copied().unwrap_or(f64::NAN),
                points: r.values.len() as u32,
                runs: r.runs,
                completeness_required: COMPLETENESS_REQUIRED,
                paired: r.paired,
                status: r.point.failure.status().to_string(),
                crossings: r.point.crossings,
                failure_point: r.point.value,
                ci_lo,
                ci_hi,
                interval: interval.to_string(),
                resamples: RESAMPLES as u32,
                resamples_crossing: r.point.resamples_crossing,
            }
        })
        .collect();
    write_rows(&StudyDir::new(dir).table(&STUDY_FAILURE_POINTS), &out)?;
    Ok(())
}
