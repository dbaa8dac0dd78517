//! The fidelity-ladder chart (docs/model.md §4.8, `reports/fidelity.png`): one point per rung,
//! simulated seconds per wall second across, agreement with the voltage rung up.

use crate::draw::{self, DrawResult, PALETTE, e};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One rung's measured speed and agreement.
#[derive(Debug, Clone, PartialEq)]
pub struct FidelityPoint {
    /// The rung's name (`voltage`, `measurement`, `auto`).
    pub label: String,
    /// Simulated seconds per wall second.
    pub sim_s_per_wall_s: f64,
    /// Agreement with the voltage rung, 0–1 (1 = the voltage rung itself).
    pub agreement: f64,
}

/// The chart's content.
#[derive(Debug, Clone)]
pub(crate) struct FidelityChart {
    pub title: String,
    pub points: Vec<FidelityPoint>,
}

pub(crate) fn draw_fidelity_chart<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &FidelityChart) -> DrawResult {
    root.fill(&WHITE).map_err(e)?;
    let body = root.titled(&c.title, (draw::FONT, draw::TITLE_PX)).map_err(e)?;
    let xs = c.points.iter().map(|p| p.sim_s_per_wall_s).filter(|x| x.is_finite());
    let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
    let (x0, x1) = if x0.is_finite() { (x0, x1) } else { (0.0, 1.0) };
    let pad = ((x1 - x0) * 0.25).max(0.05 * x1.abs().max(1.0));
    let ys = c.points.iter().map(|p| p.agreement).filter(|y| y.is_finite());
    let y0 = ys.fold(1.0f64, f64::min);
    let y_lo = (y0 - (1.0 - y0).max(0.01) * 0.5).max(0.0);
    let mut chart = ChartBuilder::on(&body)
        .margin(16)
        .margin_right(40)
        .x_label_area_size(55)
        .y_label_area_size(80)
        .build_cartesian_2d((x0 - pad)..(x1 + 2.5 * pad), y_lo..1.0 + (1.0 - y_lo) * 0.08)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("simulated seconds per wall second")
        .y_desc("agreement with the voltage rung")
        .label_style((draw::FONT, draw::TICK_PX))
        .axis_desc_style((draw::FONT, draw::AXIS_DESC_PX))
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(218, 218, 218))
        .draw()
        .map_err(e)?;
    for (i, p) in c.points.iter().enumerate() {
        let col = PALETTE[i % PALETTE.len()];
        let at = (p.sim_s_per_wall_s, p.agreement);
        let text = format!("{} ({:.1}, {:.4})", p.label, p.sim_s_per_wall_s, p.agreement);
        let font = (draw::FONT, draw::LEGEND_PX).into_font();
        let mark = EmptyElement::at(at) + Circle::new((0, 0), 9, col.filled()) + Text::new(text, (14, -22), font);
        chart.draw_series(std::iter::once(mark)).map_err(e)?;
    }
    Ok(())
}
