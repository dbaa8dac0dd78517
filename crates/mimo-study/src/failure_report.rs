//! The report's "Where each method fails" section: the stability charts and a table of every
//! method's failure point on every axis with its 95 % bootstrap interval (docs/studies.md).

use crate::charts::COMPLETENESS_REQUIRED;
use crate::failure_point::{Failure, numeric_interval};
use crate::failure_table::FailureRow;
use crate::plan::Plan;
use crate::report::value_text;
use mimo_report::study::StudyCharts;
use std::fmt::Write;

/// An estimate (a failure point or an interval end) to three significant figures, as a bootstrap
/// over ten runs supports no more: `-4.03`, `0.316`, `57.2`, `1.04e-6`. Grid values keep
/// [`value_text`].
pub(crate) fn estimate_text(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return value_text(v);
    }
    let magnitude = v.abs().log10().floor() as i32;
    if !(-3..6).contains(&magnitude) {
        return format!("{v:.2e}");
    }
    let decimals = (2 - magnitude).max(0) as usize;
    format!("{v:.decimals$}")
}

/// An interval as the table writes it: `a to b`, an end off the grid as `< v` or `> v` of the
/// grid's end on that side.
fn interval_text(r: &FailureRow) -> Option<String> {
    let (lo, hi, word) = numeric_interval(r.point.interval, r.axis.harder_when_larger());
    let min = r.values.iter().copied().fold(f64::INFINITY, f64::min);
    let max = r.values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let below = || format!("< {}", value_text(min));
    let above = || format!("> {}", value_text(max));
    let end = |v: Option<f64>, off: &dyn Fn() -> String| v.map_or_else(off, estimate_text);
    match word {
        "none" => None,
        "below_grid" => Some(below()),
        "above_grid" => Some(above()),
        _ => Some(format!("{} to {}", end(lo, &below), end(hi, &above))),
    }
}

/// One table cell: the failure point with its interval, or what holds.
fn point_text(r: &FailureRow) -> String {
    let ci = interval_text(r);
    let with = |s: String| match &ci {
        Some(ci) => format!("{s} (95 %: {ci})"),
        None => s,
    };
    let first = r.values.first().copied().map(value_text).unwrap_or_default();
    let last = r.values.last().copied().map(value_text).unwrap_or_default();
    match r.point.failure {
        Failure::At(_) => with(format!("**{}**", r.point.value.map(estimate_text).unwrap_or_default())),
        Failure::Holds => with(format!("holds over the range (to {last})")),
        Failure::FailsAtBaseline => with(format!("fails at the baseline ({first})")),
    }
}

/// The section, with a chart per axis and the table (empty without axes).
pub fn failure_md(plan: &Plan, rows: &[FailureRow], charts: &StudyCharts) -> String {
    if charts.axes.is_empty() {
        return String::new();
    }
    let mut o = String::new();
    let _ = writeln!(o, "## Where each method fails\n");
    for ax in &charts.axes {
        let _ = writeln!(o, "![stability against {0}](charts/stability_{0}.png)\n", ax.name);
    }
    let axes: Vec<_> = plan.axes.iter().map(|(a, _)| *a).collect();
    let harder: Vec<String> = axes
        .iter()
        .map(|a| format!("{} `{}`", if a.harder_when_larger() { "a larger" } else { "a smaller" }, a.name()))
        .collect();
    let _ = writeln!(
        o,
        "A method's failure point on an axis is where its mean completeness (a failed run counting as 0) falls \
         below {} %, walking from the least to the most stressing value ({}): interpolated linearly between the last \
         grid value that holds and the first that does not (holding: mean completeness at least the requirement \
         and no failed run), on log10 of the value for `pfa`. In brackets its 95 % bootstrap interval over the \
         Monte Carlo runs; an end that runs off the grid is written `< v` or `> v` of the grid's end. \"Holds over \
         the range\": no grid value fails; \"fails at the baseline\": the least stressing value already fails. \
         Diamonds and bars on the charts; the figures are in `failure_points.parquet`.\n",
        100.0 * COMPLETENESS_REQUIRED,
        harder.join("; ")
    );
    let _ = writeln!(o, "| method | scenario | {} |", axes.iter().map(|a| a.name()).collect::<Vec<_>>().join(" | "));
    let _ = writeln!(o, "|---|---|{}", "---|".repeat(axes.len()));
    for (mi, m) in plan.methods.iter().enumerate() {
        for (si, s) in plan.scenarios.iter().enumerate() {
            let mut row = format!("| {} | {} |", m.name, s.label());
            for a in &axes {
                let r = rows.iter().find(|r| r.method == mi && r.scenario == si && r.axis == *a);
                let _ = write!(row, " {} |", r.map_or_else(|| "–".into(), point_text));
            }
            let _ = writeln!(o, "{row}");
        }
    }
    let _ = writeln!(o);
    o
}

#[cfg(test)]
mod tests {
    use super::estimate_text;

    #[test]
    fn estimates_are_written_to_three_significant_figures() {
        let cases = [
            (-4.032838, "-4.03"),
            (0.315544, "0.316"),
            (57.203457, "57.2"),
            (161.230066, "161"),
            (1.041088322946308e-6, "1.04e-6"),
            (250000.0, "250000"),
            (2500000.0, "2.50e6"),
            (0.0, "0"),
        ];
        for (v, text) in cases {
            assert_eq!(estimate_text(v), text, "{v}");
        }
    }
}
