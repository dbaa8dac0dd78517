//! `DIR/challenge.parquet`, `DIR/challenge_ratios.parquet` and `DIR/frontier.parquet` (declared
//! in `mimo_store::challenge_schema`): the challenge figures of every family on every scenario
//! and stress point, the paired MIMO ÷ conventional energy ratios (total and the test article's
//! part), and each family's points with its efficient frontier, from the item records. Rows
//! follow the plan: scenarios, then stress points, then families (or family pairs) in plan order.

use crate::bootstrap::{RESAMPLES, resamples};
use crate::challenge::{
    AT_DWELL, AT_ENERGY, AT_FIRST_TRACK_MAX, AT_POWER, AT_TA_DWELL, AT_TA_ENERGY, AT_TA_POWER, Challenge, FamilyRuns,
    PointRuns, RUN_ENERGY, WithCi, all_means, challenge, energy_ratio, reason,
};
use crate::grid::{self, Cell};
use crate::plan::{Architecture, Plan};
use crate::tables::ResultRow;
use crate::tables::point_ids;
use mimo_store::StoreError;
use mimo_store::challenge_schema::{
    STUDY_CHALLENGE, STUDY_CHALLENGE_RATIOS, STUDY_FRONTIER, StudyChallengeRatiosRow, StudyChallengeRow,
    StudyFrontierRow,
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
    /// Its knob's key path (key paths joined by ` × ` for a grid).
    pub knob: Option<String>,
    /// Refinement rounds run for this family, scenario and stress point.
    pub refine_rounds: u32,
    /// A cell of the row (for the scenario and stress point).
    pub cell: usize,
    /// The cells of its points, ordered by knob value (a grid's by its values, key by key).
    pub cells: Vec<usize>,
    /// Its runs.
    pub runs: FamilyRuns,
    /// Its figures.
    pub challenge: Challenge,
}

pub(crate) fn point_runs(recs: &[ResultRow], method: &str, knob: Option<f64>) -> PointRuns {
    let m = |r: &ResultRow, name: &str| if r.failure.is_some() { None } else { r.metric(name) };
    let of = |name: &str| recs.iter().map(|r| m(r, name)).collect::<Vec<_>>();
    PointRuns {
        method: method.to_string(),
        knob,
        failed: recs.iter().map(|r| r.failure.is_some()).collect(),
        completeness: of("completeness"),
        figures: [
            of("energy_per_object_j"),
            of("dwell_time_per_object_s"),
            of("ta_energy_per_object_j"),
            of("ta_dwell_time_per_object_s"),
            of("first_track_max_s"),
        ],
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
                let grid = |c: &usize| plan.methods[cells[*c].method].grid.iter().map(|g| g.1).collect::<Vec<_>>();
                of.sort_by(|a, b| {
                    grid(a)
                        .iter()
                        .zip(grid(b).iter())
                        .map(|(x, y)| x.total_cmp(y))
                        .find(|o| o.is_ne())
                        .unwrap_or(a.cmp(b))
                });
                let Some(&first) = of.first() else { continue };
                let method = &plan.methods[cells[first].method];
                let runs = FamilyRuns {
                    points: of
                        .iter()
                        .map(|&c| {
                            let m = &plan.methods[cells[c].method];
                            point_runs(&records[c], &m.name, m.knob_value)
                        })
                        .collect(),
                    duration_s: records[first].first().map_or(f64::NAN, |r| r.duration_s),
                    energy: plan.frontier_energy,
                };
                let challenge = challenge(&runs, &boot);
                out.push(FamilyRow {
                    family: fam.to_string(),
                    architecture: method.architecture,
                    knob: method.knob.clone(),
                    refine_rounds: of.iter().filter(|&&c| plan.methods[cells[c].method].refined).count() as u32,
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
    /// The ratio of total energies and its interval, or why it is null.
    pub ratio: Result<WithCi, String>,
    /// Resamples with both crossings inside their sweeps.
    pub defined: u32,
    /// The ratio of the test article's energies and its interval, or why it is null.
    pub ta_ratio: Result<WithCi, String>,
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
                let (ratio, defined) = energy_ratio(&m.runs, &c.runs, &boot, AT_ENERGY);
                let (ta_ratio, _) = energy_ratio(&m.runs, &c.runs, &boot, AT_TA_ENERGY);
                out.push(RatioRow { mimo: i, conventional: j, ratio, defined, ta_ratio });
            }
        }
    }
    // Rows come scenario by scenario and point by point, so the pairs do too.
    out
}

/// Figure `i` of a row at 98 % with its interval; all null when the crossing or the figure is
/// not defined.
fn at_98(r: &FamilyRow, i: usize) -> Estimate {
    match r.challenge.at.as_ref().ok().and_then(|a| a.figures[i]) {
        Some(w) => (Some(w.0), w.1, w.2),
        None => (None, None, None),
    }
}

/// The bracket columns of a row: (lo method, hi method, lo energy, hi energy, gap).
type Bracket = (Option<String>, Option<String>, Option<f64>, Option<f64>, Option<f64>);

/// The bracket of a row on its frontier's energy (total, or the test article's part).
fn bracket(r: &FamilyRow) -> Bracket {
    let Ok(a) = r.challenge.at.as_ref() else { return (None, None, None, None, None) };
    let means = all_means(&r.runs);
    let (lo, hi) = a.bracket;
    let basis = r.runs.energy;
    let (e_lo, e_hi) = (means[lo].figures[basis.run_figure()], means[hi].figures[basis.run_figure()]);
    let gap = match (e_lo, e_hi, a.figures[basis.at_figure()]) {
        (Some(x), Some(y), Some((e, _, _))) if e > 0.0 => Some((y - x) / e),
        _ => None,
    };
    (Some(r.runs.points[lo].method.clone()), Some(r.runs.points[hi].method.clone()), e_lo, e_hi, gap)
}

fn challenge_row(plan: &Plan, cells: &[Cell], r: &FamilyRow) -> StudyChallengeRow {
    let (scenario, point) = (plan.scenarios[cells[r.cell].scenario].label(), point_ids(&cells[r.cell]));
    let [energy, dwell, power, ta_energy, ta_dwell, ta_power] =
        [AT_ENERGY, AT_DWELL, AT_POWER, AT_TA_ENERGY, AT_TA_DWELL, AT_TA_POWER].map(|i| at_98(r, i));
    let (bracket_lo_method, bracket_hi_method, bracket_lo_energy_j, bracket_hi_energy_j, bracket_gap) = bracket(r);
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
        knob_at_98: r.challenge.at.as_ref().ok().and_then(|a| a.knob),
        energy_at_98_j: energy.0,
        energy_at_98_ci_lo_j: energy.1,
        energy_at_98_ci_hi_j: energy.2,
        dwell_time_at_98_s: dwell.0,
        dwell_time_at_98_ci_lo_s: dwell.1,
        dwell_time_at_98_ci_hi_s: dwell.2,
        power_at_98_w: power.0,
        power_at_98_ci_lo_w: power.1,
        power_at_98_ci_hi_w: power.2,
        ta_energy_at_98_j: ta_energy.0,
        ta_energy_at_98_ci_lo_j: ta_energy.1,
        ta_energy_at_98_ci_hi_j: ta_energy.2,
        ta_dwell_time_at_98_s: ta_dwell.0,
        ta_dwell_time_at_98_ci_lo_s: ta_dwell.1,
        ta_dwell_time_at_98_ci_hi_s: ta_dwell.2,
        ta_power_at_98_w: ta_power.0,
        ta_power_at_98_ci_lo_w: ta_power.1,
        ta_power_at_98_ci_hi_w: ta_power.2,
        first_track_max_at_98_s: at_98(r, AT_FIRST_TRACK_MAX).0,
        frontier_points: r.challenge.frontier.len() as u32,
        bracket_lo_method,
        bracket_hi_method,
        bracket_lo_energy_j,
        bracket_hi_energy_j,
        bracket_gap,
        refine_rounds: r.refine_rounds,
        resamples: RESAMPLES as u32,
        resamples_crossing: r.challenge.resamples_crossing,
    }
}

/// The rows of `frontier.parquet`: every point of every family row, in the family's order.
fn frontier_rows(plan: &Plan, cells: &[Cell], rows: &[FamilyRow]) -> Vec<StudyFrontierRow> {
    let mut out = Vec::new();
    for r in rows {
        let means = all_means(&r.runs);
        for (j, &c) in r.cells.iter().enumerate() {
            out.push(StudyFrontierRow {
                family: r.family.clone(),
                method: plan.methods[cells[c].method].name.clone(),
                scenario: plan.scenarios[cells[c].scenario].label(),
                point: point_ids(&cells[c]),
                energy_per_object_j: means[j].figures[RUN_ENERGY],
                completeness: means[j].completeness,
                on_frontier: r.challenge.frontier.contains(&j),
            });
        }
    }
    out
}

/// Write `challenge.parquet`, `challenge_ratios.parquet` and `frontier.parquet` into `dir`.
pub fn write_challenge(
    plan: &Plan,
    cells: &[Cell],
    rows: &[FamilyRow],
    ratios: &[RatioRow],
    dir: &Path,
) -> Result<(), StoreError> {
    let challenge: Vec<StudyChallengeRow> = rows.iter().map(|r| challenge_row(plan, cells, r)).collect();
    write_rows(&StudyDir::new(dir).table(&STUDY_CHALLENGE), &challenge)?;
    let place = |c: usize| (plan.scenarios[cells[c].scenario].label(), point_ids(&cells[c]));
    let ratios: Vec<StudyChallengeRatiosRow> = ratios
        .iter()
        .map(|r| {
            let (scenario, point) = place(rows[r.mimo].cell);
            let ratio = r.ratio.as_ref().ok();
            let ta = r.ta_ratio.as_ref().ok();
            StudyChallengeRatiosRow {
                scenario,
                point,
                mimo_family: rows[r.mimo].family.clone(),
                conventional_family: rows[r.conventional].family.clone(),
                energy_ratio: ratio.map(|w| w.0),
                energy_ratio_ci_lo: ratio.and_then(|w| w.1),
                energy_ratio_ci_hi: ratio.and_then(|w| w.2),
                ta_energy_ratio: ta.map(|w| w.0),
                ta_energy_ratio_ci_lo: ta.and_then(|w| w.1),
                ta_energy_ratio_ci_hi: ta.and_then(|w| w.2),
                reason: r.ratio.as_ref().err().cloned(),
                resamples: RESAMPLES as u32,
                resamples_defined: r.defined,
            }
        })
        .collect();
    write_rows(&StudyDir::new(dir).table(&STUDY_CHALLENGE_RATIOS), &ratios)?;
    write_rows(&StudyDir::new(dir).table(&STUDY_FRONTIER), &frontier_rows(plan, cells, rows))?;
    Ok(())
}
