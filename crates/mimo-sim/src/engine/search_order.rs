//! A test article's search orders: checked, then turned into each addressed radar's raster and
//! pacing (docs/model.md §7.4, docs/ta-protocol.md §3).

use super::timeline::SearchShape;
use super::{Engine, Ev};
use crate::search::raster_of;
use crate::search_plan::SearchOrder;
use crate::test_article::TaFault;
use mimo_core::ids::RadarId;
use mimo_core::time::SimTime;

impl Engine<'_> {
    /// The radars an order addresses (every radar when it names none).
    fn order_radars(&self, order: &SearchOrder) -> Vec<usize> {
        match order.radar {
            Some(r) => vec![r.index()],
            None => (0..self.timelines.len()).collect(),
        }
    }

    /// Check a search order: a known radar, a valid plan, sectors the radars' faces search.
    pub(super) fn check_search(&self, order: &SearchOrder) -> Result<(), TaFault> {
        let bad = |msg: String| TaFault::InvalidRequest(format!("search: {msg}"));
        let n = self.world.n_radars();
        if let Some(r) = order.radar
            && r.index() >= n
        {
            return Err(bad(format!("radar: unknown radar {r} (the scenario has R1…R{n})")));
        }
        order.plan.check().map_err(bad)?;
        if !order.plan.sectors.is_empty() {
            let t_s = self.now.as_secs();
            for r in self.order_radars(order) {
                let ship = &self.world.scenario.ships[r];
                order
                    .plan
                    .check_sectors(&ship.radar, ship.heading_at(t_s))
                    .map_err(|e| bad(format!("{}: {e}", RadarId(r as u8))))?;
            }
        }
        Ok(())
    }

    /// Make the order's plan the search of each radar it addresses, from its raster's first
    /// beam; an idle radar picks it up at once.
    pub(super) fn order_search(&mut self, order: SearchOrder) {
        let plan = &order.plan;
        let t_s = self.now.as_secs();
        for r in self.order_radars(&order) {
            let ship = &self.world.scenario.ships[r];
            let raster = if plan.searches() {
                let spacing = self.cfg.search.spacing_beamwidths;
                raster_of(&ship.radar, ship.heading_at(t_s), &plan.bands, spacing, &plan.sectors)
            } else {
                Default::default()
            };
            let tl = &mut self.timelines[r];
            tl.cursor = 0;
            tl.shape = (plan.share < 1.0 || plan.frame_period_s.is_some()).then(|| {
                Box::new(SearchShape {
                    share: plan.share,
                    frame_period_ns: plan.frame_period_s.map(|p| SimTime::from_secs(p).0),
                    frame_starts: raster.frame_starts,
                    next_search_at: SimTime::ZERO,
                    last_frame_start: None,
                    decide_at: None,
                })
            });
            tl.raster = raster.beams;
            if tl.busy_until <= self.now && !tl.raster.is_empty() {
                self.push(self.now, Ev::Decide(r as u8));
            }
        }
    }

    /// Whether radar `r`'s next search beam must wait for its plan's pacing; if so a `Decide` is
    /// scheduled for the end of the wait (once).
    pub(super) fn search_waits(&mut self, r: usize) -> bool {
        let now = self.now;
        let tl = &mut self.timelines[r];
        let Some(shape) = tl.shape.as_mut() else { return false };
        let at = shape.earliest_start(tl.cursor);
        if at <= now {
            return false;
        }
        if shape.decide_at != Some(at) {
            shape.decide_at = Some(at);
            if at <= self.end {
                self.push(at, Ev::Decide(r as u8));
            }
        }
        true
    }
}
