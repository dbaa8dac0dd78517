//! The section `report.md` opens with: the challenge table (per scenario and stress point, each
//! family's energy, dwell time and power at 98 % completeness with bootstrap intervals) and the
//! paired MIMO ÷ conventional energy ratios.

use crate::bootstrap::RESAMPLES;
use crate::challenge::{COMPLETENESS_REQUIRED, WithCi, reason};
use crate::challenge_table::{FamilyRow, RatioRow};
use crate::grid::Cell;
use crate::plan::Plan;
use std::fmt::Write;

/// The challenge figures handed to the report.
pub struct Challenge<'a> {
    /// Every family × scenario × stress point.
    pub families: &'a [FamilyRow],
    /// Every (MIMO, conventional) pair.
    pub ratios: &'a [RatioRow],
}

fn num(v: f64, digits: usize) -> String {
    format!("{v:.digits$}")
}

/// `value (lo–hi)`; an end outside the sweep is `…`.
fn with_ci(w: &WithCi, digits: usize) -> String {
    let end = |x: Option<f64>| x.map_or_else(|| "…".to_string(), |x| num(x, digits));
    format!("{} ({}–{})", num(w.0, digits), end(w.1), end(w.2))
}

/// The section's Markdown.
pub fn challenge_md(plan: &Plan, cells: &[Cell], c: &Challenge) -> String {
    let mut o = String::new();
    let pct = 100.0 * COMPLETENESS_REQUIRED;
    let _ = writeln!(o, "## The challenge: {pct} % track completeness for the least energy\n");
    if c.families.iter().all(|f| f.knob.is_none()) {
        no_knob_md(&mut o, plan, pct);
        return o;
    }
    let _ = writeln!(
        o,
        "Per scenario, each family (a `[[methods]]` entry; a swept one is a curve of points) at the first point of \
         its knob where the mean completeness reaches {pct} % with no failed run, interpolated linearly between that \
         point and the one before: the TA energy, dwell time and power (energy ÷ duration) per scorable object. \
         In brackets, 95 % percentile intervals from {RESAMPLES} bootstrap resamples of the {} Monte Carlo run(s), \
         one resample applied to every point of a family (run k of every cell shares its random draws); `…` marks \
         an end beyond the sweep. With few runs these intervals are too narrow (three runs cover the mean about \
         three times in four): read them as the spread of the runs, and raise `runs` for a claim.\n",
        plan.runs
    );
    let _ = writeln!(
        o,
        "| scenario | stress | family | architecture | holds | knob at {pct} % | energy at {pct} % (J) | dwell time at \
         {pct} % (s) | power at {pct} % (W) |\n|---|---|---|---|---|---|---|---|---|"
    );
    for f in c.families {
        let cell = &cells[f.cell];
        let knob = |v: Option<f64>| match (&f.knob, v) {
            (Some(k), Some(v)) => format!("{k} = {}", num(v, 3)),
            _ => "–".into(),
        };
        let figures = match &f.challenge.at {
            Ok((k, e, d, p)) => format!("{} | {} | {} | {}", knob(*k), with_ci(e, 0), with_ci(d, 3), with_ci(p, 2)),
            Err(e) => format!("– | – ({}) | – | –", reason(e)),
        };
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {} | {figures} |",
            plan.scenarios[cell.scenario].label(),
            crate::report::point_text(cell),
            f.family,
            f.architecture.name(),
            if f.challenge.holds { "yes" } else { "no" },
        );
    }
    ratios_md(&mut o, plan, cells, c, pct);
    o
}

/// The section when no family sweeps a knob: why no energy at the requirement is given.
fn no_knob_md(o: &mut String, plan: &Plan, pct: f64) {
    let _ = write!(
        o,
        "No method sweeps a knob (a `[[methods]]` entry with `sweep`), so no family has a curve to cross \
         {pct} % on: the energy at {pct} % is not defined here."
    );
    if !plan.axes.is_empty() {
        let _ =
            write!(o, " Where each method stops holding {pct} % under stress is in \"Where each method fails\" below.");
    }
    let _ = writeln!(o, "\n");
}

/// The MIMO ÷ conventional energy ratios at the requirement, or why there are none.
fn ratios_md(o: &mut String, plan: &Plan, cells: &[Cell], c: &Challenge, pct: f64) {
    if c.ratios.is_empty() {
        let _ = writeln!(o, "\nNo scenario has both a MIMO and a conventional family: no ratio to give.\n");
        return;
    }
    let _ = writeln!(
        o,
        "\nMIMO ÷ conventional TA energy per scorable object at {pct} %, with the paired bootstrap interval (one \
         resample of run indices applied to both families):\n\n\
         | scenario | stress | MIMO family | conventional family | energy ratio (95 %) |\n|---|---|---|---|---|"
    );
    for r in c.ratios {
        let cell = &cells[c.families[r.mimo].cell];
        let ratio = match &r.ratio {
            Ok(w) => with_ci(w, 3),
            Err(why) => format!("– ({why})"),
        };
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {ratio} |",
            plan.scenarios[cell.scenario].label(),
            crate::report::point_text(cell),
            c.families[r.mimo].family,
            c.families[r.conventional].family,
        );
    }
    let _ = writeln!(o);
}
