//! The figures the study charts show, from the cell summaries (docs/studies.md): the drawing is
//! `mimo_report::study`'s.

use crate::challenge_table::FamilyRow;
use crate::failure_point::numeric_interval;
use crate::failure_table::FailureRow;
use crate::grid::Cell;
use crate::plan::Architecture;
use crate::plan::Plan;
use crate::tables::CellSummary;
use mimo_report::study::{Estimate, FamilyPoint, StudyAxis, StudyCell, StudyCharts, StudyFailure, StudyFamily};
use mimo_store::schema::STUDY_METRICS;

/// The completeness the challenge requires.
pub const COMPLETENESS_REQUIRED: f64 = 0.98;

/// Whether every axis of the cell sits at its baseline.
pub fn is_baseline(cell: &Cell) -> bool {
    cell.point.iter().all(|(a, v)| *v == a.baseline())
}

fn estimate(s: &CellSummary, name: &str) -> Estimate {
    let k = STUDY_METRICS.iter().position(|(n, _, _)| *n == name).unwrap_or(0);
    let (mean, lo, hi) = s.estimates[k];
    Estimate { mean, lo, hi }
}

/// The families the energy frontier draws: on each scenario, those at the baseline stress
/// point, or at the first stress point when the plan has no baseline; their points at the
/// energy their frontier is built on (the plan's `frontier_energy`).
fn frontier_families(plan: &Plan, cells: &[Cell], summaries: &[CellSummary], rows: &[FamilyRow]) -> Vec<StudyFamily> {
    let first_point = rows.first().map(|r| (cells[r.cell].point.clone(), cells[r.cell].swept));
    let any_baseline = rows.iter().any(|r| is_baseline(&cells[r.cell]));
    rows.iter()
        .filter(|r| {
            let c = &cells[r.cell];
            if any_baseline { is_baseline(c) } else { first_point.as_ref() == Some(&(c.point.clone(), c.swept)) }
        })
        .map(|r| StudyFamily {
            name: r.family.clone(),
            mimo: r.architecture == Architecture::Mimo,
            scenario: plan.scenarios[cells[r.cell].scenario].label(),
            points: r
                .cells
                .iter()
                .enumerate()
                .map(|(j, &c)| FamilyPoint {
                    knob: plan.methods[cells[c].method].knob_value,
                    energy_j: estimate(&summaries[c], plan.frontier_energy.metric()),
                    on_frontier: r.challenge.frontier.contains(&j),
                    completeness: estimate(&summaries[c], "completeness"),
                })
                .collect(),
            crossing: r
                .challenge
                .at
                .as_ref()
                .ok()
                .and_then(|a| a.figures[plan.frontier_energy.at_figure()])
                .map(|w| Estimate { mean: Some(w.0), lo: w.1, hi: w.2 }),
        })
        .collect()
}

/// The failure points as the stability charts mark them.
fn failure_marks(plan: &Plan, failures: &[FailureRow]) -> Vec<StudyFailure> {
    failures
        .iter()
        .map(|f| {
            let (lo, hi, interval) = numeric_interval(f.point.interval, f.axis.harder_when_larger());
            StudyFailure {
                method: plan.methods[f.method].name.clone(),
                scenario: plan.scenarios[f.scenario].label(),
                axis: f.axis.name().to_string(),
                status: f.point.failure.status().to_string(),
                value: f.point.value,
                lo,
                hi,
                interval: interval.to_string(),
            }
        })
        .collect()
}

/// The charts' input.
pub fn study_charts(
    plan: &Plan,
    cells: &[Cell],
    summaries: &[CellSummary],
    families: &[FamilyRow],
    failures: &[FailureRow],
) -> StudyCharts {
    let families = frontier_families(plan, cells, summaries, families);
    let cells = cells
        .iter()
        .zip(summaries)
        .map(|(c, s)| StudyCell {
            method: plan.methods[c.method].name.clone(),
            scenario: plan.scenarios[c.scenario].label(),
            swept: c.swept.map(|a| a.name().to_string()),
            point: c.point.iter().map(|(a, v)| (a.name().to_string(), *v)).collect(),
            baseline: is_baseline(c),
            runs: s.runs,
            failed: s.failed,
            metrics: STUDY_METRICS
                .iter()
                .zip(&s.estimates)
                .map(|((n, _, _), e)| (n.to_string(), Estimate { mean: e.0, lo: e.1, hi: e.2 }))
                .collect(),
            ta_cpu_per_sim_s: s.ta_cpu_per_sim_s,
            ta_kfu_per_sim_s: s.ta_kfu_per_sim_s,
        })
        .collect();
    StudyCharts {
        title: plan.title.clone(),
        methods: plan.methods.iter().map(|m| m.name.clone()).collect(),
        scenarios: plan.scenarios.iter().map(|s| s.label()).collect(),
        axes: plan
            .axes
            .iter()
            .map(|(a, values)| StudyAxis {
                name: a.name().to_string(),
                label: a.label().to_string(),
                values_by_stress: a.by_stress(values),
                log: a.log_scale(),
            })
            .collect(),
        families,
        failures: failure_marks(plan, failures),
        cells,
        completeness_required: COMPLETENESS_REQUIRED,
        frontier_on_ta_energy: plan.frontier_energy == crate::frontier_energy::FrontierEnergy::TestArticle,
    }
}
