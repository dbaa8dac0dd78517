//! The figures the study charts show, from the cell summaries (docs/studies.md): the drawing is
//! `mimo_report::study`'s.

use crate::grid::Cell;
use crate::plan::{Axis, Plan};
use crate::tables::CellSummary;
use mimo_report::study::{Estimate, StudyAxis, StudyCell, StudyCharts};
use mimo_store::schema::STUDY_METRICS;

/// The completeness the challenge requires.
pub const COMPLETENESS_REQUIRED: f64 = 0.98;

/// Whether every axis of the cell sits at its baseline.
pub fn is_baseline(cell: &Cell) -> bool {
    cell.point.iter().all(|(a, v)| *v == a.baseline())
}

/// The charts' input.
pub fn study_charts(plan: &Plan, cells: &[Cell], summaries: &[CellSummary]) -> StudyCharts {
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
                log: *a == Axis::Pfa,
            })
            .collect(),
        cells,
        completeness_required: COMPLETENESS_REQUIRED,
    }
}
