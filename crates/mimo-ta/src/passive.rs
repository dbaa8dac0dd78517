//! A test article that asks for nothing: only background search runs (`none`).

use mimo_sim::messages::{DwellFilter, DwellReport, Reply, StartInfo, Subscription};
use mimo_sim::test_article::{TaFault, TestArticle};

/// Background search only; no tracks.
pub struct Passive;

impl TestArticle for Passive {
    fn name(&self) -> &str {
        "none"
    }
    fn subscription(&self) -> Subscription {
        Subscription { dwells: DwellFilter::Own, ..Subscription::default() }
    }
    fn on_start(&mut self, _start: &StartInfo) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_dwell(&mut self, _report: &DwellReport) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
    fn on_wake(&mut self, _t_s: f64) -> Result<Reply, TaFault> {
        Ok(Reply::default())
    }
}
