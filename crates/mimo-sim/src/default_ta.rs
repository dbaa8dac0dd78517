//! The default solution (placeholder module; filled in with the tracker).

use crate::ta::{DwellReport, Request, TaContext, TestArticle};
use crate::world::World;
use mimo_core::records::TrackRow;

/// A TA that asks for nothing: background search only.
pub struct Passive;

impl TestArticle for Passive {
    fn name(&self) -> &str {
        "none"
    }
    fn on_dwell(&mut self, _ctx: &TaContext, _report: &DwellReport) -> Vec<Request> {
        Vec::new()
    }
    fn on_wake(&mut self, _ctx: &TaContext, _t_s: f64) -> Vec<Request> {
        Vec::new()
    }
    fn take_track_rows(&mut self) -> Vec<TrackRow> {
        Vec::new()
    }
}

/// The default TA.
pub struct DefaultTa;

impl DefaultTa {
    pub fn by_name(_name: &str, _world: &World) -> Option<DefaultTa> {
        None
    }
}

impl TestArticle for DefaultTa {
    fn name(&self) -> &str {
        "default"
    }
    fn on_dwell(&mut self, _ctx: &TaContext, _report: &DwellReport) -> Vec<Request> {
        Vec::new()
    }
    fn on_wake(&mut self, _ctx: &TaContext, _t_s: f64) -> Vec<Request> {
        Vec::new()
    }
    fn take_track_rows(&mut self) -> Vec<TrackRow> {
        Vec::new()
    }
}
