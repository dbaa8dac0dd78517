//! Refinement where a family's frontier crosses 98 % (docs/studies.md, "Refinement"): a plan's
//! `[refine]` (every swept family) or a `[[methods]]` entry's `refine = { fraction, rounds }`
//! adds points to a family, scenario by scenario and stress point by stress point, one a round,
//! between two points that bracket 98 % — on the family's frontier, or on a line of its grid that
//! might reach 98 % for less — until every such pair's mean energies (on the plan's
//! `frontier_energy`: total, or the test article's part) differ by at most `fraction` of the
//! energy at 98 % or `rounds` rounds are spent.
//!
//! Each round is a stage of its own: its new cells are a pure function of the plan and the item
//! records of the stages before it (every run of every cell, read from disk), so that any
//! machine, shard or resumed process derives the same cells, named by their values. The new
//! point lies at the midpoint of the bracketing points' values on every swept key where they
//! differ (one key: the midpoint of their knob values); a pair whose midpoint the family already
//! has gives way to the next. A crossing outside the sweep is not refined.

use crate::challenge::{FamilyRuns, all_means, at_required};
use crate::challenge_table::family_rows;
use crate::grid::Cell;
use crate::method_sweep::{Knob, method_at};
use crate::plan::{Ctx, Method, Plan, PlanError};
use crate::plan_toml::RawRefine;
use crate::tables::ResultRow;

/// Most refinement rounds a plan may ask for.
pub const MAX_ROUNDS: u32 = 20;

/// How a family is refined.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refine {
    /// Stop when the bracketing energies differ by at most this fraction of the energy at 98 %.
    pub fraction: f64,
    /// Most rounds.
    pub rounds: u32,
}

/// Read a `refine` table (`at` its key path); defaults: fraction 0.05, rounds 3.
pub(crate) fn read(ctx: &Ctx, at: &str, raw: &RawRefine) -> Result<Option<Refine>, PlanError> {
    let fraction = raw.fraction.unwrap_or(0.05);
    if !(fraction.is_finite() && fraction > 0.0 && fraction < 1.0) {
        return Err(ctx.err(
            format!("{at}.fraction"),
            format!("expected a fraction in (0, 1) (the largest gap between the bracketing energies), got {fraction}"),
        ));
    }
    let rounds = raw.rounds.unwrap_or(3);
    if !(0..=i64::from(MAX_ROUNDS)).contains(&rounds) {
        return Err(ctx.err(
            format!("{at}.rounds"),
            format!("expected a whole number of rounds from 0 to {MAX_ROUNDS}, got {rounds}"),
        ));
    }
    Ok(Some(Refine { fraction, rounds: rounds as u32 }))
}

/// Check that family `base` (entry `p`) can be refined as `at` asks: it sweeps, and every swept
/// key takes values between those listed (a midpoint fits its configuration).
pub(crate) fn check_family(ctx: &Ctx, p: &str, at: &str, base: &Method, knob: Option<&Knob>) -> Result<(), PlanError> {
    let Some(knob) = knob else {
        return Err(
            ctx.err(at, "expected a swept family (sweep = { \"key.path\" = [values] }): refinement adds knob values")
        );
    };
    let keys: Vec<String> = knob.keys.iter().map(|(k, _)| k.clone()).collect();
    for (i, (key, values)) in knob.keys.iter().enumerate() {
        let mut probe: Vec<f64> = knob.keys.iter().map(|(_, v)| v[0]).collect();
        probe[i] = if values.len() > 1 { 0.5 * (values[0] + values[1]) } else { values[0] + 0.5 };
        if method_at(ctx, p, base, &keys, &probe).is_err() {
            return Err(ctx.err(
                at,
                format!(
                    "expected a family whose swept keys are continuous numbers: {key} does not take {} (refinement \
                     adds midpoints)",
                    probe[i]
                ),
            ));
        }
    }
    Ok(())
}

/// A refinement stage: methods new to the plan and the cells to run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Stage {
    /// Methods the plan does not have yet, in the order first needed.
    pub methods: Vec<Method>,
    /// New cells (their methods index `plan.methods` extended by `methods`).
    pub cells: Vec<Cell>,
}

/// The point between two methods of a family: the midpoint of their values on every key.
fn midpoint(a: &Method, b: &Method) -> Vec<f64> {
    a.grid.iter().zip(&b.grid).map(|((_, x), (_, y))| if x == y { *x } else { 0.5 * (x + y) }).collect()
}

/// A place where a round may add a point: two points of a family (indices of its points) that
/// bracket 98 % on the family's frontier or on one line of its grid.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    lo: usize,
    hi: usize,
    /// The family's frontier bracket (not a line's).
    frontier: bool,
}

/// The lines of a grid family: for each swept key, the family's points grouped by their values
/// on every other key, each group (two points or more) ordered along the key. A family sweeping
/// one key has none (its frontier is its one line).
fn lines(grids: &[&[(String, f64)]]) -> Vec<Vec<usize>> {
    let keys = grids.first().map_or(0, |g| g.len());
    if keys < 2 {
        return Vec::new();
    }
    let mut out = Vec::new();
    for k in 0..keys {
        let mut groups: Vec<(Vec<f64>, Vec<usize>)> = Vec::new();
        for (i, g) in grids.iter().enumerate() {
            let rest: Vec<f64> = g.iter().enumerate().filter(|(j, _)| *j != k).map(|(_, (_, v))| *v).collect();
            match groups.iter_mut().find(|(r, _)| *r == rest) {
                Some((_, members)) => members.push(i),
                None => groups.push((rest, vec![i])),
            }
        }
        for (_, mut members) in groups.into_iter().filter(|(_, m)| m.len() >= 2) {
            members.sort_by(|a, b| grids[*a][k].1.total_cmp(&grids[*b][k].1).then(a.cmp(b)));
            out.push(members);
        }
    }
    out
}

/// The bracket of the runs' crossing of 98 % on a subset `of` of a family's points (indices into
/// the family's points), if it crosses inside them.
fn bracket_on(f: &FamilyRuns, of: &[usize], all: &[usize]) -> Option<Candidate> {
    let points = of.iter().map(|&i| f.points[i].clone()).collect();
    let sub = FamilyRuns { points, duration_s: f.duration_s, energy: f.energy };
    let at = at_required(&sub, all).ok()?;
    Some(Candidate { lo: of[at.bracket.0], hi: of[at.bracket.1], frontier: false })
}

/// Round `round`'s stage (1-based): for each refined family, scenario and stress point, at most
/// one new point. The candidates are the two frontier points that bracket the crossing and, for
/// a grid, the two points that bracket 98 % on each line of the grid (one key varied, the others
/// fixed) whose lower point costs less than the family's energy at 98 %: somewhere between them
/// the family might reach 98 % for less than its frontier says. A candidate whose two energies
/// differ by at most the family's fraction of the energy at 98 % is settled. The round refines
/// the frontier's bracket while it is open, then the open line with the least energy at its lower
/// point: where the answer could lie furthest below the current estimate. `records[c]` holds the
/// rows of `cells[c]`.
pub fn next_stage(plan: &Plan, cells: &[Cell], records: &[Vec<ResultRow>], round: u32) -> Result<Stage, PlanError> {
    let ctx = Ctx { file: &plan.file.display().to_string() };
    let mut stage = Stage::default();
    for row in family_rows(plan, cells, records) {
        let base = &plan.methods[cells[row.cell].method];
        let Some(r) = base.refine.filter(|r| r.rounds >= round) else { continue };
        let all: Vec<usize> = (0..plan.runs as usize).collect();
        let Ok(at) = at_required(&row.runs, &all) else { continue };
        let basis = row.runs.energy;
        let Some(e) = at.figures[basis.at_figure()].filter(|e| *e > 0.0) else { continue };
        let means = all_means(&row.runs);
        let energy = |i: usize| means[i].figures[basis.run_figure()];
        let (lo, hi) = at.bracket;
        let grids: Vec<&[(String, f64)]> =
            row.cells.iter().map(|&c| plan.methods[cells[c].method].grid.as_slice()).collect();
        // A line's lower point is the least energy a point between its pair can need, if
        // completeness and energy rise with every knob: only a line below the estimate can beat it.
        let lines = lines(&grids).into_iter().filter_map(|line| bracket_on(&row.runs, &line, &all));
        let mut open: Vec<(Candidate, f64)> = std::iter::once(Candidate { lo, hi, frontier: true })
            .chain(lines)
            .filter_map(|c| Some((c, energy(c.lo)?, energy(c.hi)?)))
            .filter(|(c, e_lo, e_hi)| (c.frontier || *e_lo < e) && (e_hi - e_lo).abs() / e > r.fraction)
            .map(|(c, e_lo, _)| (c, e_lo))
            .collect();
        // The frontier's own bracket (first in the list) stays first; then the lines, lowest bound
        // first (stable: in line order among equals).
        let skip = usize::from(open.first().is_some_and(|(c, _)| c.frontier));
        open[skip..].sort_by(|a, b| a.1.total_cmp(&b.1));
        let keys: Vec<String> = base.grid.iter().map(|(k, _)| k.clone()).collect();
        let family_entry = plan.methods.iter().position(|m| m.family == base.family).unwrap_or(0);
        let place = &cells[row.cell];
        for (pick, _) in open {
            let method_of = |i: usize| &plan.methods[cells[row.cells[i]].method];
            let values = midpoint(method_of(pick.lo), method_of(pick.hi));
            let mut method = method_at(&ctx, &format!("methods[{family_entry}]"), base, &keys, &values)?;
            method.refined = true;
            let known = plan.methods.iter().chain(&stage.methods).position(|m| m.name == method.name);
            let index = known.unwrap_or(plan.methods.len() + stage.methods.len());
            let cell = Cell { method: index, scenario: place.scenario, point: place.point.clone(), swept: place.swept };
            // A point the family already has here brings nothing new: the next candidate.
            if cells.contains(&cell) || stage.cells.contains(&cell) {
                continue;
            }
            if known.is_none() {
                stage.methods.push(method);
            }
            stage.cells.push(cell);
            break;
        }
    }
    Ok(stage)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn method(v: &[(&str, f64)]) -> Method {
        let plan = Plan::parse(
            "scenarios = [1]\nruns = 1\n[[methods]]\nname = \"m\"\nta = \"default\"\n",
            std::path::Path::new("p.toml"),
        )
        .expect("plan");
        Method { grid: v.iter().map(|(k, x)| (k.to_string(), *x)).collect(), ..plan.methods[0].clone() }
    }

    #[test]
    fn the_midpoint_moves_only_the_keys_that_differ() {
        let a = method(&[("b", 1.0), ("p", 2.0)]);
        let b = method(&[("b", 2.0), ("p", 2.0)]);
        assert_eq!(midpoint(&a, &b), vec![1.5, 2.0]);
        let c = method(&[("b", 3.0), ("p", 4.0)]);
        assert_eq!(midpoint(&a, &c), vec![2.0, 3.0]);
    }
}
