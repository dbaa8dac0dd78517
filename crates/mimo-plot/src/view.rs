//! The view: everything the page shows, built from a run (docs/design.md §2–§3, §6).
//!
//! What is drawn, and what is thinned to keep a 1000-s scenario-7 run small and quick to draw:
//! truth and track paths thinned within a position tolerance ([`crate::decimate`]; the path
//! between kept samples is a straight chord), ship paths at 1 Hz, every measurement, and one beam point per dwell group
//! the test article requested. Background search dwells (over 90 % of all dwells) are not drawn
//! as beams — they are the radars' own raster — but their detections are drawn as
//! measurements. The earth is a graticule, not a filled mesh (a mesh costs seconds of WebGL set-up
//! under software rendering). The page lists these choices under "dropped".

use crate::PlotError;
use crate::dwell_digest::DwellDigest;
use crate::frame::{FrameJson, PlotFrame};
use crate::framing::{Framing, framing};
use crate::globe::{Polylines, coastlines, globe_graticule, graticule};
use crate::linked::{self, RunScore};
use crate::objects::{self, BeamCols, MeasCols, MeasDropped, RadarView, TrackCols, TruthPath};
use crate::source::{RunSource, RunTables};
use mimo_core::geo::ecef_to_geodetic;
use mimo_core::records::TrackRow;
use serde::Serialize;
use std::collections::HashMap;

/// What to plot.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewOptions {
    /// Monte Carlo run id.
    pub run: u32,
    /// Window start (s); the run's start when None.
    pub from_s: Option<f64>,
    /// Window end (s); the run's end when None.
    pub to_s: Option<f64>,
    /// Truth samples kept every this many seconds before thinning (every sample when ≤ 0).
    pub truth_step_s: f64,
    /// Ship positions sampled every this many seconds.
    pub ship_step_s: f64,
    /// Position tolerance of the thinned truth and track paths (m; 0 keeps every sample):
    /// every sample left out is within it of the drawn path at its time (crate::decimate).
    pub tolerance_m: f64,
    /// Step of the framing boxes (s, crate::framing).
    pub framing_step_s: f64,
}

impl Default for ViewOptions {
    fn default() -> Self {
        ViewOptions {
            run: 0,
            from_s: None,
            to_s: None,
            truth_step_s: 0.0,
            ship_step_s: 1.0,
            tolerance_m: 20.0,
            framing_step_s: 10.0,
        }
    }
}

/// About the view.
#[derive(Debug, Clone, Serialize)]
pub struct Meta {
    /// Scenario name.
    pub scenario: String,
    /// Run directory, as given.
    pub run_dir: String,
    /// Monte Carlo run id.
    pub run: u32,
    /// Test article name.
    pub tracker: String,
    /// The run's duration (s).
    pub duration_s: f64,
    /// Window start (s).
    pub from_s: f64,
    /// Window end (s).
    pub to_s: f64,
    /// What was thinned or left out, one sentence each.
    pub dropped: Vec<String>,
    /// Dwell kind names by code.
    pub kinds: Vec<&'static str>,
    /// Track status names by code.
    pub statuses: Vec<&'static str>,
}

/// The linked metrics panel.
#[derive(Debug, Clone, Serialize)]
pub struct MetricsCols {
    /// Where completeness comes from.
    pub source: String,
    /// Scoring interval (s).
    pub interval_s: f64,
    /// Scoring times in the window (s).
    pub t: Vec<f64>,
    /// Completeness at those times (null when nothing was scorable).
    pub completeness: Vec<Option<f64>>,
    /// Scorable truths.
    pub n_scorable: Vec<u32>,
    /// Energy emitted in the interval closed by each time (J), all dwells.
    pub energy_j: Vec<f64>,
    /// The same, dwells the test article requested.
    pub ta_energy_j: Vec<f64>,
}

/// The region around the scenario: a box in the plot frame and the earth's surface under it.
#[derive(Debug, Clone, Serialize)]
pub struct Region {
    /// Lower corner (m).
    pub lo: [i64; 3],
    /// Upper corner (m).
    pub hi: [i64; 3],
    /// Parallels and meridians on the ellipsoid under the box.
    pub graticule: Polylines,
}

/// Everything the page shows.
#[derive(Debug, Clone, Serialize)]
pub struct View {
    /// About the view.
    pub meta: Meta,
    /// The plot frame.
    pub frame: FrameJson,
    /// Radars in scenario order.
    pub radars: Vec<RadarView>,
    /// Target ids in scenario order.
    pub targets: Vec<String>,
    /// Truth paths per target.
    pub truth: Vec<TruthPath>,
    /// Track states.
    pub tracks: TrackCols,
    /// Measurements.
    pub meas: MeasCols,
    /// Beams of the test article's dwells.
    pub beams: BeamCols,
    /// Linked metrics.
    pub metrics: MetricsCols,
    /// Coastlines.
    pub coast: Polylines,
    /// Parallels and meridians of the whole earth.
    pub globe: Polylines,
    /// The region around the scenario.
    pub region: Region,
    /// What the region view frames at each time.
    pub framing: Framing,
}

/// Check and resolve the time window against the run's duration.
pub fn window(opts: &ViewOptions, duration_s: f64) -> Result<(f64, f64), PlotError> {
    let from_s = opts.from_s.unwrap_or(0.0);
    let to_s = opts.to_s.unwrap_or(duration_s);
    let ok = from_s.is_finite() && to_s.is_finite() && from_s >= 0.0 && from_s < to_s && to_s <= duration_s;
    if !ok {
        return Err(PlotError::BadWindow { from_s, to_s, duration_s });
    }
    Ok((from_s, to_s))
}

fn region(frame: &PlotFrame, truth: &[TruthPath], radars: &[RadarView]) -> Region {
    let mut lo = [i64::MAX; 3];
    let mut hi = [i64::MIN; 3];
    let pts = truth.iter().flat_map(|t| t.p.chunks_exact(3)).chain(radars.iter().flat_map(|r| r.p.chunks_exact(3)));
    for c in pts {
        for (k, &x) in c.iter().enumerate() {
            lo[k] = lo[k].min(x);
            hi[k] = hi[k].max(x);
        }
    }
    if lo[0] > hi[0] {
        (lo, hi) = ([-50_000, -50_000, -1000], [50_000, 50_000, 12_000]);
    }
    // A square horizontal box with a 10 % margin (at least 30 km): the default camera frames it.
    let half = ((hi[0] - lo[0]).max(hi[1] - lo[1]) as f64 * 0.55).max(30_000.0);
    let (cx, cy) = ((lo[0] + hi[0]) as f64 / 2.0, (lo[1] + hi[1]) as f64 / 2.0);
    let (x0, x1, y0, y1) = (cx - half, cx + half, cy - half, cy + half);
    let corners = [(x0, y0), (x0, y1), (x1, y0), (x1, y1)]
        .map(|(x, y)| ecef_to_geodetic(frame.enu.to_ecef(glam::DVec3::new(x, y, 0.0))));
    let lat = corners.iter().map(|g| g.lat_deg());
    let lon = corners.iter().map(|g| g.lon_deg());
    let (la0, la1) = lat.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
    let (lo0, lo1) = lon.fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
    // Every 0.5°, sampled every 0.05° (about 5 km): the box edges are on it, so its lowest
    // point is the lowest point of the earth under the box.
    let graticule = graticule(frame, (la0, la1), (lo0, lo1), 0.5, 0.05);
    let zmin = graticule.p.chunks_exact(3).map(|c| c[2]).min().unwrap_or(-1000);
    Region {
        lo: [x0.round() as i64, y0.round() as i64, zmin - 1000],
        hi: [x1.round() as i64, y1.round() as i64, hi[2].max(1000) + 3000],
        graticule,
    }
}

/// Build the view of one run.
pub fn build_view(src: &RunSource, opts: &ViewOptions) -> Result<View, PlotError> {
    src.check_run(opts.run)?;
    let duration_s = src.manifest.duration_s;
    let (t0, t1) = window(opts, duration_s)?;
    let tables = src.read(opts.run)?;
    let score = run_score(src, &tables, opts.run)?;

    let frame = PlotFrame::at(src.scenario.centre());
    let ships = &src.scenario.ships;
    let targets: Vec<String> = src.scenario.targets.iter().map(|t| t.id.clone()).collect();
    let radars: Vec<RadarView> =
        ships.iter().map(|s| objects::radar_view(&frame, s, t0, t1, opts.ship_step_s)).collect();
    let truth = objects::truth_paths(&frame, &tables.truth, &targets, (t0, t1), opts.truth_step_s, opts.tolerance_m);
    let (tracks, tracks_thinned) =
        objects::thin_tracks(objects::track_cols(&frame, &tables.tracks, &score, &targets, t0, t1), opts.tolerance_m);

    let used_by = used_by(&tables.tracks);
    let (meas, meas_dropped) =
        objects::meas_cols(&frame, ships, &tables.measurements, &tables.dwells, &used_by, &targets, (t0, t1));
    let beams = objects::beam_cols(&frame, ships, &tables.dwells.ta_parts, t0, t1);

    let metrics = metrics_cols(&score, &tables.dwells, t0, t1);
    let dropped = dropped_notes(opts, &tables, &truth, (t0, t1), (tracks_thinned, tracks.t.len()), meas_dropped);
    let region = region(&frame, &truth, &radars);
    let framing = framing(&frame, &radars, &truth, t0, t1, opts.framing_step_s.max(1.0));
    Ok(View {
        meta: Meta {
            scenario: src.scenario.name.clone(),
            run_dir: src.run_dir.display().to_string(),
            run: opts.run,
            tracker: src.manifest.tracker.as_ref().map_or_else(|| "(none)".to_string(), |t| t.name.clone()),
            duration_s,
            from_s: t0,
            to_s: t1,
            dropped,
            kinds: objects::KINDS.iter().map(|k| k.as_str()).collect(),
            statuses: mimo_core::records::TrackStatus::LABELS.to_vec(),
        },
        frame: frame.json(),
        radars,
        targets,
        truth,
        tracks,
        meas,
        beams,
        metrics,
        coast: coastlines(&frame),
        globe: globe_graticule(&frame),
        region,
        framing,
    })
}

/// The run's metrics: from its score directory when scored, else computed here.
fn run_score(src: &RunSource, tables: &RunTables, run: u32) -> Result<RunScore, PlotError> {
    let score_dir = mimo_store::layout::RunDir::new(&src.run_dir).score();
    if score_dir.summary().is_file() {
        linked::from_score_dir(score_dir.root(), run)
    } else {
        linked::computed(src, tables)
    }
}

/// For each measurement a track state last used, the lowest id of the tracks that used it.
fn used_by(tracks: &[TrackRow]) -> HashMap<u64, u64> {
    let mut used_by: HashMap<u64, u64> = HashMap::new();
    for r in tracks {
        if let Some(m) = r.last_meas_id {
            let e = used_by.entry(m).or_insert(r.track_id);
            *e = (*e).min(r.track_id);
        }
    }
    used_by
}

/// The linked metrics panel's columns within the window [t0, t1].
fn metrics_cols(score: &RunScore, dwells: &DwellDigest, t0: f64, t1: f64) -> MetricsCols {
    let n = score.t_s.len();
    let (energy, ta_energy) = dwells.energy_per_interval(score.interval_s, n);
    let keep: Vec<usize> = (0..n).filter(|&i| score.t_s[i] >= t0 && score.t_s[i] <= t1).collect();
    MetricsCols {
        source: score.source.clone(),
        interval_s: score.interval_s,
        t: keep.iter().map(|&i| score.t_s[i]).collect(),
        completeness: keep.iter().map(|&i| score.completeness[i]).collect(),
        n_scorable: keep.iter().map(|&i| score.n_scorable[i]).collect(),
        energy_j: keep.iter().map(|&i| energy[i]).collect(),
        ta_energy_j: keep.iter().map(|&i| ta_energy[i]).collect(),
    }
}

/// What the page leaves out or thins, one sentence each; `(tracks_thinned, tracks_kept)` are
/// the track states left out and drawn.
fn dropped_notes(
    opts: &ViewOptions,
    tables: &RunTables,
    truth: &[TruthPath],
    (t0, t1): (f64, f64),
    (tracks_thinned, tracks_kept): (usize, usize),
    meas_dropped: MeasDropped,
) -> Vec<String> {
    let truth_rows = tables.truth.count_within(t0, t1);
    let truth_kept: usize = truth.iter().map(|p| p.t.len()).sum();
    let search_parts = tables.dwells.search_parts_within(t0, t1);
    let step =
        if opts.truth_step_s > 0.0 { format!(" sampled every {} s, then", opts.truth_step_s) } else { String::new() };
    let tol = opts.tolerance_m;
    let mut dropped = vec![
        format!(
            "truth thinned from {truth_rows} samples (10 Hz) to {truth_kept},{step} within {tol} m: every sample left out is within {tol} m of the drawn path (chords between kept samples) at its own time"
        ),
        format!(
            "{tracks_thinned} of {} track states left out (not drawn, not clickable), within {tol} m: each left-out state is within {tol} m of the chord between the kept states of its track at its time; every track's first and last state, every status change and every deletion are kept",
            tracks_thinned + tracks_kept
        ),
        format!(
            "the region view frames the ships and targets of the current time (boxes every {} s, kept while what is in view stays inside), not the whole run; zoom out or use the globe view for the rest",
            opts.framing_step_s
        ),
        format!(
            "{search_parts} background-search dwell parts are not drawn as beams (the radars' own raster); their detections are drawn as measurements"
        ),
        "primitives are not drawn (each measurement is its strongest primitive, docs/model.md §4.5)".to_string(),
        "the earth is drawn as parallels and meridians (every 0.5° in the region view, 15° in the globe view) over a sea-coloured floor, not as a filled surface, so the page opens quickly".to_string(),
        "the 3-D axes (box, ticks, titles in ENU metres) are not drawn: tick text is slow to draw and says little on a globe; the click panel gives positions".to_string(),
    ];
    if meas_dropped.unplaceable + meas_dropped.unknown_radar > 0 {
        dropped.push(format!(
            "{} measurements could not be placed in space (docs/model.md §5.4 conversion refused: {}, unknown radar or face: {})",
            meas_dropped.unplaceable + meas_dropped.unknown_radar,
            meas_dropped.unplaceable,
            meas_dropped.unknown_radar
        ));
    }
    dropped
}
