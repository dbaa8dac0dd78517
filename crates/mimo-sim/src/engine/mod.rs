//! The discrete-event engine of one Monte Carlo run.
//!
//! # Events and timelines
//!
//! Events are ordered by integer nanoseconds ([`SimTime`]) and, at equal times, dwell ends first
//! (in group-id order, a canonical order that offline replay reproduces), then everything else
//! in the order it was scheduled, so a run is a deterministic function of its inputs and seed.
//! Each radar executes one dwell at a time. Its [`timeline`] holds
//!
//! * *reservations*: dwells requested by the test article, placed when requested at the earliest
//!   time, at or after the requested start, when every participant (all transmitters and
//!   receivers of a MIMO dwell) is free for the whole dwell; and
//! * *background search*: whenever a radar becomes free it runs its next search beam if that
//!   dwell ends before its next reservation starts; otherwise it waits for the reservation.
//!
//! Priority rule for conflicting requests: reservations are first come, first served — a
//! request never moves an earlier reservation; requests returned together by one test-article
//! call are placed in the order `track`, `confirm`, `mimo` (then by earliest start, then as
//! returned). Background search never delays a reservation. What actually ran is what the dwells
//! table records.
//!
//! # The test article
//!
//! The engine talks to the test article only through [`crate::messages`]: `start`, then a
//! `dwell_ended` for every dwell its [`Subscription`] asks for, a `wake` when it asked for one,
//! and `finish`. Requests are checked before they are placed: an unknown radar, a non-finite
//! number or a time outside the run is a [`TaFault`] that stops the run.
//!
//! # Physics and rows
//!
//! A dwell is evaluated at its mid-time ([`execute`]): truth positions, ship sites and faces are
//! taken then, and primitives and measurements are stamped with it. Every random draw of a
//! dwell comes from a stream keyed by `(seed, run, group_id)`. Rows go to the run's
//! [`RunSink`] as they are made.

mod execute;
mod group;
mod links;
mod plan;
mod quiet;
mod registration;
mod search_order;
mod timeline;

pub use execute::first_meas_id;

use crate::messages::{
    DwellReport, DwellRequest, GeoPoint, PROTOCOL_VERSION, Reply, Request, ShipInfo, StartInfo, Subscription, TaEvent,
};
use crate::search::{SearchConfig, raster};
use crate::test_article::{TaFault, TestArticle};
use crate::world::World;
use execute::{RunKeys, execute, report};
use group::{Group, Part};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, Requester, Role};
use mimo_core::sink::{RunSink, SinkError};
use mimo_core::time::SimTime;
use mimo_radar::energy::dwell_duration_s;
use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};
use timeline::{Timeline, earliest_common_slot};

/// Engine settings for one run.
#[derive(Debug, Clone)]
pub struct EngineConfig {
    /// Master seed of every random stream.
    pub seed: u64,
    /// Simulated duration (s).
    pub duration_s: f64,
    /// Record the voltages table.
    pub record_voltages: bool,
    /// Background search.
    pub search: SearchConfig,
    /// The test article's configuration overrides, passed on in its `start` event.
    pub ta_config: serde_json::Value,
}

/// Counters of one run (or, summed with [`RunStats::add`], of several), for reports and benchmarks.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct RunStats {
    /// Dwell groups executed.
    pub dwells: u64,
    /// Background search dwells executed.
    pub search_dwells: u64,
    /// Test-article dwell groups executed.
    pub ta_dwells: u64,
    /// Test-article dwells that could not be run (no participant left, or no time left).
    pub rejected_requests: u64,
    /// Primitives made.
    pub primitives: u64,
    /// Measurements made.
    pub measurements: u64,
    /// Stop-local-tracking orders received.
    pub stop_local_tracking_orders: u64,
    /// Dwell reports delivered to the test article.
    pub reports_delivered: u64,
    /// Track rows of the test article whose covariance was slightly indefinite and was repaired
    /// (docs/design.md §7).
    #[serde(skip_serializing_if = "is_zero")]
    pub repaired_covariances: u64,
    /// The most negative smallest-to-largest eigenvalue ratio among them (0 if none).
    #[serde(skip)]
    pub worst_covariance_ratio: f64,
}

fn is_zero(n: &u64) -> bool {
    *n == 0
}

impl RunStats {
    /// Add another run's counters.
    pub fn add(&mut self, o: &RunStats) {
        self.dwells += o.dwells;
        self.search_dwells += o.search_dwells;
        self.ta_dwells += o.ta_dwells;
        self.rejected_requests += o.rejected_requests;
        self.primitives += o.primitives;
        self.measurements += o.measurements;
        self.stop_local_tracking_orders += o.stop_local_tracking_orders;
        self.reports_delivered += o.reports_delivered;
        self.repaired_covariances += o.repaired_covariances;
        self.worst_covariance_ratio = self.worst_covariance_ratio.min(o.worst_covariance_ratio);
    }
}

/// Why a run stopped early.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum EngineError {
    /// The test article failed (crash, timeout, bad reply, invalid request).
    #[error("test article '{name}': {fault}")]
    Ta {
        /// The test article's name.
        name: String,
        /// What went wrong.
        fault: TaFault,
    },
    /// The sink could not take the rows.
    #[error("{0}")]
    Sink(#[from] SinkError),
}

impl EngineError {
    /// The fault `fault` of the test article named `name`.
    pub fn ta(name: &str, fault: TaFault) -> EngineError {
        EngineError::Ta { name: name.to_string(), fault }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Ev {
    /// A radar became free and decides what to do next.
    Decide(u8),
    /// A reserved group starts.
    Start(u64),
    /// A group ends: its report goes to the TA.
    End(u64),
    /// The TA asked to be woken.
    Wake,
    /// A dwell order reached its radars (links, docs/model.md §5.6).
    Order(u64),
}

/// One run of the engine.
pub struct Engine<'a> {
    world: &'a World,
    cfg: EngineConfig,
    run: u32,
    ta: &'a mut dyn TestArticle,
    sink: &'a mut dyn RunSink,
    subscription: Subscription,
    now: SimTime,
    end: SimTime,
    seq: u64,
    /// Events keyed by (time, class, key): see the module docs for the order.
    heap: BinaryHeap<Reverse<(SimTime, u8, u64, Ev)>>,
    timelines: Vec<Timeline>,
    groups: BTreeMap<u64, Group>,
    reports: BTreeMap<u64, DwellReport>,
    next_dwell_id: u64,
    stats: RunStats,
    /// The targets at the current dwell's mid-time (a buffer reused by every dwell).
    targets: Vec<mimo_radar::Target<'a>>,
    /// Every radar's constant part of the quiet-dwell tests (indexed by radar).
    quiet_radars: Vec<mimo_radar::quiet::QuietRadar>,
    /// The parts vector of the last quiet search group, reused by the next search group (no
    /// allocation and free per search dwell).
    spare_parts: Vec<Part>,
    /// The track rows returned so far, checked reply by reply.
    track_check: crate::track_check::TrackRowCheck,
    /// Every radar's registration biases in this run; `None` when off (docs/model.md §5.5).
    biases: Option<Vec<mimo_core::registration::RadarBias>>,
    /// The run's links; `None` when every link is perfect (docs/model.md §5.6).
    links: Option<links::Links>,
    /// Dwell orders sent and not yet arrived, by order id.
    in_transit: BTreeMap<u64, DwellRequest>,
}

impl<'a> Engine<'a> {
    /// Prepare run `run` of `world` with test article `ta`, writing rows into `sink`.
    pub fn new(
        world: &'a World,
        cfg: EngineConfig,
        run: u32,
        ta: &'a mut dyn TestArticle,
        sink: &'a mut dyn RunSink,
    ) -> Engine<'a> {
        let timelines =
            world.scenario.ships.iter().map(|s| Timeline::new(raster(&s.radar, s.heading_deg, &cfg.search))).collect();
        let end = SimTime::from_secs(cfg.duration_s);
        let biases = registration::run_biases(world, cfg.seed, run);
        let links = links::Links::of(world, cfg.seed, run);
        Engine {
            world,
            cfg,
            run,
            ta,
            sink,
            subscription: Subscription::default(),
            now: SimTime::ZERO,
            end,
            seq: 0,
            heap: BinaryHeap::new(),
            timelines,
            groups: BTreeMap::new(),
            reports: BTreeMap::new(),
            next_dwell_id: 0,
            stats: RunStats::default(),
            targets: Vec::new(),
            quiet_radars: quiet::quiet_radars(world),
            spare_parts: Vec::new(),
            track_check: Default::default(),
            biases,
            links,
            in_transit: BTreeMap::new(),
        }
    }

    /// The `start` event of this run.
    pub fn start_info(world: &World, run: u32, cfg: &EngineConfig, closed_loop: bool) -> StartInfo {
        let c = world.scenario.centre();
        StartInfo {
            protocol: PROTOCOL_VERSION,
            run,
            duration_s: cfg.duration_s,
            scenario: world.scenario.name.clone(),
            centre: GeoPoint { lat_deg: c.lat_deg(), lon_deg: c.lon_deg(), alt_m: c.alt_m },
            ships: world.scenario.ships.iter().map(ShipInfo::from_ship).collect(),
            closed_loop,
            config: cfg.ta_config.clone(),
        }
    }

    fn push(&mut self, t: SimTime, ev: Ev) {
        self.seq += 1;
        let (class, key) = match ev {
            Ev::End(gid) => (0, gid),
            _ => (1, self.seq),
        };
        self.heap.push(Reverse((t, class, key, ev)));
    }

    fn fault(&self, fault: TaFault) -> EngineError {
        EngineError::ta(self.ta.name(), fault)
    }

    /// Run to the end; the rows went to the sink. Returns the run's counters.
    pub fn run(mut self) -> Result<RunStats, EngineError> {
        // The truth table, streamed a block of sample times at a time (memory flat in duration).
        const TRUTH_STEPS_PER_BLOCK: usize = 1024;
        let rate = self.world.scenario.fidelity.truth_rate_hz;
        let trajectories = self.world.trajectories();
        let n_steps = trajectories.truth_steps(rate);
        for first in (0..n_steps).step_by(TRUTH_STEPS_PER_BLOCK) {
            let steps = first..(first + TRUTH_STEPS_PER_BLOCK).min(n_steps);
            let mut truth = trajectories.truth_rows_of_steps(self.run, rate, steps);
            truth.retain(|r| r.t_s <= self.cfg.duration_s + 1e-9);
            if !truth.is_empty() {
                self.sink.truth(truth)?;
            }
        }
        if let Some(b) = &self.biases {
            self.sink.biases(registration::bias_rows(self.run, b))?;
        }
        for r in 0..self.timelines.len() {
            self.push(SimTime::ZERO, Ev::Decide(r as u8));
        }
        let start = Self::start_info(self.world, self.run, &self.cfg, true);
        let reply = self.ta.on_events(0.0, &[TaEvent::Start(start)]).map_err(|f| self.fault(f))?;
        self.subscription = self.ta.subscription();
        self.handle_reply(reply)?;
        while let Some(Reverse((t, _, _, ev))) = self.heap.pop() {
            if t > self.end {
                break;
            }
            self.now = t;
            match ev {
                Ev::Decide(r) => self.decide(r as usize)?,
                Ev::Start(g) => self.start_group(g)?,
                Ev::End(g) => {
                    if let Some(report) = self.reports.remove(&g) {
                        self.deliver(TaEvent::DwellEnded(report))?;
                    }
                }
                Ev::Wake => self.deliver(TaEvent::Wake { t_s: t.as_secs() })?,
                Ev::Order(id) => self.order_arrived(id),
            }
        }
        self.now = self.end;
        let reply = self.ta.on_finish(self.end.as_secs()).map_err(|f| self.fault(f))?;
        self.take_tracks(reply.tracks)?;
        self.take_registration(reply.registration)?;
        self.stats.repaired_covariances = self.track_check.repaired();
        self.stats.worst_covariance_ratio = self.track_check.worst_ratio();
        Ok(self.stats)
    }

    /// Deliver an event (with, in batch mode, every other TA event of the same instant).
    fn deliver(&mut self, first: TaEvent) -> Result<(), EngineError> {
        let t_s = self.now.as_secs();
        if matches!(first, TaEvent::DwellEnded(_)) {
            self.stats.reports_delivered += 1;
        }
        let reply = if self.subscription.batch {
            let mut events = vec![first];
            while let Some(Reverse((t, _, _, ev))) = self.heap.peek().copied() {
                if t != self.now || !matches!(ev, Ev::End(_) | Ev::Wake) {
                    break;
                }
                self.heap.pop();
                match ev {
                    Ev::End(g) => {
                        if let Some(r) = self.reports.remove(&g) {
                            self.stats.reports_delivered += 1;
                            events.push(TaEvent::DwellEnded(r));
                        }
                    }
                    _ => events.push(TaEvent::Wake { t_s }),
                }
            }
            self.ta.on_events(t_s, &events)
        } else {
            match &first {
                TaEvent::DwellEnded(r) => self.ta.on_dwell(r),
                TaEvent::Wake { t_s } => self.ta.on_wake(*t_s),
                other => self.ta.on_events(t_s, std::slice::from_ref(other)),
            }
        };
        let reply = reply.map_err(|f| self.fault(f))?;
        self.handle_reply(reply)
    }

    fn take_tracks(&mut self, mut rows: Vec<mimo_core::records::TrackRow>) -> Result<(), EngineError> {
        if let Err(f) = self.track_check.check(&mut rows) {
            return Err(self.fault(f));
        }
        for r in &mut rows {
            r.run = self.run;
        }
        if !rows.is_empty() {
            self.sink.tracks(rows)?;
        }
        Ok(())
    }

    /// A test article's registration estimates, checked (`crate::registration_check`) and
    /// handed to the sink.
    fn take_registration(&mut self, mut rows: Vec<mimo_core::records::RegistrationRow>) -> Result<(), EngineError> {
        if rows.is_empty() {
            return Ok(());
        }
        crate::registration_check::check_registration(&mut rows, self.world.n_radars(), self.run)
            .map_err(|f| self.fault(f))?;
        self.sink.registration(rows)?;
        Ok(())
    }

    fn handle_reply(&mut self, reply: Reply) -> Result<(), EngineError> {
        self.take_tracks(reply.tracks)?;
        self.take_registration(reply.registration)?;
        let mut reqs = reply.requests;
        for r in &reqs {
            self.check(r).map_err(|f| self.fault(f))?;
        }
        let rank = |k: DwellKind| match k {
            DwellKind::Track => 0,
            DwellKind::Confirm => 1,
            DwellKind::Mimo => 2,
            DwellKind::Search => 3,
        };
        // Stable sort: dwells by kind rank and earliest start; other requests keep their order.
        reqs.sort_by(|a, b| match (a, b) {
            (Request::Dwell(x), Request::Dwell(y)) => {
                rank(x.kind).cmp(&rank(y.kind)).then(x.earliest_s.total_cmp(&y.earliest_s))
            }
            _ => std::cmp::Ordering::Equal,
        });
        for req in reqs {
            match req {
                Request::Dwell(d) => self.order(d),
                Request::WakeAt(t_s) => {
                    let t = SimTime::from_secs(t_s).max(self.now);
                    self.push(t, Ev::Wake);
                }
                Request::StopLocalTracking(_) => self.stats.stop_local_tracking_orders += 1,
                Request::Search(order) => self.order_search(order),
            }
        }
        Ok(())
    }

    /// A request the engine cannot make sense of is the test article's fault.
    fn check(&self, req: &Request) -> Result<(), TaFault> {
        let n = self.world.n_radars();
        let known = |r: RadarId| -> Result<(), TaFault> {
            if r.index() < n {
                Ok(())
            } else {
                Err(TaFault::InvalidRequest(format!("unknown radar {r} (the scenario has R1…R{n})")))
            }
        };
        let now = self.now.as_secs();
        let duration = self.cfg.duration_s;
        match req {
            Request::Dwell(d) => {
                for tx in &d.transmitters {
                    known(tx.radar)?;
                }
                for &rx in &d.receivers {
                    known(rx)?;
                }
                if !d.aim_ecef.is_finite() {
                    return Err(TaFault::InvalidRequest(format!("dwell aim point {:?} is not finite", d.aim_ecef)));
                }
                if !(d.earliest_s.is_finite() && d.earliest_s >= 0.0 && d.earliest_s <= duration) {
                    return Err(TaFault::InvalidRequest(format!(
                        "dwell start {} s is outside the run [0, {duration}] s",
                        d.earliest_s
                    )));
                }
                if !(d.window_half_m.is_finite() && d.window_half_m >= 0.0) {
                    return Err(TaFault::InvalidRequest(format!(
                        "window_half_m {} is not a finite number >= 0",
                        d.window_half_m
                    )));
                }
                if d.predicted_snr.is_some_and(|s| !(s.is_finite() && s >= 0.0)) {
                    return Err(TaFault::InvalidRequest("predicted_snr is not a finite number >= 0".into()));
                }
                Ok(())
            }
            Request::WakeAt(t) => {
                if t.is_finite() && self.wake_time(*t) >= now - 1e-9 {
                    Ok(())
                } else {
                    Err(TaFault::InvalidRequest(format!("wake_at {t} s is not a time at or after now ({now} s)")))
                }
            }
            Request::StopLocalTracking(r) => known(*r),
            Request::Search(order) => self.check_search(order),
        }
    }

    fn alloc_group(&mut self, g: Group) -> u64 {
        let gid = self.take_ids(&g);
        self.groups.insert(gid, g);
        gid
    }

    /// Dwell ids for the parts of `g`: the group id and the ones after it.
    fn take_ids(&mut self, g: &Group) -> u64 {
        let gid = self.next_dwell_id;
        self.next_dwell_id += g.parts.len() as u64;
        gid
    }

    /// A free radar runs its next search beam, unless it would run into a reservation or its
    /// test article's plan makes it wait (a radar with no search idles).
    fn decide(&mut self, r: usize) -> Result<(), EngineError> {
        let now = self.now;
        let tl = &self.timelines[r];
        if tl.busy_until > now || tl.raster.is_empty() {
            return Ok(());
        }
        if tl.shape.is_some() && self.search_waits(r) {
            return Ok(());
        }
        let tl = &self.timelines[r];
        let beam = tl.raster[tl.cursor];
        let radar = RadarId(r as u8);
        let duration_s = dwell_duration_s(self.world.params(radar), beam.n_pulses);
        let search_end = now.plus_secs(duration_s);
        if search_end > self.end {
            return Ok(());
        }
        if tl.next_reservation().is_some_and(|s| s < search_end) {
            return Ok(()); // wait for the reservation; its Start event takes over
        }
        let n = tl.raster.len();
        let cursor = tl.cursor;
        if let Some(shape) = self.timelines[r].shape.as_mut() {
            shape.ran(cursor, now, search_end);
        }
        self.timelines[r].cursor = (cursor + 1) % n;
        let mut parts = std::mem::take(&mut self.spare_parts);
        parts.clear();
        parts.push(Part {
            radar,
            role: Role::Txrx,
            face: beam.face,
            beam_u: beam.u,
            beam_v: beam.v,
            n_pulses: beam.n_pulses,
            waveform: 0,
        });
        let group = Group {
            kind: DwellKind::Search,
            requested_by: Requester::Radar,
            aim: None,
            parts,
            duration_s,
            window_half_m: None,
            predicted_snr: None,
            tag: Vec::new(),
        };
        // A search group starts at once: it takes its id without passing through `groups`.
        let gid = self.take_ids(&group);
        self.run_group(gid, group)
    }

    /// Plan a requested dwell's parts and reserve the earliest common slot.
    fn place(&mut self, req: DwellRequest) {
        let t_plan = self.now.as_secs().max(req.earliest_s);
        let Some(group) = plan::plan(self.world, t_plan, &req) else {
            self.stats.rejected_requests += 1;
            return;
        };
        let earliest = SimTime::from_secs(req.earliest_s.max(0.0)).max(self.now);
        let radars: Vec<usize> = group.parts.iter().map(|p| p.radar.index()).collect();
        let dur_ns = SimTime::from_secs(group.duration_s).0;
        let t = earliest_common_slot(&self.timelines, &radars, earliest, dur_ns);
        let end = SimTime(t.0 + dur_ns);
        if end > self.end {
            self.stats.rejected_requests += 1;
            return;
        }
        let gid = self.alloc_group(group);
        for &r in &radars {
            self.timelines[r].reserve(t, end, gid);
        }
        self.push(t, Ev::Start(gid));
    }

    /// Execute a group now: physics, rows, report, timelines.
    fn start_group(&mut self, gid: u64) -> Result<(), EngineError> {
        let Some(g) = self.groups.remove(&gid) else { return Ok(()) };
        self.run_group(gid, g)
    }

    /// Execute group `gid` (already taken out of `groups`, or never in it) now.
    fn run_group(&mut self, gid: u64, g: Group) -> Result<(), EngineError> {
        let t0 = self.now.as_secs();
        let end = self.now.plus_secs(g.duration_s);
        for p in &g.parts {
            self.timelines[p.radar.index()].begin(gid, end);
        }
        let keys = RunKeys {
            seed: self.cfg.seed,
            run: self.run,
            record_voltages: self.cfg.record_voltages,
            biases: self.biases.as_deref(),
        };
        // A quiet search dwell the test article does not want to hear of: its row only.
        if g.requested_by == Requester::Radar
            && !self.subscription.wants(g.requested_by, 0)
            && let Some(row) =
                quiet::quiet_search_row(self.world, &self.quiet_radars, &keys, gid, &g, t0, &mut self.targets)
        {
            self.stats.dwells += 1;
            self.stats.search_dwells += 1;
            self.sink.dwell(row)?;
            for p in &g.parts {
                self.push(end, Ev::Decide(p.radar.0));
            }
            self.spare_parts = g.parts;
            return Ok(());
        }
        let ex = execute(self.world, &keys, gid, &g, t0, &mut self.targets);
        self.stats.dwells += 1;
        match g.requested_by {
            Requester::Radar => self.stats.search_dwells += 1,
            Requester::Ta => self.stats.ta_dwells += 1,
        }
        self.stats.primitives += ex.primitives.len() as u64;
        self.stats.measurements += ex.measurements.len() as u64;
        let delivered = self.subscription.wants(g.requested_by, ex.measurements.len());
        if delivered {
            let r = report(self.run, gid, &g, t0, end.as_secs(), &ex, self.subscription.primitives);
            self.reports.insert(gid, r);
        }
        for row in ex.dwells {
            self.sink.dwell(row)?;
        }
        if !ex.primitives.is_empty() {
            self.sink.primitives(ex.primitives)?;
        }
        if !ex.voltages.is_empty() {
            self.sink.voltages(ex.voltages)?;
        }
        if !ex.measurements.is_empty() {
            self.sink.measurements(ex.measurements)?;
        }
        if delivered {
            let arrives = self.report_arrives(gid, &g, end);
            self.push(arrives, Ev::End(gid));
        }
        for p in &g.parts {
            self.push(end, Ev::Decide(p.radar.0));
        }
        Ok(())
    }
}
