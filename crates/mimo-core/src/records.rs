//! Row records of the run tables (docs/design.md §3).
//!
//! These are plain structs: simulation, radar and tracking code produce them without knowing
//! about Arrow or Parquet. `mimo-store` owns the Arrow schemas (with units in the field
//! metadata), converts these rows to record batches and back, and checks `schemas/`.
//!
//! Positions and velocities are ECEF (m, m/s) unless a name says otherwise; times are seconds since
//! scenario start. Radar ids are [`RadarId`] here and the strings `R1`…`R4` on disk.

use crate::ids::RadarId;
use serde::{Deserialize, Serialize};

/// One target at one truth sample.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthRow {
    pub run: u32,
    pub t_s: f64,
    pub target: String,
    pub x_m: f64,
    pub y_m: f64,
    pub z_m: f64,
    pub vx_mps: f64,
    pub vy_mps: f64,
    pub vz_mps: f64,
    pub lat_deg: f64,
    pub lon_deg: f64,
    pub alt_m: f64,
    /// Mean radar cross-section (m²).
    pub rcs_m2: f64,
}

/// A radar's part in a dwell.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Role {
    /// Transmit only (MIMO transmitter that does not receive).
    Tx,
    /// Receive only: costs no energy.
    Rx,
    /// Transmit and receive.
    Txrx,
}

impl Role {
    pub fn as_str(self) -> &'static str {
        match self {
            Role::Tx => "tx",
            Role::Rx => "rx",
            Role::Txrx => "txrx",
        }
    }
    pub fn parse(s: &str) -> Option<Role> {
        Some(match s {
            "tx" => Role::Tx,
            "rx" => Role::Rx,
            "txrx" => Role::Txrx,
            _ => return None,
        })
    }
    /// Does this role transmit (and so cost energy and dwell time)?
    pub fn transmits(self) -> bool {
        !matches!(self, Role::Rx)
    }
}

/// Why a dwell was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DwellKind {
    Search,
    Confirm,
    Track,
    Mimo,
}

impl DwellKind {
    pub fn as_str(self) -> &'static str {
        match self {
            DwellKind::Search => "search",
            DwellKind::Confirm => "confirm",
            DwellKind::Track => "track",
            DwellKind::Mimo => "mimo",
        }
    }
    pub fn parse(s: &str) -> Option<DwellKind> {
        Some(match s {
            "search" => DwellKind::Search,
            "confirm" => DwellKind::Confirm,
            "track" => DwellKind::Track,
            "mimo" => DwellKind::Mimo,
            _ => return None,
        })
    }
}

/// Who asked for a dwell: the radar's own background search, or the test article.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Requester {
    Radar,
    Ta,
}

impl Requester {
    pub fn as_str(self) -> &'static str {
        match self {
            Requester::Radar => "radar",
            Requester::Ta => "ta",
        }
    }
    pub fn parse(s: &str) -> Option<Requester> {
        Some(match s {
            "radar" => Requester::Radar,
            "ta" => Requester::Ta,
            _ => return None,
        })
    }
}

/// One radar's part in one dwell.
#[derive(Debug, Clone, PartialEq)]
pub struct DwellRow {
    pub run: u32,
    /// Unique within a run per (dwell, radar) part.
    pub dwell_id: u64,
    /// Shared by all radars of one (MIMO) dwell; equals `dwell_id` of the first part.
    pub group_id: u64,
    pub radar: RadarId,
    pub role: Role,
    pub kind: DwellKind,
    pub requested_by: Requester,
    /// Start time (s).
    pub t_s: f64,
    /// Time the radar's timeline is occupied, τ_dwell (s).
    pub duration_s: f64,
    /// Pulse width τ_pw (s).
    pub pulse_width_s: f64,
    pub n_pulses: u32,
    pub peak_power_w: f64,
    /// Emitted energy = peak_power_w · pulse_width_s · n_pulses; 0 for `rx`.
    pub energy_j: f64,
    /// Orthogonal waveform (code) index transmitted; receivers list 0.
    pub waveform: u32,
    /// Array face used (0-based).
    pub face: u8,
    /// Beam steering direction in the face's sine space.
    pub beam_u: f64,
    pub beam_v: f64,
    /// Aim point (ECEF, m).
    pub aim_x_m: f64,
    pub aim_y_m: f64,
    pub aim_z_m: f64,
}

/// Complex voltages of one receive channel (matched filter for one transmitter) in one range
/// cell, normalized so that the noise is CN(0, 1) in every channel.
#[derive(Debug, Clone, PartialEq)]
pub struct VoltageRow {
    pub run: u32,
    pub dwell_id: u64,
    pub rx: RadarId,
    pub tx: RadarId,
    pub range_cell: i64,
    /// Equivalent monostatic range of the cell centre, ρ = R_B/2 (m).
    pub range_m: f64,
    pub sum_i: f64,
    pub sum_q: f64,
    pub az_i: f64,
    pub az_q: f64,
    pub el_i: f64,
    pub el_q: f64,
}

/// A threshold crossing after monopulse DOA estimation.
///
/// Serialized (for the test-article protocol) without `run` and `target_hint`, which the engine fills in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrimitiveRow {
    #[serde(skip)]
    pub run: u32,
    /// The receiver's dwell part.
    pub dwell_id: u64,
    pub t_s: f64,
    pub rx: RadarId,
    pub tx: RadarId,
    /// Receiver face the (u, v) refer to.
    pub rx_face: u8,
    /// Peak cell index.
    pub range_cell: i64,
    /// Centroided equivalent monostatic range ρ = R_B/2 (m).
    pub range_m: f64,
    pub u: f64,
    pub v: f64,
    /// Observed sum-channel SNR S = Σ|Σ_k|² over the cells used (dB).
    pub snr_db: f64,
    /// Imaginary-part statistic T = η_Qa²/var_a + η_Qe²/var_e (χ²₂ for one target).
    pub eta_q: f64,
    pub merged: bool,
    /// Beam steering direction of the receiver (sine space), so the monopulse ratio can be
    /// recovered offline.
    pub beam_u: f64,
    pub beam_v: f64,
    /// Variances of this primitive's estimates, from the observed SNR (docs/model.md §2.6, §4.6).
    pub var_range_m2: f64,
    pub var_u: f64,
    pub var_v: f64,
    /// Truth id of the dominant contributor (evaluation only).
    #[serde(skip)]
    pub target_hint: Option<String>,
}

/// A clustered, centroided detection handed to trackers.
///
/// Serialized (for the test-article protocol) without `run` and `target_hint`, which the engine fills in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeasurementRow {
    #[serde(skip)]
    pub run: u32,
    pub meas_id: u64,
    pub dwell_id: u64,
    pub t_s: f64,
    pub rx: RadarId,
    pub tx: RadarId,
    pub rx_face: u8,
    /// Equivalent monostatic range ρ = (R_t + R_r)/2 (m).
    pub range_m: f64,
    pub u: f64,
    pub v: f64,
    pub snr_db: f64,
    pub var_range_m2: f64,
    pub var_u: f64,
    pub var_v: f64,
    pub n_primitives: u32,
    pub merged: bool,
    /// Truth id of the dominant contributor; `None` for false alarms. Never shown to a tracker.
    #[serde(skip)]
    pub target_hint: Option<String>,
}

/// Track status.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TrackStatus {
    Tentative,
    Confirmed,
    Deleted,
}

impl TrackStatus {
    pub fn as_str(self) -> &'static str {
        match self {
            TrackStatus::Tentative => "tentative",
            TrackStatus::Confirmed => "confirmed",
            TrackStatus::Deleted => "deleted",
        }
    }
    pub fn parse(s: &str) -> Option<TrackStatus> {
        Some(match s {
            "tentative" => TrackStatus::Tentative,
            "confirmed" => TrackStatus::Confirmed,
            "deleted" => TrackStatus::Deleted,
            _ => return None,
        })
    }
}

/// A track's state at an update (or the final `deleted` row).
///
/// Serialized (for the test-article protocol) without `run`, which the engine fills in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackRow {
    #[serde(skip)]
    pub run: u32,
    pub t_s: f64,
    pub track_id: u64,
    pub status: TrackStatus,
    pub x_m: f64,
    pub y_m: f64,
    pub z_m: f64,
    pub vx_mps: f64,
    pub vy_mps: f64,
    pub vz_mps: f64,
    /// Upper triangle of the 6×6 ECEF position–velocity covariance, row-major (21 values).
    pub cov: [f64; 21],
    pub n_updates: u32,
    pub last_meas_id: Option<u64>,
}

/// Every table of one Monte Carlo run, in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunTables {
    pub truth: Vec<TruthRow>,
    pub dwells: Vec<DwellRow>,
    pub voltages: Vec<VoltageRow>,
    pub primitives: Vec<PrimitiveRow>,
    pub measurements: Vec<MeasurementRow>,
    pub tracks: Vec<TrackRow>,
}

/// Index into the 21-element upper-triangle covariance for (i, j), i, j < 6.
pub fn cov_index(i: usize, j: usize) -> usize {
    let (i, j) = if i <= j { (i, j) } else { (j, i) };
    // Row i starts after rows 0..i which hold 6, 5, … entries.
    i * 6 - i * i.saturating_sub(1) / 2 + (j - i)
}

/// Pack a symmetric 6×6 matrix (row-major `[[f64; 6]; 6]`) into its upper triangle.
pub fn pack_cov(m: &[[f64; 6]; 6]) -> [f64; 21] {
    let mut out = [0.0; 21];
    let mut k = 0;
    for (i, row) in m.iter().enumerate() {
        for &x in &row[i..] {
            out[k] = x;
            k += 1;
        }
    }
    out
}

/// Unpack an upper triangle into a symmetric 6×6 matrix.
#[allow(clippy::needless_range_loop)] // (i, j) and (j, i) are written together
pub fn unpack_cov(c: &[f64; 21]) -> [[f64; 6]; 6] {
    let mut m = [[0.0; 6]; 6];
    let mut k = 0;
    for i in 0..6 {
        for j in i..6 {
            (m[i][j], m[j][i]) = (c[k], c[k]);
            k += 1;
        }
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cov_pack_round_trip() {
        let mut m = [[0.0; 6]; 6];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = (i.min(j) * 10 + i.max(j)) as f64;
            }
        }
        let p = pack_cov(&m);
        assert_eq!(p[0], 0.0);
        assert_eq!(p[6], 11.0);
        assert_eq!(unpack_cov(&p), m);
        for i in 0..6 {
            for j in 0..6 {
                assert_eq!(p[cov_index(i, j)], m[i][j], "({i},{j})");
            }
        }
    }

    #[test]
    fn enum_strings_round_trip() {
        for r in [Role::Tx, Role::Rx, Role::Txrx] {
            assert_eq!(Role::parse(r.as_str()), Some(r));
        }
        for k in [DwellKind::Search, DwellKind::Confirm, DwellKind::Track, DwellKind::Mimo] {
            assert_eq!(DwellKind::parse(k.as_str()), Some(k));
        }
        for s in [TrackStatus::Tentative, TrackStatus::Confirmed, TrackStatus::Deleted] {
            assert_eq!(TrackStatus::parse(s.as_str()), Some(s));
        }
        assert_eq!(Requester::parse("ta"), Some(Requester::Ta));
        assert!(!Role::Rx.transmits());
    }
}
