//! Drawing study panels with plotters: axes and grids, scatter panels with error bars and the
//! front, band panels with failure crosses, and the chart's grid of panels with its legend.

use super::figure::{Band, BandPanel, Mark, ScatterPanel, StudyChart, StudyPanel};
use crate::draw::{
    AXIS_DESC_PX, DrawError, DrawResult, FONT, LEGEND_PX, PANEL_TITLE_PX, TICK_PX, TITLE_PX, darken, draw_legend, e,
    fmt_axis, fmt_num, legend_height, lighten,
};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

fn x_fmt(log: bool) -> impl Fn(&f64) -> String {
    move |v: &f64| if log { fmt_num(10f64.powf(*v)) } else { fmt_num(*v) }
}

pub(super) fn padded(lo: f64, hi: f64) -> (f64, f64) {
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

pub(super) fn range<'a>(values: impl Iterator<Item = &'a f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)))
}

pub(super) type Chart2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A panel's axes and grid: an optional title, the ranges, the axis labels, `1eN` tick labels on
/// a log10 x axis.
pub(super) fn framed<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    title: Option<&str>,
    x: (f64, f64),
    y: (f64, f64),
    labels: (&str, &str),
    log_x: bool,
) -> Result<Chart2d<'a, DB>, DrawError> {
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
    // Room below the requirement line for one row of failure marks per method.
    if let (Some(h), true) = (p.hline, p.bands.iter().any(|b| matches!(b.mark, Some(Mark::At { .. })))) {
        let (ya, yb) = range(ys.iter());
        ys.push(h - 0.035 * (p.bands.len() as f64 + 0.5) * (yb - ya).max(1.0));
    }
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
    }
    let step = 0.03 * (y1 - y0);
    for (k, band) in p.bands.iter().enumerate() {
        let y = p.hline.unwrap_or(y1) - step * (k as f64 + 0.6);
        draw_mark(&mut chart, band, y, (x0, x1), step)?;
    }
    Ok(())
}

/// A band's failure mark: a diamond at the failure point with its interval as a bar at height
/// `y` (an end on the grid with a tick, one off it to the panel's edge `x`), or a cross on the
/// curve at the least stressing value.
fn draw_mark<DB: DrawingBackend>(chart: &mut Chart2d<DB>, band: &Band, y: f64, x: (f64, f64), tick: f64) -> DrawResult {
    let style = darken(band.color, 0.3).stroke_width(3);
    match &band.mark {
        Some(Mark::At { x: at, lo, hi }) => {
            if let (Some(lo), Some(hi)) = (lo, hi) {
                let (a, b) = (if lo.1 { lo.0 } else { x.0 }, if hi.1 { hi.0 } else { x.1 });
                chart.draw_series(std::iter::once(PathElement::new(vec![(a, y), (b, y)], style))).map_err(e)?;
                for end in [lo, hi].into_iter().filter(|end| end.1) {
                    let t = vec![(end.0, y - 0.4 * tick), (end.0, y + 0.4 * tick)];
                    chart.draw_series(std::iter::once(PathElement::new(t, style))).map_err(e)?;
                }
            }
            let diamond = |cx: f64, cy: f64| {
                EmptyElement::at((cx, cy)) + Polygon::new(vec![(0, -9), (9, 0), (0, 9), (-9, 0)], band.color.filled())
            };
            chart.draw_series(std::iter::once(diamond(*at, y))).map_err(e)?;
        }
        Some(Mark::AtBaseline(xf)) => {
            if let Some(&(cx, Some(cy), _, _)) = band.points.iter().find(|q| q.0 == *xf) {
                chart.draw_series(std::iter::once(Cross::new((cx, cy), 11, style.stroke_width(4)))).map_err(e)?;
            }
        }
        None => {}
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
            StudyPanel::Curves(c) => super::frontier::draw_curves(cell, c)?,
        }
    }
    draw_legend(&legend_area, &c.legend)
}
