//! The scenario map drawn by [`crate::draw_geometry`]: ships as triangles, target trajectories as
//! lines with their names, longitude across and latitude up at equal ground scale.

use crate::draw::{self, DrawResult, PALETTE, Swatch, darken, e};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// A scenario map: ships (name, lat °, lon °) and target trajectories (name, [(lat °, lon °)]).
pub(crate) struct GeoChart {
    pub(crate) title: String,
    pub(crate) ships: Vec<(String, f64, f64)>,
    pub(crate) truth: Vec<(String, Vec<(f64, f64)>)>,
}

type MapChart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

const SHIP_COLOR: RGBColor = RGBColor(20, 40, 90);

pub(crate) fn draw_geo<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, g: &GeoChart) -> DrawResult {
    root.fill(&WHITE).map_err(e)?;
    let body = root.titled(&g.title, (draw::FONT, draw::TITLE_PX)).map_err(e)?;
    let mut legend: Vec<(String, Swatch)> = vec![("ship".into(), Swatch::Triangle(SHIP_COLOR))];
    for (i, (name, _)) in g.truth.iter().enumerate() {
        legend.push((name.clone(), Swatch::Line(PALETTE[i % PALETTE.len()], 3)));
    }
    legend.push(("trajectory start".into(), Swatch::Dot(RGBColor(90, 90, 90))));
    let (w, h) = body.dim_in_pixel();
    let lh = draw::legend_height(&body, &legend);
    let (plot, legend_area) = body.split_vertically(h.saturating_sub(lh).max(1));
    let (la0, la1, lo0, lo1) = map_extent(g, w, plot.dim_in_pixel().1);

    let mut chart = ChartBuilder::on(&plot)
        .margin_top(8)
        .margin_right(24)
        .margin_left(8)
        .x_label_area_size(55)
        .y_label_area_size(90)
        .build_cartesian_2d(lo0..lo1, la0..la1)
        .map_err(e)?;
    let deg = |v: &f64| format!("{v:.2}");
    chart
        .configure_mesh()
        .x_desc("longitude (°)")
        .y_desc("latitude (°)")
        .label_style((draw::FONT, draw::TICK_PX))
        .axis_desc_style((draw::FONT, draw::AXIS_DESC_PX))
        .x_label_formatter(&deg)
        .y_label_formatter(&deg)
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(218, 218, 218))
        .max_light_lines(4)
        .draw()
        .map_err(e)?;
    draw_trajectories(root, &mut chart, g)?;
    draw_ships(root, &chart, g)?;
    draw::draw_legend(&legend_area, &legend)
}

/// The map's extent `(lat min, lat max, lon min, lon max)` in degrees: every finite point with
/// margins, then widened so that a degree of latitude and a cos(lat)-scaled degree of longitude
/// take the same number of pixels in a plot `w_px` wide and `plot_h_px` high.
fn map_extent(g: &GeoChart, w_px: u32, plot_h_px: u32) -> (f64, f64, f64, f64) {
    let pts = g.ships.iter().map(|s| (s.1, s.2)).chain(g.truth.iter().flat_map(|t| t.1.iter().copied()));
    let pts: Vec<(f64, f64)> = pts.filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
    let (mut la0, mut la1, mut lo0, mut lo1) =
        pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY), |(a, b, c, d), p| {
            (a.min(p.0), b.max(p.0), c.min(p.1), d.max(p.1))
        });
    if !la0.is_finite() {
        (la0, la1, lo0, lo1) = (-1.0, 1.0, -1.0, 1.0);
    }
    let pad_la = ((la1 - la0) * 0.08).max(0.05);
    let pad_lo = ((lo1 - lo0) * 0.08).max(0.05);
    (la0, la1, lo0, lo1) = (la0 - pad_la, la1 + pad_la, lo0 - pad_lo, lo1 + pad_lo);
    let kx = ((la0 + la1) / 2.0).to_radians().cos().max(0.05);
    let (pw, ph) =
        (f64::from(w_px.saturating_sub(8 + 24 + 90)).max(1.0), f64::from(plot_h_px.saturating_sub(8 + 55)).max(1.0));
    let (sx, sy) = ((lo1 - lo0) * kx / pw, (la1 - la0) / ph);
    if sx > sy {
        let grow = (sx * ph - (la1 - la0)) / 2.0;
        (la0, la1) = (la0 - grow, la1 + grow);
    } else {
        let grow = (sy * pw / kx - (lo1 - lo0)) / 2.0;
        (lo0, lo1) = (lo0 - grow, lo1 + grow);
    }
    (la0, la1, lo0, lo1)
}

/// Each trajectory as a line with a dot at its start, then the names on labels, after every line
/// so that no line crosses a label.
fn draw_trajectories<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    chart: &mut MapChart<'_, DB>,
    g: &GeoChart,
) -> DrawResult {
    let n = g.truth.len();
    let mut labels = Vec::new();
    for (i, (name, path)) in g.truth.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let xy: Vec<(f64, f64)> =
            path.iter().filter(|p| p.0.is_finite() && p.1.is_finite()).map(|p| (p.1, p.0)).collect();
        if xy.is_empty() {
            continue;
        }
        chart.draw_series(LineSeries::new(xy.iter().copied(), color.stroke_width(3))).map_err(e)?;
        chart.draw_series(std::iter::once(Circle::new(xy[0], 5, darken(color, 0.2).filled()))).map_err(e)?;
        // Names at staggered positions along the paths so that formations stay readable.
        let f = if n > 1 { 0.12 + 0.76 * i as f64 / (n - 1) as f64 } else { 0.5 };
        let at = xy[((xy.len() - 1) as f64 * f).round() as usize];
        labels.push((name, chart.backend_coord(&at), darken(color, 0.3)));
    }
    for (name, (px, py), color) in labels {
        label_box(root, name, (px + 10, py - 16), color)?;
    }
    Ok(())
}

/// Each ship as a triangle with its name.
fn draw_ships<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, chart: &MapChart<'_, DB>, g: &GeoChart) -> DrawResult {
    for (name, lat, lon) in &g.ships {
        let (px, py) = chart.backend_coord(&(*lon, *lat));
        root.draw(&Polygon::new(vec![(px, py - 11), (px - 9, py + 7), (px + 9, py + 7)], SHIP_COLOR.filled()))
            .map_err(e)?;
        label_box(root, name, (px + 13, py), SHIP_COLOR)?;
    }
    Ok(())
}

/// A text label on a white box with a coloured border; `at` is the box's left edge and vertical
/// centre (pixels).
fn label_box<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    text: &str,
    at: (i32, i32),
    color: RGBColor,
) -> DrawResult {
    use plotters::style::text_anchor::{HPos, Pos, VPos};
    let font = (draw::FONT, draw::LEGEND_PX).into_font().color(&color).pos(Pos::new(HPos::Left, VPos::Center));
    let (w, h) = root.estimate_text_size(text, &font).map_err(e)?;
    let (x, y) = at;
    let half = h as i32 / 2 + 5;
    let rect = [(x, y - half), (x + w as i32 + 10, y + half)];
    root.draw(&Rectangle::new(rect, WHITE.filled())).map_err(e)?;
    root.draw(&Rectangle::new(rect, color.stroke_width(1))).map_err(e)?;
    root.draw(&Text::new(text.to_string(), (x + 5, y), font)).map_err(e)
}
