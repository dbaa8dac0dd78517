//! The default solution: the paper's baseline test article.
//!
//! * Tracking: a [`MultiTargetTracker`] (`default` = EKF with NCV, or `imm`) in a fixed ENU frame
//!   at the scenario centre, with χ² gating, GNN per dwell and channel, one-point initiation from
//!   search detections, 2-of-3 confirmation and deletion after missed looks (see `mimo-track`).
//! * Every finished dwell (search or not) goes to the tracker through [`dwell_context`], which
//!   depends only on what the dwells table records, so `mimo track` can replay a recording with
//!   exactly the same inputs. Misses are counted from the dwell's beams (a track predicted
//!   inside a non-search beam and not updated has missed a look).
//! * Scheduling: each track is looked at when the tracker says it is due (covariance-based
//!   revisit, PHYSICS.md §7.1; confirmation 0.3 s after initiation; re-dwell 50 ms after a miss).
//!   A due track gets one dwell aimed at its predicted position, with its range window
//!   `ρ̂ ± max(5σ_ρ, 1 km)`.
//! * Energy (§7.2): pulses sized for P_D = 0.9 on the best monostatic pair, assuming the track's
//!   RCS is `assumed_rcs_m2` (the TA does not know the target type), with the expected
//!   beam-pointing (V₀ = 0.2) and straddle losses; a miss is followed at once by a re-dwell with
//!   doubled energy, up to twice; after that the track is handed to the next-best radar (the
//!   best one may not see it at all, e.g. a low target just beyond its horizon).
//! * MIMO: when two or more radars can see the predicted position (scan limit, horizon,
//!   bistatic angle ≤ 150°), a confirmed track's dwell is a MIMO dwell: the radar with the best
//!   predicted SNR transmits, and every radar that can see the aim point receives.

use crate::ta::{DwellReport, DwellRequest, PartReport, Request, TaContext, TestArticle, TxOrder};
use crate::world::{Radars, World};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, TrackRow, TrackStatus};
use mimo_radar::energy::{pointing_loss, predict_pair, pulses_for, required_snr_sw1, straddle_loss};
use mimo_track::{DwellContext, Look, MultiTargetTracker, TrackerConfig, TrackerKind};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Immediate re-dwells with doubled energy after a miss before the TA tries another radar.
pub const MAX_REDWELLS: u32 = 2;

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

/// Settings of the default TA's resource manager (the tracker has its own).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DefaultTaConfig {
    /// Detection probability each track look is sized for.
    pub pd_target: f64,
    /// Detection probability the confirmation looks of a tentative track are sized for until it
    /// is seen again (without doubling on a miss). Most tentative tracks are false alarms, so
    /// these looks are cheap; once a tentative track has been seen again, looks are sized for
    /// `pd_target`.
    pub confirm_pd: f64,
    /// RCS assumed when sizing dwells (m²): the fighters' 2 m², so airliners are over-served.
    pub assumed_rcs_m2: f64,
    /// Pointing error the energy budget allows for, in beamwidths (V₀).
    pub pointing_sharpness: f64,
    /// Use MIMO dwells for confirmed tracks seen by more than one radar.
    pub mimo: bool,
    /// Smallest half-width of a track dwell's range window (m).
    pub min_window_half_m: f64,
    /// Range window half-width in predicted range standard deviations.
    pub window_sigmas: f64,
}

impl Default for DefaultTaConfig {
    fn default() -> Self {
        DefaultTaConfig {
            pd_target: 0.9,
            confirm_pd: 0.7,
            assumed_rcs_m2: 2.0,
            pointing_sharpness: 0.2,
            mimo: true,
            min_window_half_m: 1000.0,
            window_sigmas: 5.0,
        }
    }
}

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

/// The default test article.
pub struct DefaultTa<'w> {
    radars: Radars<'w>,
    name: String,
    cfg: DefaultTaConfig,
    tracker: MultiTargetTracker,
    rows: Vec<TrackRow>,
    /// Tracks with a dwell requested and not yet reported.
    pending: BTreeMap<u64, f64>,
    /// Earliest wake-up already asked for.
    next_wake_s: f64,
}

impl<'w> DefaultTa<'w> {
    /// `default` (EKF) or `imm`.
    pub fn by_name(name: &str, world: &'w World) -> Option<DefaultTa<'w>> {
        let kind = TrackerKind::parse(name)?;
        Some(DefaultTa::new(world, TrackerConfig::for_kind(kind), DefaultTaConfig::default(), name))
    }

    pub fn new(world: &'w World, tcfg: TrackerConfig, cfg: DefaultTaConfig, name: &str) -> DefaultTa<'w> {
        let radars = Radars::of(world);
        let tracker = MultiTargetTracker::new(tcfg, radars.centre());
        DefaultTa {
            radars,
            name: name.to_string(),
            cfg,
            tracker,
            rows: Vec::new(),
            pending: BTreeMap::new(),
            next_wake_s: f64::INFINITY,
        }
    }

    /// The tracker (for statistics after a run).
    pub fn tracker(&self) -> &MultiTargetTracker {
        &self.tracker
    }

    /// Requests for every due track, and a wake-up for the next one.
    fn schedule(&mut self, ctx: &TaContext) -> Vec<Request> {
        let now = ctx.t_s;
        let mut out = Vec::new();
        let mut next = f64::INFINITY;
        for info in self.tracker.tracks() {
            if info.status == TrackStatus::Deleted || self.pending.contains_key(&info.id) {
                continue;
            }
            if info.next_due_s <= now + 1e-9 {
                if let Some(req) = self.plan(ctx, info.id, info.status, info.consecutive_misses, info.n_updates) {
                    self.pending.insert(info.id, now);
                    out.push(Request::Dwell(req));
                }
            } else {
                next = next.min(info.next_due_s);
            }
        }
        if next.is_finite() && (next < self.next_wake_s - 1e-9 || self.next_wake_s <= now) {
            self.next_wake_s = next;
            out.push(Request::WakeAt(next));
        }
        out
    }

    /// One dwell for a track at time `ctx.t_s`.
    fn plan(&self, ctx: &TaContext, id: u64, status: TrackStatus, misses: u32, n_updates: u32) -> Option<DwellRequest> {
        let w = self.radars;
        let t = ctx.t_s;
        let pred = self.tracker.predict(id, t)?;
        let aim = pred.pos;
        let ids = w.ids();
        let faces: Vec<_> = ids.iter().map(|&r| w.faces_at(r, t)).collect();
        // Candidate transmitters: monostatic predictions.
        let mut candidates: Vec<(RadarId, f64, u8)> = ids
            .iter()
            .zip(&faces)
            .filter_map(|(&r, f)| {
                let p = w.params(r);
                predict_pair(p, f, p, f, aim, self.cfg.assumed_rcs_m2).map(|pp| (r, pp.snr1, pp.rx_face))
            })
            .collect();
        // Best predicted SNR first (ties by radar id, so the choice is deterministic).
        candidates.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        if candidates.is_empty() {
            return None;
        }
        // After `MAX_REDWELLS` misses in a row the best radar may not see the target at all (a
        // track just above its predicted horizon, say): hand the track to the next radar.
        let k = (misses / (MAX_REDWELLS + 1)) as usize % candidates.len();
        let (tx, snr1, face) = candidates[k];
        let p = w.params(tx);
        let losses = pointing_loss(self.cfg.pointing_sharpness, self.cfg.pointing_sharpness, true) * straddle_loss();
        // Until a tentative track is seen again, its looks are cheap (most are false alarms).
        let unconfirmed = status == TrackStatus::Tentative && n_updates <= 1;
        let pd = if unconfirmed { self.cfg.confirm_pd } else { self.cfg.pd_target };
        let mut n = pulses_for(required_snr_sw1(pd, p.pfa), snr1, losses, p.max_pulses);
        if !unconfirmed {
            // PHYSICS §7.2: re-dwell with doubled energy, up to twice.
            n = n.saturating_mul(1 << (misses % (MAX_REDWELLS + 1))).min(p.max_pulses);
        }
        let pm = self.tracker.predict_measurement(id, t, tx, tx, face, &w);
        let sigma_rho = pm.map(|m| m.sigma_rho_m).unwrap_or(0.0);
        let half = (self.cfg.window_sigmas * sigma_rho).max(self.cfg.min_window_half_m);
        let mut receivers = vec![tx];
        if self.cfg.mimo && status == TrackStatus::Confirmed {
            let tx_faces = &faces[tx.index()];
            for (&r, f) in ids.iter().zip(&faces) {
                if r != tx && predict_pair(p, tx_faces, w.params(r), f, aim, self.cfg.assumed_rcs_m2).is_some() {
                    receivers.push(r);
                }
            }
        }
        let kind = match (status, receivers.len() > 1) {
            (TrackStatus::Tentative, _) => DwellKind::Confirm,
            (_, true) => DwellKind::Mimo,
            _ => DwellKind::Track,
        };
        Some(DwellRequest {
            kind,
            earliest_s: t,
            aim_ecef: aim,
            transmitters: vec![TxOrder { radar: tx, n_pulses: n }],
            predicted_snr: (receivers.len() == 1).then(|| snr1 * f64::from(n)),
            receivers,
            window_half_m: half,
            tag: vec![id],
        })
    }
}

impl TestArticle for DefaultTa<'_> {
    fn name(&self) -> &str {
        &self.name
    }
    fn config(&self) -> serde_json::Value {
        serde_json::json!({
            "tracker": serde_json::to_value(self.tracker.config()).unwrap_or_default(),
            "resource_manager": serde_json::to_value(&self.cfg).unwrap_or_default(),
        })
    }
    fn on_dwell(&mut self, ctx: &TaContext, report: &DwellReport) -> Vec<Request> {
        for id in &report.tag {
            self.pending.remove(id);
        }
        let dctx = dwell_context(report.run, report.group_id, report.kind, report.t_s, &report.parts);
        let rows = self.tracker.process_dwell(&dctx, &report.measurements, &self.radars);
        let changed = !rows.is_empty() || !report.tag.is_empty();
        for r in &rows {
            if r.status == TrackStatus::Deleted {
                self.pending.remove(&r.track_id);
            }
        }
        self.rows.extend(rows);
        if changed { self.schedule(ctx) } else { Vec::new() }
    }
    fn on_wake(&mut self, ctx: &TaContext, t_s: f64) -> Vec<Request> {
        if t_s + 1e-9 >= self.next_wake_s {
            self.next_wake_s = f64::INFINITY;
        }
        self.schedule(ctx)
    }
    fn take_track_rows(&mut self) -> Vec<TrackRow> {
        std::mem::take(&mut self.rows)
    }
}
