//! `DIR/challenge.parquet` and `DIR/challenge_ratios.parquet` (declared in
//! `mimo_store::challenge_schema`): the challenge figures of every family on every scenario and
//! stress point, and the paired MIMO ÷ conventional energy ratios, from the item records. Rows
//! follow the plan: scenarios, then stress points, then families (or family pairs) in plan order.

use crate::bootstrap::{RESAMPLES, resamples};
use crate::challenge::{Challenge, FamilyRuns, PointRuns, challenge, energy_ratio, reason};
use crate::grid::{self, Cell};
use crate::plan::{Architecture, Axis, Plan};
use crate::tables::ResultRow;
use mimo_store::StoreError;
use mimo_store::challenge_schema::{STUDY_CHALLENGE, STUDY_CHALLENGE_RATIOS};
use mimo_store::columns::{Column, write_columns};
use std::path::Path;

/// A family on one scenario at one stress point, with its figures.
#[derive(Debug, Clone)]
pub struct FamilyRow {
    /// The family's name.
    pub family: String,
    /// MIMO or conventional.
    pub architecture: Architecture,
    /// Its knob's key path.
    pub knob: Option<String>,
    /// A cell of the row (for the scenario and stress point).
    pub cell: usize,
    /// The cells of its points, ordered by knob value.
    pub cells: Vec<usize>,
    /// Its runs.
    pub runs: FamilyRuns,
    /// Its figures.
    pub challenge: Challenge,
}

pub(crate) fn point_runs(recs: &[ResultRow], knob: Option<f64>) -> PointRuns {
    let m = |r: &ResultRow, name: &str| if r.failure.is_some() { None } else { r.metric(name) };
    PointRuns {
        knob,
        failed: recs.iter().map(|r| r.failure.is_some()).collect(),
        completeness: recs.iter().map(|r| m(r, "completeness")).collect(),
        energy_j: recs.iter().map(|r| m(r, "ta_energy_per_object_j")).collect(),
        dwell_s: recs.iter().map(|r| m(r, "ta_dwell_time_per_object_s")).collect(),
    }
}

/// Every family × scenario × stress point of the study, in table order, with its figures.
pub fn family_rows(plan: &Plan, cells: &[Cell], records: &[Vec<ResultRow>]) -> Vec<FamilyRow> {
    let boot = resamples(plan.seed, plan.runs as usize, RESAMPLES);
    let mut families: Vec<&str> = Vec::new();
    for m in &plan.methods {
        if !families.contains(&m.family.as_str()) {
            families.push(&m.family);
        }
    }
    let mut out = Vec::new();
    for s in 0..plan.scenarios.len() {
        for (point, swept) in grid::points(plan) {
            for fam in &families {
                let mut of: Vec<usize> = (0..cells.len())
                    .filter(|&c| {
                        let cell = &cells[c];
                        cell.scenario == s
                            && cell.point == point
                            && cell.swept == swept
                            && plan.methods[cell.method].family == *fam
                    })
                    .collect();
                let knob = |c: &usize| plan.methods[cells[*c].method].knob_value.unwrap_or(0.0);
                of.sort_by(|a, b| knob(a).total_cmp(&knob(b)));
                let Some(&first) = of.first() else { continue };
                let method = &plan.methods[cells[first].method];
                let runs = FamilyRuns {
                    points: of
                        .iter()
                        .map(|&c| point_runs(&records[c], plan.methods[cells[c].method].knob_value))
                        .collect(),
                    duration_s: records[first].first().map_or(f64::NAN, |r| r.duration_s),
                };
                let challenge = challenge(&runs, &boot);
                out.push(FamilyRow {
                    family: fam.to_string(),
                    architecture: method.architecture,
                    knob: method.knob.clone(),
                    cell: first,
                    cells: of,
                    runs,
                    challenge,
                });
            }
        }
    }
    out
}

/// A (MIMO, conventional) pair of rows on the same scenario and stress point, with the paired
/// energy ratio and the resamples in which it is defined.
#[derive(Debug, Clone)]
pub struct RatioRow {
    /// Index of the MIMO family's row.
    pub mimo: usize,
    /// Index of the conventional family's row.
    pub conventional: usize,
    /// The ratio and its interval, or why it is null.
    pub ratio: Result<crate::challenge::WithCi, String>,
    /// Resamples with both crossings inside their sweeps.
    pub defined: u32,
}

/// Every (MIMO, conventional) pair of families on each scenario and stress point.
pub fn ratio_rows(plan: &Plan, cells: &[Cell], rows: &[FamilyRow]) -> Vec<RatioRow> {
    let boot = resamples(plan.seed, plan.runs as usize, RESAMPLES);
    let same_place = |a: &FamilyRow, b: &FamilyRow| {
        let (x, y) = (&cells[a.cell], &cells[b.cell]);
        x.scenario == y.scenario && x.point == y.point && x.swept == y.swept
    };
    let mut out = Vec::new();
    for (i, m) in rows.iter().enumerate().filter(|(_, r)| r.architecture == Architecture::Mimo) {
        for (j, c) in rows.iter().enumerate().filter(|(_, r)| r.architecture == Architecture::Conventional) {
            if same_place(m, c) {
                let (ratio, defined) = energy_ratio(&m.runs, &c.runs, &boot);
                out.push(RatioRow { mimo: i, conventional: j, ratio, defined });
            }
        }
    }
    // Rows come scenario by scenario and point by point, so the pairs do too.
    out
}

/// The scenario and stress-point columns of rows at cells `at`.
fn place_columns(plan: &Plan, cells: &[Cell], at: &[usize]) -> Vec<Column> {
    let mut out = vec![
        Column::Utf8(at.iter().map(|&c| Some(plan.scenarios[cells[c].scenario].label())).collect()),
        Column::Utf8(at.iter().map(|&c| cells[c].swept.map(|a| a.name().to_string())).collect()),
    ];
    for axis in Axis::ALL {
        out.push(Column::F64(at.iter().map(|&c| cells[c].value(axis)).collect()));
    }
    out
}

/// Write `challenge.parquet` and `challenge_ratios.parquet` into `dir`.
pub fn write_challenge(
    plan: &Plan,
    cells: &[Cell],
    rows: &[FamilyRow],
    ratios: &[RatioRow],
    dir: &Path,
) -> Result<(), StoreError> {
    let utf8 = |f: &dyn Fn(&FamilyRow) -> Option<String>| Column::Utf8(rows.iter().map(f).collect());
    let mut cols = vec![
        utf8(&|r| Some(r.family.clone())),
        utf8(&|r| Some(r.architecture.name().to_string())),
        utf8(&|r| r.knob.clone()),
    ];
    cols.extend(place_columns(plan, cells, &rows.iter().map(|r| r.cell).collect::<Vec<_>>()));
    cols.push(Column::U32(rows.iter().map(|r| r.cells.len() as u32).collect()));
    cols.push(Column::U32(rows.iter().map(|_| plan.runs).collect()));
    cols.push(Column::F64(rows.iter().map(|_| Some(crate::challenge::COMPLETENESS_REQUIRED)).collect()));
    cols.push(Column::Bool(rows.iter().map(|r| r.challenge.holds).collect()));
    cols.push(Column::U32(rows.iter().map(|r| r.challenge.crossings).collect()));
    cols.push(utf8(&|r| r.challenge.at.as_ref().err().map(|e| reason(e).to_string())));
    cols.push(Column::F64(rows.iter().map(|r| r.challenge.at.as_ref().ok().and_then(|a| a.0)).collect()));
    for k in 0..3 {
        let get = |r: &FamilyRow| {
            r.challenge.at.as_ref().ok().map(|a| match k {
                0 => a.1,
                1 => a.2,
                _ => a.3,
            })
        };
        cols.push(Column::F64(rows.iter().map(|r| get(r).map(|w| w.0)).collect()));
        cols.push(Column::F64(rows.iter().map(|r| get(r).and_then(|w| w.1)).collect()));
        cols.push(Column::F64(rows.iter().map(|r| get(r).and_then(|w| w.2)).collect()));
    }
    cols.push(Column::U32(rows.iter().map(|_| RESAMPLES as u32).collect()));
    cols.push(Column::U32(rows.iter().map(|r| r.challenge.resamples_crossing).collect()));
    write_columns(&dir.join("challenge.parquet"), &STUDY_CHALLENGE, cols)?;

    let mut cols = place_columns(plan, cells, &ratios.iter().map(|r| rows[r.mimo].cell).collect::<Vec<_>>());
    cols.push(Column::Utf8(ratios.iter().map(|r| Some(rows[r.mimo].family.clone())).collect()));
    cols.push(Column::Utf8(ratios.iter().map(|r| Some(rows[r.conventional].family.clone())).collect()));
    cols.push(Column::F64(ratios.iter().map(|r| r.ratio.as_ref().ok().map(|w| w.0)).collect()));
    cols.push(Column::F64(ratios.iter().map(|r| r.ratio.as_ref().ok().and_then(|w| w.1)).collect()));
    cols.push(Column::F64(ratios.iter().map(|r| r.ratio.as_ref().ok().and_then(|w| w.2)).collect()));
    cols.push(Column::Utf8(ratios.iter().map(|r| r.ratio.as_ref().err().cloned()).collect()));
    cols.push(Column::U32(ratios.iter().map(|_| RESAMPLES as u32).collect()));
    cols.push(Column::U32(ratios.iter().map(|r| r.defined).collect()));
    write_columns(&dir.join("challenge_ratios.parquet"), &STUDY_CHALLENGE_RATIOS, cols)?;
    Ok(())
}
