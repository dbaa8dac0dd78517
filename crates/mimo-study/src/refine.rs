//! Refinement where a family's frontier crosses 98 % (docs/studies.md, "Refinement"): a plan's
//! `[refine]` (every swept family) or a `[[methods]]` entry's `refine = { fraction, rounds }`
//! adds points to a family, scenario by scenario and stress point by stress point, between the
//! two frontier points that bracket the crossing, until their mean total energies differ by at
//! most `fraction` of the energy at 98 % or `rounds` rounds are spent.
//!
//! Each round is a stage of its own: its new cells are a pure function of the plan and the item
//! records of the stages before it (every run of every cell, read from disk), so that any
//! machine, shard or resumed process derives the same cells, named by their values. The new
//! point lies at the midpoint of the bracketing points' values on every swept key where they
//! differ (one key: the midpoint of their knob values); a point the family already has there
//! ends its refinement. A crossing outside the sweep is not refined.

use crate::challenge::{RUN_ENERGY, all_means, at_required};
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

/// Round `round`'s stage (1-based): for each refined family, scenario and stress point whose
/// bracketing energies differ by more than its fraction, the point between them; `records[c]`
/// holds the rows of `cells[c]`.
pub fn next_stage(plan: &Plan, cells: &[Cell], records: &[Vec<ResultRow>], round: u32) -> Result<Stage, PlanError> {
    let ctx = Ctx { file: &plan.file.display().to_string() };
    let mut stage = Stage::default();
    for row in family_rows(plan, cells, records) {
        let base = &plan.methods[cells[row.cell].method];
        let Some(r) = base.refine.filter(|r| r.rounds >= round) else { continue };
        let all: Vec<usize> = (0..plan.runs as usize).collect();
        let Ok(at) = at_required(&row.runs, &all) else { continue };
        let means = all_means(&row.runs);
        let (lo, hi) = at.bracket;
        let (Some(e_lo), Some(e_hi), Some(e)) =
            (means[lo].figures[RUN_ENERGY], means[hi].figures[RUN_ENERGY], at.figures[crate::challenge::AT_ENERGY])
        else {
            continue;
        };
        if e <= 0.0 || (e_hi - e_lo).abs() / e <= r.fraction {
            continue;
        }
        let (m_lo, m_hi) = (&plan.methods[cells[row.cells[lo]].method], &plan.methods[cells[row.cells[hi]].method]);
        let values = midpoint(m_lo, m_hi);
        let keys: Vec<String> = base.grid.iter().map(|(k, _)| k.clone()).collect();
        let family_entry = plan.methods.iter().position(|m| m.family == base.family).unwrap_or(0);
        let mut method = method_at(&ctx, &format!("methods[{family_entry}]"), base, &keys, &values)?;
        method.refined = true;
        let index = match plan.methods.iter().chain(&stage.methods).position(|m| m.name == method.name) {
            Some(i) => i,
            None => {
                stage.methods.push(method);
                plan.methods.len() + stage.methods.len() - 1
            }
        };
        let place = &cells[row.cell];
        let cell = Cell { method: index, scenario: place.scenario, point: place.point.clone(), swept: place.swept };
        // A point the family already has here: no progress is possible.
        if !cells.contains(&cell) && !stage.cells.contains(&cell) {
            stage.cells.push(cell);
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
