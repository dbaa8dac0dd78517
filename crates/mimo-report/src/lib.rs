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
mod geo;
mod purpose_chart;
pub mod study;

pub use draw::{linear_fit, moving_average};
pub use fidelity::FidelityPoint;

use draw::{Area, BarChart, DrawResult, Line, PALETTE, Panel, Style, TimeChart, darken, e, fmt_num, lighten};
use geo::GeoChart;
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
        Chart::Geo(g) => geo::draw_geo(root, g),
        Chart::Study(s) => study::draw_study_chart(root, s),
        Chart::Fidelity(f) => fidelity::draw_fidelity_chart(root, f),
    }?;
    root.present().map_err(e)
}

/// Render `chart` to `path` (PNG or SVG by extension), marked as mimo's with `mark`
/// (`mimo_store::recognise::mark_image`), via a temporary file renamed into place.
fn render(chart: &Chart, path: &Path, size: (u32, u32), mark: &str) -> Result<(), ReportError> {
    let ext = path.extension().and_then(|x| x.to_str()).unwrap_or("png").to_ascii_lowercase();
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp.{ext}"));
    let draw_err = |err: draw::DrawError| ReportError::Draw { path: path.to_path_buf(), detail: err.0 };
    let drawn = if ext == "svg" {
        draw_any(&SVGBackend::new(&tmp, size).into_drawing_area(), chart)
    } else {
        draw_any(&BitMapBackend::new(&tmp, size).into_drawing_area(), chart)
    };
    let marked = drawn.map_err(draw_err).and_then(|()| {
        mimo_store::recognise::mark_image(&tmp, mark)
            .map_err(|err| ReportError::Io { path: path.to_path_buf(), detail: err.to_string() })
    });
    let done = marked.and_then(|()| {
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
        render(chart, &path, size, mimo_store::recognise::CHART_MARK)?;
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
    render_completeness(score, charts_dir, &mut out)?;
    render_per_interval(score, charts_dir, &mut out)?;
    render_cumulative(score, charts_dir, &mut out)?;
    render_radar_totals(score, charts_dir, &mut out)?;
    purpose_chart::render(score, charts_dir, &mut out)?;
    render_track_metrics(score, charts_dir, &mut out)?;
    Ok(out)
}

/// One track metric of the mean over runs against time.
fn series(score: &Score, f: fn(&mimo_metrics::TrackMetricsMeanRow) -> Option<f64>) -> Vec<(f64, Option<f64>)> {
    score.track_metrics_mean.iter().map(|r| (r.t_s, f(r))).collect()
}

/// Completeness with the required level.
fn render_completeness(score: &Score, charts_dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    let (dt, sub) = (score.options.interval_s, subtitle(score));
    let t_end = score.track_metrics_mean.last().map_or(1.0, |r| r.t_s);
    let req = score.options.completeness_required;
    let mut lines = with_ma("track completeness", PALETTE[0], series(score, |r| r.completeness), dt);
    lines.push(Line {
        label: format!("required {} %", fmt_num(req * 100.0)),
        color: PALETTE[3],
        style: Style::Reference,
        points: vec![(0.0, Some(req)), (t_end, Some(req))],
    });
    let c = single(format!("Track completeness {sub}"), "assigned ÷ scorable truths", lines, Some((0.0, 1.08)));
    save(&c, charts_dir, "completeness", (WIDTH, HEIGHT), out)
}

/// Per radar per interval, normalized by the scorable objects.
fn render_per_interval(score: &Score, charts_dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    let (dt, sub) = (score.options.interval_s, subtitle(score));
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
        save(&c, charts_dir, stem, (WIDTH + 200, 150 + rows * 340), out)?;
    }

    Ok(())
}

/// Cumulative energy and dwell time, stacked by radar.
fn render_cumulative(score: &Score, charts_dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    let sub = subtitle(score);
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
        save(&c, charts_dir, stem, (WIDTH, HEIGHT), out)?;
    }

    Ok(())
}

/// Sensor totals per radar.
fn render_radar_totals(score: &Score, charts_dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    let sub = subtitle(score);
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
        save(&c, charts_dir, stem, (WIDTH, HEIGHT), out)?;
    }

    Ok(())
}

/// The other track metrics over time.
fn render_track_metrics(score: &Score, charts_dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), ReportError> {
    let (dt, sub) = (score.options.interval_s, subtitle(score));
    type Metric<'a> = (&'a str, &'a str, &'a str, fn(&mimo_metrics::TrackMetricsMeanRow) -> Option<f64>);
    let ratio_charts: [Metric<'_>; 4] = [
        ("redundant_ratio", "Redundant track ratio", "redundant tracks ÷ scorable truths", |r| r.redundant_ratio),
        ("spurious_ratio", "Spurious track ratio", "spurious tracks ÷ tracks", |r| r.spurious_ratio),
        ("position_rmse", "Position error of assigned tracks", "position RMSE (m)", |r| r.position_rmse_m),
        ("velocity_rmse", "Velocity error of assigned tracks", "velocity RMSE (m/s)", |r| r.velocity_rmse_mps),
    ];
    for (i, (stem, title, y_label, f)) in ratio_charts.into_iter().enumerate() {
        let lines = with_ma(y_label.split(" (").next().unwrap_or(y_label), PALETTE[(i + 4) % 10], series(score, f), dt);
        save(&single(format!("{title} {sub}"), y_label, lines, None), charts_dir, stem, (WIDTH, HEIGHT), out)?;
    }
    let counts: [Metric<'_>; 2] = [
        ("breaks", "Track breaks (cumulative)", "track breaks", |r| Some(r.cum_breaks_mean)),
        ("switches", "Track switches (cumulative)", "track switches", |r| Some(r.cum_switches_mean)),
    ];
    for (i, (stem, title, y_label, f)) in counts.into_iter().enumerate() {
        let lines =
            with_fit(&format!("cumulative {y_label} per run"), PALETTE[(i + 8) % 10], series(score, f), "", 100.0);
        save(&single(format!("{title} {sub}"), y_label, lines, None), charts_dir, stem, (WIDTH, HEIGHT), out)?;
    }
    let (c_m, p) = (score.options.ospa_c_m, score.options.ospa_p);
    let mut lines = with_ma("OSPA", PALETTE[0], series(score, |r| r.ospa_m), dt);
    lines.extend(with_ma("GOSPA (α = 2)", PALETTE[3], series(score, |r| r.gospa_m), dt));
    let title = format!("OSPA and GOSPA, c = {} m, p = {} {sub}", fmt_num(c_m), fmt_num(p));
    save(&single(title, "distance (m)", lines, None), charts_dir, "ospa", (WIDTH, HEIGHT), out)?;
    Ok(())
}

/// Draw a scenario map: ships (name, lat °, lon °) as triangles, target trajectories
/// (name, [(lat °, lon °)]) as lines with their names, longitude across and latitude up at equal
/// ground scale, marked as a map mimo drew (`mimo_store::recognise::MAP_MARK`). The format
/// follows the extension of `out_png` (`.png` or `.svg`).
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
    render(&chart, out_png, (1100, 1000), mimo_store::recognise::MAP_MARK)
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
    render(&chart, out, (1000, 700), mimo_store::recognise::CHART_MARK)
}
