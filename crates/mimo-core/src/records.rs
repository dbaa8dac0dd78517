//! Row records of the run tables (docs/design.md §3).
//!
//! Each table is declared once here (a `macro_rules!` declaration, [`crate::table_decl`]): its
//! record struct, column names, units, meanings and rules. Expanded here, a declaration gives
//! plain structs that simulation, radar and tracking code produce without knowing about Arrow or
//! Parquet; expanded in `mimo-store`, the same declaration gives the Arrow schema (with units in
//! the field metadata), the conversions to record batches and back, and `schemas/`.
//!
//! Positions and velocities are ECEF (m, m/s) unless a name says otherwise; times are seconds since
//! scenario start. Radar ids are [`RadarId`] here and the strings `R1`…`R4` on disk.

use serde::{Deserialize, Serialize};

/// The `truth` table, declared once (see [`crate::table_decl`]): hands its columns to `$gen`.
#[macro_export]
macro_rules! truth_table {
    ($gen:path) => {
        $crate::table_decl! { $gen;
            /// One target at one truth sample.
            #[derive(Debug, Clone, PartialEq)]
            pub struct TruthRow / TruthColumns in TRUTH = "truth": "One row per target per truth sample (default 10 Hz)." {
                /// Monte Carlo run index, 0-based.
                run: u32 => ("", "Monte Carlo run index"),
                /// Sample time since scenario start (s).
                t_s: f64 => ("s", "time since scenario start", NonNegative) as Split + PageStats,
                /// Target id (`F-1`…`F-4`, `A`, `B`, `C` in the standard scenarios).
                target: String => ("", "target id (F-1…F-4, A, B, C in the standard scenarios)"),
                /// Target position, ECEF x (m).
                x_m: f64 => ("m", "ECEF x position") as Uncompressed,
                /// Target position, ECEF y (m).
                y_m: f64 => ("m", "ECEF y position") as Uncompressed,
                /// Target position, ECEF z (m).
                z_m: f64 => ("m", "ECEF z position") as Uncompressed,
                /// Target velocity, ECEF x (m/s).
                vx_mps: f64 => ("m/s", "ECEF x velocity") as Uncompressed,
                /// Target velocity, ECEF y (m/s).
                vy_mps: f64 => ("m/s", "ECEF y velocity") as Uncompressed,
                /// Target velocity, ECEF z (m/s).
                vz_mps: f64 => ("m/s", "ECEF z velocity") as Uncompressed,
                /// Target WGS-84 geodetic latitude (deg).
                lat_deg: f64 => ("deg", "WGS-84 geodetic latitude") as Uncompressed,
                /// Target WGS-84 geodetic longitude (deg, east positive).
                lon_deg: f64 => ("deg", "WGS-84 geodetic longitude") as Uncompressed,
                /// Target height above the WGS-84 ellipsoid (m).
                alt_m: f64 => ("m", "height above the WGS-84 ellipsoid"),
                /// Mean radar cross-section (m²).
                rcs_m2: f64 => ("m^2", "mean radar cross-section"),
            }
        }
    };
}
truth_table!(crate::record_struct);

crate::label_enum! {
    /// A radar's part in a dwell.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
    #[serde(rename_all = "lowercase")]
    pub enum Role {
        /// Transmit only (MIMO transmitter that does not receive).
        Tx = "tx",
        /// Receive only: costs no energy.
        Rx = "rx",
        /// Transmit and receive.
        Txrx = "txrx",
    }
}

impl Role {
    /// Does this role transmit (and so cost energy and dwell time)?
    pub fn transmits(self) -> bool {
        !matches!(self, Role::Rx)
    }
}

crate::label_enum! {
    /// Why a dwell was made.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
    #[serde(rename_all = "lowercase")]
    pub enum DwellKind {
        /// Background search raster (docs/model.md §7.4), or search requested by a test article.
        Search = "search",
        /// Confirmation look at a tentative track (M-of-N, docs/model.md §6.4).
        Confirm = "confirm",
        /// Update look at a track.
        Track = "track",
        /// MIMO dwell: several radars steer at one aim point, each transmitter with its own orthogonal
        /// waveform, each receiver with one matched filter per transmitter (docs/model.md §5).
        Mimo = "mimo",
    }
}

crate::label_enum! {
    /// Who asked for a dwell: the radar's own background search, or the test article.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
    #[serde(rename_all = "lowercase")]
    pub enum Requester {
        /// The radar's own background search.
        Radar = "radar",
        /// The test article.
        Ta = "ta",
    }
}

/// The `dwells` table, declared once (see [`crate::table_decl`]): hands its columns to `$gen`.
#[macro_export]
macro_rules! dwells_table {
    ($gen:path) => {
        $crate::table_decl! { $gen;
            /// One radar's part in one dwell.
            #[derive(Debug, Clone, PartialEq)]
            pub struct DwellRow / DwellColumns in DWELLS = "dwells":
                "One row per radar's part in one dwell; the radars of one MIMO dwell share group_id." {
                /// Monte Carlo run index, 0-based.
                run: u32 => ("", "Monte Carlo run index"),
                /// Unique within a run per (dwell, radar) part.
                dwell_id: u64 => ("", "id of this radar's part in the dwell, unique within a run") as Delta,
                /// Shared by all radars of one (MIMO) dwell; equals `dwell_id` of the first part.
                group_id: u64 => ("", "id shared by all radars of one (MIMO) dwell") as Delta,
                /// The radar this part belongs to (`R1`…`R4` on disk).
                radar: $crate::ids::RadarId => ("", "radar id R1…R4"),
                /// Whether this radar transmits, receives or both in the dwell.
                role: $crate::records::Role => ("", "tx, rx or txrx"),
                /// Why the dwell was made (search, confirm, track, mimo).
                kind: $crate::records::DwellKind => ("", "search, confirm, track or mimo"),
                /// Who asked for the dwell: the radar's background search or the test article.
                requested_by: $crate::records::Requester => ("", "radar (own background search) or ta (test article)"),
                /// Start time (s).
                t_s: f64 => ("s", "dwell start time", NonNegative) as Split + PageStats,
                /// Time the radar's timeline is occupied, τ_dwell (s).
                duration_s: f64 => ("s", "timeline occupancy τ_dwell", NonNegative),
                /// Pulse width τ_pw (s).
                pulse_width_s: f64 => ("s", "pulse width τ_pw"),
                /// Pulses integrated coherently.
                n_pulses: u32 => ("", "pulses integrated coherently"),
                /// Peak transmit power (W).
                peak_power_w: f64 => ("W", "peak transmit power"),
                /// Emitted energy = peak_power_w · pulse_width_s · n_pulses; 0 for `rx`.
                energy_j: f64 => ("J", "emitted energy peak_power_w·pulse_width_s·n_pulses (0 for rx)", NonNegative),
                /// Orthogonal waveform (code) index transmitted; receivers list 0.
                waveform: u32 => ("", "orthogonal waveform (code) index transmitted"),
                /// Array face used (0-based).
                face: u8 => ("", "array face used (0-based)"),
                /// Beam steering direction in the face's sine space.
                beam_u: f64 => ("", "beam steering direction cosine u in the face frame"),
                /// Beam steering direction cosine v (face-up axis) in the face frame.
                beam_v: f64 => ("", "beam steering direction cosine v in the face frame"),
                /// Aim point (ECEF, m).
                aim_x_m: f64 => ("m", "aim point ECEF x") as Split,
                /// Aim point, ECEF y (m).
                aim_y_m: f64 => ("m", "aim point ECEF y") as Split,
                /// Aim point, ECEF z (m).
                aim_z_m: f64 => ("m", "aim point ECEF z") as Split,
            }
        }
    };
}
dwells_table!(crate::record_struct);

/// The `voltages` table, declared once (see [`crate::table_decl`]): hands its columns to `$gen`.
#[macro_export]
macro_rules! voltages_table {
    ($gen:path) => {
        $crate::table_decl! { $gen;
            /// Complex voltages of one receive channel (matched filter for one transmitter) in one range
            /// cell, normalized so that the noise is CN(0, 1) in every channel; written only with
            /// `--record voltages`.
            #[derive(Debug, Clone, PartialEq)]
            pub struct VoltageRow / VoltageColumns in VOLTAGES = "voltages":
                "Complex voltages per receive channel per range cell per dwell (only with --record voltages); noise is CN(0,1)." {
                /// Monte Carlo run index, 0-based.
                run: u32 => ("", "Monte Carlo run index"),
                /// The receiver's dwell part (`DwellRow::dwell_id`).
                dwell_id: u64 => ("", "receiver's dwell part") as Delta,
                /// Receiving radar.
                rx: $crate::ids::RadarId => ("", "receiving radar"),
                /// Transmitting radar whose waveform this channel's matched filter is for.
                tx: $crate::ids::RadarId => ("", "transmitting radar (matched filter)"),
                /// Range cell index k; the cell centre is at ρ_k = k·ΔR (docs/model.md §4.1).
                range_cell: i64 => ("", "cell index k, ρ_k = k·δs"),
                /// Equivalent monostatic range of the cell centre, ρ = R_B/2 (m).
                range_m: f64 => ("m", "equivalent monostatic range ρ = R_B/2 of the cell"),
                /// Sum channel, in-phase part (√SNR units: noise is CN(0, 1)).
                sum_i: f64 => ("", "sum channel in-phase (√SNR units)"),
                /// Sum channel, quadrature part (√SNR units).
                sum_q: f64 => ("", "sum channel quadrature"),
                /// Azimuth-difference (u) channel, in-phase part (√SNR units).
                az_i: f64 => ("", "azimuth-difference channel in-phase"),
                /// Azimuth-difference (u) channel, quadrature part (√SNR units).
                az_q: f64 => ("", "azimuth-difference channel quadrature"),
                /// Elevation-difference (v) channel, in-phase part (√SNR units).
                el_i: f64 => ("", "elevation-difference channel in-phase"),
                /// Elevation-difference (v) channel, quadrature part (√SNR units).
                el_q: f64 => ("", "elevation-difference channel quadrature"),
            }
        }
    };
}
voltages_table!(crate::record_struct);

/// The `primitives` table, declared once (see [`crate::table_decl`]): hands its columns to `$gen`.
#[macro_export]
macro_rules! primitives_table {
    ($gen:path) => {
        $crate::table_decl! { $gen;
            /// A threshold crossing after monopulse DOA estimation.
            ///
            /// Serialized (for the test-article protocol) without `run` and `target_hint`, which the engine fills in.
            #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
            #[serde(deny_unknown_fields)]
            pub struct PrimitiveRow / PrimitiveColumns in PRIMITIVES = "primitives":
                "One row per threshold crossing (local maximum) after ML monopulse DOA." {
                /// Monte Carlo run index, 0-based.
                #[serde(skip)]
                run: u32 => ("", "Monte Carlo run index"),
                /// The receiver's dwell part.
                dwell_id: u64 => ("", "receiver's dwell part") as Delta,
                /// Dwell mid-time, when truth was evaluated (s since scenario start).
                t_s: f64 => ("s", "dwell time", NonNegative) as Split + PageStats,
                /// Receiving radar.
                rx: $crate::ids::RadarId => ("", "receiving radar"),
                /// Transmitting radar (equal to `rx` for the monostatic channel).
                tx: $crate::ids::RadarId => ("", "transmitting radar"),
                /// Receiver face the (u, v) refer to.
                rx_face: u8 => ("", "receiver face the (u, v) refer to"),
                /// Peak cell index.
                range_cell: i64 => ("", "peak cell index"),
                /// Centroided equivalent monostatic range ρ = R_B/2 (m).
                range_m: f64 => ("m", "centroided equivalent monostatic range ρ = R_B/2") as Uncompressed,
                /// Estimated direction cosine u (face's horizontal axis) in the receiver face.
                u: f64 => ("", "estimated direction cosine u (receiver face)") as Uncompressed,
                /// Estimated direction cosine v (face-up axis) in the receiver face.
                v: f64 => ("", "estimated direction cosine v (receiver face)") as Uncompressed,
                /// Observed sum-channel SNR S = Σ|Σ_k|² over the cells used (dB).
                snr_db: f64 => ("dB", "observed sum-channel SNR over the cells used") as Uncompressed,
                /// Imaginary-part statistic T = η_Qa²/var_a + η_Qe²/var_e (χ²₂ for one target).
                eta_q: f64 => ("", "imaginary-part monopulse statistic T (χ²₂ for one target)") as Uncompressed,
                /// Flagged as possibly two unresolved targets in one beam and cell (docs/model.md §2.7).
                merged: bool => ("", "flagged as possibly unresolved (merged) targets"),
                /// Beam steering direction of the receiver (sine space), so the monopulse ratio can be
                /// recovered offline.
                beam_u: f64 => ("", "receiver beam steering u"),
                /// Receiver beam steering direction cosine v (sine space).
                beam_v: f64 => ("", "receiver beam steering v"),
                /// Variances of this primitive's estimates, from the observed SNR (docs/model.md §2.6, §4.6).
                var_range_m2: f64 => ("m^2", "variance of range_m", Positive),
                /// Variance of `u` (dimensionless, sine space).
                var_u: f64 => ("", "variance of u", Positive) as Uncompressed,
                /// Variance of `v` (dimensionless, sine space).
                var_v: f64 => ("", "variance of v", Positive) as Uncompressed,
                /// Truth id of the dominant contributor (evaluation only).
                #[serde(skip)]
                target_hint: Option<String> =>
                    ("", "truth id of the dominant contributor (evaluation only); null for false alarms"),
            }
        }
    };
}
primitives_table!(crate::record_struct);

/// The `measurements` table, declared once (see [`crate::table_decl`]): hands its columns to `$gen`.
#[macro_export]
macro_rules! measurements_table {
    ($gen:path) => {
        $crate::table_decl! { $gen;
            /// A clustered, centroided detection handed to trackers.
            ///
            /// Serialized (for the test-article protocol) without `run` and `target_hint`, which the engine fills in.
            #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
            #[serde(deny_unknown_fields)]
            pub struct MeasurementRow / MeasurementColumns in MEASUREMENTS = "measurements":
                "One row per clustered, centroided detection handed to trackers." {
                /// Monte Carlo run index, 0-based.
                #[serde(skip)]
                run: u32 => ("", "Monte Carlo run index"),
                /// Measurement id, unique within a run; ids of dwell group `g` start at `g << 12`.
                meas_id: u64 => ("", "measurement id, unique within a run") as Delta,
                /// The receiver's dwell part (`DwellRow::dwell_id`).
                dwell_id: u64 => ("", "receiver's dwell part") as Delta,
                /// Dwell mid-time, when truth was evaluated (s since scenario start).
                t_s: f64 => ("s", "dwell time", NonNegative) as Split + PageStats,
                /// Receiving radar.
                rx: $crate::ids::RadarId => ("", "receiving radar"),
                /// Transmitting radar (equal to `rx` for a monostatic measurement).
                tx: $crate::ids::RadarId => ("", "transmitting radar"),
                /// Receiver face the (u, v) refer to (0-based).
                rx_face: u8 => ("", "receiver face the (u, v) refer to"),
                /// Equivalent monostatic range ρ = (R_t + R_r)/2 (m).
                range_m: f64 => ("m", "equivalent monostatic range ρ = (R_t+R_r)/2") as Uncompressed,
                /// Direction cosine u (face's horizontal axis) in the receiver face.
                u: f64 => ("", "direction cosine u (receiver face)") as Uncompressed,
                /// Direction cosine v (face-up axis) in the receiver face.
                v: f64 => ("", "direction cosine v (receiver face)") as Uncompressed,
                /// Observed sum-channel SNR of the strongest primitive of the cluster (dB).
                snr_db: f64 => ("dB", "observed SNR") as Uncompressed,
                /// Variance of `range_m` (m²).
                var_range_m2: f64 => ("m^2", "variance of range_m", Positive),
                /// Variance of `u` (dimensionless, sine space).
                var_u: f64 => ("", "variance of u", Positive) as Uncompressed,
                /// Variance of `v` (dimensionless, sine space).
                var_v: f64 => ("", "variance of v", Positive) as Uncompressed,
                /// Number of primitives clustered into this measurement.
                n_primitives: u32 => ("", "primitives merged into this measurement"),
                /// Possibly unresolved targets: set when any primitive of the cluster is merged.
                merged: bool => ("", "possibly unresolved targets"),
                /// Truth id of the dominant contributor; `None` for false alarms. Never shown to a tracker.
                #[serde(skip)]
                target_hint: Option<String> =>
                    ("", "truth id of the dominant contributor; null for false alarms (evaluation only)"),
            }
        }
    };
}
measurements_table!(crate::record_struct);

crate::label_enum! {
    /// Track status.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
    #[serde(rename_all = "lowercase")]
    pub enum TrackStatus {
        /// Started, not yet confirmed (the default tracker confirms by M-of-N, docs/model.md §6.4).
        Tentative = "tentative",
        /// Confirmed: scoring counts a track from its first confirmed row on (docs/design.md §6).
        Confirmed = "confirmed",
        /// Ended: the track's last row, written once.
        Deleted = "deleted",
    }
}

/// The `tracks` table, declared once (see [`crate::table_decl`]): hands its columns to `$gen`.
#[macro_export]
macro_rules! tracks_table {
    ($gen:path) => {
        $crate::table_decl! { $gen;
            /// A track's state at an update (or the final `deleted` row).
            ///
            /// Serialized (for the test-article protocol) without `run`, which the engine fills in.
            #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
            #[serde(deny_unknown_fields)]
            pub struct TrackRow / TrackColumns in TRACKS = "tracks":
                "Track state at each update, plus one row when the track ends (status deleted)." {
                /// Monte Carlo run index, 0-based.
                #[serde(skip)]
                run: u32 => ("", "Monte Carlo run index"),
                /// Time of the state (s since scenario start).
                t_s: f64 => ("s", "time of the state", NonNegative) as Split + PageStats,
                /// Track id, unique within a run.
                track_id: u64 => ("", "track id, unique within a run"),
                /// Track status at this row.
                status: $crate::records::TrackStatus => ("", "tentative, confirmed or deleted"),
                /// Estimated position, ECEF x (m).
                x_m: f64 => ("m", "ECEF x position"),
                /// Estimated position, ECEF y (m).
                y_m: f64 => ("m", "ECEF y position"),
                /// Estimated position, ECEF z (m).
                z_m: f64 => ("m", "ECEF z position"),
                /// Estimated velocity, ECEF x (m/s).
                vx_mps: f64 => ("m/s", "ECEF x velocity"),
                /// Estimated velocity, ECEF y (m/s).
                vy_mps: f64 => ("m/s", "ECEF y velocity"),
                /// Estimated velocity, ECEF z (m/s).
                vz_mps: f64 => ("m/s", "ECEF z velocity"),
                /// Upper triangle of the 6×6 ECEF position–velocity covariance, row-major (21 values).
                cov: [f64; 21] => (
                    "m^2, m^2/s, m^2/s^2",
                    "upper triangle of the 6×6 ECEF position-velocity covariance, row-major"
                ),
                /// Measurement updates so far.
                n_updates: u32 => ("", "measurement updates so far"),
                /// Last measurement used (`MeasurementRow::meas_id`); `None` if none.
                last_meas_id: Option<u64> => ("", "last measurement used; null if none"),
            }
        }
    };
}
tracks_table!(crate::record_struct);

/// The `biases` table, declared once (see [`crate::table_decl`]): hands its columns to `$gen`.
#[macro_export]
macro_rules! biases_table {
    ($gen:path) => {
        $crate::table_decl! { $gen;
            /// One radar's registration biases in one run, as drawn or set (docs/model.md §5.5).
            #[derive(Debug, Clone, PartialEq)]
            pub struct BiasRow / BiasColumns in BIASES = "biases":
                "One row per radar: the registration biases its measurements carried in the run (only with [biases] on)." {
                /// Monte Carlo run index, 0-based.
                run: u32 => ("", "Monte Carlo run index"),
                /// The radar (`R1`…`R4` on disk).
                radar: $crate::ids::RadarId => ("", "radar id R1…R4"),
                /// Range bias (m); a bistatic ρ carries half the sum of its two radars'.
                range_m: f64 => ("m", "range bias; a bistatic rho carries half the sum of both radars'"),
                /// Bias of the direction cosine u of the radar's receiving faces.
                u: f64 => ("", "bias of the measured direction cosine u"),
                /// Bias of the direction cosine v of the radar's receiving faces.
                v: f64 => ("", "bias of the measured direction cosine v"),
                /// Heading bias (deg, clockwise): a target at azimuth A is reported at A + heading_deg.
                heading_deg: f64 => ("deg", "heading bias, clockwise: azimuth A is reported at A + heading_deg"),
            }
        }
    };
}
biases_table!(crate::record_struct);

/// The `registration` table, declared once (see [`crate::table_decl`]): hands its columns to `$gen`.
#[macro_export]
macro_rules! registration_table {
    ($gen:path) => {
        $crate::table_decl! { $gen;
            /// A test article's estimate of one radar's registration biases (docs/model.md §6.9),
            /// with the 4 × 4 block of its covariance that belongs to the radar.
            ///
            /// Serialized (for the test-article protocol) without `run`, which the engine fills in.
            #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
            #[serde(deny_unknown_fields)]
            pub struct RegistrationRow / RegistrationColumns in REGISTRATION = "registration":
                "One row per radar and report: a test article's estimate of the radar's registration biases and its covariance." {
                /// Monte Carlo run index, 0-based.
                #[serde(skip)]
                run: u32 => ("", "Monte Carlo run index"),
                /// Time of the estimate (s since scenario start).
                t_s: f64 => ("s", "time of the estimate", NonNegative),
                /// The radar (`R1`…`R4` on disk).
                radar: $crate::ids::RadarId => ("", "radar id R1…R4"),
                /// Estimated range bias (m).
                range_m: f64 => ("m", "estimated range bias"),
                /// Estimated bias of the direction cosine u.
                u: f64 => ("", "estimated bias of the direction cosine u"),
                /// Estimated bias of the direction cosine v.
                v: f64 => ("", "estimated bias of the direction cosine v"),
                /// Estimated heading bias (deg, clockwise).
                heading_deg: f64 => ("deg", "estimated heading bias, clockwise"),
                /// Variance of `range_m` (m²).
                var_range_m2: f64 => ("m^2", "variance of range_m", Positive),
                /// Variance of `u`.
                var_u: f64 => ("", "variance of u", Positive),
                /// Variance of `v`.
                var_v: f64 => ("", "variance of v", Positive),
                /// Variance of `heading_deg` (deg²).
                var_heading_deg2: f64 => ("deg^2", "variance of heading_deg", Positive),
                /// Covariance of `range_m` and `u` (m).
                cov_range_u_m: f64 => ("m", "covariance of range_m and u"),
                /// Covariance of `range_m` and `v` (m).
                cov_range_v_m: f64 => ("m", "covariance of range_m and v"),
                /// Covariance of `range_m` and `heading_deg` (m·deg).
                cov_range_heading_m_deg: f64 => ("m deg", "covariance of range_m and heading_deg"),
                /// Covariance of `u` and `v`.
                cov_u_v: f64 => ("", "covariance of u and v"),
                /// Covariance of `u` and `heading_deg` (deg).
                cov_u_heading_deg: f64 => ("deg", "covariance of u and heading_deg"),
                /// Covariance of `v` and `heading_deg` (deg).
                cov_v_heading_deg: f64 => ("deg", "covariance of v and heading_deg"),
                /// Looks the estimate has learnt from so far.
                looks: u64 => ("", "looks the estimate has learnt from so far"),
            }
        }
    };
}
registration_table!(crate::record_struct);

impl RegistrationRow {
    /// The estimate as a bias.
    pub fn bias(&self) -> crate::registration::RadarBias {
        crate::registration::RadarBias { range_m: self.range_m, u: self.u, v: self.v, heading_deg: self.heading_deg }
    }

    /// The 4 × 4 covariance of (range, u, v, heading), in the table's units.
    pub fn covariance(&self) -> [[f64; 4]; 4] {
        let (a, b, c, d) = (self.cov_range_u_m, self.cov_range_v_m, self.cov_range_heading_m_deg, self.cov_u_v);
        let (e, f) = (self.cov_u_heading_deg, self.cov_v_heading_deg);
        [[self.var_range_m2, a, b, c], [a, self.var_u, d, e], [b, d, self.var_v, f], [c, e, f, self.var_heading_deg2]]
    }
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
    /// Rows of the `biases` table (empty unless registration biases are on).
    pub biases: Vec<BiasRow>,
    /// Rows of the `registration` table (a test article's bias estimates, if it reports any).
    pub registration: Vec<RegistrationRow>,
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
