//! # mimo-report
//!
//! Charts of a [`mimo_metrics::Score`], as PNG and SVG, in the spirit of the seed paper's
//! figures 6–14 (docs/design.md §6). [`render_all`] writes into `score/charts/`:
//!
//! | file stem | content |
//! |---|---|
//! | `completeness` | track completeness over time (mean over runs) with the required level (98 %) |
//! | `energy_per_interval`, `dwell_time_per_interval` | per radar (one panel each), emitted energy and dwell time per scoring interval per scorable object (the paper's `E[m,j]`, `T[m,j]`), all dwells and TA-requested dwells |
//! | `cumulative_energy`, `cumulative_dwell_time` | cumulative energy and dwell time over time, stacked by radar (one sees when each radar starts to work), with the TA-requested total |
//! | `radar_energy`, `radar_dwell_time` | sensor totals per radar over a run (bars), all dwells and TA-requested |
//! | `energy_by_purpose` | energy per scoring interval summed over radars, stacked by purpose: search, confirmation looks at objects and at false alarms, track looks on objects and on nothing (moving averages) |
//! | `redundant_ratio`, `spurious_ratio`, `breaks`, `switches`, `position_rmse`, `velocity_rmse`, `ospa` | the other track metrics over time |
//!
//! Every time chart carries a labelled trend: a centred moving average (window given in the
//! legend, in seconds) for rates and errors, and a least-squares straight line for cumulative
//! counts and totals (its slope is given in the legend). Raw per-time values are drawn thin and
//! light, trends thick and dark. Gaps in a line are times where the value is undefined (e.g. no
//! scorable truth). The legend is drawn below the plot so it never covers data.
//!
//! [`draw_geometry`] draws a scenario map (ships as triangles, target trajectories as lines with
//! their names) for `scenarios/geometry.png`.
//!
//! Text uses DejaVu Sans (embedded via the `dejavu` crate), registered once as plotters'
//! `sans-serif` family, so charts look the same on every machine and need no system fonts.

#![warn(missing_docs)]

mod draw;
mod fidelity;
mod purpose_chart;
pub mod study;

pub use draw::{linear_fit, moving_average};
pub use fidelity::FidelityPoint;

use draw::{Area, BarChart, DrawResult, Line, PALETTE, Panel, Style, Swatch, TimeChart, darken, e, fmt_num, lighten};
use mimo_metrics::Score;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::register_font;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use thiserror::Error;

/// Chart errors.
#[derive(Debug, Error)]
pub enum ReportError {
    /// The embedded font could not be registered.
    #[error("cannot register the chart font: {0}")]
    Font(String),
    /// A file or directory could not be written: an output directory could not be created, or a
    /// finished chart could not be renamed from its temporary file into place.
    #[error("cannot write {}: {detail}", path.display())]
    Io {
        /// The directory or chart file.
        path: PathBuf,
        /// The operating system's message.
        detail: String,
    },
    /// Plotters failed to draw a chart, or to write it to its temporary file.
    #[error("cannot draw {}: {detail}", path.display())]
    Draw {
        /// The chart file (PNG or SVG) being drawn.
        path: PathBuf,
        /// The plotters error message.
        detail: String,
    },
}

/// Register DejaVu Sans as `sans-serif` (once per process).
pub fn ensure_font() -> Result<(), ReportError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        register_font(draw::FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
            && register_font(draw::FONT, FontStyle::Bold, dejavu::sans::bold()).is_ok()
    });
    if ok { Ok(()) } else { Err(ReportError::Font("DejaVu Sans could not be parsed".into())) }
}

/// A chart of any kind.
enum Chart {
    Time(TimeChart),
    Bar(BarChart),
    Geo(GeoChart),
    Study(study::StudyChart),
    Fidelity(fidelity::FidelityChart),
}

fn draw_any<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &Chart) -> DrawResult {
    match c {
        Chart::Time(t) => draw::draw_time_chart(root, t),
        Chart::Bar(b) => draw::draw_bar_chart(root, b),
        Chart::Geo(g) => draw_geo(root, g),
        Chart::Study(s) => study::draw_study_chart(root, s),
        Chart::Fidelity(f) => fidelity::draw_fidelity_chart(root, f),
    }?;
    root.present().map_err(e)
}

/// Render `chart` to `path` (PNG or SVG by extension), via a temporary file renamed into place.
fn render(chart: &Chart, path: &Path, size: (u32, u32)) -> Result<(), ReportError> {
    let ext = path.extension().and_then(|x| x.to_str()).unwrap_or("png").to_ascii_lowercase();
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp.{ext}"));
    let draw_err = |err: draw::DrawError| ReportError::Draw { path: path.to_path_buf(), detail: err.0 };
    let drawn = if ext == "svg" {
        draw_any(&SVGBackend::new(&tmp, size).into_drawing_area(), chart)
    } else {
        draw_any(&BitMapBackend::new(&tmp, size).into_drawing_area(), chart)
    };
    let done = drawn.map_err(draw_err).and_then(|()| {
        std::fs::rename(&tmp, path).map_err(|err| ReportError::Io { path: path.to_path_buf(), detail: err.to_string() })
    });
    // A drawing that failed (a full disk) leaves no temporary file behind.
    if done.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    done
}

/// Render `chart` as `dir/stem.png` and `dir/stem.svg`.
fn save(chart: &Chart, dir: &Path, stem: &str, size: (u32, u32), out: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    for ext in ["png", "svg"] {
        let path = dir.join(format!("{stem}.{ext}"));
        render(chart, &path, size)?;
        out.push(path);
    }
    Ok(())
}

const WIDTH: u32 = 1200;
const HEIGHT: u32 = 680;

/// Half-width (in samples) of the moving-average window for `n` samples.
fn ma_half(n: usize) -> usize {
    (n / 40).clamp(2, 30)
}

fn ma_label(what: &str, half: usize, dt: f64) -> String {
    let w = (2 * half + 1) as f64 * dt;
    if what.is_empty() {
        format!("{} s moving average", fmt_num(w))
    } else {
        format!("{what}, {} s moving average", fmt_num(w))
    }
}

/// A raw series plus its moving average.
fn with_ma(label: &str, color: RGBColor, points: Vec<(f64, Option<f64>)>, dt: f64) -> Vec<Line> {
    let half = ma_half(points.len());
    let trend = moving_average(&points, half);
    vec![
        Line { label: label.to_string(), color: lighten(color, 0.55), style: Style::Raw, points },
        Line { label: ma_label(label, half, dt), color: darken(color, 0.15), style: Style::Trend, points: trend },
    ]
}

/// A series plus its least-squares line, the slope given per `rate_unit` seconds.
fn with_fit(label: &str, color: RGBColor, points: Vec<(f64, Option<f64>)>, unit: &str, per_s: f64) -> Vec<Line> {
    let mut out = vec![Line { label: label.to_string(), color, style: Style::Solid, points: points.clone() }];
    if let Some((a, b)) = linear_fit(&points) {
        let (x0, x1) = (points.first().map_or(0.0, |p| p.0), points.last().map_or(1.0, |p| p.0));
        let per = if per_s == 1.0 { "/s".to_string() } else { format!(" per {} s", fmt_num(per_s)) };
        out.push(Line {
            label: format!("least-squares linear fit ({} {unit}{per})", fmt_num(b * per_s)),
            color: RGBColor(60, 60, 60),
            style: Style::Reference,
            points: vec![(x0, Some(a + b * x0)), (x1, Some(a + b * x1))],
        });
    }
    out
}

fn subtitle(score: &Score) -> String {
    let name = &score.options.scenario;
    let runs = score.runs.len();
    let r = if runs == 1 { "1 run".to_string() } else { format!("mean of {runs} runs") };
    if name.is_empty() { format!("({r})") } else { format!("— {name} ({r})") }
}

fn single(title: String, y_label: &str, lines: Vec<Line>, y_range: Option<(f64, f64)>) -> Chart {
    Chart::Time(TimeChart {
        title,
        x_label: "time since scenario start (s)".into(),
        panels: vec![Panel { title: None, y_label: y_label.into(), lines, areas: vec![], y_range }],
        columns: 1,
    })
}

fn radar_color(score: &Score, radar: &str) -> RGBColor {
    let i = score.radars.iter().position(|r| r == radar).unwrap_or(0);
    PALETTE[i % PALETTE.len()]
}

/// Render every chart of `score` into `charts_dir` (created if needed) as PNG and SVG. Returns
/// the files written.
pub fn render_all(score: &Score, charts_dir: &Path) -> Result<Vec<PathBuf>, ReportError> {
    ensure_font()?;
    std::fs::create_dir_all(charts_dir)
        .map_err(|err| ReportError::Io { path: charts_dir.to_path_buf(), detail: err.to_string() })?;
    let mut out = Vec::new();
    let dt = score.options.interval_s;
    let sub = subtitle(score);
    let m = &score.track_metrics_mean;
    let series = |f: fn(&mimo_metrics::TrackMetricsMeanRow) -> Option<f64>| -> Vec<(f64, Option<f64>)> {
        m.iter().map(|r| (r.t_s, f(r))).collect()
    };
    let t_end = m.last().map_or(1.0, |r| r.t_s);

    // Completeness with the required level.
    let req = score.options.completeness_required;
    let mut lines = with_ma("track completeness", PALETTE[0], series(|r| r.completeness), dt);
    lines.push(Line {
        label: format!("required {} %", fmt_num(req * 100.0)),
        color: PALETTE[3],
        style: Style::Reference,
        points: vec![(0.0, Some(req)), (t_end, Some(req))],
    });
    let c = single(format!("Track completeness {sub}"), "assigned ÷ scorable truths", lines, Some((0.0, 1.08)));
    save(&c, charts_dir, "completeness", (WIDTH, HEIGHT), &mut out)?;

    // Per radar per interval, normalized by the scorable objects.
    type Pick = fn(&mimo_metrics::UsageRow) -> Option<f64>;
    let per_interval: [(&str, &str, &str, Pick, Pick); 2] = [
        (
            "energy_per_interval",
            "Emitted energy per scoring interval and scorable object",
            "energy per object (J)",
            |u| u.energy_per_object_j,
            |u| u.ta_energy_per_object_j,
        ),
        (
            "dwell_time_per_interval",
            "Dwell time per scoring interval and scorable object",
            "dwell time per object (s)",
            |u| u.dwell_time_per_object_s,
            |u| u.ta_dwell_time_per_object_s,
        ),
    ];
    for (stem, title, y_label, all, ta) in per_interval {
        let panels: Vec<Panel> = score
            .radars
            .iter()
            .map(|radar| {
                let rows: Vec<&mimo_metrics::UsageRow> = score.usage.iter().filter(|u| &u.radar == radar).collect();
                let mid = |u: &mimo_metrics::UsageRow| 0.5 * (u.t_start_s + u.t_end_s);
                let mut lines = with_ma("all dwells", PALETTE[0], rows.iter().map(|u| (mid(u), all(u))).collect(), dt);
                lines.extend(with_ma("TA-requested", PALETTE[1], rows.iter().map(|u| (mid(u), ta(u))).collect(), dt));
                Panel {
                    title: Some(format!("radar {radar}")),
                    y_label: y_label.into(),
                    lines,
                    areas: vec![],
                    y_range: None,
                }
            })
            .collect();
        let columns = if panels.len() >= 3 { 2 } else { 1 };
        let rows = panels.len().div_ceil(columns).max(1) as u32;
        let c = Chart::Time(TimeChart {
            title: format!("{title} {sub}"),
            x_label: "time since scenario start (s)".into(),
            panels,
            columns,
        });
        save(&c, charts_dir, stem, (WIDTH + 200, 150 + rows * 340), &mut out)?;
    }

    // Cumulative, stacked by radar.
    type Cum = fn(&mimo_metrics::UsageRow) -> f64;
    type CumT = fn(&mimo_metrics::UsageTotalRow) -> f64;
    let cumulative: [(&str, &str, &str, &str, Cum, CumT, CumT); 2] = [
        (
            "cumulative_energy",
            "Cumulative emitted energy by radar",
            "cumulative energy (J)",
            "J",
            |u| u.cum_energy_j,
            |u| u.cum_energy_j,
            |u| u.cum_ta_energy_j,
        ),
        (
            "cumulative_dwell_time",
            "Cumulative dwell time by radar",
            "cumulative dwell time (s)",
            "s",
            |u| u.cum_dwell_time_s,
            |u| u.cum_dwell_time_s,
            |u| u.cum_ta_dwell_time_s,
        ),
    ];
    for (stem, title, y_label, unit, cum, cum_total, cum_ta) in cumulative {
        // Stack: curve k is the sum of radars 0..=k; draw the top one first.
        let n_int = score.usage_total.len();
        let mut stack = vec![0.0; n_int];
        let mut areas = Vec::new();
        for radar in &score.radars {
            let mut pts = vec![(0.0, 0.0)];
            for (i, u) in score.usage.iter().filter(|u| &u.radar == radar).enumerate().take(n_int) {
                stack[i] += cum(u);
                pts.push((u.t_end_s, stack[i]));
            }
            areas.push(Area { label: radar.clone(), color: radar_color(score, radar), points: pts });
        }
        let total: Vec<(f64, Option<f64>)> = std::iter::once((0.0, Some(0.0)))
            .chain(score.usage_total.iter().map(|u| (u.t_end_s, Some(cum_total(u)))))
            .collect();
        let mut lines = Vec::new();
        if let Some((a, b)) = linear_fit(&total) {
            let x1 = total.last().map_or(1.0, |p| p.0);
            lines.push(Line {
                label: format!("least-squares linear fit of the total ({} {unit}/s)", fmt_num(b)),
                color: RGBColor(30, 30, 30),
                style: Style::Reference,
                points: vec![(0.0, Some(a)), (x1, Some(a + b * x1))],
            });
        }
        lines.push(Line {
            label: "TA-requested, all radars".into(),
            color: RGBColor(20, 20, 20),
            style: Style::Solid,
            points: std::iter::once((0.0, Some(0.0)))
                .chain(score.usage_total.iter().map(|u| (u.t_end_s, Some(cum_ta(u)))))
                .collect(),
        });
        let c = Chart::Time(TimeChart {
            title: format!("{title} {sub}"),
            x_label: "time since scenario start (s)".into(),
            panels: vec![Panel { title: None, y_label: y_label.into(), lines, areas, y_range: None }],
            columns: 1,
        });
        save(&c, charts_dir, stem, (WIDTH, HEIGHT), &mut out)?;
    }

    // Sensor totals per radar.
    let groups: Vec<String> = score.usage_radar.iter().map(|r| r.radar.clone()).collect();
    type Bars<'a> = (&'a str, &'a str, &'a str, Vec<f64>, Vec<f64>);
    let bars: [Bars<'_>; 2] = [
        (
            "radar_energy",
            "Emitted energy per radar over a run",
            "energy per run (J)",
            score.usage_radar.iter().map(|r| r.energy_j).collect(),
            score.usage_radar.iter().map(|r| r.ta_energy_j).collect(),
        ),
        (
            "radar_dwell_time",
            "Dwell time per radar over a run",
            "dwell time per run (s)",
            score.usage_radar.iter().map(|r| r.dwell_time_s).collect(),
            score.usage_radar.iter().map(|r| r.ta_dwell_time_s).collect(),
        ),
    ];
    for (stem, title, y_label, all, ta) in bars {
        let c = Chart::Bar(BarChart {
            title: format!("{title} {sub}"),
            y_label: y_label.into(),
            groups: groups.clone(),
            series: vec![("all dwells".into(), PALETTE[0], all), ("TA-requested".into(), PALETTE[1], ta)],
        });
        save(&c, charts_dir, stem, (WIDTH, HEIGHT), &mut out)?;
    }

    purpose_chart::render(score, charts_dir, &mut out)?;

    // Other track metrics over time.
    type Metric<'a> = (&'a str, &'a str, &'a str, fn(&mimo_metrics::TrackMetricsMeanRow) -> Option<f64>);
    let ratio_charts: [Metric<'_>; 4] = [
        ("redundant_ratio", "Redundant track ratio", "redundant tracks ÷ scorable truths", |r| r.redundant_ratio),
        ("spurious_ratio", "Spurious track ratio", "spurious tracks ÷ tracks", |r| r.spurious_ratio),
        ("position_rmse", "Position error of assigned tracks", "position RMSE (m)", |r| r.position_rmse_m),
        ("velocity_rmse", "Velocity error of assigned tracks", "velocity RMSE (m/s)", |r| r.velocity_rmse_mps),
    ];
    for (i, (stem, title, y_label, f)) in ratio_charts.into_iter().enumerate() {
        let lines = with_ma(y_label.split(" (").next().unwrap_or(y_label), PALETTE[(i + 4) % 10], series(f), dt);
        save(&single(format!("{title} {sub}"), y_label, lines, None), charts_dir, stem, (WIDTH, HEIGHT), &mut out)?;
    }
    let counts: [Metric<'_>; 2] = [
        ("breaks", "Track breaks (cumulative)", "track breaks", |r| Some(r.cum_breaks_mean)),
        ("switches", "Track switches (cumulative)", "track switches", |r| Some(r.cum_switches_mean)),
    ];
    for (i, (stem, title, y_label, f)) in counts.into_iter().enumerate() {
        let lines = with_fit(&format!("cumulative {y_label} per run"), PALETTE[(i + 8) % 10], series(f), "", 100.0);
        save(&single(format!("{title} {sub}"), y_label, lines, None), charts_dir, stem, (WIDTH, HEIGHT), &mut out)?;
    }
    let (c_m, p) = (score.options.ospa_c_m, score.options.ospa_p);
    let mut lines = with_ma("OSPA", PALETTE[0], series(|r| r.ospa_m), dt);
    lines.extend(with_ma("GOSPA (α = 2)", PALETTE[3], series(|r| r.gospa_m), dt));
    let title = format!("OSPA and GOSPA, c = {} m, p = {} {sub}", fmt_num(c_m), fmt_num(p));
    save(&single(title, "distance (m)", lines, None), charts_dir, "ospa", (WIDTH, HEIGHT), &mut out)?;
    Ok(out)
}

// ---------------------------------------------------------------------------------------------
// Geometry map

struct GeoChart {
    title: String,
    ships: Vec<(String, f64, f64)>,
    truth: Vec<(String, Vec<(f64, f64)>)>,
}

/// Draw a scenario map: ships (name, lat °, lon °) as triangles, target trajectories
/// (name, [(lat °, lon °)]) as lines with their names, longitude across and latitude up at equal
/// ground scale. The format follows the extension of `out_png` (`.png` or `.svg`).
pub fn draw_geometry(
    ships: &[(String, f64, f64)],
    truth: &[(String, Vec<(f64, f64)>)],
    title: &str,
    out_png: &Path,
) -> Result<(), ReportError> {
    ensure_font()?;
    if let Some(dir) = out_png.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|err| ReportError::Io { path: dir.to_path_buf(), detail: err.to_string() })?;
    }
    let chart = Chart::Geo(GeoChart { title: title.to_string(), ships: ships.to_vec(), truth: truth.to_vec() });
    render(&chart, out_png, (1100, 1000))
}

/// Draw the fidelity-ladder chart (docs/model.md §4.8): one point per rung, simulated seconds per
/// wall second against agreement with the voltage rung. PNG or SVG by the extension of `out`.
pub fn draw_fidelity(points: &[FidelityPoint], title: &str, out: &Path) -> Result<(), ReportError> {
    ensure_font()?;
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .map_err(|err| ReportError::Io { path: dir.to_path_buf(), detail: err.to_string() })?;
    }
    let chart = Chart::Fidelity(fidelity::FidelityChart { title: title.to_string(), points: points.to_vec() });
    render(&chart, out, (1000, 700))
}

fn draw_geo<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, g: &GeoChart) -> DrawResult {
    root.fill(&WHITE).map_err(e)?;
    let body = root.titled(&g.title, (draw::FONT, draw::TITLE_PX)).map_err(e)?;
    let mut legend: Vec<(String, Swatch)> = vec![("ship".into(), Swatch::Triangle(RGBColor(20, 40, 90)))];
    for (i, (name, _)) in g.truth.iter().enumerate() {
        legend.push((name.clone(), Swatch::Line(PALETTE[i % PALETTE.len()], 3)));
    }
    legend.push(("trajectory start".into(), Swatch::Dot(RGBColor(90, 90, 90))));
    let (w, h) = body.dim_in_pixel();
    let lh = draw::legend_height(&body, &legend);
    let (plot, legend_area) = body.split_vertically(h.saturating_sub(lh).max(1));

    // Extent with margins, then widened so that a degree of latitude and a cos(lat)-scaled
    // degree of longitude take the same number of pixels.
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
    let (pw, ph) = (
        f64::from(w.saturating_sub(8 + 24 + 90)).max(1.0),
        f64::from(plot.dim_in_pixel().1.saturating_sub(8 + 55)).max(1.0),
    );
    let (sx, sy) = ((lo1 - lo0) * kx / pw, (la1 - la0) / ph);
    if sx > sy {
        let grow = (sx * ph - (la1 - la0)) / 2.0;
        (la0, la1) = (la0 - grow, la1 + grow);
    } else {
        let grow = (sy * pw / kx - (lo1 - lo0)) / 2.0;
        (lo0, lo1) = (lo0 - grow, lo1 + grow);
    }

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
    // Labels after every line, so no line crosses a label.
    for (name, (px, py), color) in labels {
        label_box(root, name, (px + 10, py - 16), color)?;
    }
    let ship_color = RGBColor(20, 40, 90);
    for (name, lat, lon) in &g.ships {
        let (px, py) = chart.backend_coord(&(*lon, *lat));
        root.draw(&Polygon::new(vec![(px, py - 11), (px - 9, py + 7), (px + 9, py + 7)], ship_color.filled()))
            .map_err(e)?;
        label_box(root, name, (px + 13, py), ship_color)?;
    }
    draw::draw_legend(&legend_area, &legend)
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
