//! `DIR/report.md`: the page a reader opens first — what was compared, what the charts show,
//! which method meets the completeness requirement for the least energy in each scenario, where
//! each method fails under stress, and the summary table.

use crate::challenge_report::{Challenge, challenge_md};
use crate::charts::COMPLETENESS_REQUIRED;
use crate::failure_table::FailureRow;
use crate::frontier_energy::FrontierEnergy;
use crate::grid::Cell;
use crate::paired::paired_rows;
use crate::plan::{MethodTa, Plan, Sweep};
use crate::tables::CellSummary;
use crate::tables::ResultRow;
use mimo_report::study::StudyCharts;
use mimo_store::schema::STUDY_METRICS;
use std::fmt::Write;

/// A value as a reader writes it: `0.25`, `-3`, `1e-6` (paths use `grid::value_text`).
pub(crate) fn value_text(v: f64) -> String {
    if v != 0.0 && (v.abs() < 1e-2 || v.abs() >= 1e6) {
        crate::grid::value_text(v)
    } else {
        let s = format!("{v:.6}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

fn k(name: &str) -> usize {
    STUDY_METRICS.iter().position(|(n, _, _)| *n == name).unwrap_or(0)
}

fn num(v: Option<f64>, scale: f64, digits: usize) -> String {
    v.map(|x| format!("{:.*}", digits, x * scale)).unwrap_or_else(|| "–".into())
}

fn with_ci(s: &CellSummary, metric: &str, scale: f64, digits: usize) -> String {
    let (m, lo, hi) = s.estimates[k(metric)];
    match (m, lo, hi) {
        (Some(_), Some(lo), Some(hi)) => {
            format!("{} ({}–{})", num(m, scale, digits), num(Some(lo), scale, digits), num(Some(hi), scale, digits))
        }
        _ => num(m, scale, digits),
    }
}

/// A cell's stress point as a reader writes it (`—` without axes).
pub(crate) fn point_text(cell: &Cell) -> String {
    if cell.point.is_empty() {
        return "—".into();
    }
    match cell.swept {
        Some(a) => format!("{} = {}", a.name(), value_text(cell.value(a).unwrap_or(f64::NAN))),
        None => {
            cell.point.iter().map(|(a, v)| format!("{} = {}", a.name(), value_text(*v))).collect::<Vec<_>>().join(", ")
        }
    }
}

fn meets(s: &CellSummary) -> bool {
    s.failed == 0 && s.estimates[k("completeness")].0.is_some_and(|c| c >= COMPLETENESS_REQUIRED)
}

/// What the report is written from.
pub struct StudyFigures<'a> {
    /// The plan.
    pub plan: &'a Plan,
    /// Every cell.
    pub cells: &'a [Cell],
    /// Every cell's summary.
    pub summaries: &'a [CellSummary],
    /// Every cell's rows, run by run.
    pub records: &'a [Vec<ResultRow>],
    /// The challenge figures.
    pub challenge: Challenge<'a>,
    /// Every method's failure points.
    pub failures: &'a [FailureRow],
}

/// The report's Markdown text: it opens with the challenge table.
pub fn report_md(s: &StudyFigures, charts: &StudyCharts) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "# {}\n", s.plan.title);
    o.push_str(&challenge_md(s.plan, s.cells, &s.challenge));
    o.push_str(&setup_md(s.plan));
    o.push_str(&energy_md(s));
    o.push_str(&compute_md());
    o.push_str(&crate::failure_report::failure_md(s.plan, s.failures, charts));
    o.push_str(&paired_md(s.plan, s.cells, s.records));
    o.push_str(&summary_md(s));
    o
}

/// What was compared: scenarios and runs, the methods, the stress axes.
fn setup_md(plan: &Plan) -> String {
    let mut o = String::new();
    let dur = plan.duration_s.map(|d| format!("{d} s")).unwrap_or_else(|| "each scenario's own duration".into());
    let _ = writeln!(
        o,
        "Scenarios {}; {} Monte Carlo run(s) per cell of {dur}; master seed {} (run k of every cell uses the same \
         random numbers, so methods are compared on common draws). Written by `mimo study` from `plan.toml`; \
         the numbers are in `summary.parquet` (per cell) and `results.parquet` (per run), timings in `costs.parquet`.\n",
        plan.scenarios.iter().map(|s| s.label()).collect::<Vec<_>>().join(", "),
        plan.runs,
        plan.seed
    );
    let _ = writeln!(
        o,
        "| method (family) | architecture | test article | configuration over its defaults | swept |\n|---|---|---|---|---|"
    );
    let mut families = std::collections::BTreeSet::new();
    for m in plan.methods.iter().filter(|m| families.insert(m.family.clone())) {
        let ta = match &m.ta {
            MethodTa::Builtin { ta, .. } => format!("built-in `{ta}`"),
            MethodTa::Process { cmd, .. } => format!("process `{cmd}`"),
        };
        let swept = swept_text(plan, &m.family);
        let mut shown = m.overrides.clone();
        if let Some(obj) = shown.as_object_mut() {
            // The swept keys' values are in the swept column; show the configuration common to the family.
            for (k, _) in &m.grid {
                remove_path(obj, k);
            }
        }
        let _ = writeln!(o, "| {} | {} | {ta} | `{shown}` | {swept} |", m.family, m.architecture.name());
    }
    if !plan.axes.is_empty() {
        let how = match plan.sweep {
            Sweep::Grid => "every combination",
            Sweep::Each => "one axis at a time, the others at the scenario's own values",
        };
        let _ = writeln!(o, "\nStress axes ({how}):\n");
        for (a, v) in &plan.axes {
            let vals: Vec<String> = v.iter().map(|x| value_text(*x)).collect();
            let _ = writeln!(o, "- `{}` ({}): {}", a.name(), a.label(), vals.join(", "));
        }
    }
    o
}

/// The energy chart and, per scenario, the method that meets the requirement for the least energy.
fn energy_md(s: &StudyFigures) -> String {
    let (plan, cells, sums) = (s.plan, s.cells, s.summaries);
    let mut o = String::new();
    let _ = writeln!(o, "\n## Energy against completeness\n");
    let basis = plan.frontier_energy;
    let x = match basis {
        FrontierEnergy::Total => {
            "total energy per scorable object, every transmit dwell of every radar, search and test article"
        }
        FrontierEnergy::TestArticle => {
            "the test article's energy per scorable object, its own transmit dwells alone (the plan's \
             frontier_energy; background search left out)"
        }
    };
    let _ = writeln!(
        o,
        "![energy against completeness](charts/energy_vs_completeness.png)\n\n\
         x: {x} (the \
         sum over 1-s scoring intervals of energy ÷ objects some radar can see); y: mean track completeness. Each \
         family is its points (labels: knob values; an unswept method is one point) and its efficient frontier, \
         the line through the points no other point of the family beats (at least their completeness for at most \
         their energy), MIMO solid, conventional dashed, points off the frontier smaller; bars are 95 % \
         confidence intervals of the Monte Carlo means; triangles mark where a frontier crosses the requirement, \
         with the bootstrap interval of its energy.\n"
    );
    for (si, sc) in plan.scenarios.iter().enumerate() {
        let mut seen = std::collections::BTreeSet::new();
        let base: Vec<usize> = (0..cells.len())
            .filter(|&c| cells[c].scenario == si && crate::charts::is_baseline(&cells[c]))
            .filter(|&c| seen.insert(cells[c].method))
            .collect();
        if base.is_empty() {
            continue;
        }
        let ok: Vec<usize> = base.iter().copied().filter(|&c| meets(&sums[c])).collect();
        let energy = |c: usize| sums[c].estimates[k(basis.metric())].0.unwrap_or(f64::INFINITY);
        let least = match basis {
            FrontierEnergy::Total => "total energy",
            FrontierEnergy::TestArticle => "test-article energy",
        };
        let line = match ok.iter().copied().min_by(|&a, &b| energy(a).total_cmp(&energy(b))) {
            Some(best) => format!(
                "meets {} % with the least {least}: **{}** ({} J per object); {} of {} method(s) meet it",
                100.0 * COMPLETENESS_REQUIRED,
                plan.methods[cells[best].method].name,
                num(Some(energy(best)), 1.0, 0),
                ok.len(),
                base.len()
            ),
            None => format!("no method meets {} % completeness", 100.0 * COMPLETENESS_REQUIRED),
        };
        let _ = writeln!(o, "- Scenario {}: {line}.", sc.label());
    }
    o
}

/// The compute chart.
fn compute_md() -> String {
    "\n## Compute against accuracy\n\n\
     ![compute against accuracy](charts/compute_vs_accuracy.png)\n\n\
     x: compute inside the test article per simulated second, in reference EKF cycles (`ta_cpu_kfu` of \
     `costs.parquet`: CPU time ÷ the CPU time of one 6-state EKF predict + update measured on the same \
     machine; CPU seconds when a run lacks the reference); y: position RMSE and GOSPA (c = 1000 m, p = 2).\n\n"
        .to_string()
}

/// The summary table of every cell and the list of failed runs.
fn summary_md(s: &StudyFigures) -> String {
    let (plan, cells, sums) = (s.plan, s.cells, s.summaries);
    let mut o = String::new();
    let _ = writeln!(o, "## Summary\n");
    let _ = writeln!(
        o,
        "Means over the completed runs with 95 % confidence intervals in brackets (Student t over the runs, clipped \
         to the range the metric can take; none with fewer than two runs). Energy and dwell time are per scorable \
         object: the total (search and test article) first, then the test article's part.\n"
    );
    let _ = writeln!(
        o,
        "| method | scenario | stress | runs (failed) | completeness % | energy (J) | dwell (s) | TA energy (J) | TA dwell (s) | breaks | switches | position RMSE (m) | GOSPA (m) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|---|---|"
    );
    for (c, s) in cells.iter().zip(sums) {
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} ({}) | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            plan.methods[c.method].name,
            plan.scenarios[c.scenario].label(),
            point_text(c),
            s.runs,
            s.failed,
            with_ci(s, "completeness", 100.0, 2),
            with_ci(s, "energy_per_object_j", 1.0, 0),
            with_ci(s, "dwell_time_per_object_s", 1.0, 2),
            with_ci(s, "ta_energy_per_object_j", 1.0, 0),
            with_ci(s, "ta_dwell_time_per_object_s", 1.0, 2),
            with_ci(s, "breaks", 1.0, 1),
            with_ci(s, "switches", 1.0, 1),
            with_ci(s, "position_rmse_m", 1.0, 1),
            with_ci(s, "gospa_m", 1.0, 0),
        );
    }
    let failures: Vec<String> = cells
        .iter()
        .zip(sums)
        .filter_map(|(c, s)| {
            let f = s.failure.as_ref()?;
            let (m, sc) = (&plan.methods[c.method].name, plan.scenarios[c.scenario].label());
            Some(format!(
                "- {m} / scenario {sc} / {}: {} of {} runs failed; the first: {f}",
                point_text(c),
                s.failed,
                s.runs
            ))
        })
        .collect();
    if !failures.is_empty() {
        let _ = writeln!(o, "\n## Failed runs\n\n{}", failures.join("\n"));
    }
    o
}

/// Remove the dotted key `path` from a JSON object, and any table it leaves empty.
/// The swept column of `family`: each key with the values the plan gives it, joined by ` × ` for
/// a grid (every combination), then the points refinement added (docs/studies.md, "Refinement"):
/// values for one key, `(v₁, v₂, …)` in the keys' order for a grid. `–` when it sweeps nothing.
fn swept_text(plan: &Plan, family: &str) -> String {
    let members: Vec<&crate::plan::Method> = plan.methods.iter().filter(|x| x.family == family).collect();
    let Some(keys) = members.first().map(|m| m.grid.iter().map(|(k, _)| k.as_str()).collect::<Vec<_>>()) else {
        return "–".into();
    };
    if keys.is_empty() {
        return "–".into();
    }
    let axes: Vec<String> = keys
        .iter()
        .enumerate()
        .map(|(i, k)| {
            let mut values: Vec<f64> = Vec::new();
            for m in members.iter().filter(|m| !m.refined) {
                let v = m.grid[i].1;
                if !values.contains(&v) {
                    values.push(v);
                }
            }
            format!("`{k}` = {}", values.into_iter().map(value_text).collect::<Vec<_>>().join(", "))
        })
        .collect();
    let mut text = axes.join(" × ");
    let refined: Vec<String> = members
        .iter()
        .filter(|m| m.refined)
        .map(|m| {
            let v: Vec<String> = m.grid.iter().map(|(_, x)| value_text(*x)).collect();
            if v.len() == 1 { v.concat() } else { format!("({})", v.join(", ")) }
        })
        .collect();
    if !refined.is_empty() {
        let _ = write!(text, "; refined: {}", refined.join(", "));
    }
    text
}

fn remove_path(obj: &mut serde_json::Map<String, serde_json::Value>, path: &str) {
    match path.split_once('.') {
        None => {
            obj.remove(path);
        }
        Some((head, rest)) => {
            if let Some(serde_json::Value::Object(inner)) = obj.get_mut(head) {
                remove_path(inner, rest);
                if inner.is_empty() {
                    obj.remove(head);
                }
            }
        }
    }
}

/// `mean (lo–hi)` of a paired difference, scaled.
fn diff_text(d: (Option<f64>, Option<f64>, Option<f64>), scale: f64, digits: usize) -> String {
    match d {
        (Some(m), Some(lo), Some(hi)) => {
            format!("{:+.*} ({:+.*} to {:+.*})", digits, m * scale, digits, lo * scale, digits, hi * scale)
        }
        (m, _, _) => num(m, scale, digits),
    }
}

/// The paired differences between MIMO methods and their conventional counterparts.
fn paired_md(plan: &Plan, cells: &[Cell], records: &[Vec<ResultRow>]) -> String {
    let rows = paired_rows(plan, cells, records);
    if rows.is_empty() {
        return String::new();
    }
    let mut o = String::new();
    let _ = writeln!(o, "## MIMO against its conventional counterpart, run by run\n");
    let _ = writeln!(
        o,
        "Each MIMO method beside the conventional method with the same test article and knob value: the mean of the \
         per-run differences (MIMO − conventional; run k of both shares its random draws) with its paired Student-t \
         95 % interval, over the runs both completed.\n"
    );
    let _ = writeln!(
        o,
        "| scenario | stress | MIMO | conventional | runs | Δ completeness (points of %) | Δ energy per object (J, search and TA) |\n\
         |---|---|---|---|---|---|---|"
    );
    for r in rows {
        let c = &cells[r.mimo];
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} | {} | {} | {} |",
            plan.scenarios[c.scenario].label(),
            point_text(c),
            plan.methods[c.method].name,
            plan.methods[cells[r.conventional].method].name,
            r.runs,
            diff_text(r.completeness, 100.0, 2),
            diff_text(r.energy_j, 1.0, 0),
        );
    }
    let _ = writeln!(o);
    o
}

#[cfg(test)]
mod tests {
    use crate::plan::Plan;

    fn plan(text: &str) -> Plan {
        Plan::parse(text, std::path::Path::new("p.toml")).expect("plan")
    }

    /// The method table's row of `family` (docs/studies.md, "What a study writes").
    fn row(plan: &Plan, family: &str) -> String {
        let md = super::setup_md(plan);
        md.lines().find(|l| l.starts_with(&format!("| {family} |"))).unwrap_or_else(|| panic!("{md}")).to_string()
    }

    #[test]
    fn a_grid_family_lists_every_key_with_its_values() {
        let mut p = plan(
            "scenarios = [1]\nruns = 1\n[[methods]]\nname = \"g\"\nta = \"default\"\n\
             config = { resource_manager = { mimo = false } }\n\
             sweep = { \"search_manager.held_share\" = [0.0, 0.1, 1.0], \"resource_manager.power_budget_w\" = [1.0, 4.0] }\n\
             [[methods]]\nname = \"c\"\nta = \"default\"\nsweep = { \"resource_manager.power_budget_w\" = [0.25, 2.0] }\n\
             [[methods]]\nname = \"u\"\nta = \"default\"\n",
        );
        assert_eq!(p.methods.len(), 6 + 2 + 1);
        let g = row(&p, "g");
        assert!(
            g.ends_with("| `resource_manager.power_budget_w` = 1, 4 × `search_manager.held_share` = 0, 0.1, 1 |"),
            "{g}"
        );
        // The configuration column is what the family's points share: the swept keys are not in it.
        assert!(g.contains("| `{\"resource_manager\":{\"mimo\":false}}` |"), "{g}");
        assert!(row(&p, "c").ends_with("| `{}` | `resource_manager.power_budget_w` = 0.25, 2 |"));
        assert!(row(&p, "u").ends_with("| `{}` | – |"));

        // Points refinement added are listed after the plan's values, in the keys' order for a grid.
        let mut refined = p.methods[1].clone();
        refined.grid = vec![("resource_manager.power_budget_w".into(), 2.5), ("search_manager.held_share".into(), 0.0)];
        refined.refined = true;
        let mut curve = p.methods[6].clone();
        curve.grid = vec![("resource_manager.power_budget_w".into(), 1.125)];
        curve.refined = true;
        p.methods.extend([refined, curve]);
        let g = row(&p, "g");
        assert!(g.ends_with("`search_manager.held_share` = 0, 0.1, 1; refined: (2.5, 0) |"), "{g}");
        let c = row(&p, "c");
        assert!(c.ends_with("`resource_manager.power_budget_w` = 0.25, 2; refined: 1.125 |"), "{c}");
    }

    #[test]
    fn values_read_as_written() {
        let t: Vec<String> = [0.25, -3.0, 1e-6, 0.0, 2.0, 0.5].iter().map(|v| super::value_text(*v)).collect();
        assert_eq!(t, ["0.25", "-3", "1e-6", "0", "2", "0.5"]);
    }
}
