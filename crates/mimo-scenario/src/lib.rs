//! # mimo-scenario
//!
//! Scenario files, their validation, aircraft and ship trajectories, and truth sampling.
//!
//! * [`load_standard`]`(n)` loads standard scenario `n` (1–7, the seed paper's Table 1), whose
//!   TOML files are embedded in the binary; [`load_path`] loads a user's scenario file, which
//!   may define everything inline or `include` files relative to its own directory (or the
//!   built-in definitions as `builtin:ships.toml` …). [`list_standard`] lists the standard set.
//! * A [`Scenario`] is plain serde data: the run manifest stores it whole, and a run can be
//!   repeated from it (deserialize, then [`Scenario::validate`]).
//! * [`Ship`] gives each radar's position, heading and array faces at any time
//!   ([`Ship::position_at`], [`Ship::faces_at`]) and whether it could see a point
//!   ([`Ship::sees`]).
//! * [`Scenario::build_trajectories`] flies every target once (RK4 on the WGS-84 ellipsoid at
//!   [`STEP_S`], docs/model.md §8) and checks it against its flight envelope; the resulting
//!   [`Trajectories`] evaluate any target at any time cheaply ([`Trajectories::state_at`]) and
//!   produce the truth table ([`Trajectories::truth_rows`]). Truth is deterministic.
//!
//! Errors are [`ScenarioError`]s with one-line messages that name the file, the field and what
//! was expected. `scenarios/README.md` documents the file format and the standard scenarios.
//!
//! ```
//! use mimo_scenario::load_standard;
//!
//! let scenario = load_standard(7)?;
//! let truth = scenario.build_trajectories()?;
//! let f1 = truth.index_of("F-1").expect("F-1 flies in scenario 7");
//! let state = truth.state_at(f1, 110.0); // mid-crossover
//! assert!((state.geodetic.alt_m - 6000.0).abs() < 1.0);
//! let r1 = &scenario.ships[0];
//! assert_eq!(r1.faces_at(110.0).len(), 4);
//! assert!(r1.sees(110.0, state.pos_ecef, state.geodetic.alt_m));
//! let rows = truth.truth_rows(0, scenario.fidelity.truth_rate_hz);
//! assert_eq!(rows.len(), 10_001 * 7);
//! # Ok::<(), mimo_scenario::ScenarioError>(())
//! ```

#![warn(missing_docs)]

pub mod biases;
pub mod epoch_balls;
mod error;
mod flight;
pub mod links;
mod load;
mod model;
pub mod raid;
mod ship;
pub mod ship_frames;
pub mod stress;
/// Reading small text inputs within a memory budget (kept here for the callers that found it
/// here; it lives in mimo-core so that the store reads manifests the same way).
pub use mimo_core::text_file;
pub mod toml_path;
mod trajectory;
mod validate;

pub use error::ScenarioError;
pub use flight::STEP_S;
pub use load::BUILTIN_PREFIX;
pub use model::{
    Aircraft, AircraftType, Crossover, DEFAULT_ARRAY_HEIGHT_M, DEFAULT_DURATION_S, DEFAULT_RAMP_S, Envelope, Formation,
    Group, LatLonAlt, Manoeuvre, Member, Move, Offset, Scenario, Ship, Split, Target,
};
pub use ship_frames::ShipFrames;
pub use stress::Stress;
pub use trajectory::{MARGIN_S, TargetState, Trajectories};
pub use validate::MAX_DURATION_S;

use mimo_core::geo::{Geodetic, ecef_to_geodetic};
use std::path::Path;

/// Numbers of the standard scenarios.
pub const STANDARD_SCENARIOS: std::ops::RangeInclusive<u32> = 1..=7;

/// Load standard scenario `n` (1–7): four ships R1–R4 and the targets of the seed paper's
/// Table 1 (1: F-1, 2: F-2, 3: F-3, 4: F-4, 5: F-1 and F-2, 6: F-3 and F-4, 7: F-1…F-4; each
/// with airliners A, B and C).
pub fn load_standard(n: u32) -> Result<Scenario, ScenarioError> {
    if !STANDARD_SCENARIOS.contains(&n) {
        return Err(ScenarioError::UnknownScenario { number: n, max: *STANDARD_SCENARIOS.end() });
    }
    load::load_builtin(&format!("{n}.toml"), &format!("scenario-{n}"))
}

/// Load a scenario TOML file. Relative `include`s are looked up beside it; `builtin:NAME`
/// includes name the embedded standard files (`ships.toml`, `fighters.toml`,
/// `airliners.toml`, `1.toml` … `7.toml`).
pub fn load_path(path: impl AsRef<Path>) -> Result<Scenario, ScenarioError> {
    load::load_file(path.as_ref())
}

/// Load a scenario from TOML text, as if it were the file `name` in `include_dir` (where its
/// relative includes are looked up; with `None`, only `builtin:` includes work).
pub fn load_str(text: &str, name: &str, include_dir: Option<&Path>) -> Result<Scenario, ScenarioError> {
    load::load_string(text, name, include_dir)
}

/// Every standard scenario with its number, for `mimo scenarios`.
pub fn list_standard() -> Result<Vec<(u32, Scenario)>, ScenarioError> {
    STANDARD_SCENARIOS.map(|n| load_standard(n).map(|s| (n, s))).collect()
}

impl Scenario {
    /// Target ids in scenario order.
    pub fn target_ids(&self) -> Vec<&str> {
        self.targets.iter().map(|t| t.id.as_str()).collect()
    }

    /// Index of a target id in [`Scenario::targets`].
    pub fn target_index(&self, id: &str) -> Option<usize> {
        self.targets.iter().position(|t| t.id == id)
    }

    /// The scenario centre: the point on the ellipsoid (height 0) below the centroid of the
    /// ships' start positions. A natural origin for a fixed local ENU tracking frame
    /// (docs/model.md §6.1) and for plots.
    pub fn centre(&self) -> Geodetic {
        let n = self.ships.len().max(1) as f64;
        let sum = self.ships.iter().map(|s| s.start_position().to_ecef()).fold(glam::DVec3::ZERO, |a, b| a + b);
        let mut g = ecef_to_geodetic(sum / n);
        g.alt_m = 0.0;
        g
    }
}
