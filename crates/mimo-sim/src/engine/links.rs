//! The links between the ships and the test article (docs/model.md §5.6): a dwell order reaches
//! its radars, and a dwell report the test article, after each ship's link delay (± its jitter).
//! A look is placed when its last order arrives, as if it had been requested then; a report is
//! delivered when the slowest of its receiving ships' reports arrives. With every link perfect
//! (the default) none of this runs and the engine is what it was.

use super::group::Group;
use super::{Engine, Ev};
use crate::messages::DwellRequest;
use crate::world::World;
use mimo_core::ids::RadarId;
use mimo_core::rng::{Stream, domain};
use mimo_core::time::SimTime;
use mimo_scenario::links::ShipLink;

/// What a message is, in the key of its jitter's stream.
const ORDER: u64 = 1;
const REPORT: u64 = 2;

/// The links of one run.
pub(super) struct Links {
    /// Every ship's link, by radar.
    ships: Vec<ShipLink>,
    seed: u64,
    run: u32,
    /// Dwell orders sent so far (the key of an order's jitter).
    sent: u64,
}

impl Links {
    /// The links of run `run` of `world`; `None` when every link is perfect.
    pub(super) fn of(world: &World, seed: u64, run: u32) -> Option<Links> {
        let l = &world.scenario.links;
        (!l.is_off()).then(|| Links {
            ships: world.radar_ids().into_iter().map(|r| l.of(r)).collect(),
            seed,
            run,
            sent: 0,
        })
    }

    /// How long message `id` of kind `kind` between the test article and `radars` takes: the
    /// slowest ship's travel time, each drawn from its own stream `(seed, LINK, run, kind, id,
    /// radar)`.
    fn travel_s(&self, kind: u64, id: u64, radars: impl Iterator<Item = RadarId>) -> f64 {
        radars
            .map(|r| {
                let l = self.ships.get(r.index()).copied().unwrap_or_default();
                if l.jitter_s == 0.0 {
                    return l.delay_s;
                }
                let mut s = Stream::new(self.seed, &[domain::LINK, u64::from(self.run), kind, id, r.index() as u64]);
                l.travel_s(s.uniform())
            })
            .fold(0.0, f64::max)
    }
}

impl Engine<'_> {
    /// Send a dwell order: placed at once over perfect links, else when its last order arrives.
    pub(super) fn order(&mut self, req: DwellRequest) {
        let Some(links) = &mut self.links else { return self.place(req) };
        let id = links.sent;
        links.sent += 1;
        let radars = req.transmitters.iter().map(|t| t.radar).chain(req.receivers.iter().copied());
        let arrives = self.now.plus_secs(links.travel_s(ORDER, id, radars));
        self.in_transit.insert(id, req);
        self.push(arrives, Ev::Order(id));
    }

    /// An order arrived at its radars: place it now.
    pub(super) fn order_arrived(&mut self, id: u64) {
        if let Some(req) = self.in_transit.remove(&id) {
            self.place(req);
        }
    }

    /// When the report of group `gid` (ended at `end`) reaches the test article.
    pub(super) fn report_arrives(&self, gid: u64, g: &Group, end: SimTime) -> SimTime {
        match &self.links {
            None => end,
            Some(l) => end.plus_secs(l.travel_s(REPORT, gid, g.parts.iter().filter(|p| p.receives()).map(|p| p.radar))),
        }
    }

    /// A wake-up asked for time `t_s`: over imperfect links a test article cannot know how
    /// late its last report came, so a time already past is taken as now (docs/ta-protocol.md).
    pub(super) fn wake_time(&self, t_s: f64) -> f64 {
        if self.links.is_some() { t_s.max(self.now.as_secs()) } else { t_s }
    }
}
