//! # mimo-ta
//!
//! The test articles that come with `mimo`, and what lets any other one take part:
//!
//! * [`registry`]: the one list of built-in test articles (`default`, `imm`, `jpda`, `imm-jpda`,
//!   `cued`, `none`),
//!   their default configurations and how to build one.
//! * [`overrides`]: `--ta-config FILE.toml`, `--set key=value` and a study method's `config`,
//!   merged over a built-in's defaults with every key checked.
//! * [`default_ta`]: the baseline solution (tracker + resource manager); [`cued`]: the
//!   truth-cued fixed schedule; [`passive`]: background search only.
//! * [`replay`]: the open-loop re-run behind `mimo track`: any test article over a recording's
//!   dwells, in the order the closed loop delivered them.
//! * [`geometry`]: the ships of a `start` event as the tracker's sensor geometry.
//! * [`process`]: a test article in another process, in any language, speaking the protocol over
//!   its stdin and stdout.
//! * [`resource_manager`]: a built-in's tracker with the looks decided by a process in another
//!   language (the resource-manager role of docs/ta-protocol.md §7).
//!
//! Every test article here talks to the engine only through `mimo_sim::messages`, exactly as a
//! test article in another process does (docs/ta-protocol.md).

#![warn(missing_docs)]

pub mod cued;
pub mod default_ta;
pub mod dense;
pub mod geometry;
pub mod overrides;
pub mod passive;
pub mod process;
pub mod registration;
pub mod registry;
pub mod replay;
pub mod resource_manager;

pub use overrides::ConfigError;
