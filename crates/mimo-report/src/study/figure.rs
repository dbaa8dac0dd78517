//! What each study chart shows: its panels, the points with their confidence bars, the
//! non-dominated front, the stability bands and each method's failure point.

use super::{Estimate, StudyAxis, StudyCell, StudyCharts, StudyFailure};
use crate::draw::{PALETTE, Swatch, fmt_num};
use plotters::style::{BLACK, RGBColor};

#[derive(Debug, Clone)]
pub(super) struct Dot {
    pub(super) color: RGBColor,
    pub(super) x: f64,
    pub(super) x_bar: Option<(f64, f64)>,
    pub(super) y: f64,
    pub(super) y_bar: Option<(f64, f64)>,
    pub(super) label: Option<String>,
}

#[derive(Debug, Clone)]
pub(super) struct ScatterPanel {
    pub(super) title: Option<String>,
    pub(super) x_label: String,
    pub(super) y_label: String,
    pub(super) log_x: bool,
    pub(super) dots: Vec<Dot>,
    pub(super) hline: Option<f64>,
    pub(super) front: Vec<(f64, f64)>,
}

/// (x, mean, lo, hi)
pub(super) type BandPoint = (f64, Option<f64>, Option<f64>, Option<f64>);

/// An end of a failure point's interval on the chart: x, and whether it lies on the grid (drawn
/// with a tick) or runs off it (drawn to the panel's edge).
pub(super) type MarkEnd = (f64, bool);

/// A method's failure point as a band panel marks it (x on the chart's scale).
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Mark {
    /// The interpolated failure point and its interval (`None` ends: no interval).
    At { x: f64, lo: Option<MarkEnd>, hi: Option<MarkEnd> },
    /// Fails already at the least stressing grid value, at this x.
    AtBaseline(f64),
}

#[derive(Debug, Clone)]
pub(super) struct Band {
    pub(super) color: RGBColor,
    pub(super) points: Vec<BandPoint>,
    pub(super) mark: Option<Mark>,
}

#[derive(Debug, Clone)]
pub(super) struct BandPanel {
    pub(super) title: Option<String>,
    pub(super) x_label: String,
    pub(super) y_label: String,
    pub(super) log_x: bool,
    pub(super) bands: Vec<Band>,
    pub(super) hline: Option<f64>,
}

#[derive(Debug, Clone)]
pub(super) enum StudyPanel {
    Scatter(ScatterPanel),
    Bands(BandPanel),
    Curves(super::frontier::CurvePanel),
}

/// A study chart: a title, panels in a grid and a legend strip.
#[derive(Debug, Clone)]
pub(crate) struct StudyChart {
    pub(super) title: String,
    pub(super) panels: Vec<StudyPanel>,
    pub(super) columns: usize,
    pub(super) legend: Vec<(String, Swatch)>,
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

fn method_legend(charts: &StudyCharts) -> Vec<(String, Swatch)> {
    charts.methods.iter().map(|m| (m.clone(), Swatch::Dot(method_color(charts, m)))).collect()
}

fn bar(e: Estimate, scale: f64) -> Option<(f64, f64)> {
    Some((e.lo? * scale, e.hi? * scale))
}

pub(super) fn compute_vs_accuracy(charts: &StudyCharts) -> StudyChart {
    let several = charts.scenarios.len() > 1;
    // Machine-independent reference Kalman-filter cycles when every run measured them.
    let kfu = charts.cells.iter().all(|c| c.runs == c.failed || c.ta_kfu_per_sim_s.is_some());
    let x_label = if kfu {
        "TA compute per simulated second (reference EKF cycles, log)"
    } else {
        "TA CPU seconds per simulated second (log)"
    };
    let panel = |metric: &str, y_label: &str| {
        let mut dots = Vec::new();
        for m in &charts.methods {
            for s in &charts.scenarios {
                for c in shown(charts, m, s) {
                    let x = if kfu { c.ta_kfu_per_sim_s } else { c.ta_cpu_per_sim_s };
                    let (Some(x), Some(y)) = (x, c.get(metric).mean) else { continue };
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
            x_label: x_label.into(),
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
pub(super) fn sweep_cells<'a>(
    charts: &'a StudyCharts,
    axis: &str,
    method: &str,
    scenario: &str,
) -> Vec<(f64, &'a StudyCell)> {
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

/// The mark of a failure point on an axis drawn from `grid.0` to `grid.1` (chart scale).
pub(super) fn mark(f: &StudyFailure, ax: &StudyAxis, grid: (f64, f64)) -> Option<Mark> {
    match f.status.as_str() {
        "crosses" => {
            let x = lg(f.value?, ax.log);
            let (lo, hi) = match f.interval.as_str() {
                "closed" | "open_below" | "open_above" | "open_both" => (
                    Some(f.lo.map_or((grid.0, false), |v| (lg(v, ax.log), true))),
                    Some(f.hi.map_or((grid.1, false), |v| (lg(v, ax.log), true))),
                ),
                _ => (None, None),
            };
            Some(Mark::At { x, lo, hi })
        }
        "fails_at_baseline" => ax.values_by_stress.first().map(|v| Mark::AtBaseline(lg(*v, ax.log))),
        _ => None,
    }
}

pub(super) fn stability(charts: &StudyCharts, ax: &StudyAxis) -> StudyChart {
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
                    let xs = cells.iter().map(|(x, _)| lg(*x, ax.log));
                    let grid = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| (a.min(x), b.max(x)));
                    let of = |f: &&StudyFailure| f.method == *m && f.scenario == *s && f.axis == ax.name;
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
                        mark: charts.failures.iter().find(of).and_then(|f| mark(f, ax, grid)).filter(|_| k == 0),
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
        "◆ failure point (mean completeness through the requirement, interpolated) and bar: its 95 % bootstrap \
         interval, one row per method below the requirement line; no end tick: runs off the grid; × fails at the \
         least stressing value"
            .into(),
        Swatch::Line(BLACK, 2),
    ));
    StudyChart { title: format!("Stability against {} — {}", ax.name, charts.title), panels, columns: 3, legend }
}
