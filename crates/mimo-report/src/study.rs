//! Charts of a study (docs/studies.md): methods side by side.
//!
//! | file stem | content |
//! |---|---|
//! | `energy_vs_completeness` | per scenario (one panel each), a point per method: the test article's energy per scorable object (x) against track completeness (y), both with their 95 % confidence intervals as bars, the required completeness as a dashed line and the non-dominated front (less energy, more completeness) as a grey step line |
//! | `compute_vs_accuracy` | a point per method and scenario: the test article's CPU seconds per simulated second (log x) against position RMSE and against GOSPA |
//! | `stability_<axis>` | completeness, switches and TA energy per object against the axis value, a line per method with its confidence band; each method's failure point (the first value, from the least to the most stressing, where mean completeness falls below the requirement or a run fails) marked with a cross |
//!
//! The charts take plain figures ([`StudyCell`]), so this crate needs nothing of the study
//! machinery. Logarithmic axes are drawn on log10 of the value with tick labels `1.0e-6`, ….

use crate::draw::{
    AXIS_DESC_PX, DrawResult, FONT, LEGEND_PX, PALETTE, PANEL_TITLE_PX, Swatch, TICK_PX, TITLE_PX, darken, draw_legend,
    e, fmt_axis, fmt_num, legend_height, lighten,
};
use crate::{Chart, ReportError, ensure_font, save};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A Monte Carlo mean and its 95 % confidence interval (null where undefined).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Estimate {
    /// Mean.
    pub mean: Option<f64>,
    /// Lower end of the interval.
    pub lo: Option<f64>,
    /// Upper end of the interval.
    pub hi: Option<f64>,
}

/// One cell of a study: a method on a scenario at a stress point.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StudyCell {
    /// Method name.
    pub method: String,
    /// Scenario label.
    pub scenario: String,
    /// The axis this cell varies (one-axis-at-a-time sweeps).
    pub swept: Option<String>,
    /// Axis values at this cell (axis name, value).
    pub point: Vec<(String, f64)>,
    /// Whether every axis sits at its baseline here (the cell the scatter charts show).
    pub baseline: bool,
    /// Monte Carlo runs and how many failed.
    pub runs: u32,
    /// Failed runs.
    pub failed: u32,
    /// Metric name (as in the results table) → estimate.
    pub metrics: BTreeMap<String, Estimate>,
    /// Mean test-article CPU seconds per simulated second (from the costs table).
    pub ta_cpu_per_sim_s: Option<f64>,
}

impl StudyCell {
    fn get(&self, name: &str) -> Estimate {
        self.metrics.get(name).copied().unwrap_or_default()
    }
}

/// An axis of the study as the stability charts need it.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyAxis {
    /// Name (`rcs_offset_db`, …).
    pub name: String,
    /// Label with unit for the chart.
    pub label: String,
    /// Values, ordered from the least to the most stressing.
    pub values_by_stress: Vec<f64>,
    /// Draw on a logarithmic axis.
    pub log: bool,
}

/// What the study charts show.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyCharts {
    /// The plan's title.
    pub title: String,
    /// Methods in plan order (their colours follow this order).
    pub methods: Vec<String>,
    /// Scenarios in plan order.
    pub scenarios: Vec<String>,
    /// The swept axes.
    pub axes: Vec<StudyAxis>,
    /// Every cell.
    pub cells: Vec<StudyCell>,
    /// The completeness required (0.98).
    pub completeness_required: f64,
}

/// A point with optional error bars.
#[derive(Debug, Clone)]
struct Dot {
    color: RGBColor,
    x: f64,
    x_bar: Option<(f64, f64)>,
    y: f64,
    y_bar: Option<(f64, f64)>,
    label: Option<String>,
}

#[derive(Debug, Clone)]
struct ScatterPanel {
    title: Option<String>,
    x_label: String,
    y_label: String,
    log_x: bool,
    dots: Vec<Dot>,
    hline: Option<f64>,
    front: Vec<(f64, f64)>,
}

/// (x, mean, lo, hi)
type BandPoint = (f64, Option<f64>, Option<f64>, Option<f64>);

#[derive(Debug, Clone)]
struct Band {
    color: RGBColor,
    points: Vec<BandPoint>,
    fail_at: Option<f64>,
}

#[derive(Debug, Clone)]
struct BandPanel {
    title: Option<String>,
    x_label: String,
    y_label: String,
    log_x: bool,
    bands: Vec<Band>,
    hline: Option<f64>,
}

#[derive(Debug, Clone)]
enum StudyPanel {
    Scatter(ScatterPanel),
    Bands(BandPanel),
}

/// A study chart: a title, panels in a grid and a legend strip.
#[derive(Debug, Clone)]
pub(crate) struct StudyChart {
    title: String,
    panels: Vec<StudyPanel>,
    columns: usize,
    legend: Vec<(String, Swatch)>,
}

fn method_color(charts: &StudyCharts, method: &str) -> RGBColor {
    PALETTE[charts.methods.iter().position(|m| m == method).unwrap_or(0) % PALETTE.len()]
}

fn lg(v: f64, log: bool) -> f64 {
    if log { v.max(1e-300).log10() } else { v }
}

/// The cells the scatter charts show for a (method, scenario): the baseline cell, or all cells
/// when there is none.
fn shown<'a>(charts: &'a StudyCharts, method: &str, scenario: &str) -> Vec<&'a StudyCell> {
    let of: Vec<&StudyCell> =
        charts.cells.iter().filter(|c| c.method == method && c.scenario == scenario && c.runs > c.failed).collect();
    match of.iter().find(|c| c.baseline) {
        Some(c) => vec![*c],
        None => of,
    }
}

fn point_text(c: &StudyCell) -> Option<String> {
    if c.baseline || c.point.is_empty() {
        return None;
    }
    Some(c.point.iter().map(|(a, v)| format!("{a}={}", fmt_num(*v))).collect::<Vec<_>>().join(" "))
}

/// Points not dominated by another (x smaller is better, y larger is better), by increasing x.
fn front(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut p: Vec<(f64, f64)> = points.to_vec();
    p.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    let mut out: Vec<(f64, f64)> = Vec::new();
    for q in p {
        if out.last().is_none_or(|l| q.1 > l.1) {
            out.push(q);
        }
    }
    out
}

fn method_legend(charts: &StudyCharts) -> Vec<(String, Swatch)> {
    charts.methods.iter().map(|m| (m.clone(), Swatch::Dot(method_color(charts, m)))).collect()
}

fn bar(e: Estimate, scale: f64) -> Option<(f64, f64)> {
    Some((e.lo? * scale, e.hi? * scale))
}

fn energy_vs_completeness(charts: &StudyCharts) -> StudyChart {
    let mut panels = Vec::new();
    for s in &charts.scenarios {
        let mut dots = Vec::new();
        for m in &charts.methods {
            for c in shown(charts, m, s) {
                let (x, y) = (c.get("ta_energy_per_object_j"), c.get("completeness"));
                let (Some(xm), Some(ym)) = (x.mean, y.mean) else { continue };
                dots.push(Dot {
                    color: method_color(charts, m),
                    x: xm,
                    x_bar: bar(x, 1.0),
                    y: 100.0 * ym,
                    y_bar: bar(y, 100.0),
                    label: point_text(c),
                });
            }
        }
        let pts: Vec<(f64, f64)> = dots.iter().map(|d| (d.x, d.y)).collect();
        panels.push(StudyPanel::Scatter(ScatterPanel {
            title: (charts.scenarios.len() > 1).then(|| format!("scenario {s}")),
            x_label: "TA energy per scorable object (J)".into(),
            y_label: "track completeness (%)".into(),
            log_x: false,
            front: front(&pts),
            dots,
            hline: Some(100.0 * charts.completeness_required),
        }));
    }
    let mut legend = method_legend(charts);
    legend.push((format!("{} % required", fmt_num(100.0 * charts.completeness_required)), Swatch::Dashed(BLACK)));
    legend.push(("non-dominated front".into(), Swatch::Line(RGBColor(150, 150, 150), 2)));
    legend.push(("bars: 95 % confidence intervals of the means".into(), Swatch::Line(RGBColor(90, 90, 90), 1)));
    StudyChart {
        title: format!("Energy against completeness — {}", charts.title),
        columns: charts.scenarios.len().clamp(1, 4),
        panels,
        legend,
    }
}

fn compute_vs_accuracy(charts: &StudyCharts) -> StudyChart {
    let several = charts.scenarios.len() > 1;
    let panel = |metric: &str, y_label: &str| {
        let mut dots = Vec::new();
        for m in &charts.methods {
            for s in &charts.scenarios {
                for c in shown(charts, m, s) {
                    let (Some(x), Some(y)) = (c.ta_cpu_per_sim_s, c.get(metric).mean) else { continue };
                    if x <= 0.0 {
                        continue;
                    }
                    let mut label = point_text(c);
                    if several {
                        label = Some(match label {
                            Some(l) => format!("s{s} {l}"),
                            None => format!("s{s}"),
                        });
                    }
                    dots.push(Dot {
                        color: method_color(charts, m),
                        x: x.log10(),
                        x_bar: None,
                        y,
                        y_bar: bar(c.get(metric), 1.0),
                        label,
                    });
                }
            }
        }
        StudyPanel::Scatter(ScatterPanel {
            title: None,
            x_label: "TA CPU seconds per simulated second (log)".into(),
            y_label: y_label.into(),
            log_x: true,
            dots,
            hline: None,
            front: Vec::new(),
        })
    };
    let mut legend = method_legend(charts);
    legend.push(("bars: 95 % confidence intervals of the means".into(), Swatch::Line(RGBColor(90, 90, 90), 1)));
    StudyChart {
        title: format!("Compute against accuracy — {}", charts.title),
        panels: vec![panel("position_rmse_m", "position RMSE (m)"), panel("gospa_m", "GOSPA (m)")],
        columns: 2,
        legend,
    }
}

/// The cells of an axis's sweep for a (method, scenario), by axis value.
fn sweep_cells<'a>(charts: &'a StudyCharts, axis: &str, method: &str, scenario: &str) -> Vec<(f64, &'a StudyCell)> {
    let mut out: Vec<(f64, &StudyCell)> = charts
        .cells
        .iter()
        .filter(|c| c.method == method && c.scenario == scenario)
        .filter(|c| match &c.swept {
            Some(s) => s == axis,
            // A full grid: the cells where every other axis is at its baseline.
            None => other_base(charts, c, axis),
        })
        .filter_map(|c| c.point.iter().find(|(a, _)| a == axis).map(|(_, v)| (*v, c)))
        .collect();
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out.dedup_by(|a, b| a.0 == b.0);
    out
}

/// Whether every axis of `c` other than `axis` has the value of the study's baseline cell.
fn other_base(charts: &StudyCharts, c: &StudyCell, axis: &str) -> bool {
    let Some(base) = charts.cells.iter().find(|b| b.baseline) else { return false };
    c.point.iter().filter(|(a, _)| a != axis).all(|(a, v)| base.point.iter().any(|(b, w)| a == b && v == w))
}

/// The first value, from least to most stressing, where the method fails.
fn failure_point(ax: &StudyAxis, cells: &[(f64, &StudyCell)], required: f64) -> Option<f64> {
    ax.values_by_stress.iter().copied().find(|v| {
        cells
            .iter()
            .find(|(x, _)| x == v)
            .is_some_and(|(_, c)| c.failed > 0 || c.get("completeness").mean.is_none_or(|m| m < required))
    })
}

fn stability(charts: &StudyCharts, ax: &StudyAxis) -> StudyChart {
    let metrics = [
        ("completeness", "track completeness (%)", 100.0),
        ("switches", "track switches per run", 1.0),
        ("ta_energy_per_object_j", "TA energy per scorable object (J)", 1.0),
    ];
    let mut panels = Vec::new();
    for s in &charts.scenarios {
        for (k, (metric, y_label, scale)) in metrics.iter().enumerate() {
            let bands = charts
                .methods
                .iter()
                .map(|m| {
                    let cells = sweep_cells(charts, &ax.name, m, s);
                    let fail_at = failure_point(ax, &cells, charts.completeness_required);
                    Band {
                        color: method_color(charts, m),
                        points: cells
                            .iter()
                            .map(|(x, c)| {
                                let e = c.get(metric);
                                let f = |v: Option<f64>| v.map(|v| v * scale);
                                (lg(*x, ax.log), f(e.mean), f(e.lo), f(e.hi))
                            })
                            .collect(),
                        fail_at: fail_at.map(|v| lg(v, ax.log)),
                    }
                })
                .collect();
            let title = match (k, charts.scenarios.len() > 1) {
                (0, true) => Some(format!("scenario {s}")),
                _ => None,
            };
            panels.push(StudyPanel::Bands(BandPanel {
                title,
                x_label: ax.label.clone(),
                y_label: (*y_label).into(),
                log_x: ax.log,
                bands,
                hline: (k == 0).then_some(100.0 * charts.completeness_required),
            }));
        }
    }
    let mut legend = method_legend(charts);
    legend.push(("band: 95 % confidence interval".into(), Swatch::Box(RGBColor(215, 215, 215))));
    legend.push((
        "× failure point (first value with completeness below the requirement or a failed run)".into(),
        Swatch::Line(BLACK, 2),
    ));
    StudyChart { title: format!("Stability against {} — {}", ax.name, charts.title), panels, columns: 3, legend }
}

fn x_fmt(log: bool) -> impl Fn(&f64) -> String {
    move |v: &f64| if log { format!("{:.1e}", 10f64.powf(*v)) } else { fmt_num(*v) }
}

fn padded(lo: f64, hi: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    if hi - lo < 1e-12 {
        let d = if lo.abs() > 0.0 { 0.05 * lo.abs() } else { 1.0 };
        return (lo - d, hi + d);
    }
    let d = 0.08 * (hi - lo);
    (lo - d, hi + d)
}

fn range<'a>(values: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)))
}

type Chart2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A panel's axes and grid: an optional title, the ranges, the axis labels, `1eN` tick labels on
/// a log10 x axis.
fn framed<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    title: Option<&str>,
    x: (f64, f64),
    y: (f64, f64),
    labels: (&str, &str),
    log_x: bool,
) -> Result<Chart2d<'a, DB>, String> {
    let mut b = ChartBuilder::on(area);
    b.margin_top(8).margin_right(24).margin_left(8).x_label_area_size(48).y_label_area_size(78);
    if let Some(t) = title {
        b.caption(t, (FONT, PANEL_TITLE_PX));
    }
    let mut chart = b.build_cartesian_2d(x.0..x.1, y.0..y.1).map_err(e)?;
    let xf = x_fmt(log_x);
    let y_max = y.0.abs().max(y.1.abs());
    // A narrow axis (completeness between 99 and 100 %) needs a decimal to tell its ticks apart.
    let narrow = (y.1 - y.0) < 20.0 && y_max < 1e4;
    let yf = |v: &f64| if narrow { format!("{v:.1}") } else { fmt_axis(*v, y_max) };
    chart
        .configure_mesh()
        .x_desc(labels.0)
        .y_desc(labels.1)
        .label_style((FONT, TICK_PX))
        .axis_desc_style((FONT, AXIS_DESC_PX))
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .max_light_lines(4)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(e)?;
    Ok(chart)
}

fn draw_scatter<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &ScatterPanel) -> DrawResult {
    let xs: Vec<f64> =
        p.dots.iter().flat_map(|d| [Some(d.x), d.x_bar.map(|b| b.0), d.x_bar.map(|b| b.1)]).flatten().collect();
    let mut ys: Vec<f64> =
        p.dots.iter().flat_map(|d| [Some(d.y), d.y_bar.map(|b| b.0), d.y_bar.map(|b| b.1)]).flatten().collect();
    ys.extend(p.hline);
    let (x0, x1) = padded(range(xs.iter()).0, range(xs.iter()).1);
    let (y0, y1) = padded(range(ys.iter()).0, range(ys.iter()).1);
    let mut chart = framed(area, p.title.as_deref(), (x0, x1), (y0, y1), (&p.x_label, &p.y_label), p.log_x)?;
    if let Some(h) = p.hline {
        chart.draw_series(DashedLineSeries::new(vec![(x0, h), (x1, h)], 10, 6, BLACK.stroke_width(2))).map_err(e)?;
    }
    if p.front.len() > 1 {
        let mut steps = Vec::new();
        for w in p.front.windows(2) {
            steps.push(w[0]);
            steps.push((w[1].0, w[0].1));
        }
        steps.extend(p.front.last());
        chart.draw_series(LineSeries::new(steps, RGBColor(150, 150, 150).stroke_width(2))).map_err(e)?;
    }
    for d in &p.dots {
        let bar_style = darken(d.color, 0.2).stroke_width(2);
        if let Some((lo, hi)) = d.y_bar {
            chart.draw_series(std::iter::once(PathElement::new(vec![(d.x, lo), (d.x, hi)], bar_style))).map_err(e)?;
        }
        if let Some((lo, hi)) = d.x_bar {
            chart.draw_series(std::iter::once(PathElement::new(vec![(lo, d.y), (hi, d.y)], bar_style))).map_err(e)?;
        }
        chart.draw_series(std::iter::once(Circle::new((d.x, d.y), 7, d.color.filled()))).map_err(e)?;
        if let Some(l) = &d.label {
            let style = (FONT, LEGEND_PX - 3).into_font().color(&RGBColor(60, 60, 60));
            chart
                .draw_series(std::iter::once(EmptyElement::at((d.x, d.y)) + Text::new(l.clone(), (10, -18), style)))
                .map_err(e)?;
        }
    }
    Ok(())
}

fn draw_bands<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &BandPanel) -> DrawResult {
    let xs: Vec<f64> = p.bands.iter().flat_map(|b| b.points.iter().map(|q| q.0)).collect();
    let mut ys: Vec<f64> =
        p.bands.iter().flat_map(|b| b.points.iter().flat_map(|q| [q.1, q.2, q.3]).flatten()).collect();
    ys.extend(p.hline);
    let (xa, xb) = range(xs.iter());
    let (x0, x1) = padded(xa, xb);
    let (y0, y1) = padded(range(ys.iter()).0, range(ys.iter()).1);
    let mut chart = framed(area, p.title.as_deref(), (x0, x1), (y0, y1), (&p.x_label, &p.y_label), p.log_x)?;
    for band in &p.bands {
        let lo: Vec<(f64, f64)> = band.points.iter().filter_map(|q| Some((q.0, q.2?))).collect();
        let hi: Vec<(f64, f64)> = band.points.iter().filter_map(|q| Some((q.0, q.3?))).collect();
        if lo.len() > 1 && lo.len() == hi.len() {
            let mut poly = hi.clone();
            poly.extend(lo.iter().rev());
            chart.draw_series(std::iter::once(Polygon::new(poly, lighten(band.color, 0.78).filled()))).map_err(e)?;
        }
    }
    if let Some(h) = p.hline {
        chart.draw_series(DashedLineSeries::new(vec![(x0, h), (x1, h)], 10, 6, BLACK.stroke_width(2))).map_err(e)?;
    }
    for band in &p.bands {
        let line: Vec<(f64, f64)> = band.points.iter().filter_map(|q| Some((q.0, q.1?))).collect();
        chart.draw_series(LineSeries::new(line.clone(), band.color.stroke_width(3))).map_err(e)?;
        chart.draw_series(line.iter().map(|&q| Circle::new(q, 5, band.color.filled()))).map_err(e)?;
        let fail = band.fail_at.and_then(|xf| band.points.iter().find(|q| q.0 == xf));
        if let Some(&(x, Some(y), _, _)) = fail {
            chart
                .draw_series(std::iter::once(Cross::new((x, y), 11, darken(band.color, 0.3).stroke_width(4))))
                .map_err(e)?;
        }
    }
    Ok(())
}

pub(crate) fn draw_study_chart<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &StudyChart) -> DrawResult {
    root.fill(&WHITE).map_err(e)?;
    let body = root.titled(&c.title, (FONT, TITLE_PX)).map_err(e)?;
    let (_, h) = body.dim_in_pixel();
    let lh = legend_height(&body, &c.legend);
    let (plots, legend_area) = body.split_vertically(h.saturating_sub(lh).max(1));
    let cols = c.columns.max(1);
    let rows = c.panels.len().div_ceil(cols).max(1);
    let cells = plots.split_evenly((rows, cols));
    for (p, cell) in c.panels.iter().zip(cells.iter()) {
        match p {
            StudyPanel::Scatter(s) => draw_scatter(cell, s)?,
            StudyPanel::Bands(b) => draw_bands(cell, b)?,
        }
    }
    draw_legend(&legend_area, &c.legend)
}

fn size_for(c: &StudyChart) -> (u32, u32) {
    let cols = c.columns.max(1) as u32;
    let rows = c.panels.len().div_ceil(c.columns.max(1)).max(1) as u32;
    ((560 * cols).max(1400), 140 + 420 * rows)
}

/// Render every study chart into `dir` (created if needed) as PNG and SVG; returns the files
/// written.
pub fn render_study(charts: &StudyCharts, dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
    ensure_font()?;
    std::fs::create_dir_all(dir).map_err(|err| ReportError::Io { path: dir.to_path_buf(), detail: err.to_string() })?;
    let mut out = Vec::new();
    let mut all = vec![
        ("energy_vs_completeness".to_string(), energy_vs_completeness(charts)),
        ("compute_vs_accuracy".to_string(), compute_vs_accuracy(charts)),
    ];
    for ax in &charts.axes {
        all.push((format!("stability_{}", ax.name), stability(charts, ax)));
    }
    for (stem, chart) in all {
        let size = size_for(&chart);
        save(&Chart::Study(chart), dir, &stem, size, &mut out)?;
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_front_keeps_the_non_dominated_points() {
        // (energy, completeness): (3, 99) is dominated by (2, 99.5); (1, 90) and (5, 100) are not.
        let pts = [(3.0, 99.0), (1.0, 90.0), (2.0, 99.5), (5.0, 100.0), (6.0, 100.0)];
        assert_eq!(front(&pts), vec![(1.0, 90.0), (2.0, 99.5), (5.0, 100.0)]);
    }

    fn cell(method: &str, v: f64, completeness: f64, failed: u32) -> StudyCell {
        let mut metrics = BTreeMap::new();
        metrics.insert("completeness".into(), Estimate { mean: Some(completeness), lo: None, hi: None });
        StudyCell {
            method: method.into(),
            scenario: "7".into(),
            swept: Some("rcs_offset_db".into()),
            point: vec![("rcs_offset_db".into(), v)],
            baseline: v == 0.0,
            runs: 3,
            failed,
            metrics,
            ta_cpu_per_sim_s: Some(0.01),
        }
    }

    #[test]
    fn the_failure_point_walks_from_the_least_stress() {
        let ax = StudyAxis {
            name: "rcs_offset_db".into(),
            label: "RCS offset (dB)".into(),
            values_by_stress: vec![0.0, -3.0, -6.0, -9.0],
            log: false,
        };
        let cells =
            [cell("a", 0.0, 0.99, 0), cell("a", -3.0, 0.985, 0), cell("a", -6.0, 0.97, 0), cell("a", -9.0, 0.99, 1)];
        let charts = StudyCharts {
            title: "t".into(),
            methods: vec!["a".into()],
            scenarios: vec!["7".into()],
            axes: vec![ax.clone()],
            cells: cells.to_vec(),
            completeness_required: 0.98,
        };
        let sw = sweep_cells(&charts, "rcs_offset_db", "a", "7");
        assert_eq!(sw.iter().map(|s| s.0).collect::<Vec<_>>(), vec![-9.0, -6.0, -3.0, 0.0]);
        assert_eq!(failure_point(&ax, &sw, 0.98), Some(-6.0));
        // A failed run counts even when the completed runs look fine.
        let sw2: Vec<(f64, &StudyCell)> = sw.iter().copied().filter(|(v, _)| *v != -6.0).collect();
        assert_eq!(failure_point(&ax, &sw2, 0.98), Some(-9.0));
        let dir = tempfile::tempdir().expect("tmp");
        let files = render_study(&charts, dir.path()).expect("render");
        assert_eq!(files.len(), 6, "{files:?}");
        for f in files {
            assert!(std::fs::metadata(&f).expect("file").len() > 1000, "{f:?}");
        }
    }
}
