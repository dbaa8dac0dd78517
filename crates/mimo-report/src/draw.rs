//! Chart primitives: time charts with one or more panels, stacked areas, grouped bars, and a
//! legend strip drawn below the plot so it never covers data. Every chart is drawn through one
//! generic function per kind, so PNG and SVG come out identical.

use plotters::coord::Shift;
use plotters::prelude::*;

/// A drawing failure inside plotters. Its error types are generic over the backend (bitmap or
/// SVG), so what is kept is the backend's message; the caller adds the chart's path.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub(crate) struct DrawError(pub(crate) String);

pub(crate) type DrawResult = Result<(), DrawError>;

/// Map any plotters error to a [`DrawError`].
pub(crate) fn e<E: std::fmt::Display>(err: E) -> DrawError {
    DrawError(err.to_string())
}

pub(crate) const FONT: &str = "sans-serif";
pub(crate) const TITLE_PX: u32 = 26;
pub(crate) const PANEL_TITLE_PX: u32 = 19;
pub(crate) const AXIS_DESC_PX: u32 = 18;
pub(crate) const TICK_PX: u32 = 15;
pub(crate) const LEGEND_PX: u32 = 16;

/// Tableau-10 colours; radar `Rn` gets colour `n − 1`.
pub(crate) const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Blend a colour towards white (`f` = 0: unchanged, 1: white). Used instead of alpha so that
/// PNG and SVG look the same and overlaps stay readable.
pub(crate) fn lighten(c: RGBColor, f: f64) -> RGBColor {
    let l = |x: u8| (f64::from(x) + (255.0 - f64::from(x)) * f).round().clamp(0.0, 255.0) as u8;
    RGBColor(l(c.0), l(c.1), l(c.2))
}

/// Blend a colour towards black.
pub(crate) fn darken(c: RGBColor, f: f64) -> RGBColor {
    let d = |x: u8| (f64::from(x) * (1.0 - f)).round().clamp(0.0, 255.0) as u8;
    RGBColor(d(c.0), d(c.1), d(c.2))
}

/// Tick label: short, without float noise, with k/M/G for large values.
pub(crate) fn fmt_num(v: f64) -> String {
    let a = v.abs();
    let trim = |s: String| {
        if s.contains('.') {
            let t = s.trim_end_matches('0').trim_end_matches('.');
            if t == "-0" { "0".to_string() } else { t.to_string() }
        } else {
            s
        }
    };
    if a == 0.0 {
        "0".into()
    } else if a >= 1e9 {
        format!("{}G", trim(format!("{:.2}", v / 1e9)))
    } else if a >= 1e6 {
        format!("{}M", trim(format!("{:.2}", v / 1e6)))
    } else if a >= 1e4 {
        format!("{}k", trim(format!("{:.2}", v / 1e3)))
    } else if a >= 100.0 {
        trim(format!("{v:.0}"))
    } else if a >= 1.0 {
        trim(format!("{v:.2}"))
    } else if a >= 1e-3 {
        trim(format!("{v:.4}"))
    } else {
        format!("{v:.1e}")
    }
}

/// Tick label for an axis whose largest magnitude is `max_abs`: one scale (k, M, G) for the
/// whole axis, so 5000 and 10000 read as 5k and 10k.
pub(crate) fn fmt_axis(v: f64, max_abs: f64) -> String {
    let (div, suffix) = if max_abs >= 1e9 {
        (1e9, "G")
    } else if max_abs >= 1e6 {
        (1e6, "M")
    } else if max_abs >= 1e4 {
        (1e3, "k")
    } else {
        return fmt_num(v);
    };
    if v == 0.0 {
        return "0".into();
    }
    let s = format!("{:.2}", v / div);
    let s = s.trim_end_matches('0').trim_end_matches('.');
    format!("{s}{suffix}")
}

/// How a line is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Style {
    /// The data, thin and light.
    Raw,
    /// A plain data line of normal weight.
    Solid,
    /// A trend line: thick and dark.
    Trend,
    /// A reference level: dashed.
    Reference,
}

/// One line of a panel; `None` values leave gaps.
#[derive(Debug, Clone)]
pub(crate) struct Line {
    pub label: String,
    pub color: RGBColor,
    pub style: Style,
    pub points: Vec<(f64, Option<f64>)>,
}

/// A filled area from 0 up to the curve. Stacked curves are given bottom first (each the sum of
/// itself and those below) and drawn top first.
#[derive(Debug, Clone)]
pub(crate) struct Area {
    pub label: String,
    pub color: RGBColor,
    pub points: Vec<(f64, f64)>,
}

/// One plot of a time chart.
#[derive(Debug, Clone, Default)]
pub(crate) struct Panel {
    pub title: Option<String>,
    pub y_label: String,
    pub lines: Vec<Line>,
    pub areas: Vec<Area>,
    pub y_range: Option<(f64, f64)>,
}

/// A chart of one or more panels sharing the time axis.
#[derive(Debug, Clone)]
pub(crate) struct TimeChart {
    pub title: String,
    pub x_label: String,
    pub panels: Vec<Panel>,
    /// Panels side by side in this many columns.
    pub columns: usize,
}

/// A grouped bar chart (one group per radar).
#[derive(Debug, Clone)]
pub(crate) struct BarChart {
    pub title: String,
    pub y_label: String,
    pub groups: Vec<String>,
    /// (label, colour, value per group)
    pub series: Vec<(String, RGBColor, Vec<f64>)>,
}

/// A legend swatch.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Swatch {
    Line(RGBColor, u32),
    Dashed(RGBColor),
    Box(RGBColor),
    Triangle(RGBColor),
    Dot(RGBColor),
}

fn swatch_of(style: Style, color: RGBColor) -> Swatch {
    match style {
        Style::Raw => Swatch::Line(color, 2),
        Style::Solid => Swatch::Line(color, 2),
        Style::Trend => Swatch::Line(color, 4),
        Style::Reference => Swatch::Dashed(color),
    }
}

/// Height of the legend strip for `items` at this width.
pub(crate) fn legend_height<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, items: &[(String, Swatch)]) -> u32 {
    if items.is_empty() {
        return 0;
    }
    let rows = legend_layout(area, items).last().map_or(1, |&(_, _, row)| row + 1);
    10 + rows as u32 * 26
}

/// (x, item index, row) of each legend item.
fn legend_layout<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    items: &[(String, Swatch)],
) -> Vec<(i32, usize, usize)> {
    let width = area.dim_in_pixel().0 as i32;
    let font: TextStyle = (FONT, LEGEND_PX).into_font().into();
    let (mut x, mut row) = (20, 0);
    let mut out = Vec::new();
    for (i, (label, _)) in items.iter().enumerate() {
        let tw = area.estimate_text_size(label, &font).map(|(w, _)| w as i32).unwrap_or(8 * label.len() as i32);
        let w = 36 + tw + 28;
        if x + w > width - 10 && x > 20 {
            x = 20;
            row += 1;
        }
        out.push((x, i, row));
        x += w;
    }
    out
}

/// Draw the legend items left to right, wrapping, in `area`.
pub(crate) fn draw_legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, items: &[(String, Swatch)]) -> DrawResult {
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let font = (FONT, LEGEND_PX).into_font().color(&BLACK).pos(Pos::new(HPos::Left, VPos::Center));
    for (x, i, row) in legend_layout(area, items) {
        let (label, sw) = &items[i];
        let y = 8 + row as i32 * 26 + 10;
        match *sw {
            Swatch::Line(c, w) => {
                area.draw(&PathElement::new(vec![(x, y), (x + 28, y)], c.stroke_width(w))).map_err(e)?;
            }
            Swatch::Dashed(c) => {
                for k in 0..3 {
                    let x0 = x + k * 11;
                    area.draw(&PathElement::new(vec![(x0, y), (x0 + 6, y)], c.stroke_width(2))).map_err(e)?;
                }
            }
            Swatch::Box(c) => {
                area.draw(&Rectangle::new([(x + 4, y - 8), (x + 24, y + 8)], c.filled())).map_err(e)?;
            }
            Swatch::Triangle(c) => {
                area.draw(&Polygon::new(vec![(x + 14, y - 9), (x + 5, y + 7), (x + 23, y + 7)], c.filled()))
                    .map_err(e)?;
            }
            Swatch::Dot(c) => {
                area.draw(&Circle::new((x + 14, y), 5, c.filled())).map_err(e)?;
            }
        }
        area.draw(&Text::new(label.clone(), (x + 36, y), font.clone())).map_err(e)?;
    }
    Ok(())
}

/// Legend items of a set of panels, unique by label, in first-seen order.
fn time_legend(panels: &[Panel]) -> Vec<(String, Swatch)> {
    let mut items: Vec<(String, Swatch)> = Vec::new();
    let mut push = |label: &str, sw: Swatch| {
        if !label.is_empty() && !items.iter().any(|(l, _)| l == label) {
            items.push((label.to_string(), sw));
        }
    };
    for p in panels {
        for a in &p.areas {
            push(&a.label, Swatch::Box(a.color));
        }
        for l in &p.lines {
            push(&l.label, swatch_of(l.style, l.color));
        }
    }
    items
}

fn data_range(panel: &Panel) -> (f64, f64) {
    if let Some(r) = panel.y_range {
        return r;
    }
    let vals = panel
        .lines
        .iter()
        .flat_map(|l| l.points.iter().filter_map(|p| p.1))
        .chain(panel.areas.iter().flat_map(|a| a.points.iter().map(|p| p.1)))
        .filter(|v| v.is_finite());
    let (lo, hi) = vals.fold((0.0f64, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    let hi = if hi.is_finite() { hi } else { 1.0 };
    let span = hi - lo;
    if span <= 1e-12 * hi.abs().max(1.0) { (lo, lo + 1.0) } else { (lo, hi + 0.08 * span) }
}

pub(crate) fn x_extent(panels: &[Panel]) -> (f64, f64) {
    let xs = panels
        .iter()
        .flat_map(|p| {
            p.lines
                .iter()
                .flat_map(|l| l.points.iter().map(|q| q.0))
                .chain(p.areas.iter().flat_map(|a| a.points.iter().map(|q| q.0)))
        })
        .filter(|x| x.is_finite());
    let hi = xs.fold(f64::NEG_INFINITY, f64::max);
    if hi.is_finite() && hi > 0.0 { (0.0, hi) } else { (0.0, 1.0) }
}

/// Contiguous runs of defined points.
fn segments(points: &[(f64, Option<f64>)]) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut cur = Vec::new();
    for &(x, y) in points {
        match y {
            Some(y) if y.is_finite() => cur.push((x, y)),
            _ => {
                if !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                }
            }
        }
    }
    if !cur.is_empty() {
        out.push(cur);
    }
    out
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &Panel,
    x: (f64, f64),
    x_label: &str,
) -> DrawResult {
    let (y0, y1) = data_range(p);
    let mut builder = ChartBuilder::on(area);
    builder.margin_top(8).margin_right(24).margin_left(8).x_label_area_size(48).y_label_area_size(78);
    if let Some(t) = &p.title {
        builder.caption(t, (FONT, PANEL_TITLE_PX));
    }
    let mut chart = builder.build_cartesian_2d(x.0..x.1, y0..y1).map_err(e)?;
    let y_max = y0.abs().max(y1.abs());
    let x_fmt = |v: &f64| fmt_num(*v);
    let y_fmt = |v: &f64| fmt_axis(*v, y_max);
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(p.y_label.as_str())
        .label_style((FONT, TICK_PX))
        .axis_desc_style((FONT, AXIS_DESC_PX))
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .max_light_lines(4)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(e)?;
    // Areas are given bottom first (stacked curves); draw the top one first so each lower one
    // paints over it.
    for a in p.areas.iter().rev() {
        chart
            .draw_series(
                AreaSeries::new(a.points.iter().copied(), 0.0, a.color.filled()).border_style(darken(a.color, 0.25)),
            )
            .map_err(e)?;
    }
    // Raw data first, then solid lines, references and trends on top.
    for pass in [Style::Raw, Style::Solid, Style::Reference, Style::Trend] {
        for l in p.lines.iter().filter(|l| l.style == pass) {
            for seg in segments(&l.points) {
                match l.style {
                    Style::Raw => {
                        if seg.len() == 1 {
                            chart.draw_series(std::iter::once(Circle::new(seg[0], 2, l.color.filled()))).map_err(e)?;
                        } else {
                            chart.draw_series(LineSeries::new(seg, l.color.stroke_width(1))).map_err(e)?;
                        }
                    }
                    Style::Solid => {
                        chart.draw_series(LineSeries::new(seg, l.color.stroke_width(2))).map_err(e)?;
                    }
                    Style::Trend => {
                        chart.draw_series(LineSeries::new(seg, l.color.stroke_width(3))).map_err(e)?;
                    }
                    Style::Reference => {
                        chart.draw_series(DashedLineSeries::new(seg, 10, 6, l.color.stroke_width(2))).map_err(e)?;
                    }
                }
            }
        }
    }
    Ok(())
}

/// Draw a time chart: title, panels in a grid, legend strip at the bottom.
pub(crate) fn draw_time_chart<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &TimeChart) -> DrawResult {
    root.fill(&WHITE).map_err(e)?;
    let body = root.titled(&c.title, (FONT, TITLE_PX)).map_err(e)?;
    let legend = time_legend(&c.panels);
    let (w, h) = body.dim_in_pixel();
    let lh = legend_height(&body, &legend);
    let (plots, legend_area) = body.split_vertically(h.saturating_sub(lh).max(1));
    let x = x_extent(&c.panels);
    let cols = c.columns.max(1);
    let rows = c.panels.len().div_ceil(cols).max(1);
    let cells = plots.split_evenly((rows, cols));
    for (p, cell) in c.panels.iter().zip(cells.iter()) {
        draw_panel(cell, p, x, &c.x_label)?;
    }
    let _ = w;
    draw_legend(&legend_area, &legend)
}

/// Draw a grouped bar chart with value labels above the bars and group names below.
pub(crate) fn draw_bar_chart<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &BarChart) -> DrawResult {
    root.fill(&WHITE).map_err(e)?;
    let body = root.titled(&c.title, (FONT, TITLE_PX)).map_err(e)?;
    let legend: Vec<(String, Swatch)> = c.series.iter().map(|(l, col, _)| (l.clone(), Swatch::Box(*col))).collect();
    let (_, h) = body.dim_in_pixel();
    let lh = legend_height(&body, &legend);
    let (plot, legend_area) = body.split_vertically(h.saturating_sub(lh).max(1));
    let n = c.groups.len().max(1);
    let ymax = c.series.iter().flat_map(|s| s.2.iter().copied()).filter(|v| v.is_finite()).fold(0.0f64, f64::max);
    let ymax = if ymax > 0.0 { ymax * 1.15 } else { 1.0 };
    let mut chart = ChartBuilder::on(&plot)
        .margin_top(8)
        .margin_right(24)
        .margin_left(8)
        .x_label_area_size(48)
        .y_label_area_size(78)
        .build_cartesian_2d(0.0..n as f64, 0.0..ymax)
        .map_err(e)?;
    let fmt = |v: &f64| fmt_axis(*v, ymax);
    chart
        .configure_mesh()
        .max_light_lines(4)
        .disable_x_mesh()
        .x_labels(0)
        .x_desc("radar")
        .y_desc(c.y_label.as_str())
        .label_style((FONT, TICK_PX))
        .axis_desc_style((FONT, AXIS_DESC_PX))
        .y_label_formatter(&fmt)
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(215, 215, 215))
        .draw()
        .map_err(e)?;
    let k = c.series.len().max(1) as f64;
    let bar_w = 0.8 / k;
    let label_font = (FONT, TICK_PX).into_font().color(&BLACK);
    for (si, (_, col, values)) in c.series.iter().enumerate() {
        for (g, &v) in values.iter().enumerate() {
            let color = *col;
            let x0 = g as f64 + 0.1 + si as f64 * bar_w;
            let x1 = x0 + bar_w * 0.92;
            chart.draw_series(std::iter::once(Rectangle::new([(x0, 0.0), (x1, v)], color.filled()))).map_err(e)?;
            let (px, py) = chart.backend_coord(&((x0 + x1) / 2.0, v));
            let text = fmt_axis(v, ymax);
            let tw = root.estimate_text_size(&text, &label_font).map(|(w, _)| w as i32).unwrap_or(0);
            root.draw(&Text::new(text, (px - tw / 2, py - 20), label_font.clone())).map_err(e)?;
        }
    }
    let name_font = (FONT, AXIS_DESC_PX).into_font().color(&BLACK);
    for (g, name) in c.groups.iter().enumerate() {
        let (px, py) = chart.backend_coord(&(g as f64 + 0.5, 0.0));
        let tw = root.estimate_text_size(name, &name_font).map(|(w, _)| w as i32).unwrap_or(0);
        root.draw(&Text::new(name.clone(), (px - tw / 2, py + 8), name_font.clone())).map_err(e)?;
    }
    draw_legend(&legend_area, &legend)
}

/// Centred moving average over `2·half + 1` samples (undefined samples are skipped; the output
/// is undefined where the input is).
pub fn moving_average(points: &[(f64, Option<f64>)], half: usize) -> Vec<(f64, Option<f64>)> {
    let n = points.len();
    let mut sum = vec![0.0; n + 1];
    let mut cnt = vec![0usize; n + 1];
    for (i, &(_, y)) in points.iter().enumerate() {
        let (s, c) = match y {
            Some(y) if y.is_finite() => (y, 1),
            _ => (0.0, 0),
        };
        sum[i + 1] = sum[i] + s;
        cnt[i + 1] = cnt[i] + c;
    }
    points
        .iter()
        .enumerate()
        .map(|(i, &(x, y))| {
            let (a, b) = (i.saturating_sub(half), (i + half + 1).min(n));
            let c = cnt[b] - cnt[a];
            let v = (y.is_some_and(f64::is_finite) && c > 0).then(|| (sum[b] - sum[a]) / c as f64);
            (x, v)
        })
        .collect()
}

/// Least-squares line `y = a + b·x` through the defined points; `None` with fewer than two.
pub fn linear_fit(points: &[(f64, Option<f64>)]) -> Option<(f64, f64)> {
    let pts: Vec<(f64, f64)> =
        points.iter().filter_map(|&(x, y)| y.filter(|v| v.is_finite()).map(|y| (x, y))).collect();
    if pts.len() < 2 {
        return None;
    }
    let n = pts.len() as f64;
    let mx = pts.iter().map(|p| p.0).sum::<f64>() / n;
    let my = pts.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx) * (p.0 - mx)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let b = sxy / sxx;
    Some((my - b * mx, b))
}
