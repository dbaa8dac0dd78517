//! Charts of a study (docs/studies.md): methods side by side.
//!
//! | file stem | content |
//! |---|---|
//! | `energy_vs_completeness` | per scenario (one panel each), each family's points (an unswept method is a single point): the total energy (search and test article) per scorable object, or the test article's part when the study's frontiers are built on it (x), against mean track completeness (y), both with their 95 % confidence intervals as bars, and the family's efficient frontier as a line through the points on it; MIMO families solid with dots, conventional ones dashed with open squares, points off the frontier smaller; the required completeness as a dashed line and each family's crossing on its frontier as a triangle with its bootstrap interval |
//! | `compute_vs_accuracy` | a point per method and scenario: the test article's CPU seconds per simulated second (log x) against position RMSE and against GOSPA |
//! | `stability_<axis>` | completeness, switches and TA energy per object against the axis value, a line per method with its confidence band; on the completeness panel each method's failure point (where its mean completeness falls through the requirement, interpolated between grid values) as a diamond with its 95 % bootstrap interval as a bar, stacked just below the requirement line one row per method, an end without a tick running off the grid; a method that fails already at the least stressing value marked there with a cross |
//!
//! The charts take plain figures ([`StudyCell`]), so this crate needs nothing of the study
//! machinery. Logarithmic axes are drawn on log10 of the value with tick labels `1.0e-6`, ….
//!
//! The module has three parts: this file holds the figures a study hands over and the entry point;
//! `figure` decides what each chart shows (panels, points, bands, the front, failure points);
//! `paint` draws panels with plotters.

mod figure;
mod frontier;
mod paint;

pub(crate) use paint::draw_study_chart;

use crate::{Chart, ReportError, ensure_font, save};
pub(crate) use figure::StudyChart;
use figure::{compute_vs_accuracy, stability};
use frontier::energy_frontier;
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
    /// The same in reference Kalman-filter cycles per simulated second (`None` when a run has no
    /// reference measurement).
    pub ta_kfu_per_sim_s: Option<f64>,
}

impl StudyCell {
    fn get(&self, name: &str) -> Estimate {
        self.metrics.get(name).copied().unwrap_or_default()
    }
}

/// One point of a family: a method at one knob value (or one point of its grid).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct FamilyPoint {
    /// The knob value (`None` for an unswept method or a grid's point).
    pub knob: Option<f64>,
    /// Energy per scorable object (J) on the frontier's basis: total (search and TA), or the
    /// test article's part ([`StudyCharts::frontier_on_ta_energy`]).
    pub energy_j: Estimate,
    /// Whether the point lies on its family's efficient frontier.
    pub on_frontier: bool,
    /// Track completeness (fraction).
    pub completeness: Estimate,
}

/// A family (a swept method, or an unswept one as a single point) on one scenario, as the
/// energy-frontier chart draws it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StudyFamily {
    /// The family's name.
    pub name: String,
    /// MIMO (solid) or conventional (dashed).
    pub mimo: bool,
    /// Scenario label.
    pub scenario: String,
    /// Points in knob order.
    pub points: Vec<FamilyPoint>,
    /// Energy per scorable object (on the frontier's basis) where the frontier crosses the
    /// requirement, with its
    /// bootstrap interval (an end `None` lies beyond the sweep).
    pub crossing: Option<Estimate>,
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

/// A method's failure point on one axis (docs/studies.md, "Where each method fails").
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StudyFailure {
    /// Method name.
    pub method: String,
    /// Scenario label.
    pub scenario: String,
    /// Axis name.
    pub axis: String,
    /// `crosses`, `holds` or `fails_at_baseline`.
    pub status: String,
    /// The interpolated failure point (status `crosses`).
    pub value: Option<f64>,
    /// Numerically lower end of its 95 % interval (`None`: runs off the grid or none).
    pub lo: Option<f64>,
    /// Numerically upper end.
    pub hi: Option<f64>,
    /// `closed`, `open_below`, `open_above`, `open_both`, `below_grid`, `above_grid` or `none`.
    pub interval: String,
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
    /// Every family on every scenario (at the baseline stress point), for the energy frontier.
    pub families: Vec<StudyFamily>,
    /// Every method's failure point on every scenario and axis.
    pub failures: Vec<StudyFailure>,
    /// The completeness required (0.98).
    pub completeness_required: f64,
    /// The energy-frontier chart's energy is the test article's part alone (a plan's
    /// `frontier_energy = "test_article"`), not the total of search and test article.
    pub frontier_on_ta_energy: bool,
}

/// A point with optional error bars.
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
        ("energy_vs_completeness".to_string(), energy_frontier(charts)),
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
    use super::figure::{Mark, mark, sweep_cells};
    use super::*;

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
            ta_kfu_per_sim_s: Some(5000.0),
        }
    }

    fn family(name: &str, mimo: bool, pts: &[(f64, f64, f64)], crossing: Option<f64>) -> StudyFamily {
        let est = |m: f64, d: f64| Estimate { mean: Some(m), lo: Some(m - d), hi: Some(m + d) };
        StudyFamily {
            name: name.into(),
            mimo,
            scenario: "7".into(),
            points: pts
                .iter()
                .map(|&(k, x, y)| FamilyPoint {
                    knob: Some(k),
                    energy_j: est(x, 50.0),
                    on_frontier: true,
                    completeness: est(y, 0.005),
                })
                .collect(),
            crossing: crossing.map(|c| Estimate { mean: Some(c), lo: Some(c - 100.0), hi: None }),
        }
    }

    fn failure(
        method: &str,
        status: &str,
        value: Option<f64>,
        ci: (Option<f64>, Option<f64>),
        interval: &str,
    ) -> StudyFailure {
        StudyFailure {
            method: method.into(),
            scenario: "7".into(),
            axis: "rcs_offset_db".into(),
            status: status.into(),
            value,
            lo: ci.0,
            hi: ci.1,
            interval: interval.into(),
        }
    }

    #[test]
    fn failure_points_are_marked_with_their_intervals() {
        let ax = StudyAxis {
            name: "rcs_offset_db".into(),
            label: "RCS offset (dB)".into(),
            values_by_stress: vec![0.0, -3.0, -6.0, -9.0],
            log: false,
        };
        let mut cells: Vec<StudyCell> =
            [(0.0, 0.99), (-3.0, 0.985), (-6.0, 0.97), (-9.0, 0.95)].iter().map(|&(v, c)| cell("a", v, c, 0)).collect();
        cells.extend([(0.0, 0.97), (-3.0, 0.96), (-6.0, 0.95), (-9.0, 0.9)].iter().map(|&(v, c)| cell("b", v, c, 0)));
        let charts = StudyCharts {
            title: "t".into(),
            methods: vec!["a".into(), "b".into()],
            scenarios: vec!["7".into()],
            axes: vec![ax.clone()],
            cells,
            families: vec![family("a", true, &[(1.0, 900.0, 0.97), (2.0, 1500.0, 0.99)], Some(1200.0))],
            failures: vec![
                failure("a", "crosses", Some(-4.0), (None, Some(-3.2)), "open_below"),
                failure("b", "fails_at_baseline", None, (None, None), "above_grid"),
            ],
            completeness_required: 0.98,
            frontier_on_ta_energy: false,
        };
        let sw = sweep_cells(&charts, "rcs_offset_db", "a", "7");
        assert_eq!(sw.iter().map(|s| s.0).collect::<Vec<_>>(), vec![-9.0, -6.0, -3.0, 0.0]);
        // The interval's open lower end runs to the grid's edge, without a tick.
        let m = mark(&charts.failures[0], &ax, (-9.0, 0.0));
        assert_eq!(m, Some(Mark::At { x: -4.0, lo: Some((-9.0, false)), hi: Some((-3.2, true)) }));
        assert_eq!(mark(&charts.failures[1], &ax, (-9.0, 0.0)), Some(Mark::AtBaseline(0.0)));
        let holds = failure("a", "holds", None, (None, None), "below_grid");
        assert_eq!(mark(&holds, &ax, (-9.0, 0.0)), None, "nothing to mark inside the grid");
        // On a log axis the marks are on log10 of the value.
        let pfa = StudyAxis { name: "pfa".into(), label: "pfa".into(), values_by_stress: vec![1e-6, 1e-4], log: true };
        let f = failure("a", "crosses", Some(1e-5), (Some(1e-6), Some(1e-4)), "closed");
        assert_eq!(
            mark(&f, &pfa, (-6.0, -4.0)),
            Some(Mark::At { x: -5.0, lo: Some((-6.0, true)), hi: Some((-4.0, true)) })
        );
        let dir = tempfile::tempdir().expect("tmp");
        let files = render_study(&charts, dir.path()).expect("render");
        assert_eq!(files.len(), 6, "{files:?}");
        for f in files {
            assert!(std::fs::metadata(&f).expect("file").len() > 1000, "{f:?}");
        }
    }
}
