//! The default solution: the paper's baseline test article.
//!
//! * Tracking: a [`MultiTargetTracker`] (EKF with NCV by default, or IMM) in a fixed ENU frame at
//!   the scenario centre, with χ² gating, GNN per dwell and channel, one-point initiation,
//!   2-of-3 confirmation and deletion after missed looks (see `mimo-track`, docs/model.md §6).
//! * Every delivered dwell goes to the tracker through [`dwell_context`], which depends only on
//!   what the dwells table records, so `mimo track` replays a recording with exactly the same
//!   inputs. Misses are counted from the dwell's beams (a track predicted inside a non-search
//!   beam and not updated has missed a look). It subscribes to dwells with detections and its
//!   own dwells: an empty search dwell changes nothing in its tracks.
//! * Scheduling ([`planner`]): each track is looked at when the tracker says it is due
//!   (covariance-based revisit, docs/model.md §7.1), with one dwell aimed at its predicted
//!   position and pulses sized for the wanted detection probability (§7.2); MIMO dwells for
//!   confirmed tracks more than one radar can see (§7.5).

mod afford;
mod budget;
mod config;
mod due_index;
#[cfg(test)]
mod fixture;
pub mod group;
mod hold;
pub mod near_index;
pub mod planner;
pub mod power;
pub mod search_manager;
pub mod snapshot;

pub use config::{DefaultTaConfig, ResourceConfig, check_optional_numbers};
pub use search_manager::SearchManagerConfig;

use crate::geometry::ShipGeometry;
use afford::Afford;
use budget::RadarBudget;
use due_index::DueIndex;
use mimo_core::ids::RadarId;
use mimo_core::records::Requester;
use mimo_core::records::{DwellKind, TrackStatus};
use mimo_sim::messages::{DwellReport, DwellRequest, PartReport, Reply, Request, StartInfo};
use mimo_sim::test_article::{TaFault, TestArticle};
use mimo_track::{DwellContext, Look, MultiTargetTracker, TrackDue};
use near_index::NearIndex;
use search_manager::SearchManager;
use snapshot::Snapshot;
use std::cell::RefCell;
use std::collections::{BTreeMap, BTreeSet};

/// The tracker's view of a finished dwell: everything comes from what the dwells table records
/// (kind, time, and each part's radar, role, face and beam), so closed loop and replay agree.
pub fn dwell_context(run: u32, group_id: u64, kind: DwellKind, t_mid_s: f64, parts: &[PartReport]) -> DwellContext {
    if kind == DwellKind::Search {
        return DwellContext::search(run, group_id, t_mid_s);
    }
    let mut ctx = DwellContext::aimed(run, group_id, t_mid_s, kind, Vec::new());
    for tx in parts.iter().filter(|p| p.transmits) {
        for rx in parts.iter().filter(|p| p.receives) {
            ctx.looks.push(Look {
                tx: tx.radar,
                rx: rx.radar,
                rx_face: rx.face,
                beam_u: rx.beam_u,
                beam_v: rx.beam_v,
                rho_window_m: None,
            });
        }
    }
    ctx
}

/// What the test article has once the run started.
struct Running {
    geom: ShipGeometry,
    /// `geom.ids()`, made once.
    radar_ids: Vec<RadarId>,
    tracker: MultiTargetTracker,
    run: u32,
    closed_loop: bool,
    /// The radars' registration, when on (docs/model.md §6.9).
    registration: Option<crate::registration::Registration>,
}

/// The default test article.
pub struct DefaultTa {
    name: String,
    cfg: DefaultTaConfig,
    state: Option<Running>,
    /// Tracks with a dwell requested and not yet reported.
    pending: BTreeMap<u64, f64>,
    /// Earliest wake-up already asked for.
    next_wake_s: f64,
    /// Each radar's recent test-article dwell time.
    budget: RadarBudget,
    /// Tracks whose last look returned a merged measurement.
    merged_last: BTreeSet<u64>,
    /// Tracks held as unresolved: not looked at again before this time (s).
    hold_until: BTreeMap<u64, f64>,
    /// The power budget (docs/model.md §7.6); `None` when unlimited.
    afford: Option<Afford>,
    /// The live tracks by the time they may be looked at ([`held_due`]).
    dues: DueIndex,
    /// The tracks' position balls in their grid, kept across passes ([`Snapshot::with_index`]).
    near: RefCell<NearIndex>,
    /// The background search it orders (nothing with the default settings).
    search: SearchManager,
}

impl DefaultTa {
    /// A default test article with this configuration, recorded under `name`.
    pub fn new(name: &str, cfg: DefaultTaConfig) -> DefaultTa {
        DefaultTa {
            name: name.to_string(),
            state: None,
            pending: BTreeMap::new(),
            next_wake_s: f64::INFINITY,
            budget: RadarBudget::default(),
            merged_last: BTreeSet::new(),
            hold_until: BTreeMap::new(),
            afford: Afford::of(&cfg.resource_manager),
            dues: DueIndex::default(),
            near: RefCell::default(),
            search: SearchManager::default(),
            cfg,
        }
    }

    /// The configuration.
    pub fn settings(&self) -> &DefaultTaConfig {
        &self.cfg
    }

    /// The registration estimate (`None` before `start` or when registration is off).
    pub fn registration(&self) -> Option<&crate::registration::Registration> {
        self.state.as_ref().and_then(|s| s.registration.as_ref())
    }

    /// The tracker (for statistics after a run; `None` before `start`).
    pub fn tracker(&self) -> Option<&MultiTargetTracker> {
        self.state.as_ref().map(|s| &s.tracker)
    }

    /// In the resource-manager role (docs/ta-protocol.md §7, [`crate::resource_manager`]) the
    /// looks this test article plans are proposals: those the external resource manager did not
    /// accept were never requested, so their tracks are not waiting for a report, and the rule
    /// proposes them again at the next event while they are due.
    pub fn forget_proposals<'a>(&mut self, rejected: impl IntoIterator<Item = &'a DwellRequest>) {
        for d in rejected {
            for id in &d.tag {
                self.pending.remove(id);
            }
        }
    }

    fn not_started() -> TaFault {
        TaFault::BadMessage("an event arrived before `start`".into())
    }

    /// Requests for every due track, and a wake-up for the next one.
    fn schedule(&mut self, now: f64) -> Vec<Request> {
        let Some(st) = &self.state else { return Vec::new() };
        if !st.closed_loop {
            return Vec::new();
        }
        #[cfg(test)]
        self.assert_dues_are_the_trackers();
        let rm = &self.cfg.resource_manager;
        self.budget.forget_before(now - rm.budget_window_s.max(rm.rx_busy_window_s));
        let limit_s = now + 1e-9;
        // The tracks to plan, in the tracker's order (by id): the due ones from the index, or
        // under a power budget every track in the budget's order.
        let due_now = self.dues.due_by(limit_s);
        let dues: Vec<TrackDue> = match &mut self.afford {
            None => due_now.iter().filter_map(|&id| st.tracker.track_due(id)).collect(),
            Some(a) => {
                let mut dues: Vec<_> = st.tracker.track_dues().collect();
                a.begin_pass(now);
                a.order(&mut dues);
                dues
            }
        };
        let pending_before: BTreeSet<u64> = self.pending.keys().copied().collect();
        let (mut out, waiting, mut next, ahead) = self.plan_pass(now, &dues);
        if self.afford.is_none() {
            // The earliest time another track falls due: every track not due now, except those
            // pending before their turn in the tracker's order (the pass saw only the due ones).
            let skip = |id: u64| due_now.contains(&id) || pending_before.contains(&id) || ahead.contains(&id);
            next = next.min(self.dues.next_after(limit_s, skip).unwrap_or(f64::INFINITY));
        }
        self.finish_pass(&mut out, waiting, next, now);
        out
    }

    /// Plan the tracks of `dues` in their order at `now`. Returns the requests, whether a look
    /// waits for the power budget, the earliest time of a track of `dues` not due yet, and the
    /// tracks not due now that rode along with a look before their turn in id order.
    fn plan_pass(&mut self, now: f64, dues: &[TrackDue]) -> (Vec<Request>, bool, f64, BTreeSet<u64>) {
        let (mut out, mut waiting, mut next, mut ahead) = (Vec::new(), false, f64::INFINITY, BTreeSet::new());
        let Some(st) = &self.state else { return (out, waiting, next, ahead) };
        let rm = &self.cfg.resource_manager;
        // Faces, heights and predicted positions at `now`, kept for every plan of this pass.
        let snap = Snapshot::new(&st.tracker, &st.geom, &st.radar_ids, now).with_index(&self.near);
        // The radars over their budget and those too busy to receive, found at the first look the
        // pass plans (most passes of a raid plan none: their tracks are not due yet).
        let mut shares: Option<(Vec<RadarId>, Vec<RadarId>)> = None;
        // The confirmed tracks due by the group look-ahead, found at the first group look.
        let mut soon_pool: Option<Vec<u64>> = None;
        for info in dues {
            if info.status == TrackStatus::Deleted || self.pending.contains_key(&info.id) {
                continue;
            }
            let due = held_due(&self.hold_until, info.id, info.next_due_s);
            if due > now + 1e-9 || due.is_nan() {
                next = next.min(due);
                continue;
            }
            let trouble = self.in_trouble(info);
            let (over_budget, busy_rx) = shares.get_or_insert_with(|| {
                let budget = &self.budget;
                (
                    radars_at_share(budget, snap.ids(), now, rm.max_ta_share, rm.budget_window_s),
                    radars_at_share(budget, snap.ids(), now, rm.rx_busy_share, rm.rx_busy_window_s),
                )
            });
            let planned = match &mut self.afford {
                None => planner::plan(rm, &snap, info, over_budget, &[], busy_rx, trouble),
                Some(a) => a.plan(rm, &snap, info, over_budget, busy_rx, trouble),
            };
            waiting |= planned.is_none() && self.afford.is_some();
            let Some((mut req, unresolved)) = planned else { continue };
            if unresolved {
                self.hold_until.insert(info.id, now + rm.unresolved_revisit_s);
            } else {
                self.hold_until.remove(&info.id);
            }
            self.dues.refresh(&st.tracker, &self.hold_until, info.id);
            self.pending.insert(info.id, now);
            if rm.group_looks && info.status == TrackStatus::Confirmed {
                // Confirmed tracks due soon in the same beam ride along (docs/model.md §7.2).
                let pool = soon_pool.get_or_insert_with(|| self.dues.confirmed_due_by(now + rm.group_lookahead_s));
                let pending = &self.pending;
                let soon = |o: u64| o != info.id && !pending.contains_key(&o);
                for id in ride_along(rm, &snap, &mut req, pool, soon) {
                    self.pending.insert(id, now);
                    if id > info.id {
                        ahead.insert(id);
                    }
                }
            }
            out.push(Request::Dwell(req));
        }
        (out, waiting, next, ahead)
    }

    /// Unit tests: the due index holds every live track at its [`held_due`], and nothing else.
    #[cfg(test)]
    fn assert_dues_are_the_trackers(&self) {
        let Some(st) = &self.state else { return };
        let walk: BTreeMap<u64, (u64, bool)> = st
            .tracker
            .track_dues()
            .map(|d| {
                let due = held_due(&self.hold_until, d.id, d.next_due_s).to_bits();
                (d.id, (due, d.status == TrackStatus::Confirmed))
            })
            .collect();
        let index: BTreeMap<u64, (u64, bool)> =
            self.dues.times().iter().map(|(&id, &(t, c))| (id, (t.to_bits(), c))).collect();
        assert_eq!(index, walk, "the due index is not the tracker's");
    }

    /// Whether a look at the due track `info` is in trouble: the last look missed, returned a
    /// merged measurement, or left the track so vague that the tracker wants it again at its
    /// shortest revisit.
    fn in_trouble(&self, info: &TrackDue) -> bool {
        let at_t_min = info.next_due_s - info.t_last_update_s <= self.cfg.tracker.revisit.t_min_s + 1e-6;
        info.consecutive_misses > 0 || self.merged_last.contains(&info.id) || at_t_min
    }

    /// End a scheduling pass: requests in the tracker's order under a power budget, and a
    /// wake-up at `next` (or when the budget frees energy for a `waiting` look) if not asked yet.
    fn finish_pass(&mut self, out: &mut Vec<Request>, waiting: bool, mut next: f64, now: f64) {
        if self.afford.is_some() {
            // Requests go out in the tracker's order, whatever order the budget planned them in,
            // so that a budget that never binds places exactly the same dwells.
            out.sort_by_key(|r| match r {
                Request::Dwell(d) => d.tag.first().copied().unwrap_or(u64::MAX),
                _ => u64::MAX,
            });
        }
        if waiting && let Some(t) = self.afford.as_ref().and_then(Afford::next_release_s) {
            // A look waits for the budget: plan again when the window frees energy.
            next = next.min(t);
        }
        if next.is_finite() && (next < self.next_wake_s - 1e-9 || self.next_wake_s <= now) {
            self.next_wake_s = next;
            out.push(Request::WakeAt(next));
        }
    }
}

/// The radars whose test-article share of the last `window_s` is at least `limit` (none when
/// `limit` ≥ 1).
fn radars_at_share(budget: &RadarBudget, ids: &[RadarId], now: f64, limit: f64, window_s: f64) -> Vec<RadarId> {
    if limit < 1.0 {
        ids.iter().copied().filter(|&r| budget.share(r, now, window_s) >= limit).collect()
    } else {
        Vec::new()
    }
}

/// When track `id`, due at `next_due_s`, may be looked at: not before its hold ends.
fn held_due(hold_until: &BTreeMap<u64, f64>, id: u64, next_due_s: f64) -> f64 {
    next_due_s.max(hold_until.get(&id).copied().unwrap_or(f64::NEG_INFINITY))
}

/// Add the tracks of `pool` (sorted by id) that `soon` accepts and that lie in the beam of
/// `req` to its tag, widening its range window to take them; returns the tracks added.
fn ride_along(
    rm: &ResourceConfig,
    snap: &Snapshot,
    req: &mut DwellRequest,
    pool: &[u64],
    soon: impl Fn(u64) -> bool,
) -> Vec<u64> {
    let Some(tx) = req.transmitters.first().map(|t| t.radar) else { return Vec::new() };
    let half = req.window_half_m;
    let members = group::members(rm, snap, req.aim_ecef, tx, pool, soon);
    for &(id, dist) in &members {
        req.tag.push(id);
        req.window_half_m = req.window_half_m.max(half + dist);
    }
    members.into_iter().map(|(id, _)| id).collect()
}

impl TestArticle for DefaultTa {
    fn name(&self) -> &str {
        &self.name
    }
    fn config(&self) -> serde_json::Value {
        serde_json::to_value(&self.cfg).unwrap_or_default()
    }
    fn on_start(&mut self, start: &StartInfo) -> Result<Reply, TaFault> {
        let geom = ShipGeometry::from_start(start);
        let tracker = MultiTargetTracker::new(self.cfg.tracker.clone(), geom.centre());
        let radar_ids = geom.ids();
        let reg = &self.cfg.registration;
        let registration = reg.enabled.then(|| crate::registration::Registration::new(radar_ids.len(), reg));
        self.state =
            Some(Running { geom, radar_ids, tracker, run: start.run, closed_loop: start.closed_loop, registration });
        self.pending.clear();
        self.next_wake_s = f64::INFINITY;
        self.budget.clear();
        self.merged_last.clear();
        self.hold_until.clear();
        self.dues.clear();
        *self.near.get_mut() = NearIndex::default();
        self.afford = Afford::of(&self.cfg.resource_manager);
        Ok(Reply::requests(self.search.start(&self.cfg.search_manager, start.closed_loop)))
    }
    fn on_dwell(&mut self, report: &DwellReport) -> Result<Reply, TaFault> {
        let merged = report.measurements.iter().any(|m| m.merged);
        for id in &report.tag {
            self.pending.remove(id);
            if merged {
                self.merged_last.insert(*id);
            } else {
                self.merged_last.remove(id);
            }
        }
        if report.requested_by == Requester::Ta {
            for p in &report.parts {
                self.budget.record(p.radar, report.t_s, report.duration_s);
            }
        }
        let st = self.state.as_mut().ok_or_else(Self::not_started)?;
        let dctx = dwell_context(st.run, report.group_id, report.kind, report.t_s, &report.parts);
        // With registration on, the tracker sees measurements corrected by the estimate so far,
        // and the look then teaches the estimate (docs/model.md §6.9).
        let corrected = st.registration.as_ref().map(|r| r.correct(report, &st.geom));
        let rows = st.tracker.process_dwell(&dctx, corrected.as_deref().unwrap_or(&report.measurements), &st.geom);
        if let Some(r) = &mut st.registration {
            r.learn(report, &st.geom);
        }
        let changed = !rows.is_empty() || !report.tag.is_empty();
        if let Some(a) = &mut self.afford {
            a.on_dwell(report, report.requested_by == Requester::Ta, &rows, &st.geom);
        }
        for r in &rows {
            if r.status == TrackStatus::Deleted {
                self.pending.remove(&r.track_id);
                self.merged_last.remove(&r.track_id);
                self.hold_until.remove(&r.track_id);
            }
        }
        for &id in st.tracker.changed_tracks() {
            self.dues.refresh(&st.tracker, &self.hold_until, id);
        }
        self.near.get_mut().mark(st.tracker.changed_tracks());
        let mut requests = if changed { self.schedule(report.end_s) } else { Vec::new() };
        self.search.note_rows(&rows, report.end_s);
        requests.extend(self.search.update(&self.cfg.search_manager, report.end_s));
        Ok(Reply::with_tracks(requests, rows))
    }
    /// At the end of the run, the registration estimate (when registration is on) goes into the
    /// run's `registration` table (docs/model.md §6.9).
    fn on_finish(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        let Some(st) = self.state.as_ref() else { return Ok(Reply::default()) };
        let registration = st.registration.as_ref().map(|r| r.rows(t_s, &st.radar_ids)).unwrap_or_default();
        Ok(Reply { registration, ..Reply::default() })
    }
    fn on_wake(&mut self, t_s: f64) -> Result<Reply, TaFault> {
        if t_s + 1e-9 >= self.next_wake_s {
            self.next_wake_s = f64::INFINITY;
        }
        let mut requests = self.schedule(t_s);
        requests.extend(self.search.update(&self.cfg.search_manager, t_s));
        Ok(Reply::requests(requests))
    }
}
