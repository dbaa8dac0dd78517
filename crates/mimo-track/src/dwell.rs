//! What the tracker is told about a finished dwell besides its measurements: its kind, time, the
//! tracks it was aimed at and its receive beams.

use mimo_core::ids::RadarId;
use mimo_core::records::DwellKind;

/// A beam of one receive channel in a dwell: which tracks it could have seen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    /// Transmitting radar.
    pub tx: RadarId,
    /// Receiving radar.
    pub rx: RadarId,
    /// Receive face.
    pub rx_face: u8,
    /// Receive beam steering direction in the face's sine space.
    pub beam_u: f64,
    /// Receive beam steering v.
    pub beam_v: f64,
    /// Equivalent monostatic range window ρ (m) of the channel, if limited.
    pub rho_window_m: Option<(f64, f64)>,
}

/// What the tracker is told about a finished dwell besides its measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct DwellContext {
    /// Monte Carlo run.
    pub run: u32,
    /// Dwell time (s) (start or mid-time, as the measurements' `t_s`).
    pub t_s: f64,
    /// Dwell (group) id, for logs.
    pub dwell_id: u64,
    /// Search dwells initiate tracks from unclaimed detections; the other kinds look at tracks.
    pub kind: DwellKind,
    /// Tracks this dwell was aimed at: each one not updated by the dwell counts a miss.
    pub target_tracks: Vec<u64>,
    /// Receive beams of the dwell (optional). For non-search dwells, a track predicted inside a
    /// beam (see [`TrackerConfig::beam_miss_fraction`]) and not updated also counts a miss; this
    /// is how offline replay, which does not know the original tracker's track ids, counts
    /// misses.
    pub looks: Vec<Look>,
}

impl DwellContext {
    /// A search dwell.
    pub fn search(run: u32, dwell_id: u64, t_s: f64) -> DwellContext {
        DwellContext { run, t_s, dwell_id, kind: DwellKind::Search, target_tracks: Vec::new(), looks: Vec::new() }
    }

    /// A dwell aimed at `tracks` (kind `Track`, `Confirm` or `Mimo`).
    pub fn aimed(run: u32, dwell_id: u64, t_s: f64, kind: DwellKind, tracks: Vec<u64>) -> DwellContext {
        DwellContext { run, t_s, dwell_id, kind, target_tracks: tracks, looks: Vec::new() }
    }
}
