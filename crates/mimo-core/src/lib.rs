//! # mimo-core
//!
//! The vocabulary every other `mimo` crate shares, with no I/O and no heavy dependencies:
//!
//! * [`geo`]: WGS-84 geodetic ⇄ ECEF, the local ENU rotation, the 4/3-earth horizon
//!   (docs/model.md §1.1, §1.2, §1.7).
//! * [`face`]: array-face frames and sine space (docs/model.md §1.3–§1.5).
//! * [`rng`]: counter-keyed random streams. Every draw in the simulator comes from a stream keyed
//!   by `(seed, run, radar, dwell, …)`, never from a shared generator, so results do not depend on
//!   the thread count or on the order in which runs are scheduled.
//! * [`time`]: integer-nanosecond simulation time, so event ordering never depends on rounding.
//! * [`ids`]: radar and target identifiers (`R1`…`R4`, `F-1`…`F-4`, `A`, `B`, `C`).
//! * [`assign`]: an exact rectangular assignment solver (shortest augmenting path, Jonker–Volgenant
//!   style) shared by the tracker's GNN and the metrics engine's truth–track pairing;
//!   [`assign_components`] splits a gated problem into the components of its graph, which the
//!   metrics engine solves one by one.
//! * [`polarimetry`]: a target's polarimetric scattering statistics (docs/model.md §3.5).
//! * [`table_rules`]: what a well-formed table keeps beyond its schema (unique ids, ordered times),
//!   checked by every reader of the tables.
//! * [`records`]: the plain row structs of the run tables (docs/design.md §3). Stages push these into
//!   sinks ([`sink::RunSink`]); only `mimo-store` turns them into Arrow.
//!
//! Units are SI and carried in names (`range_m`, `t_s`); frames are carried in names too
//! (`face_from_ecef` maps ECEF vectors into a face frame).

#![warn(missing_docs)]

pub mod assign;
pub mod assign_components;
pub mod covariance;
pub mod face;
pub mod geo;
pub mod ids;
pub mod nearly_sorted;
pub mod params;
pub mod polarimetry;
pub mod quote;
pub mod records;
pub mod registration;
pub mod rng;
pub mod sink;
pub mod table_decl;
pub mod table_rules;
pub mod text_file;
pub mod time;

pub use glam::{DMat3, DVec3};

/// Speed of light in vacuum (m/s).
pub const SPEED_OF_LIGHT_MPS: f64 = 299_792_458.0;
/// Boltzmann's constant (J/K).
pub const BOLTZMANN_J_PER_K: f64 = 1.380_649e-23;
/// Standard noise reference temperature T0 (K).
pub const T0_K: f64 = 290.0;
/// Standard gravity (m/s²).
pub const G0_MPS2: f64 = 9.806_65;

/// Convert decibels to a linear power ratio.
pub fn db_to_lin(db: f64) -> f64 {
    10f64.powf(db / 10.0)
}

/// Convert a linear power ratio to decibels.
pub fn lin_to_db(lin: f64) -> f64 {
    10.0 * lin.log10()
}
