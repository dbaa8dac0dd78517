//! The test-article (TA) trait.
//!
//! A TA is the user's tracker and resource manager. The engine drives it with the events of
//! [`crate::messages`] — `start`, `dwell_ended` (for the dwells it subscribed to), `wake` (when
//! it asked for one) and `finish` — and it answers each with a [`Reply`]: requests (dwells,
//! wake-ups, stop-local-tracking orders) and the track rows it produced. The same messages go
//! to a TA in another process as JSON (docs/ta-protocol.md). Truth never reaches a TA.
//!
//! # Writing your own TA
//!
//! ```
//! use mimo_sim::messages::{DwellReport, Reply, StartInfo};
//! use mimo_sim::test_article::{TaFault, TestArticle};
//!
//! /// A TA that never asks for anything: only background search runs.
//! struct Passive { seen: usize }
//!
//! impl TestArticle for Passive {
//!     fn name(&self) -> &str { "passive" }
//!     fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> { Ok(Reply::default()) }
//!     fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault> {
//!         self.seen += report.measurements.len();
//!         Ok(Reply::default())
//!     }
//!     fn on_wake(&mut self, _t_s: f64) -> Result<Reply, TaFault> { Ok(Reply::default()) }
//! }
//! ```
//!
//! Run it with [`crate::run_one`] (or [`crate::run_monte_carlo`] with a factory closure).

use crate::messages::{DwellReport, Reply, StartInfo, Subscription, TaEvent};

/// Why a test article could not go on. The run stops; nothing it wrote is kept.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TaFault {
    /// The TA process exited or closed its output before the run ended.
    #[error("crashed: {0}")]
    Crashed(String),
    /// The TA did not answer in time.
    #[error("no reply within {0} s (--ta-timeout)")]
    Timeout(f64),
    /// The TA wrote something that is not a reply.
    #[error("bad reply: {0}")]
    BadMessage(String),
    /// The TA asked for something impossible (an unknown radar, a non-finite number, a time
    /// outside the run).
    #[error("invalid request: {0}")]
    InvalidRequest(String),
    /// Reading from or writing to the TA failed.
    #[error("i/o: {0}")]
    Io(String),
}

/// A test article: the tracker and resource manager under test.
pub trait TestArticle {
    /// Short name recorded in the manifest.
    fn name(&self) -> &str;
    /// Configuration recorded in the manifest.
    fn config(&self) -> serde_json::Value {
        serde_json::Value::Null
    }
    /// What the TA wants to be sent; asked once, after `start`. The default is every dwell with
    /// a detection plus the TA's own dwells.
    fn subscription(&self) -> Subscription {
        Subscription::default()
    }
    /// The run starts: ships, radars and parameters (never truth).
    fn on_start(&mut self, start: &StartInfo) -> Result<Reply, TaFault>;
    /// A subscribed dwell ended.
    fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault>;
    /// A wake-up the TA asked for.
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault>;
    /// The run ends at `t_s`: the last chance to emit track rows (e.g. `deleted` rows).
    fn on_finish(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    /// Several events of one instant (only with `batch` in the subscription, and for `start`).
    /// The default handles them one by one and joins the replies.
    fn on_events(&mut self, _t_s: f64, events: &[TaEvent]) -> Result<Reply, TaFault> {
        let mut out = Reply::default();
        for e in events {
            out.extend(match e {
                TaEvent::Start(s) => self.on_start(s)?,
                TaEvent::DwellEnded(r) => self.on_dwell(r)?,
                TaEvent::Wake { t_s } => self.on_wake(*t_s)?,
                TaEvent::Finish { t_s } => self.on_finish(*t_s)?,
            });
        }
        Ok(out)
    }
}
