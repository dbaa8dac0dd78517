//! # mimo-plot
//!
//! `mimo plot`: one run in 3-D on the globe, in one self-contained, offline HTML page. The
//! page shows the earth (Natural Earth 110 m coastlines, shipped in the crate), the ships and
//! their array faces, truth paths, tracks (coloured by id, styled by status), measurements
//! (monostatic and bistatic apart) and the beams of the test article's dwells, at a time chosen
//! with a slider (with play/pause and a trailing window). Clicking an object shows its position
//! (lat/lon/alt, ECEF), time, SNR, dwell kind, transmitting and receiving radars, track and
//! assigned truth, and its 1σ/3σ covariance ellipsoid; a selected measurement or dwell draws a
//! solid line from each transmitter and a dotted line from each receiver. A linked 2-D panel
//! plots completeness and energy per scoring interval (docs/design.md §6); clicking it moves the
//! 3-D view to that time.
//!
//! * [`source`] opens a run directory (following `parent` links, docs/design.md §2) and reads
//!   one run's tables; its truth streams into compact per-target samples ([`truth_samples`]),
//!   its dwells into what the page keeps of them ([`dwell_digest`]).
//! * [`view`] builds the [`View`]: every position in a local ENU plot frame ([`frame`]), objects
//!   as time-sorted columns ([`objects`]), the earth ([`globe`]), the linked metrics
//!   ([`linked`]), covariance ellipsoid axes ([`ellipsoid`]), truth and track paths thinned within
//!   a position tolerance ([`decimate`]), and boxes that frame what is in view at each time
//!   ([`framing`]).
//! * [`html`] renders the page with plotly.js (gl3d bundle) inlined; [`write_page`] writes it.
//!
//! Rendering uses plotly.js rather than hand-written WebGL; see
//! docs/decisions/0013-run-viewer-single-page.md for the choice of bundle. What the view thins or
//! leaves out to stay small is listed on the page and in [`view`].

#![warn(missing_docs)]

mod error;

pub mod decimate;
pub mod dwell_digest;
pub mod ellipsoid;
pub mod frame;
pub mod framing;
pub mod globe;
pub mod html;
pub mod linked;
pub mod objects;
pub mod source;
pub mod truth_samples;
pub mod view;

pub use error::PlotError;
pub use source::RunSource;
pub use view::{View, ViewOptions, build_view};

use std::path::Path;

/// Build the page of a run: open it, build its view and render the HTML.
pub fn plot_run(run_dir: &Path, opts: &ViewOptions) -> Result<String, PlotError> {
    let src = RunSource::open(run_dir)?;
    let view = build_view(&src, opts)?;
    html::render(&view).map_err(|e| PlotError::Internal(format!("cannot encode the view: {e}")))
}

/// Whether `out` may be written: it does not exist, or (with `force`) it is a page `mimo plot`
/// wrote. Anything else is refused, even with `force`.
pub fn check_out(out: &Path, force: bool) -> Result<(), PlotError> {
    let what = "a page mimo plot wrote";
    Ok(mimo_store::output::check_file_output(out, force, mimo_store::recognise::is_plot_page, what)?)
}

/// Write a page to `out` atomically (a hidden temporary file beside it, then a rename; the
/// temporary file is removed if the write fails, and on an interrupt), creating its folder if
/// it is missing, as every command creates its output's (docs/design.md §7). An existing file is
/// replaced only with `force`, and only if it is a page `mimo plot` wrote (its head carries
/// [`mimo_store::recognise::PLOT_MARK`]): any other file is refused, even with `force`.
pub fn write_page(out: &Path, page: &str, force: bool) -> Result<(), PlotError> {
    use mimo_store::output;
    check_out(out, force)?;
    let tmp = output::sibling(out, "tmp")?;
    let io = |e: std::io::Error| PlotError::Io { path: out.to_path_buf(), why: e.to_string() };
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    output::register(&tmp);
    let written = std::fs::write(&tmp, page).and_then(|()| std::fs::rename(&tmp, out)).map_err(io);
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    output::unregister(&tmp);
    written
}
