//! # mimo-sim
//!
//! The closed loop of the benchmark (DESIGN.md §5):
//!
//! * [`world::World`]: a scenario with its trajectories — ships, radars and truth.
//! * [`engine::Engine`]: the discrete-event engine of one run — radar timelines, background
//!   search ([`search`]), reservations for test-article dwells (monostatic and MIMO), and the
//!   radar model of `mimo-radar` evaluated for every dwell.
//! * [`ta`]: the test-article trait a user implements, and the requests it answers with.
//! * Built-in test articles: [`cued::Cued`] (truth-cued fixed schedule, no tracking) and
//!   [`default_ta::DefaultTa`] (the paper's baseline: EKF or IMM tracker, GNN, confirmation,
//!   adaptive revisit and energy, MIMO dwells).
//! * [`run_monte_carlo`]: runs in parallel with rayon; every random draw is keyed by
//!   `(seed, run, dwell)`, so results are identical whatever the thread count.

pub mod cued;
pub mod default_ta;
pub mod engine;
pub mod replay;
pub mod search;
pub mod ta;
pub mod world;

pub use engine::{EngineConfig, RunStats};
pub use search::SearchConfig;
pub use ta::TestArticle;
pub use world::World;

use mimo_core::records::RunTables;
use rayon::prelude::*;

/// Names of the built-in test articles for `--tracker`.
pub const TRACKERS: &[&str] = &["default", "imm", "cued", "none"];

/// Make a built-in test article by name.
pub fn builtin_ta<'w>(name: &str, world: &'w World) -> Option<Box<dyn TestArticle + 'w>> {
    match name {
        "cued" => Some(Box::new(cued::Cued::new(world))),
        "none" => Some(Box::new(default_ta::Passive)),
        other => default_ta::DefaultTa::by_name(other, world).map(|t| Box::new(t) as Box<dyn TestArticle + 'w>),
    }
}

/// What the schedule of a run with this TA is, for the manifest.
pub fn schedule_description(name: &str) -> String {
    match name {
        "cued" => "truth-cued fixed schedule (no tracking; reads truth) plus background search".into(),
        "none" => "background search only".into(),
        other => format!("closed loop: background search plus dwells requested by the '{other}' test article"),
    }
}

/// Run one Monte Carlo run with a test article.
pub fn run_one(world: &World, cfg: &EngineConfig, run: u32, ta: &mut dyn TestArticle) -> (RunTables, RunStats) {
    engine::Engine::new(world, cfg.clone(), run, ta).run()
}

/// Run `runs` in parallel (on the current rayon pool), handing each run's tables to `sink` as
/// soon as it is done. `make_ta(run)` builds a fresh test article per run.
#[allow(clippy::needless_lifetimes)] // the test articles may borrow the world
pub fn run_monte_carlo<'w, E: Send>(
    world: &'w World,
    cfg: &EngineConfig,
    runs: &[u32],
    make_ta: &(dyn Fn(u32) -> Box<dyn TestArticle + 'w> + Sync),
    sink: &(dyn Fn(u32, RunTables, RunStats) -> Result<(), E> + Sync),
) -> Result<(), E> {
    runs.par_iter().try_for_each(|&run| {
        let mut ta = make_ta(run);
        let (tables, stats) = run_one(world, cfg, run, ta.as_mut());
        sink(run, tables, stats)
    })
}
