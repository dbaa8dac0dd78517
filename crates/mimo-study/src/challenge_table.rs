//! `DIR/challenge.parquet` and `DIR/challenge_ratios.parquet` (declared in
//! `mimo_store::challenge_schema`): the challenge figures of every family on every scenario and
//! stress point, and the paired MIMO ÷ conventional energy ratios, from the item records. Rows
//! follow the plan: scenarios, then stress points, then families (or family pairs) in plan order.

use crate::bootstrap::{RESAMPLES, resamples};
use crate::challenge::{Challenge, FamilyRuns, PointRuns, challenge, energy_ratio, reason};
use crate::grid::{self, Cell};
use crate::plan::{Architecture, Plan};
use crate::tables::ResultRow;
use crate::tables::point_ids;
use mimo_store::StoreError;
use mimo_store::challenge_schema::{
    STUDY_CHALLENGE, STUDY_CHALLENGE_RATIOS, StudyChallengeRatiosRow, StudyChallengeRow,
};
use mimo_store::columns::write_rows;
use mimo_store::layout::StudyDir;
use mimo_store::study_schema::Estimate;
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

/// The figures of a row at 98 %: (knob, energy, dwell time, power), each figure with its
/// interval; all null when the crossing is not defined.
fn at_98(r: &FamilyRow) -> (Option<f64>, [Estimate; 3]) {
    match r.challenge.at.as_ref() {
        Ok(a) => (a.0, [a.1, a.2, a.3].map(|w| (Some(w.0), w.1, w.2))),
        Err(_) => (None, [(None, None, None); 3]),
    }
}

/// Write `challenge.parquet` and `challenge_ratios.parquet` into `dir`.
pub fn write_challenge(
    plan: &Plan,
    cells: &[Cell],
    rows: &[FamilyRow],
    ratios: &[RatioRow],
    dir: &Path,
) -> Result<(), StoreError> {
    let place = |c: usize| (plan.scenarios[cells[c].scenario].label(), point_ids(&cells[c]));
    let challenge: Vec<StudyChallengeRow> = rows
        .iter()
        .map(|r| {
            let (scenario, point) = place(r.cell);
            let (knob_at_98, [energy, dwell, power]) = at_98(r);
            StudyChallengeRow {
                family: r.family.clone(),
                architecture: r.architecture.name().to_string(),
                knob: r.knob.clone(),
                scenario,
                point,
                points: r.cells.len() as u32,
                runs: plan.runs,
                completeness_required: crate::challenge::COMPLETENESS_REQUIRED,
                holds: r.challenge.holds,
                crossings: r.challenge.crossings,
                reason: r.challenge.at.as_ref().err().map(|e| reason(e).to_string()),
                knob_at_98,
                energy_at_98_j: energy.0,
                energy_at_98_ci_lo_j: energy.1,
                energy_at_98_ci_hi_j: energy.2,
                dwell_time_at_98_s: dwell.0,
                dwell_time_at_98_ci_lo_s: dwell.1,
                dwell_time_at_98_ci_hi_s: dwell.2,
                power_at_98_w: power.0,
                power_at_98_ci_lo_w: power.1,
                power_at_98_ci_hi_w: power.2,
                resamples: RESAMPLES as u32,
                resamples_crossing: r.challenge.resamples_crossing,
            }
        })
        .collect();
    write_rows(&StudyDir::new(dir).table(&STUDY_CHALLENGE), &challenge)?;
    let ratios: Vec<StudyChallengeRatiosRow> = ratios
        .iter()
        .map(|r| {
            let (scenario, point) = place(rows[r.mimo].cell);
            let ratio = r.ratio.as_ref().ok();
            StudyChallengeRatiosRow {
                scenario,
                point,
                mimo_family: rows[r.mimo].family.clone(),
                conventional_family: rows[r.conventional].family.clone(),
                energy_ratio: ratio.map(|w| w.0),
                energy_ratio_ci_lo: ratio.and_then(|w| w.1),
                energy_ratio_ci_hi: ratio.and_then(|w| w.2),
                reason: r.ratio.as_ref().err().cloned(),
                resamples: RESAMPLES as u32,
                resamples_defined: r.defined,
            }
        })
        .collect();
    write_rows(&StudyDir::new(dir).table(&STUDY_CHALLENGE_RATIOS), &ratios)?;
    Ok(())
}
