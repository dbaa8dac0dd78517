//! The energy-frontier chart (`energy_vs_completeness`): per scenario, each family of the study
//! as its points (x: total energy, search and test article, per scorable object, or the test
//! article's part alone when the study's frontiers are built on it; y: mean completeness) with
//! 95 % confidence bars on both axes, and its efficient frontier as a line
//! through the points on it, by energy (docs/studies.md, "The challenge"); MIMO families solid
//! with filled dots, conventional ones dashed with open squares, points off the frontier smaller;
//! the required completeness as a dashed line and each family's crossing on its frontier as a
//! triangle with its bootstrap interval.

use super::figure::{StudyChart, StudyPanel};
use super::paint::{framed, padded, range};
use super::{Estimate, StudyCharts, StudyFamily};
use crate::draw::{DrawResult, FONT, LEGEND_PX, PALETTE, Swatch, darken, e, fmt_num};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One point of a curve: (x, x bar, y, y bar, knob label, on the frontier).
type CurvePoint = (f64, Option<(f64, f64)>, f64, Option<(f64, f64)>, Option<String>, bool);

/// One family's curve on a panel.
#[derive(Debug, Clone)]
pub(super) struct Curve {
    color: RGBColor,
    mimo: bool,
    /// (x, x bar, y, y bar, knob label, on the frontier)
    points: Vec<CurvePoint>,
    /// (x, x bar ends where inside the sweep)
    crossing: Option<(f64, Option<f64>, Option<f64>)>,
}

/// A panel of curves.
#[derive(Debug, Clone)]
pub(super) struct CurvePanel {
    title: Option<String>,
    curves: Vec<Curve>,
    hline: f64,
    /// The energy axis's label.
    x_label: &'static str,
}

fn family_color(charts: &StudyCharts, name: &str) -> RGBColor {
    let mut names: Vec<&str> = Vec::new();
    for f in &charts.families {
        if !names.contains(&f.name.as_str()) {
            names.push(&f.name);
        }
    }
    PALETTE[names.iter().position(|n| *n == name).unwrap_or(0) % PALETTE.len()]
}

fn bar(e: Estimate, scale: f64) -> Option<(f64, f64)> {
    Some((e.lo? * scale, e.hi? * scale))
}

/// Energy on the log10 axis (energies span four decades from a starved budget to none; below
/// 1 J is drawn at 1 J).
fn log_j(x: f64) -> f64 {
    x.max(1.0).log10()
}

fn curve(charts: &StudyCharts, f: &StudyFamily) -> Curve {
    let points = f
        .points
        .iter()
        .filter_map(|p| {
            let (x, y) = (p.energy_j.mean?, p.completeness.mean?);
            let x_bar = bar(p.energy_j, 1.0).map(|(lo, hi)| (log_j(lo), log_j(hi)));
            Some((log_j(x), x_bar, 100.0 * y, bar(p.completeness, 100.0), p.knob.map(fmt_num), p.on_frontier))
        })
        .collect();
    Curve {
        color: family_color(charts, &f.name),
        mimo: f.mimo,
        points,
        crossing: f.crossing.and_then(|c| Some((log_j(c.mean?), c.lo.map(log_j), c.hi.map(log_j)))),
    }
}

/// The chart.
pub(super) fn energy_frontier(charts: &StudyCharts) -> StudyChart {
    let panels = charts
        .scenarios
        .iter()
        .map(|s| {
            StudyPanel::Curves(CurvePanel {
                title: Some(format!("scenario {s}")),
                curves: charts.families.iter().filter(|f| &f.scenario == s).map(|f| curve(charts, f)).collect(),
                hline: 100.0 * charts.completeness_required,
                x_label: if charts.frontier_on_ta_energy {
                    "test-article energy per scorable object, search left out (J, log scale)"
                } else {
                    "energy per scorable object, search and TA (J, log scale)"
                },
            })
        })
        .collect();
    let mut legend: Vec<(String, Swatch)> = Vec::new();
    for f in &charts.families {
        if !legend.iter().any(|(l, _)| l.starts_with(&format!("{} (", f.name))) {
            let c = family_color(charts, &f.name);
            let (label, sw) = if f.mimo { ("MIMO", Swatch::Line(c, 3)) } else { ("conventional", Swatch::Dashed(c)) };
            legend.push((format!("{} ({label})", f.name), sw));
        }
    }
    let req = fmt_num(100.0 * charts.completeness_required);
    legend.push((format!("{req} % required"), Swatch::Dashed(BLACK)));
    legend.push((format!("crossing of {req} % (bar: bootstrap 95 %)"), Swatch::Triangle(RGBColor(40, 40, 40))));
    legend.push((
        "lines: efficient frontiers; bars: 95 % confidence intervals of the means; labels: knob values".into(),
        Swatch::Line(RGBColor(90, 90, 90), 1),
    ));
    let energy = if charts.frontier_on_ta_energy { "Test-article energy" } else { "Total energy" };
    StudyChart {
        title: format!(
            "{energy} against track completeness, with each family's efficient frontier (energy on a log scale)"
        ),
        columns: charts.scenarios.len().clamp(1, 3),
        panels,
        legend,
    }
}

/// The axes follow the means and crossings (with room around them), not the bars: with few runs
/// a bar can be many times longer than the curve and would squash it; bars are cut at the frame.
fn axis_ranges(p: &CurvePanel) -> ((f64, f64), (f64, f64)) {
    let mut xs = Vec::new();
    let mut ys = vec![p.hline];
    for c in &p.curves {
        for q in &c.points {
            xs.push(q.0);
            ys.push(q.2);
        }
        if let Some((x, _, _)) = c.crossing {
            xs.push(x);
        }
    }
    if xs.is_empty() {
        xs.push(0.0);
    }
    let widen = |(a, b): (f64, f64)| {
        let d = 0.25 * (b - a).max(1e-9 * a.abs().max(1.0));
        (a - d, b + d)
    };
    let (xa, xb) = widen(range(xs.iter()));
    let (ya, yb) = widen(range(ys.iter()));
    (padded(xa, xb), padded(ya, yb.min(100.0)))
}

fn clip(v: f64, r: (f64, f64)) -> f64 {
    v.clamp(r.0, r.1)
}

/// Draw a panel of curves.
pub(super) fn draw_curves<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &CurvePanel) -> DrawResult {
    let (x, y) = axis_ranges(p);
    let labels = (p.x_label, "mean track completeness (%)");
    let mut chart = framed(area, p.title.as_deref(), x, y, labels, true)?;
    chart
        .draw_series(DashedLineSeries::new(vec![(x.0, p.hline), (x.1, p.hline)], 10, 6, BLACK.stroke_width(2)))
        .map_err(e)?;
    for c in &p.curves {
        let mut line: Vec<(f64, f64)> = c.points.iter().filter(|q| q.5).map(|q| (q.0, q.2)).collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        if c.mimo {
            chart.draw_series(LineSeries::new(line.clone(), c.color.stroke_width(3))).map_err(e)?;
        } else {
            chart.draw_series(DashedLineSeries::new(line.clone(), 12, 7, c.color.stroke_width(3))).map_err(e)?;
        }
        let bar_style = darken(c.color, 0.2).stroke_width(2);
        for q in &c.points {
            if let Some((lo, hi)) = q.3 {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(q.0, clip(lo, y)), (q.0, clip(hi, y))],
                        bar_style,
                    )))
                    .map_err(e)?;
            }
            if let Some((lo, hi)) = q.1 {
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        vec![(clip(lo, x), q.2), (clip(hi, x), q.2)],
                        bar_style,
                    )))
                    .map_err(e)?;
            }
            // Points off the frontier are drawn smaller.
            let r = if q.5 { 6 } else { 4 };
            if c.mimo {
                chart.draw_series(std::iter::once(Circle::new((q.0, q.2), r, c.color.filled()))).map_err(e)?;
            } else {
                let sq = EmptyElement::at((q.0, q.2)) + Rectangle::new([(-r, -r), (r, r)], WHITE.filled());
                chart.draw_series(std::iter::once(sq)).map_err(e)?;
                let sq = EmptyElement::at((q.0, q.2)) + Rectangle::new([(-r, -r), (r, r)], c.color.stroke_width(3));
                chart.draw_series(std::iter::once(sq)).map_err(e)?;
            }
            if let Some(l) = &q.4 {
                let style = (FONT, LEGEND_PX - 3).into_font().color(&RGBColor(70, 70, 70));
                let at = if c.mimo { (9, -20) } else { (9, 6) };
                chart
                    .draw_series(std::iter::once(EmptyElement::at((q.0, q.2)) + Text::new(l.clone(), at, style)))
                    .map_err(e)?;
            }
        }
        if let Some((xc, lo, hi)) = c.crossing {
            let dark = darken(c.color, 0.35);
            let (l, h) = (clip(lo.unwrap_or(x.0), x), clip(hi.unwrap_or(x.1), x));
            chart
                .draw_series(std::iter::once(PathElement::new(vec![(l, p.hline), (h, p.hline)], dark.stroke_width(2))))
                .map_err(e)?;
            let tri = EmptyElement::at((xc, p.hline)) + Polygon::new(vec![(0, -11), (-9, 6), (9, 6)], dark.filled());
            chart.draw_series(std::iter::once(tri)).map_err(e)?;
        }
    }
    Ok(())
}
