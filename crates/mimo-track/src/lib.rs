//! # mimo-track
//!
//! Tracking components for `mimo`, in the spirit of Stone Soup: one small trait per component
//! family, the built-in implementations, and trackers composed from them. Configuration is plain
//! serde structs whose every field has a documented default ([`TrackerConfig`]). The physics and
//! parameter choices follow docs/model.md §5.4 (measurement model), §6 (tracking) and §7 (revisit
//! and energy).
//!
//! ## Frames
//!
//! Tracks live in one fixed ENU frame at the scenario centre ([`frame::TrackFrame`]); state
//! `x = [p; v]` (m, m/s). Radar sites and faces are converted into it when a measurement is used.
//! Everything the tracker hands out ([`TrackRow`](mimo_core::records::TrackRow),
//! [`frame::StateEcef`]) is ECEF, with the 6×6 covariance rotated and packed as the 21-element
//! upper triangle.
//!
//! ## Component families
//!
//! | family | trait | implementations |
//! |---|---|---|
//! | sensor geometry (caller-supplied) | [`geometry::SensorGeometry`] | [`geometry::StaticGeometry`] |
//! | measurement model | [`measurement::MeasurementModel`] | [`measurement::BistaticRuv`] (R_B, u, v; analytic Jacobian and ruv→cart), [`measurement::PositionMeasurement`] |
//! | motion model | [`motion::MotionModel`] | [`motion::Ncv`] (DWNA/CWNA), [`motion::HorizontalTurn`] |
//! | predictor | [`motion::Predictor`] | [`motion::KalmanPredictor`] |
//! | updater | [`update::Updater`] | [`update::EkfUpdater`] (Joseph form, Cholesky gain, PD repair, iterated) |
//! | filter (predictor + updater per track) | [`filter::TrackFilter`] | [`filter::SingleModelFilter`] (EKF), [`filter::ImmFilter`] |
//! | gater | [`gating::Gater`] | [`gating::ChiSquareGate`] (NIS ≤ 11.34 / 16.27) |
//! | associator | [`association::Associator`] | [`association::GnnAssociator`] (exact, NIS or likelihood cost), [`association::GreedyAssociator`], [`jpda::JpdaAssociator`] (soft, marginal probabilities) |
//! | initiator | [`initiation::Initiator`] | [`initiation::OnePointInitiator`], [`initiation::TwoPointInitiator`] |
//! | confirmer | [`initiation::Confirmer`] | [`initiation::MOfN`] |
//! | deleter | [`deletion::Deleter`] | [`deletion::MissCountDeleter`], [`deletion::CovarianceDeleter`], [`deletion::CoastDeleter`], [`deletion::AnyDeleter`] |
//! | policy (pure functions for the scheduler) | — | [`policy::revisit_interval`], [`policy::due_tracks`], [`policy::pulses_required`] |
//!
//! ## The multi-target tracker
//!
//! [`MultiTargetTracker`] runs one dwell at a time ([`MultiTargetTracker::process_dwell`]):
//!
//! 1. Measurement rows are validated (bad rows are skipped and counted, never a panic) and put in
//!    the tracking frame as `z = (R_B = 2ρ, u, v)` with `R = diag(4σ_ρ², σ_u², σ_v²)`,
//!    inflated for `merged` rows (docs/model.md §2.7).
//! 2. Per receive channel (tx, rx), in a fixed order: every track is predicted to the
//!    measurement time, gated on its NIS (pairs that cannot gate are recognised first from a
//!    bound and skipped, with the same result), and the channel's measurements are assigned by GNN
//!    (exact assignment with a miss option); a `merged` measurement may also update a gated
//!    track that GNN left empty. Assigned tracks are updated (iterated EKF for the first
//!    updates). With `association_method = jpda` ([`jpda`]) each track is instead updated with
//!    every gated measurement, weighted by its marginal association probability. Detections
//!    outside every gate and every track's resolution cell start tentative tracks (search
//!    dwells and monostatic channels).
//! 3. Every track the dwell looked at (`DwellContext::target_tracks`, or inside a non-search
//!    beam listed in `DwellContext::looks`) counts a hit or a miss. Tentative tracks are confirmed
//!    or dropped by M-of-N; confirmed tracks count consecutive misses.
//! 4. The deleter ends tracks (misses, covariance growth, coasting) with one `deleted` row each.
//!
//! It returns one [`TrackRow`](mimo_core::records::TrackRow) per track updated or started in the
//! dwell and one `deleted` row per track ended. All state is in ordered maps and vectors; the
//! result never depends on hash order or on the order of the input rows.
//!
//! The scheduler (in `mimo-sim`) asks the tracker for predictions
//! ([`MultiTargetTracker::predict`], [`MultiTargetTracker::predict_measurement_of`]), revisit
//! intervals ([`MultiTargetTracker::revisit_interval`]), due tracks
//! ([`MultiTargetTracker::due_tracks`]) and track snapshots ([`MultiTargetTracker::tracks`]).
//! Every update's NIS is logged ([`MultiTargetTracker::nis_log`]) for consistency checks.
//!
//! ```
//! use mimo_core::geo::Geodetic;
//! use mimo_core::ids::RadarId;
//! use mimo_core::params::RadarParams;
//! use mimo_core::records::MeasurementRow;
//! use mimo_track::{DwellContext, MultiTargetTracker, geometry::StaticGeometry};
//!
//! let centre = Geodetic::from_deg(36.0, -70.0, 0.0);
//! let mut geom = StaticGeometry::new();
//! geom.add_ship(RadarId(0), Geodetic::from_deg(36.0, -70.0, 20.0), 0.0, &RadarParams::default());
//! let mut tracker = MultiTargetTracker::by_name("imm", centre).expect("known tracker");
//!
//! // A search detection on R1, face 0: 80 km out, a little off boresight.
//! let row = MeasurementRow {
//!     run: 0, meas_id: 1, dwell_id: 10, t_s: 5.0, rx: RadarId(0), tx: RadarId(0), rx_face: 0,
//!     range_m: 80_000.0, u: 0.05, v: -0.02, snr_db: 22.0, var_range_m2: 9.0,
//!     var_u: 1e-6, var_v: 1e-6, n_primitives: 2, merged: false, target_hint: None,
//! };
//! let rows = tracker.process_dwell(&DwellContext::search(0, 10, 5.0), &[row], &geom);
//! assert_eq!(rows.len(), 1); // a new tentative track
//! let id = rows[0].track_id;
//! // The scheduler asks where to look next, and when.
//! let predicted = tracker.predict(id, 5.3).expect("live track");
//! assert!(predicted.pos.is_finite());
//! assert_eq!(tracker.due_tracks(5.3, 0.0), vec![id]);
//! ```
//!
//! ## Composing your own tracker
//!
//! Build a [`Components`] (e.g. start from [`Components::from_config`] and swap the associator
//! for a [`association::GreedyAssociator`], or the filter for an IMM with turn modes) and pass
//! it to [`MultiTargetTracker::with_components`]. Each family is a small object-safe trait, so
//! a new filter, gate or deletion rule is one `impl` away.

#![warn(missing_docs)]

pub mod association;
mod channel;
pub mod components;
pub mod config;
mod cv_sandwich;
pub mod deletion;
mod deletion_quiet;
pub mod diagnostics;
pub mod dwell;
mod dwell_predictions;
pub mod filter;
pub mod frame;
pub mod gating;
pub mod geometry;
pub mod group;
mod imm;
pub mod initiation;
pub mod initiation_evidence;
pub mod jpda;
pub mod linalg;
pub mod measurement;
pub mod motion;
pub mod partner;
pub mod policy;
pub mod position_ball;
mod pregate;
mod queries;
mod quiet_expiry;
mod reached;
pub mod second_return;
mod state_stamp;
mod track_balls;
pub mod tracker;
#[cfg(test)]
mod tracker_expiry_tests;
pub mod update;

pub use components::Components;
pub use config::{
    AssociationMethod, ImmConfig, InitiateOn, InitiationExclusion, InitiatorConfig, JpdaLimits, TrackerConfig,
    TrackerConfigError, TrackerKind,
};
pub use diagnostics::{NisRecord, PredictedMeasurement, TrackInfo, TrackerStats};
pub use dwell::{DwellContext, Look};
pub use frame::{Gaussian, StateEcef, TrackFrame};
pub use geometry::{SensorGeometry, StaticGeometry};
pub use queries::TrackDue;
pub use tracker::{MultiTargetTracker, Track};
