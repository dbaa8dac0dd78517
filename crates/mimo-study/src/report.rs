//! `DIR/report.md`: the page a reader opens first — what was compared, what the charts show,
//! which method meets the completeness requirement for the least energy in each scenario, where
//! each method fails under stress, and the summary table.

use crate::charts::COMPLETENESS_REQUIRED;
use crate::grid::Cell;
use crate::plan::{MethodTa, Plan, Sweep};
use crate::tables::CellSummary;
use mimo_report::study::StudyCharts;
use mimo_store::schema::STUDY_METRICS;
use std::fmt::Write;

/// A value as a reader writes it: `0.25`, `-3`, `1e-6` (paths use `grid::value_text`).
fn value_text(v: f64) -> String {
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

fn point_text(cell: &Cell) -> String {
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

/// The report's Markdown text.
pub fn report_md(plan: &Plan, cells: &[Cell], sums: &[CellSummary], charts: &StudyCharts) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "# {}\n", plan.title);
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
    let _ = writeln!(o, "| method | test article | configuration over its defaults |\n|---|---|---|");
    for m in &plan.methods {
        let ta = match &m.ta {
            MethodTa::Builtin { ta, .. } => format!("built-in `{ta}`"),
            MethodTa::Process { cmd, .. } => format!("process `{cmd}`"),
        };
        let _ = writeln!(o, "| {} | {ta} | `{}` |", m.name, m.overrides);
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

    let _ = writeln!(o, "\n## Energy against completeness\n");
    let _ = writeln!(
        o,
        "![energy against completeness](charts/energy_vs_completeness.png)\n\n\
         x: energy of the dwells the test article requested, per scorable object (the sum over 1-s scoring \
         intervals of energy ÷ objects some radar can see; background search is the same for every method and \
         left out); y: track completeness. Bars are 95 % confidence intervals of the Monte Carlo means; the \
         grey step line is the non-dominated front.\n"
    );
    for (si, s) in plan.scenarios.iter().enumerate() {
        let base: Vec<usize> =
            (0..cells.len()).filter(|&c| cells[c].scenario == si && crate::charts::is_baseline(&cells[c])).collect();
        let mut seen = std::collections::BTreeSet::new();
        let base: Vec<usize> = base.into_iter().filter(|&c| seen.insert(cells[c].method)).collect();
        if base.is_empty() {
            continue;
        }
        let ok: Vec<usize> = base.iter().copied().filter(|&c| meets(&sums[c])).collect();
        let energy = |c: usize| sums[c].estimates[k("ta_energy_per_object_j")].0.unwrap_or(f64::INFINITY);
        let line = match ok.iter().copied().min_by(|&a, &b| energy(a).total_cmp(&energy(b))) {
            Some(best) => format!(
                "meets {} % with the least energy: **{}** ({} J per object); {} of {} method(s) meet it",
                100.0 * COMPLETENESS_REQUIRED,
                plan.methods[cells[best].method].name,
                num(Some(energy(best)), 1.0, 0),
                ok.len(),
                base.len()
            ),
            None => format!("no method meets {} % completeness", 100.0 * COMPLETENESS_REQUIRED),
        };
        let _ = writeln!(o, "- Scenario {}: {line}.", s.label());
    }

    let _ = writeln!(o, "\n## Compute against accuracy\n");
    let _ = writeln!(
        o,
        "![compute against accuracy](charts/compute_vs_accuracy.png)\n\n\
         x: CPU seconds spent inside the test article per simulated second (machine-dependent: from \
         `costs.parquet`); y: position RMSE and GOSPA (c = 1000 m, p = 2).\n"
    );

    if !charts.axes.is_empty() {
        let _ = writeln!(o, "## Where each method fails\n");
        for ax in &charts.axes {
            let _ = writeln!(o, "![stability against {0}](charts/stability_{0}.png)\n", ax.name);
        }
        let _ = writeln!(
            o,
            "The failure point is the first value, from the least to the most stressing, where the mean \
             completeness falls below {} % or a run fails (crosses on the charts).\n",
            100.0 * COMPLETENESS_REQUIRED
        );
        let _ = writeln!(
            o,
            "| method | scenario | {} |",
            charts.axes.iter().map(|a| a.name.as_str()).collect::<Vec<_>>().join(" | ")
        );
        let _ = writeln!(o, "|---|---|{}", "---|".repeat(charts.axes.len()));
        for (mi, m) in plan.methods.iter().enumerate() {
            for (si, s) in plan.scenarios.iter().enumerate() {
                let mut row = format!("| {} | {} |", m.name, s.label());
                for (a, values) in &plan.axes {
                    let at = a.by_stress(values).into_iter().find(|v| {
                        cells.iter().zip(sums).any(|(c, sm)| {
                            c.method == mi
                                && c.scenario == si
                                && c.value(*a) == Some(*v)
                                && (c.swept.is_none_or(|x| x == *a))
                                && !meets(sm)
                        })
                    });
                    let _ = write!(
                        row,
                        " {} |",
                        at.map(|v| format!("fails at {}", value_text(v)))
                            .unwrap_or_else(|| "holds over the range".into())
                    );
                }
                let _ = writeln!(o, "{row}");
            }
        }
        let _ = writeln!(o);
    }

    let _ = writeln!(o, "## Summary\n");
    let _ = writeln!(
        o,
        "Means over the completed runs with 95 % confidence intervals in brackets (Student t; none with fewer than \
         two runs). Energy and dwell time are per scorable object.\n"
    );
    let _ = writeln!(
        o,
        "| method | scenario | stress | runs (failed) | completeness % | TA energy (J) | TA dwell (s) | breaks | switches | position RMSE (m) | GOSPA (m) |\n\
         |---|---|---|---|---|---|---|---|---|---|---|"
    );
    for (c, s) in cells.iter().zip(sums) {
        let _ = writeln!(
            o,
            "| {} | {} | {} | {} ({}) | {} | {} | {} | {} | {} | {} | {} |",
            plan.methods[c.method].name,
            plan.scenarios[c.scenario].label(),
            point_text(c),
            s.runs,
            s.failed,
            with_ci(s, "completeness", 100.0, 2),
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
            s.failure.as_ref().map(|f| {
                format!(
                    "- {} / scenario {} / {}: {} of {} runs failed; the first: {f}",
                    plan.methods[c.method].name,
                    plan.scenarios[c.scenario].label(),
                    point_text(c),
                    s.failed,
                    s.runs
                )
            })
        })
        .collect();
    if !failures.is_empty() {
        let _ = writeln!(o, "\n## Failed runs\n\n{}", failures.join("\n"));
    }
    o
}

#[cfg(test)]
mod tests {
    #[test]
    fn values_read_as_written() {
        let t: Vec<String> = [0.25, -3.0, 1e-6, 0.0, 2.0, 0.5].iter().map(|v| super::value_text(*v)).collect();
        assert_eq!(t, ["0.25", "-3", "1e-6", "0", "2", "0.5"]);
    }
}
