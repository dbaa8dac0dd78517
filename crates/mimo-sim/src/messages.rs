//! The test-article boundary as owned, serializable messages (docs/ta-protocol.md).
//!
//! Every value that crosses between the engine and a test article is defined here: the events
//! the engine sends ([`TaEvent`]: `start`, `dwell_ended`, `wake`, `finish`) and what a test
//! article answers ([`Reply`]: [`Request`]s and track rows). They own their data (no borrow of
//! the engine's world), so the built-in test articles and a test article in another process
//! receive exactly the same thing; serde gives the JSON of the protocol.

use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use mimo_core::records::{DwellKind, MeasurementRow, PrimitiveRow, RegistrationRow, Requester, TrackRow};
use mimo_scenario::Ship;

pub use crate::search::SearchBand;
pub use crate::search_plan::{AzSector, SearchOrder, SearchPlan};
use serde::{Deserialize, Serialize};

/// Version of the protocol; sent in every `start` event. Bump it whenever a message changes.
pub const PROTOCOL_VERSION: u32 = 1;

/// A geodetic point (degrees, metres above the WGS-84 ellipsoid).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GeoPoint {
    /// Latitude (deg).
    pub lat_deg: f64,
    /// Longitude (deg).
    pub lon_deg: f64,
    /// Height above the ellipsoid (m).
    pub alt_m: f64,
}

/// A ship and its radar, as a test article may know them: where it starts, how it moves, and
/// every radar parameter. A ship steams along a great circle at constant speed
/// (docs/model.md §8.3); [`ShipInfo::to_ship`] gives its pose at any time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShipInfo {
    /// The radar's id (`R1`, …).
    pub radar: RadarId,
    /// Latitude of the array centre at t = 0 (deg).
    pub lat_deg: f64,
    /// Longitude of the array centre at t = 0 (deg).
    pub lon_deg: f64,
    /// Height of the array centre above the ellipsoid (m).
    pub array_height_m: f64,
    /// Heading at t = 0, clockwise from north (deg).
    pub heading_deg: f64,
    /// Speed over ground (m/s); 0 when stationary.
    pub speed_mps: f64,
    /// The radar's parameters (SI units, names as in the scenario files).
    pub params: RadarParams,
}

impl ShipInfo {
    /// The message form of a scenario ship.
    pub fn from_ship(s: &Ship) -> ShipInfo {
        ShipInfo {
            radar: s.id,
            lat_deg: s.lat_deg,
            lon_deg: s.lon_deg,
            array_height_m: s.array_height_m,
            heading_deg: s.heading_deg,
            speed_mps: s.speed_mps,
            params: s.radar.clone(),
        }
    }

    /// Back to a scenario ship, whose methods give its position, heading and faces at any time.
    pub fn to_ship(&self) -> Ship {
        Ship {
            id: self.radar,
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            array_height_m: self.array_height_m,
            heading_deg: self.heading_deg,
            speed_mps: self.speed_mps,
            radar: self.params.clone(),
        }
    }
}

/// The `start` event: everything a test article may know before the run, never truth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartInfo {
    /// [`PROTOCOL_VERSION`].
    pub protocol: u32,
    /// Monte Carlo run index.
    pub run: u32,
    /// Simulated duration of the run (s).
    pub duration_s: f64,
    /// Scenario name.
    pub scenario: String,
    /// Scenario centre: a natural origin for a local tracking frame.
    pub centre: GeoPoint,
    /// Every ship and radar, in radar-id order.
    pub ships: Vec<ShipInfo>,
    /// True in the closed loop; false in an open-loop re-run (`mimo track`), where requests are
    /// ignored, so a test article may skip its scheduling.
    pub closed_loop: bool,
    /// The test article's configuration overrides (`--ta-config`, `--set`), an object.
    pub config: serde_json::Value,
}

/// A radar's part in a finished dwell.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartReport {
    /// The radar.
    pub radar: RadarId,
    /// This part's row in the dwells table.
    pub dwell_id: u64,
    /// Whether the radar transmitted.
    pub transmits: bool,
    /// Whether the radar received.
    pub receives: bool,
    /// Array face used (0-based).
    pub face: u8,
    /// Beam direction in the face's sine space.
    pub beam_u: f64,
    /// Beam direction in the face's sine space.
    pub beam_v: f64,
    /// Pulses transmitted (0 for a receive-only part).
    pub n_pulses: u32,
    /// Array centre at mid-dwell (ECEF, m).
    pub site_ecef: DVec3,
    /// Rotation ECEF → face at mid-dwell, by rows (face x, face y, boresight).
    pub face_from_ecef: [[f64; 3]; 3],
}

impl PartReport {
    /// The face frame this part used.
    pub fn frame(&self) -> FaceFrame {
        let [x, y, n] = self.face_from_ecef;
        FaceFrame {
            origin_ecef: self.site_ecef,
            face_from_ecef: mimo_core::DMat3::from_cols(x.into(), y.into(), n.into()).transpose(),
        }
    }

    /// The rows of a face frame's rotation.
    pub fn rows_of(frame: &FaceFrame) -> [[f64; 3]; 3] {
        let m = frame.face_from_ecef;
        [m.row(0).to_array(), m.row(1).to_array(), m.row(2).to_array()]
    }
}

/// What a test article learns when a dwell ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DwellReport {
    /// Monte Carlo run index.
    pub run: u32,
    /// The dwell group (a MIMO dwell's parts share it).
    pub group_id: u64,
    /// Why the dwell was made.
    pub kind: DwellKind,
    /// Background search (`radar`) or the test article (`ta`).
    pub requested_by: Requester,
    /// Mid-time of the dwell (s): truth was evaluated then and measurements carry it.
    pub t_s: f64,
    /// Time the participants' timelines were occupied (s).
    pub duration_s: f64,
    /// When the dwell ended (s): the time of this event, when the test article's requests are
    /// placed.
    pub end_s: f64,
    /// Aim point (ECEF, m); for search, the beam direction at half the instrumented range.
    pub aim_ecef: DVec3,
    /// The request's tag (empty for search).
    #[serde(default)]
    pub tag: Vec<u64>,
    /// One entry per participating radar.
    pub parts: Vec<PartReport>,
    /// Measurements of every receive channel (no truth: `target_hint` is never set).
    #[serde(default)]
    pub measurements: Vec<MeasurementRow>,
    /// Primitives of every channel, when the subscription asks for them (else empty).
    #[serde(default)]
    pub primitives: Vec<PrimitiveRow>,
}

/// One transmitter of a requested dwell.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TxOrder {
    /// The transmitting radar.
    pub radar: RadarId,
    /// Pulses to integrate (clipped to the radar's `max_pulses`).
    pub n_pulses: u32,
}

/// A dwell requested by the test article. A monostatic dwell has one transmitter that is also
/// the only receiver; a MIMO dwell has several transmitters (each on its own orthogonal
/// waveform) and/or several receivers, all steered at `aim_ecef`. Every participant's timeline
/// is occupied for the whole dwell, which lasts as long as its longest transmission. A
/// participant that cannot steer at the aim point (scan limit) is left out; the dwell is not run
/// (and counted as rejected) when no transmitter or no receiver is left, or when it would end
/// after the run. List each radar at most once as a transmitter.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DwellRequest {
    /// `confirm`, `track`, `mimo` or `search` (reported back and recorded; a `search` dwell
    /// requested by the test article is recorded with `requested_by = ta`, e.g. a cued or a
    /// multistatic search beam).
    pub kind: DwellKind,
    /// Earliest start time (s): the dwell starts at the first time every participant is free
    /// at or after it.
    pub earliest_s: f64,
    /// Aim point (ECEF, m).
    pub aim_ecef: DVec3,
    /// Transmitters, each with its pulse count.
    pub transmitters: Vec<TxOrder>,
    /// Receivers.
    pub receivers: Vec<RadarId>,
    /// Half-width of each receive channel's range window around the aim point's equivalent
    /// monostatic range ρ (m).
    pub window_half_m: f64,
    /// Predicted mean SNR (linear) of the return aimed at, for the ML monopulse bias factor.
    #[serde(default)]
    pub predicted_snr: Option<f64>,
    /// Opaque tag echoed back in the [`DwellReport`] (e.g. the track ids the dwell is for).
    #[serde(default)]
    pub tag: Vec<u64>,
}

/// A test article's request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Request {
    /// Run a dwell.
    Dwell(DwellRequest),
    /// Deliver a `wake` event at this time (s).
    WakeAt(f64),
    /// Tell a radar to stop tracking on its own (the test article tracks for it). The built-in
    /// radars run background search only, so this is recorded and has no further effect.
    StopLocalTracking(RadarId),
    /// Set the background search of one radar or of every radar from now on (docs/model.md
    /// §7.4). A test article that never sends one gets the default raster.
    Search(SearchOrder),
}

/// Which dwells a test article is sent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DwellFilter {
    /// Every dwell, background search included.
    All,
    /// Every dwell with at least one measurement, and every dwell the test article requested.
    #[default]
    Detections,
    /// Only the dwells the test article requested.
    Own,
}

/// What a test article wants to be sent (docs/ta-protocol.md §4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Subscription {
    /// Which dwells.
    pub dwells: DwellFilter,
    /// Include the primitives in dwell reports.
    pub primitives: bool,
    /// Deliver events of the same instant in one call (their requests are then placed after
    /// all of them are processed).
    pub batch: bool,
}

impl Subscription {
    /// Whether a dwell with this requester and this many measurements is delivered.
    pub fn wants(&self, requested_by: Requester, n_measurements: usize) -> bool {
        match self.dwells {
            DwellFilter::All => true,
            DwellFilter::Detections => requested_by == Requester::Ta || n_measurements > 0,
            DwellFilter::Own => requested_by == Requester::Ta,
        }
    }
}

/// An event the engine sends a test article.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "event", rename_all = "snake_case")]
pub enum TaEvent {
    /// The run starts (always the first event).
    Start(StartInfo),
    /// A dwell the test article subscribed to has ended.
    DwellEnded(DwellReport),
    /// A wake-up the test article asked for.
    Wake {
        /// Simulation time (s).
        t_s: f64,
    },
    /// The run ends (always the last event).
    Finish {
        /// Simulation time (s): the end of the run.
        t_s: f64,
    },
}

/// One message of the protocol from `mimo` to a test article: the events of one instant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EventMessage {
    /// Simulation time of the events (s).
    pub t_s: f64,
    /// The events, in the order to process them.
    pub events: Vec<TaEvent>,
}

/// A test article's answer to one call: requests and the track rows it produced.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Reply {
    /// Dwells, wake-ups and orders, placed in the order `track`, `confirm`, `mimo` (then by
    /// earliest start, then as listed); other requests in the order given.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub requests: Vec<Request>,
    /// Track rows (their `run` is filled in by the engine).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tracks: Vec<TrackRow>,
    /// The test article's registration estimates, one row per radar (docs/model.md §6.9; their
    /// `run` is filled in by the engine). Written to the run's `registration` table when the
    /// scenario has biases on.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub registration: Vec<RegistrationRow>,
}

impl Reply {
    /// A reply with requests only.
    pub fn requests(requests: Vec<Request>) -> Reply {
        Reply { requests, ..Reply::default() }
    }

    /// A reply with requests and track rows.
    pub fn with_tracks(requests: Vec<Request>, tracks: Vec<TrackRow>) -> Reply {
        Reply { requests, tracks, ..Reply::default() }
    }

    /// Append another reply's requests and rows.
    pub fn extend(&mut self, other: Reply) {
        self.requests.extend(other.requests);
        self.tracks.extend(other.tracks);
        self.registration.extend(other.registration);
    }
}

/// The wire form of a reply to the message holding `start`: a [`Reply`] plus what the test
/// article says about itself.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReplyMessage {
    /// Requests.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub requests: Vec<Request>,
    /// Track rows.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tracks: Vec<TrackRow>,
    /// Registration estimates (see [`Reply::registration`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub registration: Vec<RegistrationRow>,
    /// Name recorded in the manifest (start reply only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// Configuration recorded in the manifest (start reply only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub config: Option<serde_json::Value>,
    /// What the test article wants to be sent (start reply only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub subscribe: Option<Subscription>,
}
