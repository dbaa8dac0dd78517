//! What the tracker reports besides track rows: track snapshots for the scheduler, predicted
//! measurements, the NIS log and counters.

use crate::deletion::DeleteReason;
use crate::linalg::Mat3;
use crate::queries::TrackDue;
use mimo_core::ids::RadarId;
use std::collections::BTreeMap;

/// A snapshot of a track for the scheduler: its scheduling state ([`TrackDue`], whose fields
/// it derefs to) and more.
#[derive(Debug, Clone, PartialEq)]
pub struct TrackInfo {
    /// Id, status, last update, misses and due time.
    pub due: TrackDue,
    /// Receiver and face of the last update.
    pub last_face: Option<(RadarId, u8)>,
    /// IMM mode probabilities (`[1.0]` for the EKF).
    pub mode_probabilities: Vec<f64>,
    /// Mean NIS over the track's updates (NaN before the first update).
    pub mean_nis: f64,
}

impl std::ops::Deref for TrackInfo {
    type Target = TrackDue;
    fn deref(&self) -> &TrackDue {
        &self.due
    }
}

/// The NIS of one update, for consistency checks (χ²₃ when the filter is consistent).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NisRecord {
    /// Monte Carlo run.
    pub run: u32,
    /// Measurement time (s).
    pub t_s: f64,
    /// Track updated.
    pub track_id: u64,
    /// Measurement used.
    pub meas_id: u64,
    /// Transmitter of the measurement.
    pub tx: RadarId,
    /// Receiver of the measurement.
    pub rx: RadarId,
    /// Normalized innovation squared.
    pub nis: f64,
}

/// A predicted measurement of a track on a channel (scheduler: beam pointing, range windows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictedMeasurement {
    /// Equivalent monostatic range ρ = R_B/2 (m).
    pub rho_m: f64,
    /// Predicted u (sine space of the receive face).
    pub u: f64,
    /// Predicted v (sine space of the receive face).
    pub v: f64,
    /// Standard deviation of ρ from the track covariance, `√(h P hᵀ)/2` (m).
    pub sigma_rho_m: f64,
    /// `H P Hᵀ` in `(R_B, u, v)` (no measurement noise).
    pub cov: Mat3,
}

/// Counters.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrackerStats {
    /// Dwells processed.
    pub dwells: u64,
    /// Measurement rows received.
    pub measurements: u64,
    /// Rows skipped as invalid.
    pub rejected_measurements: u64,
    /// Track updates.
    pub updates: u64,
    /// Updates that failed numerically.
    pub failed_updates: u64,
    /// Updates that needed jitter to stay positive definite.
    pub jitter_events: u64,
    /// Tentative tracks started.
    pub initiated: u64,
    /// Tracks confirmed.
    pub confirmed: u64,
    /// Tracks ended, by reason.
    pub deleted: BTreeMap<DeleteReason, u64>,
}
