//! A test article wrapped to measure the CPU time spent inside it (the costs table's
//! `ta_cpu_s`). For a test article in another process the time is what this thread spends
//! waiting for its replies, which includes the protocol (docs/studies.md).

use crate::cpu::thread_cpu;
use mimo_sim::messages::{DwellReport, Reply, StartInfo, Subscription, TaEvent};
use mimo_sim::test_article::{TaFault, TestArticle};
use std::time::{Duration, Instant};

/// A test article and the time spent in it.
pub struct Timed<'w> {
    inner: Box<dyn TestArticle + 'w>,
    /// Measure wall time instead of thread CPU time (a child process works on its own CPU).
    wall: bool,
    /// Time spent in the test article so far.
    pub spent: Duration,
}

impl<'w> Timed<'w> {
    /// Wrap a test article; `wall` for one in another process.
    pub fn new(inner: Box<dyn TestArticle + 'w>, wall: bool) -> Timed<'w> {
        Timed { inner, wall, spent: Duration::ZERO }
    }

    fn time<T>(&mut self, f: impl FnOnce(&mut dyn TestArticle) -> T) -> T {
        let (c0, w0) = (thread_cpu(), Instant::now());
        let out = f(self.inner.as_mut());
        self.spent += if self.wall { w0.elapsed() } else { thread_cpu().saturating_sub(c0) };
        out
    }
}

impl TestArticle for Timed<'_> {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn config(&self) -> serde_json::Value {
        self.inner.config()
    }
    fn subscription(&self) -> Subscription {
        self.inner.subscription()
    }
    fn on_start(&mut self, start: &StartInfo) -> Result<Reply, TaFault> {
        self.time(|t| t.on_start(start))
    }
    fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault> {
        self.time(|t| t.on_dwell(report))
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.time(|t| t.on_wake(t_s))
    }
    fn on_finish(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        self.time(|t| t.on_finish(t_s))
    }
    fn on_events(&mut self, t_s: f64, events: &[TaEvent]) -> Result<Reply, TaFault> {
        self.time(|t| t.on_events(t_s, events))
    }
}
