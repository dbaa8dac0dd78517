//! The section `report.md` opens with: the challenge table (per scenario and stress point, each
//! family's total energy, dwell time and power at 98 % completeness on its efficient frontier,
//! with bootstrap intervals, its test article's part, the worst target's time to first track and
//! the bracketing frontier points) and the paired MIMO ÷ conventional energy ratios.

use crate::bootstrap::RESAMPLES;
use crate::challenge::{
    AT_DWELL, AT_ENERGY, AT_FIRST_TRACK_MAX, AT_POWER, AT_TA_ENERGY, COMPLETENESS_REQUIRED, WithCi, reason,
};
use crate::challenge_table::{FamilyRow, RatioRow};
use crate::frontier_energy::FrontierEnergy;
use crate::frontier_steps::{marginal_costs, steeper_share};
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
        "Per scenario, each family (a `[[methods]]` entry; a swept one is a set of points, a curve or a grid) read \
         on its efficient frontier: of its points, those no other point beats (at least their mean completeness for \
         at most their mean energy). The crossing lies between the first frontier point whose mean completeness \
         reaches {pct} % with no failed run and the frontier point before it, interpolated linearly in \
         completeness. Energy, dwell time and power (energy ÷ duration) per scorable object are **totals**: every \
         transmit dwell of every radar, search and test article; the test article's own part is in the TA column \
         and in `ta_energy_at_98_j` of `challenge.parquet`. In brackets, 95 % percentile intervals from {RESAMPLES} \
         bootstrap resamples of the {} Monte Carlo run(s), one resample applied to every point of a family (run k \
         of every cell shares its random draws), each resample rebuilding the frontier from its own means and \
         re-reading the crossing on it; `…` marks an end beyond the sweep. With few runs these intervals are too \
         narrow: raise `runs` for a claim. The bracket gives the two frontier points around the crossing and their \
         energy gap as a fraction of the energy at {pct} %; the first-track column is the mean over runs of the \
         time from first scorable to first confirmed track of the run's worst target, at the crossing.\n",
        plan.runs
    );
    if plan.frontier_energy == FrontierEnergy::TestArticle {
        let _ = writeln!(
            o,
            "**This study's frontiers are built on the test article's energy** (`frontier_energy = \"test_article\"`; \
             docs/decisions/0318-frontier-on-the-test-articles-energy.md): each point sits at its mean TA energy per \
             scorable object, the background search left out, since its knob shapes only what the test article \
             spends. The crossing, the bracket and its gap are read on that energy; the totals at the crossing are \
             still given.\n"
        );
    }
    let _ = writeln!(
        o,
        "| scenario | stress | family | architecture | holds | knob at {pct} % | energy at {pct} % (J) | dwell time at \
         {pct} % (s) | power at {pct} % (W) | TA energy at {pct} % (J) | worst first track (s) | bracket (gap) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for f in c.families {
        let cell = &cells[f.cell];
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {} | {} |",
            plan.scenarios[cell.scenario].label(),
            crate::report::point_text(cell),
            f.family,
            f.architecture.name(),
            if f.challenge.holds { "yes" } else { "no" },
            figures_md(f),
        );
    }
    ratios_md(&mut o, plan, cells, c, pct);
    steps_md(&mut o, plan, cells, c);
    o
}

/// Each family's frontier point by point with the marginal cost of each step (energy per point
/// of completeness gained from the frontier point before it); nothing when no frontier has two
/// points.
fn steps_md(o: &mut String, plan: &Plan, cells: &[Cell], c: &Challenge) {
    if c.families.iter().all(|f| f.challenge.frontier.len() < 2) {
        return;
    }
    let basis = plan.frontier_energy;
    let _ = writeln!(
        o,
        "Each family's efficient frontier point by point, on its {}, with the marginal cost of each step: the \
         energy added per point of completeness gained from the frontier point before it. Where the marginal cost \
         falls (↓), the frontier is not convex at that step. From the third point on, the last column gives the \
         share of the {RESAMPLES} bootstrap resamples of the runs in which the step into the point gains \
         completeness faster per joule than the step before (the same points, their means re-read): a fall that \
         holds in at least 97.5 % of them is a knee the runs resolve; one in fewer may be the runs' spread.\n\n\
         | scenario | stress | family | frontier point | energy (J) | completeness % | J per point | falls in resamples |\n\
         |---|---|---|---|---|---|---|---|",
        basis.words()
    );
    let boot = crate::bootstrap::resamples(plan.seed, plan.runs as usize, RESAMPLES);
    for f in c.families.iter().filter(|f| f.challenge.frontier.len() >= 2) {
        let cell = &cells[f.cell];
        let means = crate::challenge::all_means(&f.runs);
        let points: Vec<(usize, f64, f64)> = f
            .challenge
            .frontier
            .iter()
            .filter_map(|&j| Some((j, means[j].figures[basis.run_figure()]?, means[j].completeness?)))
            .collect();
        let costs = marginal_costs(&points.iter().map(|&(_, e, c)| (e, c)).collect::<Vec<_>>());
        let shares = steeper_share(&f.runs, &points.iter().map(|&(j, _, _)| j).collect::<Vec<_>>(), &boot);
        let mut last_cost: Option<f64> = None;
        for ((&(j, e, done), &cost), share) in points.iter().zip(&costs).zip(&shares) {
            let cost_text = match (cost, last_cost) {
                (Some(x), Some(before)) if x < before => format!("{} ↓", num(x, 1)),
                (Some(x), _) => num(x, 1),
                (None, _) => "–".to_string(),
            };
            let _ = writeln!(
                o,
                "| {} | {} | {} | {} | {} | {} | {cost_text} | {} |",
                plan.scenarios[cell.scenario].label(),
                crate::report::point_text(cell),
                f.family,
                f.runs.points[j].method,
                num(e, 0),
                num(100.0 * done, 2),
                share.map_or_else(|| "–".to_string(), |x| format!("{} %", num(100.0 * x, 1))),
            );
            last_cost = cost.or(last_cost);
        }
    }
    let _ = writeln!(o);
}

/// The figures of a family's row, from the knob on.
fn figures_md(f: &FamilyRow) -> String {
    let a = match &f.challenge.at {
        Ok(a) => a,
        Err(e) => return format!("– | – ({}) | – | – | – | – | – |", reason(e)),
    };
    let knob = match (&f.knob, a.knob) {
        (Some(k), Some(v)) => format!("{k} = {}", num(v, 3)),
        _ => "–".into(),
    };
    let fig = |i: usize, digits: usize| a.figures[i].map_or_else(|| "–".to_string(), |w| with_ci(&w, digits));
    let (lo, hi) = a.bracket;
    let means = crate::challenge::all_means(&f.runs);
    // On the frontier's energy (total, or the test article's part).
    let run_energy = f.runs.energy.run_figure();
    let e = |j: usize| means[j].figures[run_energy].map_or_else(|| "–".into(), |x| num(x, 0));
    let gap = match (means[lo].figures[run_energy], means[hi].figures[run_energy], a.figures[f.runs.energy.at_figure()])
    {
        (Some(x), Some(y), Some(w)) if w.0 > 0.0 => format!("{:.1} %", 100.0 * (y - x) / w.0),
        _ => "–".into(),
    };
    let bracket =
        format!("{} ({} J) – {} ({} J): {gap}", f.runs.points[lo].method, e(lo), f.runs.points[hi].method, e(hi));
    format!(
        "{knob} | {} | {} | {} | {} | {} | {bracket}",
        fig(AT_ENERGY, 0),
        fig(AT_DWELL, 3),
        fig(AT_POWER, 2),
        fig(AT_TA_ENERGY, 0),
        fig(AT_FIRST_TRACK_MAX, 1),
    )
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
        "\nMIMO ÷ conventional energy per scorable object at {pct} %, total (search and test article) and the test \
         article's part, with the paired bootstrap interval (one resample of run indices applied to both families, \
         each rebuilding both frontiers):\n\n\
         | scenario | stress | MIMO family | conventional family | energy ratio (95 %) | TA energy ratio (95 %) |\n\
         |---|---|---|---|---|---|"
    );
    for r in c.ratios {
        let cell = &cells[c.families[r.mimo].cell];
        let text = |r: &Result<WithCi, String>| match r {
            Ok(w) => with_ci(w, 3),
            Err(why) => format!("– ({why})"),
        };
        let (ratio, ta_ratio) = (text(&r.ratio), text(&r.ta_ratio));
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {ratio} | {ta_ratio} |",
            plan.scenarios[cell.scenario].label(),
            crate::report::point_text(cell),
            c.families[r.mimo].family,
            c.families[r.conventional].family,
        );
    }
    let _ = writeln!(o);
}
