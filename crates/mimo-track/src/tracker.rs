//! The multi-target tracker: components composed into a dwell-by-dwell tracking loop.

use crate::components::Components;
use crate::config::{InitiateOn, TrackerConfig, TrackerKind};
use crate::deletion::{DeleteReason, TrackView};
use crate::diagnostics::{NisRecord, TrackerStats};
use crate::dwell::{DwellContext, Look};
use crate::filter::FilterState;
use crate::frame::{Gaussian, StateEcef, TrackFrame};
use crate::geometry::SensorGeometry;
use crate::initiation::Confirmation;
use crate::measurement::{BistaticRuv, PreparedMeasurement};
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, MeasurementRow, TrackRow, TrackStatus, pack_cov};
use std::collections::{BTreeMap, BTreeSet};
use std::fmt;

/// A live track.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// Track id (unique within a tracker).
    pub id: u64,
    /// Tentative or confirmed.
    pub status: TrackStatus,
    /// Filter state at `t_s`.
    pub state: FilterState,
    /// Time of the last update (or initiation) (s).
    pub t_s: f64,
    /// Time of initiation (s).
    pub t_init_s: f64,
    /// Updates so far (counting the initiating detections).
    pub n_updates: u32,
    /// Last measurement used.
    pub last_meas_id: Option<u64>,
    /// Confirmation looks while tentative (`true` = detected), starting with the initiation.
    pub looks: Vec<bool>,
    /// Missed looks in a row.
    pub consecutive_misses: u32,
    /// When the track should next be looked at (s).
    pub next_due_s: f64,
    /// Receiver and face of the last update.
    pub last_face: Option<(RadarId, u8)>,
    /// Sum of NIS over updates.
    pub nis_sum: f64,
    /// Number of updates in `nis_sum`.
    pub nis_count: u32,
}

impl Track {
    /// A track `id` in `state` started at `t_s` from an external estimate: no updates, no
    /// misses, no measurement, due at once.
    fn started(id: u64, status: TrackStatus, state: FilterState, t_s: f64) -> Track {
        Track {
            id,
            status,
            state,
            t_s,
            t_init_s: t_s,
            n_updates: 0,
            last_meas_id: None,
            looks: vec![true],
            consecutive_misses: 0,
            next_due_s: t_s,
            last_face: None,
            nis_sum: 0.0,
            nis_count: 0,
        }
    }

    /// A confirmed track `id` in `state` at `t_s` after `n_updates` updates, with no misses, for
    /// the unit tests.
    #[cfg(test)]
    pub(crate) fn confirmed_for_test(id: u64, state: FilterState, t_s: f64, n_updates: u32) -> Track {
        Track { n_updates, ..Track::started(id, TrackStatus::Confirmed, state, t_s) }
    }
}

/// A multi-target tracker: filter, gate, GNN association, initiation, M-of-N confirmation and
/// deletion, driven one dwell at a time.
pub struct MultiTargetTracker {
    pub(crate) config: TrackerConfig,
    pub(crate) frame: TrackFrame,
    pub(crate) c: Components,
    pub(crate) tracks: BTreeMap<u64, Track>,
    pub(crate) next_id: u64,
    pub(crate) nis_log: Vec<NisRecord>,
    pub(crate) stats: TrackerStats,
    /// Deletion checks known to keep their track (docs/model.md §6.4).
    pub(crate) quiet: crate::deletion_quiet::QuietTracks,
    /// Predictions made in the current dwell, for its other channels and its deletion pass.
    pub(crate) preds: crate::dwell_predictions::DwellPredictions,
    /// Observed power (linear SNR) of each live track's initiating detection: the score by which
    /// the tentative-track budget sheds (docs/model.md §6.4).
    pub(crate) initiation_power: BTreeMap<u64, f64>,
    /// Where each track can be over the next seconds (the channels' spatial pre-selection).
    pub(crate) balls: crate::track_balls::TrackBalls,
    /// Tracks started, updated, looked at or deleted by the last dwell, and started by
    /// [`Self::spawn_track`] since ([`Self::changed_tracks`]).
    pub(crate) changed: Vec<u64>,
}

impl fmt::Debug for MultiTargetTracker {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MultiTargetTracker")
            .field("filter", &self.c.filter.name())
            .field("tracks", &self.tracks.len())
            .field("stats", &self.stats)
            .finish()
    }
}

impl MultiTargetTracker {
    /// A built-in tracker tracking in the ENU frame at `centre`.
    pub fn new(config: TrackerConfig, centre: Geodetic) -> MultiTargetTracker {
        let c = Components::from_config(&config);
        MultiTargetTracker::with_components(config, centre, c)
    }

    /// A built-in tracker by name (`"default"`, `"imm"`) with its default configuration.
    pub fn by_name(name: &str, centre: Geodetic) -> Option<MultiTargetTracker> {
        TrackerKind::parse(name).map(|k| MultiTargetTracker::new(TrackerConfig::for_kind(k), centre))
    }

    /// A tracker from custom components. `config` still supplies the measurement handling,
    /// IEKF schedule, revisit policy and the other tracker-level settings.
    pub fn with_components(config: TrackerConfig, centre: Geodetic, components: Components) -> MultiTargetTracker {
        MultiTargetTracker {
            config,
            frame: TrackFrame::new(centre),
            c: components,
            tracks: BTreeMap::new(),
            next_id: 1,
            nis_log: Vec::new(),
            stats: TrackerStats::default(),
            quiet: Default::default(),
            preds: Default::default(),
            initiation_power: BTreeMap::new(),
            balls: Default::default(),
            changed: Vec::new(),
        }
    }

    /// The configuration.
    pub fn config(&self) -> &TrackerConfig {
        &self.config
    }

    /// The tracking frame.
    pub fn frame(&self) -> &TrackFrame {
        &self.frame
    }

    /// Name of the filter (for manifests).
    pub fn filter_name(&self) -> String {
        self.c.filter.name()
    }

    /// Counters so far.
    pub fn stats(&self) -> &TrackerStats {
        &self.stats
    }

    /// Every update's NIS so far.
    pub fn nis_log(&self) -> &[NisRecord] {
        &self.nis_log
    }

    /// Take (and clear) the NIS log.
    pub fn take_nis_log(&mut self) -> Vec<NisRecord> {
        std::mem::take(&mut self.nis_log)
    }

    /// The tracks whose scheduling state ([`crate::TrackDue`]) the last [`Self::process_dwell`]
    /// may have changed (started, updated, looked at or deleted), and those started by
    /// [`Self::spawn_track`] since, in no particular order and possibly repeated: every other
    /// track is as it was.
    pub fn changed_tracks(&self) -> &[u64] {
        &self.changed
    }

    /// A live track.
    pub fn track(&self, id: u64) -> Option<&Track> {
        self.tracks.get(&id)
    }
    /// Start a track from an external estimate (a cue, or a test). Returns its id and row.
    pub fn spawn_track(
        &mut self,
        run: u32,
        t_s: f64,
        state: &StateEcef,
        status: TrackStatus,
    ) -> Option<(u64, TrackRow)> {
        let g = self.frame.state_from_ecef(state);
        if !g.is_finite() || !t_s.is_finite() || status == TrackStatus::Deleted {
            return None;
        }
        let id = self.next_id;
        self.next_id += 1;
        let track = Track::started(id, status, self.c.filter.init(g), t_s);
        let row = self.row_of(run, &track, &track.state.combined(), t_s, status);
        self.tracks.insert(id, track);
        self.quiet.touch(id);
        self.changed.push(id);
        Some((id, row))
    }

    fn row_of(&self, run: u32, t: &Track, g: &Gaussian, t_s: f64, status: TrackStatus) -> TrackRow {
        let e = self.frame.state_to_ecef(g);
        TrackRow {
            run,
            t_s,
            track_id: t.id,
            status,
            x_m: e.pos.x,
            y_m: e.pos.y,
            z_m: e.pos.z,
            vx_mps: e.vel.x,
            vy_mps: e.vel.y,
            vz_mps: e.vel.z,
            cov: pack_cov(&e.cov),
            n_updates: t.n_updates,
            last_meas_id: t.last_meas_id,
        }
    }

    /// Process one finished dwell: associate its measurements (per receive channel, GNN),
    /// update tracks, count misses on the tracks it looked at, initiate tentative tracks from
    /// unclaimed search detections, run confirmation and deletion. Returns one row per track
    /// updated or initiated (its state after the dwell) and one `deleted` row per track ended.
    /// Invalid measurement rows are skipped and counted in [`TrackerStats`].
    pub fn process_dwell(
        &mut self,
        ctx: &DwellContext,
        meas: &[MeasurementRow],
        geom: &dyn SensorGeometry,
    ) -> Vec<TrackRow> {
        let mut rows = Vec::new();
        if !ctx.t_s.is_finite() {
            self.stats.rejected_measurements += meas.len() as u64;
            return rows;
        }
        self.stats.dwells += 1;
        self.stats.measurements += meas.len() as u64;
        self.preds.clear();
        self.changed.clear();

        // Validate and group by channel; order within a channel by measurement id so that the
        // result never depends on the caller's row order.
        let mut channels: BTreeMap<(RadarId, RadarId), Vec<PreparedMeasurement>> = BTreeMap::new();
        for row in meas {
            match PreparedMeasurement::from_row(row, geom, &self.frame, &self.config.measurement) {
                Ok(pm) => channels.entry((pm.tx, pm.rx)).or_default().push(pm),
                Err(_) => self.stats.rejected_measurements += 1,
            }
        }
        for list in channels.values_mut() {
            list.sort_by(|a, b| a.meas_id.cmp(&b.meas_id).then(a.rx_face.cmp(&b.rx_face)));
        }

        let initiate_on = self.config.initiate_on;
        let may_initiate = |tx: RadarId, rx: RadarId| match initiate_on {
            _ if ctx.kind == DwellKind::Search => true,
            InitiateOn::Search => false,
            InitiateOn::SearchAndMonostatic => tx == rx,
            InitiateOn::AnyDwell => true,
        };
        let mut updated: BTreeSet<u64> = BTreeSet::new();
        let mut excused: BTreeSet<u64> = BTreeSet::new();
        let mut new_ids: Vec<u64> = Vec::new();
        for list in channels.values() {
            let init = list.first().is_some_and(|m| may_initiate(m.tx, m.rx));
            self.process_channel(ctx, list, init, &mut updated, &mut excused, &mut new_ids);
        }

        // Looks: explicit targets, plus tracks inside a non-search beam.
        let mut looked: BTreeSet<u64> = ctx.target_tracks.iter().copied().collect();
        if ctx.kind != DwellKind::Search && self.config.beam_miss_fraction > 0.0 {
            looked.extend(self.tracks_in_looks(ctx, geom));
        }
        // A track whose unresolved partner took the pair's return missed nothing (docs/model.md §6.5).
        looked.retain(|id| !excused.contains(id));

        let mut rejected: BTreeSet<u64> = BTreeSet::new();
        // Only the tracks the dwell started, updated or looked at change (in id order, as every
        // track's turn would come).
        let mut touched = looked;
        touched.extend(updated.iter().copied().chain(new_ids.iter().copied()));
        for id in touched {
            let is_new = new_ids.contains(&id);
            let hit = updated.contains(&id);
            let Some(track) = self.tracks.get_mut(&id) else { continue };
            self.quiet.touch(id);
            self.changed.push(id);
            if is_new {
                // Initiation may already satisfy M-of-N (two-point initiation).
                if self.c.confirmer.decide(&track.looks) == Confirmation::Confirm {
                    track.status = TrackStatus::Confirmed;
                    self.stats.confirmed += 1;
                }
                track.next_due_s = track.t_s + self.config.revisit.confirm_delay_s;
            } else {
                if track.status == TrackStatus::Tentative {
                    track.looks.push(hit);
                    match self.c.confirmer.decide(&track.looks) {
                        Confirmation::Confirm => {
                            track.status = TrackStatus::Confirmed;
                            self.stats.confirmed += 1;
                        }
                        Confirmation::Reject => {
                            rejected.insert(id);
                        }
                        Confirmation::Pending => {}
                    }
                }
                if hit {
                    track.consecutive_misses = 0;
                } else {
                    track.consecutive_misses += 1;
                    track.next_due_s = ctx.t_s + self.config.revisit.redwell_delay_s;
                }
            }
            if hit || is_new {
                let next = self.next_due_after_update(id, geom);
                let Some(track) = self.tracks.get_mut(&id) else { continue };
                if let Some(next) = next {
                    track.next_due_s = next;
                }
                let track = &self.tracks[&id];
                let g = track.state.combined();
                rows.push(self.row_of(ctx.run, track, &g, track.t_s, track.status));
            }
        }

        rejected.extend(self.over_budget_tentative());
        rows.extend(self.delete_pass(ctx.run, ctx.t_s, &rejected));
        rows
    }

    /// The tentative tracks beyond `false_tracks.max_tentative`, weakest initiating detection
    /// first (docs/model.md §6.4).
    fn over_budget_tentative(&self) -> Vec<u64> {
        let max = self.config.false_tracks.max_tentative;
        if max == 0 {
            return Vec::new();
        }
        let mut tentative: Vec<(u64, f64)> = self
            .tracks
            .values()
            .filter(|t| t.status == TrackStatus::Tentative)
            .map(|t| (t.id, self.initiation_power.get(&t.id).copied().unwrap_or(0.0)))
            .collect();
        crate::initiation_evidence::shed_weakest(&mut tentative, max)
    }

    /// Run only the deletion rules at `t_s` (coasting limits, covariance growth); use between
    /// dwells if the scheduler wants tracks to end on time. Returns the `deleted` rows.
    pub fn maintain(&mut self, run: u32, t_s: f64) -> Vec<TrackRow> {
        if !t_s.is_finite() {
            return Vec::new();
        }
        self.delete_pass(run, t_s, &BTreeSet::new())
    }

    fn next_due_after_update(&self, id: u64, geom: &dyn SensorGeometry) -> Option<f64> {
        let t = self.tracks.get(&id)?;
        if t.status != TrackStatus::Confirmed {
            return Some(t.t_s + self.config.revisit.confirm_delay_s);
        }
        let (rx, face) = t.last_face?;
        let f = geom.face(rx, face, t.t_s)?;
        Some(t.t_s + self.revisit_interval(id, &f)?)
    }

    fn tracks_in_looks(&self, ctx: &DwellContext, geom: &dyn SensorGeometry) -> Vec<u64> {
        let theta = self.config.revisit.beamwidth * self.config.beam_miss_fraction;
        let mut out = Vec::new();
        let models: Vec<(Look, BistaticRuv)> = ctx
            .looks
            .iter()
            .filter_map(|l| {
                BistaticRuv::from_geometry(&self.frame, geom, l.tx, l.rx, l.rx_face, ctx.t_s).ok().map(|m| (*l, m))
            })
            .collect();
        for (id, t) in &self.tracks {
            // A track whose kept ball is clear of every look's beam is in none of them: its
            // prediction, which the ball holds, is not needed (crate::track_balls).
            let ball = self.balls.kept(t, ctx.t_s - t.t_s);
            if ball.is_some_and(|b| models.iter().all(|(look, m)| b.clear_of_beam(m, look.beam_u, look.beam_v, theta)))
            {
                continue;
            }
            let x = self.c.filter.predict_mean(&t.state, ctx.t_s - t.t_s);
            let p = mimo_core::DVec3::new(x[0], x[1], x[2]);
            for (look, m) in &models {
                let l = crate::linalg::mul_vec(&m.m, &(p - m.rx).to_array());
                if l[2] <= 0.0 {
                    continue;
                }
                let z = m.h_pos(p);
                let (du, dv) = (z[1] - look.beam_u, z[2] - look.beam_v);
                let in_beam = du * du + dv * dv <= theta * theta;
                let in_window = look.rho_window_m.is_none_or(|(lo, hi)| z[0] / 2.0 >= lo && z[0] / 2.0 <= hi);
                if in_beam && in_window {
                    out.push(*id);
                    break;
                }
            }
        }
        out
    }
    /// The deletion rules at `t_s` for the tracks the certificates' expiry queue names and the
    /// `rejected` ones, in id order: every other track's check is sure to keep it
    /// (docs/model.md §6.4, `crate::quiet_expiry`).
    fn delete_pass(&mut self, run: u32, t_s: f64, rejected: &BTreeSet<u64>) -> Vec<TrackRow> {
        let mut rows = Vec::new();
        let mut gone = Vec::new();
        let mut named = self.quiet.candidates(t_s);
        named.extend(rejected.iter().copied());
        #[cfg(test)]
        self.assert_named_cover_scan(t_s, rejected, &named);
        for id in &named {
            let Some(t) = self.tracks.get(id) else { continue };
            if !rejected.contains(id) && self.quiet.is_quiet(&*self.c.filter, &*self.c.deleter, t, t_s) {
                continue;
            }
            let g = match self.preds.find(t, t_s) {
                Some(p) => p.combined,
                None => self.c.filter.predict(&t.state, t_s - t.t_s).combined,
            };
            let reason = if rejected.contains(id) {
                Some(DeleteReason::Unconfirmed)
            } else if !g.is_finite() {
                Some(DeleteReason::Divergence)
            } else {
                self.c.deleter.check(&TrackView::of(t, t_s, &g))
            };
            if let Some(r) = reason {
                // The final row carries the last estimate (extrapolated to the deletion time
                // when it is finite).
                let out = if g.is_finite() { g } else { t.state.combined() };
                rows.push(self.row_of(run, t, &out, t_s, TrackStatus::Deleted));
                gone.push((*id, r));
            }
        }
        for (id, r) in gone {
            self.tracks.remove(&id);
            self.initiation_power.remove(&id);
            self.quiet.forget(id);
            self.balls.forget(id);
            self.changed.push(id);
            *self.stats.deleted.entry(r).or_insert(0) += 1;
        }
        rows
    }

    /// Unit tests: every track the full scan would check at `t_s` (rejected, or not quiet) is
    /// among the `named` ones.
    #[cfg(test)]
    fn assert_named_cover_scan(&mut self, t_s: f64, rejected: &BTreeSet<u64>, named: &BTreeSet<u64>) {
        for (id, t) in &self.tracks {
            let checked = rejected.contains(id) || !self.quiet.is_quiet(&*self.c.filter, &*self.c.deleter, t, t_s);
            assert!(!checked || named.contains(id), "track {id} checked by the scan at {t_s} but not named");
        }
    }
}
