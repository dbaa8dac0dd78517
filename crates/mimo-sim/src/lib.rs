//! # mimo-sim
//!
//! The closed loop of the benchmark (docs/design.md §5):
//!
//! * [`world::World`]: a scenario with its trajectories — ships, radars and truth.
//! * [`engine::Engine`]: the discrete-event engine of one run — radar timelines, background
//!   search ([`search`]), reservations for test-article dwells (monostatic and MIMO), and the
//!   radar model of `mimo-radar` evaluated for every dwell. Rows go into a
//!   [`RunSink`](mimo_core::sink::RunSink) as they are made.
//! * [`test_article`]: the trait a test article implements, and [`messages`]: everything that
//!   crosses the boundary (events, requests, replies), owned and serializable — the same values a
//!   test article in another language receives as JSON (docs/ta-protocol.md).
//! * [`run_monte_carlo`]: runs in parallel with rayon; every random draw is keyed by
//!   `(seed, run, dwell)`, so results are identical whatever the thread count.
//!
//! The built-in test articles (the default solution, the cued schedule) live in `mimo-ta`.

#![warn(missing_docs)]

pub mod engine;
pub mod messages;
pub mod registration_check;
pub mod search;
pub mod search_plan;
pub mod test_article;
pub mod track_check;
pub mod world;

pub use engine::{EngineConfig, EngineError, RunStats};
pub use search::SearchConfig;
pub use test_article::{TaFault, TestArticle};
pub use world::World;

use mimo_core::sink::RunSink;

/// The default master seed: runs are reproducible unless a seed is given.
pub const DEFAULT_SEED: u64 = 20_261_122;
use rayon::prelude::*;

/// What a test article said about itself, for the manifest.
#[derive(Debug, Clone, PartialEq)]
pub struct TaInfo {
    /// Its name.
    pub name: String,
    /// Its configuration.
    pub config: serde_json::Value,
}

/// Run one Monte Carlo run with a test article, writing rows into `sink`.
pub fn run_one(
    world: &World,
    cfg: &EngineConfig,
    run: u32,
    ta: &mut dyn TestArticle,
    sink: &mut dyn RunSink,
) -> Result<RunStats, EngineError> {
    engine::Engine::new(world, cfg.clone(), run, ta, sink).run()
}

/// Run `runs` in parallel (on the current rayon pool). For each run, `make_ta(run)` builds a
/// fresh test article and `make_sink(run)` its sink; when the run is done, `done` gets the sink
/// back with the run's counters and what the test article said about itself.
#[allow(clippy::needless_lifetimes)] // the test articles may borrow the world
pub fn run_monte_carlo<'w, S: RunSink + Send, E: Send + From<EngineError>>(
    world: &'w World,
    cfg: &EngineConfig,
    runs: &[u32],
    make_ta: &(dyn Fn(u32) -> Result<Box<dyn TestArticle + 'w>, E> + Sync),
    make_sink: &(dyn Fn(u32) -> Result<S, E> + Sync),
    done: &(dyn Fn(u32, S, RunStats, TaInfo) -> Result<(), E> + Sync),
) -> Result<(), E> {
    runs.par_iter().try_for_each(|&run| {
        let mut ta = make_ta(run)?;
        let mut sink = make_sink(run)?;
        let stats = run_one(world, cfg, run, ta.as_mut(), &mut sink)?;
        let info = TaInfo { name: ta.name().to_string(), config: ta.config() };
        done(run, sink, stats, info)
    })
}
