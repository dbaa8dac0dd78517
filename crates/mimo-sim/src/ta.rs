//! The test-article (TA) interface.
//!
//! A TA is the user's tracker and resource manager. The event engine drives it:
//!
//! * [`TestArticle::on_dwell`] is called when a dwell ends, with the dwell's measurements and
//!   primitives per receive channel — for background search dwells as well as the TA's own.
//!   Truth never reaches a TA: the `target_hint` column is cleared before delivery.
//! * [`TestArticle::on_wake`] is called at a time the TA asked for with [`Request::WakeAt`].
//! * Both answer with [`Request`]s: dwells (monostatic, or MIMO: several transmitters with
//!   orthogonal waveforms and several receivers, one aim point, one earliest start time),
//!   wake-ups, and orders to a radar to stop its local tracking.
//! * [`TestArticle::take_track_rows`] hands over the track rows the TA produced since the last
//!   call; the engine writes them to the run's tracks table.
//!
//! # Writing your own TA
//!
//! ```
//! use mimo_sim::ta::{DwellReport, Request, TaContext, TestArticle};
//! use mimo_core::records::TrackRow;
//!
//! /// A TA that never asks for anything: only background search runs.
//! struct Passive { seen: usize }
//!
//! impl TestArticle for Passive {
//!     fn name(&self) -> &str { "passive" }
//!     fn on_dwell(&mut self, _ctx: &TaContext, report: &DwellReport) -> Vec<Request> {
//!         self.seen += report.measurements.len();
//!         Vec::new()
//!     }
//!     fn on_wake(&mut self, _ctx: &TaContext, _t_s: f64) -> Vec<Request> { Vec::new() }
//!     fn take_track_rows(&mut self) -> Vec<TrackRow> { Vec::new() }
//! }
//! ```
//!
//! Run it with [`crate::run_one`] (or [`crate::run_monte_carlo`] with a factory closure).

use crate::world::Radars;
use mimo_core::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, MeasurementRow, PrimitiveRow, Requester, TrackRow};

/// What a TA may look at when it decides: the ships and radars (not the targets), and the time.
pub struct TaContext<'a> {
    pub radars: Radars<'a>,
    /// Current simulation time (s).
    pub t_s: f64,
    pub run: u32,
}

/// One transmitter of a requested dwell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TxOrder {
    pub radar: RadarId,
    /// Pulses to integrate (clipped to the radar's `max_pulses`).
    pub n_pulses: u32,
}

/// A dwell requested by the TA. A monostatic dwell has one transmitter that is also the only
/// receiver; a MIMO dwell has several transmitters (each on its own orthogonal waveform) and/or
/// several receivers, all steered at `aim_ecef`. Every participant's timeline is occupied for
/// the whole dwell, which lasts as long as its longest transmission. A participant that cannot
/// steer at the aim point (scan limit) is left out; the request is rejected (and counted in
/// `RunStats::rejected_requests`) only when no transmitter or no receiver is left, or when its
/// start is not a time inside the run. List each radar at most once as a transmitter.
#[derive(Debug, Clone, PartialEq)]
pub struct DwellRequest {
    pub kind: DwellKind,
    /// Earliest start time (s); the engine starts the dwell at the first time every participant
    /// is free at or after it.
    pub earliest_s: f64,
    pub aim_ecef: DVec3,
    pub transmitters: Vec<TxOrder>,
    pub receivers: Vec<RadarId>,
    /// Half-width of each receive channel's range window around the aim point's equivalent
    /// monostatic range ρ (m).
    pub window_half_m: f64,
    /// Predicted mean SNR (linear) of the return aimed at, for the ML monopulse bias factor.
    pub predicted_snr: Option<f64>,
    /// Opaque tag echoed back in the [`DwellReport`] (e.g. the track ids the dwell is for).
    pub tag: Vec<u64>,
}

/// A TA's answer.
#[derive(Debug, Clone, PartialEq)]
pub enum Request {
    Dwell(DwellRequest),
    /// Call [`TestArticle::on_wake`] at this time (s).
    WakeAt(f64),
    /// Tell a radar to stop tracking on its own (the TA tracks for it). The built-in radars
    /// run background search only, so this is recorded and has no further effect.
    StopLocalTracking(RadarId),
}

/// A radar's part in a finished dwell.
#[derive(Debug, Clone, PartialEq)]
pub struct PartReport {
    pub radar: RadarId,
    pub dwell_id: u64,
    pub transmits: bool,
    pub receives: bool,
    pub face: u8,
    pub beam_u: f64,
    pub beam_v: f64,
    pub n_pulses: u32,
}

/// What the TA learns when a dwell ends.
#[derive(Debug, Clone, PartialEq)]
pub struct DwellReport {
    pub run: u32,
    pub group_id: u64,
    pub kind: DwellKind,
    pub requested_by: Requester,
    /// Mid-time of the dwell (s): truth was evaluated then and measurements are stamped with it.
    pub t_s: f64,
    pub duration_s: f64,
    pub aim_ecef: DVec3,
    pub parts: Vec<PartReport>,
    /// The tag of the request (empty for search).
    pub tag: Vec<u64>,
    /// Measurements of every channel (target hints cleared).
    pub measurements: Vec<MeasurementRow>,
    /// Primitives of every channel (target hints cleared).
    pub primitives: Vec<PrimitiveRow>,
}

/// A test article: the tracker and resource manager under test.
pub trait TestArticle {
    /// Short name recorded in the manifest.
    fn name(&self) -> &str;
    /// Configuration recorded in the manifest.
    fn config(&self) -> serde_json::Value {
        serde_json::Value::Null
    }
    /// Called once at t = 0 before anything runs.
    fn start(&mut self, _ctx: &TaContext) -> Vec<Request> {
        Vec::new()
    }
    /// A dwell ended.
    fn on_dwell(&mut self, ctx: &TaContext, report: &DwellReport) -> Vec<Request>;
    /// A wake-up the TA asked for.
    fn on_wake(&mut self, ctx: &TaContext, t_s: f64) -> Vec<Request>;
    /// Track rows produced since the last call.
    fn take_track_rows(&mut self) -> Vec<TrackRow>;
    /// Called once at the end of the run; may return final rows (e.g. `deleted` rows).
    fn finish(&mut self, _ctx: &TaContext) -> Vec<TrackRow> {
        Vec::new()
    }
}
