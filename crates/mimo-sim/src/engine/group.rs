//! A dwell group as the engine keeps it between its reservation and its execution: one part per
//! participating radar.

use mimo_core::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, Requester, Role};

/// One radar's part in a group.
#[derive(Debug, Clone)]
pub(crate) struct Part {
    pub radar: RadarId,
    pub role: Role,
    pub face: u8,
    pub beam_u: f64,
    pub beam_v: f64,
    pub n_pulses: u32,
    pub waveform: u32,
}

impl Part {
    /// Whether the part receives (and so has channels and measurements).
    pub fn receives(&self) -> bool {
        matches!(self.role, Role::Rx | Role::Txrx)
    }
}

/// A dwell group: one background search beam, or a test article's monostatic or MIMO dwell.
#[derive(Debug, Clone)]
pub(crate) struct Group {
    pub kind: DwellKind,
    pub requested_by: Requester,
    /// Aim point; `None` for search, whose beam is fixed in the face (the recorded aim is then
    /// the beam direction at half the instrumented range, from the face at mid-dwell).
    pub aim: Option<DVec3>,
    pub parts: Vec<Part>,
    pub duration_s: f64,
    /// Receive window half-width around the aim point's ρ (m); `None` for search (whole range).
    pub window_half_m: Option<f64>,
    pub predicted_snr: Option<f64>,
    pub tag: Vec<u64>,
}
