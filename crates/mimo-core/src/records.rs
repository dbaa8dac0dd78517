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
    /// Monte Carlo run index, 0-based.
    pub run: u32,
    /// Sample time since scenario start (s).
    pub t_s: f64,
    /// Target id (`F-1`…`F-4`, `A`, `B`, `C` in the standard scenarios).
    pub target: String,
    /// Target position, ECEF x (m).
    pub x_m: f64,
    /// Target position, ECEF y (m).
    pub y_m: f64,
    /// Target position, ECEF z (m).
    pub z_m: f64,
    /// Target velocity, ECEF x (m/s).
    pub vx_mps: f64,
    /// Target velocity, ECEF y (m/s).
    pub vy_mps: f64,
    /// Target velocity, ECEF z (m/s).
    pub vz_mps: f64,
    /// Target WGS-84 geodetic latitude (deg).
    pub lat_deg: f64,
    /// Target WGS-84 geodetic longitude (deg, east positive).
    pub lon_deg: f64,
    /// Target height above the WGS-84 ellipsoid (m).
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
    /// Every on-disk label, in declaration order (the values the table's column may hold).
    pub const LABELS: [&'static str; 3] = ["tx", "rx", "txrx"];
    /// The on-disk string: `tx`, `rx` or `txrx`.
    pub fn as_str(self) -> &'static str {
        match self {
            Role::Tx => "tx",
            Role::Rx => "rx",
            Role::Txrx => "txrx",
        }
    }
    /// The role written as `s` (`tx`, `rx`, `txrx`); `None` for any other string.
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
    /// Background search raster (docs/model.md §7.4), or search requested by a test article.
    Search,
    /// Confirmation look at a tentative track (M-of-N, docs/model.md §6.4).
    Confirm,
    /// Update look at a track.
    Track,
    /// MIMO dwell: several radars steer at one aim point, each transmitter with its own orthogonal
    /// waveform, each receiver with one matched filter per transmitter (docs/model.md §5).
    Mimo,
}

impl DwellKind {
    /// Every on-disk label, in declaration order (the values the table's column may hold).
    pub const LABELS: [&'static str; 4] = ["search", "confirm", "track", "mimo"];
    /// The on-disk string: `search`, `confirm`, `track` or `mimo`.
    pub fn as_str(self) -> &'static str {
        match self {
            DwellKind::Search => "search",
            DwellKind::Confirm => "confirm",
            DwellKind::Track => "track",
            DwellKind::Mimo => "mimo",
        }
    }
    /// The kind written as `s`; `None` for any string but `search`, `confirm`, `track`, `mimo`.
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
    /// The radar's own background search.
    Radar,
    /// The test article.
    Ta,
}

impl Requester {
    /// Every on-disk label, in declaration order (the values the table's column may hold).
    pub const LABELS: [&'static str; 2] = ["radar", "ta"];
    /// The on-disk string: `radar` or `ta`.
    pub fn as_str(self) -> &'static str {
        match self {
            Requester::Radar => "radar",
            Requester::Ta => "ta",
        }
    }
    /// The requester written as `s` (`radar`, `ta`); `None` for any other string.
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
    /// Monte Carlo run index, 0-based.
    pub run: u32,
    /// Unique within a run per (dwell, radar) part.
    pub dwell_id: u64,
    /// Shared by all radars of one (MIMO) dwell; equals `dwell_id` of the first part.
    pub group_id: u64,
    /// The radar this part belongs to (`R1`…`R4` on disk).
    pub radar: RadarId,
    /// Whether this radar transmits, receives or both in the dwell.
    pub role: Role,
    /// Why the dwell was made (search, confirm, track, mimo).
    pub kind: DwellKind,
    /// Who asked for the dwell: the radar's background search or the test article.
    pub requested_by: Requester,
    /// Start time (s).
    pub t_s: f64,
    /// Time the radar's timeline is occupied, τ_dwell (s).
    pub duration_s: f64,
    /// Pulse width τ_pw (s).
    pub pulse_width_s: f64,
    /// Pulses integrated coherently.
    pub n_pulses: u32,
    /// Peak transmit power (W).
    pub peak_power_w: f64,
    /// Emitted energy = peak_power_w · pulse_width_s · n_pulses; 0 for `rx`.
    pub energy_j: f64,
    /// Orthogonal waveform (code) index transmitted; receivers list 0.
    pub waveform: u32,
    /// Array face used (0-based).
    pub face: u8,
    /// Beam steering direction in the face's sine space.
    pub beam_u: f64,
    /// Beam steering direction cosine v (face-up axis) in the face frame.
    pub beam_v: f64,
    /// Aim point (ECEF, m).
    pub aim_x_m: f64,
    /// Aim point, ECEF y (m).
    pub aim_y_m: f64,
    /// Aim point, ECEF z (m).
    pub aim_z_m: f64,
}

/// Complex voltages of one receive channel (matched filter for one transmitter) in one range
/// cell, normalized so that the noise is CN(0, 1) in every channel.
#[derive(Debug, Clone, PartialEq)]
pub struct VoltageRow {
    /// Monte Carlo run index, 0-based.
    pub run: u32,
    /// The receiver's dwell part (`DwellRow::dwell_id`).
    pub dwell_id: u64,
    /// Receiving radar.
    pub rx: RadarId,
    /// Transmitting radar whose waveform this channel's matched filter is for.
    pub tx: RadarId,
    /// Range cell index k; the cell centre is at ρ_k = k·ΔR (docs/model.md §4.1).
    pub range_cell: i64,
    /// Equivalent monostatic range of the cell centre, ρ = R_B/2 (m).
    pub range_m: f64,
    /// Sum channel, in-phase part (√SNR units: noise is CN(0, 1)).
    pub sum_i: f64,
    /// Sum channel, quadrature part (√SNR units).
    pub sum_q: f64,
    /// Azimuth-difference (u) channel, in-phase part (√SNR units).
    pub az_i: f64,
    /// Azimuth-difference (u) channel, quadrature part (√SNR units).
    pub az_q: f64,
    /// Elevation-difference (v) channel, in-phase part (√SNR units).
    pub el_i: f64,
    /// Elevation-difference (v) channel, quadrature part (√SNR units).
    pub el_q: f64,
}

/// A threshold crossing after monopulse DOA estimation.
///
/// Serialized (for the test-article protocol) without `run` and `target_hint`, which the engine fills in.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PrimitiveRow {
    /// Monte Carlo run index, 0-based.
    #[serde(skip)]
    pub run: u32,
    /// The receiver's dwell part.
    pub dwell_id: u64,
    /// Dwell mid-time, when truth was evaluated (s since scenario start).
    pub t_s: f64,
    /// Receiving radar.
    pub rx: RadarId,
    /// Transmitting radar (equal to `rx` for the monostatic channel).
    pub tx: RadarId,
    /// Receiver face the (u, v) refer to.
    pub rx_face: u8,
    /// Peak cell index.
    pub range_cell: i64,
    /// Centroided equivalent monostatic range ρ = R_B/2 (m).
    pub range_m: f64,
    /// Estimated direction cosine u (face's horizontal axis) in the receiver face.
    pub u: f64,
    /// Estimated direction cosine v (face-up axis) in the receiver face.
    pub v: f64,
    /// Observed sum-channel SNR S = Σ|Σ_k|² over the cells used (dB).
    pub snr_db: f64,
    /// Imaginary-part statistic T = η_Qa²/var_a + η_Qe²/var_e (χ²₂ for one target).
    pub eta_q: f64,
    /// Flagged as possibly two unresolved targets in one beam and cell (docs/model.md §2.7).
    pub merged: bool,
    /// Beam steering direction of the receiver (sine space), so the monopulse ratio can be
    /// recovered offline.
    pub beam_u: f64,
    /// Receiver beam steering direction cosine v (sine space).
    pub beam_v: f64,
    /// Variances of this primitive's estimates, from the observed SNR (docs/model.md §2.6, §4.6).
    pub var_range_m2: f64,
    /// Variance of `u` (dimensionless, sine space).
    pub var_u: f64,
    /// Variance of `v` (dimensionless, sine space).
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
    /// Monte Carlo run index, 0-based.
    #[serde(skip)]
    pub run: u32,
    /// Measurement id, unique within a run; ids of dwell group `g` start at `g << 12`.
    pub meas_id: u64,
    /// The receiver's dwell part (`DwellRow::dwell_id`).
    pub dwell_id: u64,
    /// Dwell mid-time, when truth was evaluated (s since scenario start).
    pub t_s: f64,
    /// Receiving radar.
    pub rx: RadarId,
    /// Transmitting radar (equal to `rx` for a monostatic measurement).
    pub tx: RadarId,
    /// Receiver face the (u, v) refer to (0-based).
    pub rx_face: u8,
    /// Equivalent monostatic range ρ = (R_t + R_r)/2 (m).
    pub range_m: f64,
    /// Direction cosine u (face's horizontal axis) in the receiver face.
    pub u: f64,
    /// Direction cosine v (face-up axis) in the receiver face.
    pub v: f64,
    /// Observed sum-channel SNR of the strongest primitive of the cluster (dB).
    pub snr_db: f64,
    /// Variance of `range_m` (m²).
    pub var_range_m2: f64,
    /// Variance of `u` (dimensionless, sine space).
    pub var_u: f64,
    /// Variance of `v` (dimensionless, sine space).
    pub var_v: f64,
    /// Number of primitives clustered into this measurement.
    pub n_primitives: u32,
    /// Possibly unresolved targets: set when any primitive of the cluster is merged.
    pub merged: bool,
    /// Truth id of the dominant contributor; `None` for false alarms. Never shown to a tracker.
    #[serde(skip)]
    pub target_hint: Option<String>,
}

/// Track status.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TrackStatus {
    /// Started, not yet confirmed (the default tracker confirms by M-of-N, docs/model.md §6.4).
    Tentative,
    /// Confirmed: scoring counts a track from its first confirmed row on (docs/design.md §6).
    Confirmed,
    /// Ended: the track's last row, written once.
    Deleted,
}

impl TrackStatus {
    /// Every on-disk label, in declaration order (the values the table's column may hold).
    pub const LABELS: [&'static str; 3] = ["tentative", "confirmed", "deleted"];
    /// The on-disk string: `tentative`, `confirmed` or `deleted`.
    pub fn as_str(self) -> &'static str {
        match self {
            TrackStatus::Tentative => "tentative",
            TrackStatus::Confirmed => "confirmed",
            TrackStatus::Deleted => "deleted",
        }
    }
    /// The status written as `s`; `None` for any string but `tentative`, `confirmed`, `deleted`.
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
    /// Monte Carlo run index, 0-based.
    #[serde(skip)]
    pub run: u32,
    /// Time of the state (s since scenario start).
    pub t_s: f64,
    /// Track id, unique within a run.
    pub track_id: u64,
    /// Track status at this row.
    pub status: TrackStatus,
    /// Estimated position, ECEF x (m).
    pub x_m: f64,
    /// Estimated position, ECEF y (m).
    pub y_m: f64,
    /// Estimated position, ECEF z (m).
    pub z_m: f64,
    /// Estimated velocity, ECEF x (m/s).
    pub vx_mps: f64,
    /// Estimated velocity, ECEF y (m/s).
    pub vy_mps: f64,
    /// Estimated velocity, ECEF z (m/s).
    pub vz_mps: f64,
    /// Upper triangle of the 6×6 ECEF position–velocity covariance, row-major (21 values).
    pub cov: [f64; 21],
    /// Measurement updates so far.
    pub n_updates: u32,
    /// Last measurement used (`MeasurementRow::meas_id`); `None` if none.
    pub last_meas_id: Option<u64>,
}

/// Every table of one Monte Carlo run, in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunTables {
    /// Rows of the `truth` table.
    pub truth: Vec<TruthRow>,
    /// Rows of the `dwells` table.
    pub dwells: Vec<DwellRow>,
    /// Rows of the `voltages` table (empty unless voltages are recorded).
    pub voltages: Vec<VoltageRow>,
    /// Rows of the `primitives` table.
    pub primitives: Vec<PrimitiveRow>,
    /// Rows of the `measurements` table.
    pub measurements: Vec<MeasurementRow>,
    /// Rows of the `tracks` table.
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
        // The label lists are the parsers' languages, in order.
        assert_eq!(Role::LABELS.map(|l| Role::parse(l).map(Role::as_str)), Role::LABELS.map(Some));
        assert_eq!(DwellKind::LABELS.map(|l| DwellKind::parse(l).map(DwellKind::as_str)), DwellKind::LABELS.map(Some));
        assert_eq!(Requester::LABELS.map(|l| Requester::parse(l).map(Requester::as_str)), Requester::LABELS.map(Some));
        assert_eq!(
            TrackStatus::LABELS.map(|l| TrackStatus::parse(l).map(TrackStatus::as_str)),
            TrackStatus::LABELS.map(Some)
        );
    }
}
