//! The discrete-event engine of one Monte Carlo run.
//!
//! # Events and timelines
//!
//! Events are ordered by integer nanoseconds ([`SimTime`]) and, at equal times, by the order in
//! which they were scheduled, so a run is a deterministic function of its inputs and seed.
//! Each radar executes one dwell at a time. Its timeline holds
//!
//! * *reservations*: dwells requested by the test article, placed when requested at the earliest
//!   time, at or after the requested start, when every participant (all transmitters and
//!   receivers of a MIMO dwell) is free for the whole dwell; and
//! * *background search*: whenever a radar becomes free it runs its next search beam if that
//!   dwell ends before its next reservation starts; otherwise it waits for the reservation.
//!
//! Priority rule for conflicting requests: reservations are first come, first served — a
//! request never moves an earlier reservation; requests returned together by one TA call are
//! placed in the order `track`, `confirm`, `mimo` (then by earliest start, then as returned).
//! Background search never delays a reservation. What actually ran is what the dwells table
//! records.
//!
//! # Physics
//!
//! A dwell is evaluated at its mid-time: truth positions, ship sites and faces are taken then,
//! and primitives and measurements are stamped with it. The radar model (`mimo-radar`) does the
//! rest. Every random draw of a dwell comes from a stream keyed by `(seed, run, group_id)`.

use crate::search::{SearchBeam, SearchConfig, raster};
use crate::ta::{DwellReport, DwellRequest, PartReport, Request, TaContext, TestArticle};
use crate::world::World;
use mimo_core::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, Role, RunTables};
use mimo_core::time::SimTime;
use mimo_radar::energy::{dwell_duration_s, dwell_energy_j};
use mimo_radar::geometry::beam_point;
use std::cmp::Reverse;
use std::collections::{BTreeMap, BinaryHeap};

/// Measurement ids of a dwell group start at `group_id << 12`, so they depend only on the group
/// (offline re-forming of measurements from primitives reproduces them without replaying the
/// engine's order). A dwell yields far fewer than 4096 measurements.
pub fn first_meas_id(group_id: u64) -> u64 {
    group_id << 12
}

/// Engine settings for one run.
#[derive(Debug, Clone)]
pub struct EngineConfig {
    pub seed: u64,
    pub duration_s: f64,
    pub record_voltages: bool,
    pub search: SearchConfig,
}

/// Counters of one run (or, summed with [`RunStats::add`], of several), for reports and benchmarks.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct RunStats {
    pub dwells: u64,
    pub search_dwells: u64,
    pub ta_dwells: u64,
    pub rejected_requests: u64,
    pub primitives: u64,
    pub measurements: u64,
    pub stop_local_tracking_orders: u64,
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
}

#[derive(Debug, Clone)]
struct Part {
    radar: RadarId,
    role: Role,
    face: u8,
    beam_u: f64,
    beam_v: f64,
    n_pulses: u32,
    waveform: u32,
}

#[derive(Debug, Clone)]
struct Group {
    kind: DwellKind,
    requested_by: Requester,
    /// Aim point; `None` for search, whose beam is fixed in the face (the recorded aim is then
    /// the beam direction at half the instrumented range, from the face at mid-dwell).
    aim: Option<DVec3>,
    parts: Vec<Part>,
    duration_s: f64,
    window_half_m: Option<f64>,
    predicted_snr: Option<f64>,
    tag: Vec<u64>,
}

struct RadarState {
    busy_until: SimTime,
    /// Future reservations (start, end, group), sorted by start.
    reservations: Vec<(SimTime, SimTime, u64)>,
    raster: Vec<SearchBeam>,
    cursor: usize,
}

/// One run of the engine.
pub struct Engine<'w, 'ta> {
    world: &'w World,
    cfg: EngineConfig,
    run: u32,
    ta: &'ta mut dyn TestArticle,
    now: SimTime,
    end: SimTime,
    seq: u64,
    /// Events keyed by (time, class, key): at equal times dwell ends come first, in group-id
    /// order (a canonical order that offline replay reproduces), then everything else in the
    /// order it was scheduled.
    heap: BinaryHeap<Reverse<(SimTime, u8, u64, Ev)>>,
    radars: Vec<RadarState>,
    groups: BTreeMap<u64, Group>,
    reports: BTreeMap<u64, DwellReport>,
    next_dwell_id: u64,
    tables: RunTables,
    stats: RunStats,
}

impl<'w, 'ta> Engine<'w, 'ta> {
    /// Prepare run `run` of `world` with test article `ta`.
    pub fn new(world: &'w World, cfg: EngineConfig, run: u32, ta: &'ta mut dyn TestArticle) -> Engine<'w, 'ta> {
        let radars = world
            .scenario
            .ships
            .iter()
            .map(|s| RadarState {
                busy_until: SimTime::ZERO,
                reservations: Vec::new(),
                raster: raster(&s.radar, s.heading_deg, &cfg.search),
                cursor: 0,
            })
            .collect();
        let end = SimTime::from_secs(cfg.duration_s);
        Engine {
            world,
            cfg,
            run,
            ta,
            now: SimTime::ZERO,
            end,
            seq: 0,
            heap: BinaryHeap::new(),
            radars,
            groups: BTreeMap::new(),
            reports: BTreeMap::new(),
            next_dwell_id: 0,
            tables: RunTables::default(),
            stats: RunStats::default(),
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

    fn ctx(&self) -> TaContext<'w> {
        TaContext { radars: crate::world::Radars::of(self.world), t_s: self.now.as_secs(), run: self.run }
    }

    /// Run to the end and return the run's tables (truth included) and counters.
    pub fn run(mut self) -> (RunTables, RunStats) {
        let rate = self.world.scenario.fidelity.truth_rate_hz;
        self.tables.truth = self.world.trajectories.truth_rows(self.run, rate);
        self.tables.truth.retain(|r| r.t_s <= self.cfg.duration_s + 1e-9);
        for r in 0..self.radars.len() {
            self.push(SimTime::ZERO, Ev::Decide(r as u8));
        }
        let reqs = self.ta.start(&self.ctx());
        self.handle_requests(reqs);
        while let Some(Reverse((t, _, _, ev))) = self.heap.pop() {
            if t > self.end {
                break;
            }
            self.now = t;
            match ev {
                Ev::Decide(r) => self.decide(r as usize),
                Ev::Start(g) => self.start_group(g),
                Ev::End(g) => {
                    if let Some(report) = self.reports.remove(&g) {
                        let ctx = self.ctx();
                        let reqs = self.ta.on_dwell(&ctx, &report);
                        self.collect_tracks();
                        self.handle_requests(reqs);
                    }
                }
                Ev::Wake => {
                    let ctx = self.ctx();
                    let reqs = self.ta.on_wake(&ctx, t.as_secs());
                    self.collect_tracks();
                    self.handle_requests(reqs);
                }
            }
        }
        self.now = self.end;
        let ctx = self.ctx();
        let rows = self.ta.finish(&ctx);
        self.tables.tracks.extend(rows);
        self.collect_tracks();
        (self.tables, self.stats)
    }

    fn collect_tracks(&mut self) {
        let rows = self.ta.take_track_rows();
        self.tables.tracks.extend(rows);
    }

    fn decide(&mut self, r: usize) {
        let now = self.now;
        let st = &self.radars[r];
        if st.busy_until > now || st.raster.is_empty() {
            return;
        }
        let beam = st.raster[st.cursor];
        let radar = RadarId(r as u8);
        let duration_s = dwell_duration_s(self.world.params(radar), beam.n_pulses);
        let search_end = now.plus_secs(duration_s);
        if search_end > self.end {
            return;
        }
        let next_res = st.reservations.first().map(|x| x.0);
        if next_res.is_some_and(|s| s < search_end) {
            return; // wait for the reservation; its Start event takes over
        }
        let n = st.raster.len();
        self.radars[r].cursor = (self.radars[r].cursor + 1) % n;
        let group = Group {
            kind: DwellKind::Search,
            requested_by: Requester::Radar,
            aim: None,
            parts: vec![Part {
                radar,
                role: Role::Txrx,
                face: beam.face,
                beam_u: beam.u,
                beam_v: beam.v,
                n_pulses: beam.n_pulses,
                waveform: 0,
            }],
            duration_s,
            window_half_m: None,
            predicted_snr: None,
            tag: Vec::new(),
        };
        let gid = self.alloc_group(group);
        self.start_group(gid);
    }

    fn alloc_group(&mut self, g: Group) -> u64 {
        let gid = self.next_dwell_id;
        self.next_dwell_id += g.parts.len() as u64;
        self.groups.insert(gid, g);
        gid
    }

    fn handle_requests(&mut self, mut reqs: Vec<Request>) {
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
                Request::Dwell(d) => self.place(d),
                Request::WakeAt(t_s) => {
                    if t_s.is_finite() {
                        let t = SimTime::from_secs(t_s).max(self.now);
                        self.push(t, Ev::Wake);
                    }
                }
                Request::StopLocalTracking(_) => self.stats.stop_local_tracking_orders += 1,
            }
        }
    }

    /// Plan a requested dwell's parts and reserve the earliest common slot.
    fn place(&mut self, req: DwellRequest) {
        // A start that is not a finite time inside the run can never be served.
        if !(req.earliest_s.is_finite() && req.earliest_s <= self.cfg.duration_s) {
            self.stats.rejected_requests += 1;
            return;
        }
        let Some(group) = self.plan(&req) else {
            self.stats.rejected_requests += 1;
            return;
        };
        let earliest = SimTime::from_secs(req.earliest_s.max(0.0)).max(self.now);
        let radars: Vec<usize> = group.parts.iter().map(|p| p.radar.index()).collect();
        let dur_ns = SimTime::from_secs(group.duration_s).0;
        let mut t = earliest;
        for &r in &radars {
            t = t.max(self.radars[r].busy_until);
        }
        // Move past overlapping reservations until every participant is free for [t, t+dur).
        loop {
            let mut moved = false;
            for &r in &radars {
                for &(s, e, _) in &self.radars[r].reservations {
                    if s.0 < t.0 + dur_ns && t < e {
                        t = e;
                        moved = true;
                    }
                }
            }
            if !moved {
                break;
            }
        }
        if SimTime(t.0 + dur_ns) > self.end {
            self.stats.rejected_requests += 1;
            return;
        }
        let gid = self.alloc_group(group);
        let end = SimTime(t.0 + dur_ns);
        for &r in &radars {
            let res = &mut self.radars[r].reservations;
            let pos = res.partition_point(|x| x.0 <= t);
            res.insert(pos, (t, end, gid));
        }
        self.push(t, Ev::Start(gid));
    }

    fn plan(&self, req: &DwellRequest) -> Option<Group> {
        if !req.aim_ecef.is_finite() || req.transmitters.is_empty() || req.receivers.is_empty() {
            return None;
        }
        let t = self.now.as_secs().max(req.earliest_s);
        let n = self.world.n_radars();
        let mut parts: Vec<Part> = Vec::new();
        let mut waveform = 0u32;
        let mut duration_s: f64 = 0.0;
        let add = |radar: RadarId, tx: Option<u32>, rx: bool, parts: &mut Vec<Part>| -> Option<()> {
            if radar.index() >= n {
                return None;
            }
            let params = self.world.params(radar);
            let faces = self.world.faces_at(radar, t);
            let bp = beam_point(&faces, params, req.aim_ecef)?;
            if let Some(p) = parts.iter_mut().find(|p| p.radar == radar) {
                // Already present (a transmitter that also receives).
                if rx {
                    p.role = Role::Txrx;
                }
                return Some(());
            }
            let n_pulses = tx.map(|n| n.clamp(1, params.max_pulses)).unwrap_or(0);
            let role = match (tx.is_some(), rx) {
                (true, true) => Role::Txrx,
                (true, false) => Role::Tx,
                _ => Role::Rx,
            };
            parts.push(Part { radar, role, face: bp.face, beam_u: bp.u, beam_v: bp.v, n_pulses, waveform: 0 });
            Some(())
        };
        for tx in &req.transmitters {
            let is_rx = req.receivers.contains(&tx.radar);
            if add(tx.radar, Some(tx.n_pulses), is_rx, &mut parts).is_some() {
                let p = self.world.params(tx.radar);
                let np = tx.n_pulses.clamp(1, p.max_pulses);
                duration_s = duration_s.max(dwell_duration_s(p, np));
                if let Some(part) = parts.iter_mut().find(|x| x.radar == tx.radar) {
                    part.waveform = waveform;
                    part.n_pulses = np;
                }
                waveform += 1;
            }
        }
        if !parts.iter().any(|p| p.role.transmits()) {
            return None;
        }
        for &rx in &req.receivers {
            let _ = add(rx, None, true, &mut parts);
        }
        if !parts.iter().any(|p| matches!(p.role, Role::Rx | Role::Txrx)) {
            return None;
        }
        Some(Group {
            kind: req.kind,
            requested_by: Requester::Ta,
            aim: Some(req.aim_ecef),
            parts,
            duration_s,
            window_half_m: Some(req.window_half_m.max(0.0)),
            predicted_snr: req.predicted_snr,
            tag: req.tag.clone(),
        })
    }

    /// Execute a group now: physics, rows, report, timelines.
    fn start_group(&mut self, gid: u64) {
        let Some(g) = self.groups.remove(&gid) else { return };
        let t0 = self.now.as_secs();
        let end = self.now.plus_secs(g.duration_s);
        let t_mid = t0 + 0.5 * g.duration_s;
        for p in &g.parts {
            let st = &mut self.radars[p.radar.index()];
            st.reservations.retain(|x| x.2 != gid);
            st.busy_until = end;
        }
        let world = self.world;
        // Participants' faces at mid-dwell.
        let faces: Vec<Vec<mimo_core::face::FaceFrame>> =
            g.parts.iter().map(|p| world.faces_at(p.radar, t_mid)).collect();
        let aim = g.aim.unwrap_or_else(|| {
            let (p, f) = (&g.parts[0], faces[0][g.parts[0].face as usize]);
            let d = f.face_from_ecef.transpose()
                * DVec3::new(p.beam_u, p.beam_v, (1.0 - p.beam_u * p.beam_u - p.beam_v * p.beam_v).max(0.0).sqrt());
            f.origin_ecef + d * (0.5 * world.params(p.radar).instrumented_range_m)
        });
        let txs: Vec<mimo_radar::Transmitter> = g
            .parts
            .iter()
            .zip(&faces)
            .filter(|(p, _)| p.role.transmits())
            .map(|(p, f)| mimo_radar::Transmitter {
                radar: p.radar,
                params: world.params(p.radar),
                frame: f[p.face as usize],
                beam_u: p.beam_u,
                beam_v: p.beam_v,
                n_pulses: p.n_pulses,
                waveform: p.waveform,
            })
            .collect();
        let rxs: Vec<mimo_radar::Receiver> = g
            .parts
            .iter()
            .enumerate()
            .zip(&faces)
            .filter(|((_, p), _)| matches!(p.role, Role::Rx | Role::Txrx))
            .map(|((i, p), f)| {
                let params = world.params(p.radar);
                let frame = f[p.face as usize];
                let window = match g.window_half_m {
                    None => mimo_radar::dwell::RangeWindow::Fixed {
                        rho_min_m: params.min_range_m,
                        rho_max_m: params.instrumented_range_m,
                    },
                    Some(half) => mimo_radar::dwell::RangeWindow::AroundAim { aim_ecef: aim, half_width_m: half },
                };
                mimo_radar::Receiver {
                    radar: p.radar,
                    dwell_id: gid + i as u64,
                    params,
                    face: p.face,
                    frame,
                    beam_u: p.beam_u,
                    beam_v: p.beam_v,
                    window,
                    predicted_snr: g.predicted_snr,
                }
            })
            .collect();
        let truth = world.targets_at(t_mid);
        let targets: Vec<mimo_radar::Target> = truth
            .iter()
            .map(|x| mimo_radar::Target { id: x.id, index: x.index, pos_ecef: x.pos_ecef, rcs_m2: x.rcs_m2 })
            .collect();
        let keys = [u64::from(self.run), gid];
        let dwell = mimo_radar::Dwell {
            run: self.run,
            t_s: t_mid,
            seed: self.cfg.seed,
            keys: &keys,
            transmitters: &txs,
            receivers: &rxs,
            fidelity: &world.scenario.fidelity,
            record_voltages: self.cfg.record_voltages,
            simulate_all_cells: false,
        };
        let out = mimo_radar::evaluate(&dwell, &targets);
        let meas = mimo_radar::measurements_from_primitives(&out.primitives, first_meas_id(gid));

        // Dwell rows.
        for (i, p) in g.parts.iter().enumerate() {
            let params = world.params(p.radar);
            let tx = p.role.transmits();
            self.tables.dwells.push(DwellRow {
                run: self.run,
                dwell_id: gid + i as u64,
                group_id: gid,
                radar: p.radar,
                role: p.role,
                kind: g.kind,
                requested_by: g.requested_by,
                t_s: t0,
                duration_s: g.duration_s,
                pulse_width_s: params.pulse_width_s,
                n_pulses: p.n_pulses,
                peak_power_w: if tx { params.peak_power_w } else { 0.0 },
                energy_j: if tx { dwell_energy_j(params, p.n_pulses) } else { 0.0 },
                waveform: p.waveform,
                face: p.face,
                beam_u: p.beam_u,
                beam_v: p.beam_v,
                aim_x_m: aim.x,
                aim_y_m: aim.y,
                aim_z_m: aim.z,
            });
        }
        self.stats.dwells += 1;
        match g.requested_by {
            Requester::Radar => self.stats.search_dwells += 1,
            Requester::Ta => self.stats.ta_dwells += 1,
        }
        self.stats.primitives += out.primitives.len() as u64;
        self.stats.measurements += meas.len() as u64;

        // The TA's view: no truth.
        let mut tm = meas.clone();
        tm.iter_mut().for_each(|m| m.target_hint = None);
        let mut tp = out.primitives.clone();
        tp.iter_mut().for_each(|p| p.target_hint = None);
        let parts = g
            .parts
            .iter()
            .enumerate()
            .map(|(i, p)| PartReport {
                radar: p.radar,
                dwell_id: gid + i as u64,
                transmits: p.role.transmits(),
                receives: matches!(p.role, Role::Rx | Role::Txrx),
                face: p.face,
                beam_u: p.beam_u,
                beam_v: p.beam_v,
                n_pulses: p.n_pulses,
            })
            .collect();
        let report = DwellReport {
            run: self.run,
            group_id: gid,
            kind: g.kind,
            requested_by: g.requested_by,
            t_s: t_mid,
            duration_s: g.duration_s,
            aim_ecef: aim,
            parts,
            tag: g.tag,
            measurements: tm,
            primitives: tp,
        };
        self.tables.primitives.extend(out.primitives);
        self.tables.voltages.extend(out.voltages);
        self.tables.measurements.extend(meas);
        self.reports.insert(gid, report);
        self.push(end, Ev::End(gid));
        for p in &g.parts {
            self.push(end, Ev::Decide(p.radar.0));
        }
    }
}
