//! One receive channel of a dwell: gate every track against the channel's measurements,
//! associate, update, and start tentative tracks from unclaimed detections (docs/model.md §6.4,
//! §6.5).

use crate::association::HypothesisTable;
use crate::diagnostics::NisRecord;
use crate::dwell::DwellContext;
use crate::dwell_predictions::DwellPredictions;
use crate::filter::{FilterPrediction, FilterUpdate, TrackFilter};
use crate::jpda::{AssociationProbabilities, combine};
use crate::measurement::{MeasurementModel, PreparedMeasurement};
use crate::partner::PartnerMode;
use crate::pregate::{BoundCache, PreGate};
use crate::reached;
use crate::state_stamp::StateStamp;
use crate::tracker::{MultiTargetTracker, Track};
use mimo_core::records::TrackStatus;
use std::collections::BTreeSet;

/// Per-track cache of predictions within one channel (usually one time), seeded with the
/// dwell's earlier predictions from the same state and handed back to them at the channel's end
/// ([`DwellPredictions`]). Every prediction of a channel is made from the track's state at the
/// channel's start (a track is updated at most once per channel, after its predictions).
#[derive(Default)]
struct PredCache {
    basis: Option<StateStamp>,
    entries: Vec<(f64, FilterPrediction)>,
}

impl PredCache {
    fn seeded(store: &mut DwellPredictions, track: &Track) -> PredCache {
        match store.take(track) {
            Some((basis, entries)) => PredCache { basis: Some(basis), entries },
            None => PredCache { basis: None, entries: Vec::new() },
        }
    }

    fn get(&mut self, filter: &dyn TrackFilter, track: &Track, t_s: f64) -> &FilterPrediction {
        let k = match self.entries.iter().position(|(t, _)| *t == t_s) {
            Some(k) => k,
            None => {
                if self.basis.is_none() {
                    self.basis = Some(StateStamp::of(track));
                }
                self.entries.push((t_s, filter.predict(&track.state, t_s - track.t_s)));
                self.entries.len() - 1
            }
        };
        &self.entries[k].1
    }
}

/// A channel's association hypotheses: its measurements (the table's columns), the live tracks'
/// ids (its rows) and the table of the pairs that gate.
#[derive(Clone, Copy)]
struct Hypotheses<'a> {
    list: &'a [PreparedMeasurement],
    ids: &'a [u64],
    table: &'a HypothesisTable,
}

impl MultiTargetTracker {
    pub(crate) fn process_channel(
        &mut self,
        ctx: &DwellContext,
        list: &[PreparedMeasurement],
        may_initiate: bool,
        updated: &mut BTreeSet<u64>,
        excused: &mut BTreeSet<u64>,
        new_ids: &mut Vec<u64>,
    ) {
        let all_ids: Vec<u64> = self.tracks.keys().copied().collect();
        let n_m = list.len();
        let gated = self.gate_channel(list);
        let near = gated.near;
        // The soft (JPDA) path sees only the tracks the channel reached: a track no pair reached
        // gates nothing, forms a cluster of its own and misses for sure, so it changes no
        // probability and no track (docs/model.md §6.8).
        let ids: Vec<u64> = gated.rows.iter().map(|&i| all_ids[i]).collect();
        let mut table = gated.table;
        let mut caches = gated.caches;
        let mut second = vec![false; n_m];
        let (ids, claimed) = match self.c.associator.probabilities(&table) {
            Some(probs) => {
                if self.config.second_return_max_beta > 0.0 {
                    second =
                        crate::second_return::second_returns(&table, &probs.beta, self.config.second_return_max_beta);
                }
                self.soft_updates(ctx, Hypotheses { list, ids: &ids, table: &table }, &mut caches, &probs, updated);
                (ids, vec![false; n_m])
            }
            None => {
                // The hard path (GNN, partners) still sees every track, as its rules ask.
                (table, caches) = reached::widen(table, caches, &gated.rows, all_ids.len());
                let claimed = self.hard_updates(
                    ctx,
                    Hypotheses { list, ids: &all_ids, table: &table },
                    &mut caches,
                    updated,
                    excused,
                );
                (all_ids, claimed)
            }
        };
        // The channel's predictions, for the dwell's other channels and its deletion pass.
        for (id, cache) in ids.iter().zip(caches) {
            if let Some(basis) = cache.basis {
                self.preds.put(*id, basis, cache.entries);
            }
        }

        if !may_initiate {
            return;
        }
        // Unclaimed detections outside every existing track's gate start tentative tracks,
        // strongest first; a detection inside the gate of a track started in this dwell is taken
        // as the same target and skipped.
        let mut cand: Vec<usize> = (0..n_m)
            .filter(|&j| {
                !claimed[j] && !near[j] && (second[j] || (0..table.n_tracks).all(|i| table.get(i, j).is_none()))
            })
            .filter(|&j| self.config.false_tracks.admits(ctx.kind, list[j].snr_db))
            .collect();
        cand.sort_by(|&a, &b| list[b].snr_db.total_cmp(&list[a].snr_db).then(list[a].meas_id.cmp(&list[b].meas_id)));
        self.initiate(list, &cand, new_ids);
    }

    /// Gate every track (in id order) against the channel's measurements. Returns the tracks one of
    /// whose pairs passed the pre-gate, their hypotheses that gate and their predictions, and
    /// which measurements lie inside an existing track's resolution cell or its initiation
    /// exclusion gate (such a measurement never starts a track, docs/model.md §6.4).
    fn gate_channel(&mut self, list: &[PreparedMeasurement]) -> reached::Reached<PredCache> {
        let n_m = list.len();
        let filter = &*self.c.filter;
        let mut out = reached::Reached::new(n_m);
        let excl = self.config.initiation_exclusion;
        let cell_uv = excl.beam_fraction * self.config.revisit.beamwidth;
        // Pairs that cannot gate are skipped before their prediction (docs/model.md §6.5).
        let pregate = PreGate::new(&*self.c.gater, &excl);
        // Row `i` is the `i`-th track in id order (`all_ids` of the caller): the map is walked,
        // not searched once per track and channel.
        for (i, track) in self.tracks.values().enumerate() {
            let mut bound = BoundCache::default();
            let ball = match list.first() {
                Some(m) => self.balls.get(filter, track, m.t_s - track.t_s),
                None => None,
            };
            // A track's cache is seeded from the dwell's store when one of its pairs passes the
            // pre-gate (a far track costs no lookup).
            let mut cache: Option<PredCache> = None;
            for (j, m) in list.iter().enumerate() {
                let far = ball.is_some_and(|b| b.covers(track, m.t_s - track.t_s) && pregate.excludes_ball(b, m));
                if far || pregate.excludes(filter, track, m, &mut bound) {
                    continue;
                }
                let pred =
                    cache.get_or_insert_with(|| PredCache::seeded(&mut self.preds, track)).get(filter, track, m.t_s);
                if pred.modes.len() > 1 && pregate.excludes_prediction(pred, m) {
                    continue;
                }
                if let Ok(h) = filter.hypothesis(pred, m.observation()) {
                    if self.c.gater.accepts(&h) {
                        out.gate(j, h);
                    }
                    out.near[j] |= h.nis <= excl.nis;
                }
                let zp = m.model.h(&pred.combined.x);
                let (dr, du, dv) = (m.z[0] - zp[0], m.z[1] - zp[1], m.z[2] - zp[2]);
                out.near[j] |= dr.abs() <= 2.0 * excl.range_cell_m && du * du + dv * dv <= cell_uv * cell_uv;
            }
            if let Some(cache) = cache {
                out.push_row(i, cache);
            }
        }
        out.finish()
    }

    /// Start a tentative track from each candidate measurement in `cand` (in order), unless it
    /// falls inside the gate of a track started in this dwell (`new_ids`), which takes it as the
    /// same target.
    fn initiate(&mut self, list: &[PreparedMeasurement], cand: &[usize], new_ids: &mut Vec<u64>) {
        let filter = &*self.c.filter;
        for &j in cand {
            let m = &list[j];
            let dup = new_ids.iter().any(|nid| {
                self.tracks.get(nid).is_some_and(|t| {
                    let pred = filter.predict(&t.state, m.t_s - t.t_s);
                    filter.hypothesis(&pred, m.observation()).is_ok_and(|h| self.c.gater.accepts(&h))
                })
            });
            if dup {
                continue;
            }
            let Some(init) = self.c.initiator.initiate(m) else { continue };
            let id = self.next_id;
            self.next_id += 1;
            let track = Track {
                id,
                status: TrackStatus::Tentative,
                state: filter.init(init.state),
                t_s: m.t_s,
                t_init_s: m.t_s,
                n_updates: init.meas_ids.len() as u32,
                last_meas_id: Some(m.meas_id),
                looks: init.looks,
                consecutive_misses: 0,
                next_due_s: m.t_s + self.config.revisit.confirm_delay_s,
                last_face: Some((m.rx, m.rx_face)),
                nis_sum: 0.0,
                nis_count: 0,
            };
            self.tracks.insert(id, track);
            self.initiation_power.insert(id, 10f64.powf(m.snr_db / 10.0));
            self.stats.initiated += 1;
            new_ids.push(id);
        }
    }

    /// GNN: each track is updated with its assigned measurement (plus, with `share_merged`, a
    /// gated `merged` measurement left to it). Returns which measurements were claimed.
    fn hard_updates(
        &mut self,
        ctx: &DwellContext,
        hyps: Hypotheses,
        caches: &mut [PredCache],
        updated: &mut BTreeSet<u64>,
        excused: &mut BTreeSet<u64>,
    ) -> Vec<bool> {
        let Hypotheses { list, ids, table } = hyps;
        let n_m = list.len();
        let mut assign = self.c.associator.associate(table);
        assign.resize(ids.len(), None);
        let mut claimed = vec![false; n_m];
        for j in assign.iter().flatten() {
            if *j < n_m {
                claimed[*j] = true;
            }
        }
        let partnered = self.partner_assignments(list, ids, caches, table, &mut assign, excused);
        let shared =
            if self.config.share_merged { share_merged(list, table, &mut assign) } else { vec![false; ids.len()] };
        let pu = self.config.partner_update;
        // With the group update, the tracks GNN assigned go first and leave their correction of
        // each merged measurement for the tracks sharing it (docs/model.md §6.5).
        let group = self.config.share_merged && self.config.merged_group_update;
        let follows = |i: usize| partnered[i] || (group && shared[i]);
        let order: Vec<usize> = if group || pu.enabled() {
            (0..ids.len()).filter(|&i| !follows(i)).chain((0..ids.len()).filter(|&i| follows(i))).collect()
        } else {
            (0..ids.len()).collect()
        };
        let mut correction: Vec<Option<[f64; 6]>> = vec![None; n_m];

        for i in order {
            let id = &ids[i];
            let Some(j) = assign[i].filter(|&j| j < n_m) else { continue };
            let m = &list[j];
            let Some(track) = self.tracks.get(id) else { continue };
            let filter = &*self.c.filter;
            let iterations =
                if track.n_updates < self.config.iekf_first_updates { self.config.iekf_iterations } else { 1 };
            let pred = caches[i].get(filter, track, m.t_s).clone();
            let outcome = filter.update(&pred, m.observation(), iterations).map(|mut u| {
                if partnered[i] {
                    if let Some(dx) = correction[j] {
                        crate::group::shift_modes(&mut u.state, &pred, &dx);
                    }
                } else if pu.enabled() && !shared[i] {
                    correction[j] = Some(crate::group::correction(&u.state, &pred));
                } else if group && m.merged {
                    match (shared[i], correction[j]) {
                        (true, Some(dx)) => crate::group::shift_modes(&mut u.state, &pred, &dx),
                        (false, _) => correction[j] = Some(crate::group::correction(&u.state, &pred)),
                        (true, None) => {}
                    }
                }
                u
            });
            match outcome {
                Ok(u) if u.state.is_finite() => self.commit_update(ctx, *id, m, u, updated),
                _ => self.stats.failed_updates += 1,
            }
        }

        claimed
    }

    /// With `partner_update` (docs/model.md §6.5), tracks inside the resolution cell of the track
    /// GNN gave a measurement share it as an unresolved pair's return: `shift` assigns it to them
    /// (returned as `true`), `excuse` adds them to `excused`.
    fn partner_assignments(
        &self,
        list: &[PreparedMeasurement],
        ids: &[u64],
        caches: &mut [PredCache],
        table: &HypothesisTable,
        assign: &mut [Option<usize>],
        excused: &mut BTreeSet<u64>,
    ) -> Vec<bool> {
        let filter = &*self.c.filter;
        let pu = self.config.partner_update;
        let mut partnered = vec![false; ids.len()];
        if pu.enabled() {
            let tracks = &self.tracks;
            let mut zp = |i: usize, j: usize| {
                let track = tracks.get(ids.get(i)?)?;
                let m = list.get(j)?;
                Some(m.model.h(&caches[i].get(filter, track, m.t_s).combined.x))
            };
            let chosen = pu.partners(table, assign, self.config.revisit.beamwidth, &mut zp);
            for (i, j) in chosen.into_iter().enumerate() {
                match (j, pu.mode) {
                    (Some(j), PartnerMode::Shift) => {
                        assign[i] = Some(j);
                        partnered[i] = true;
                    }
                    (Some(_), PartnerMode::Excuse) => {
                        excused.insert(ids[i]);
                    }
                    (None, _) => {}
                }
            }
        }
        partnered
    }

    /// Record a successful update `u` of track `id` with measurement `m`.
    fn commit_update(
        &mut self,
        ctx: &DwellContext,
        id: u64,
        m: &PreparedMeasurement,
        u: FilterUpdate,
        updated: &mut BTreeSet<u64>,
    ) {
        let Some(track) = self.tracks.get_mut(&id) else { return };
        track.state = u.state;
        track.t_s = m.t_s;
        track.n_updates += 1;
        track.last_meas_id = Some(m.meas_id);
        track.last_face = Some((m.rx, m.rx_face));
        track.nis_sum += u.innovation.nis;
        track.nis_count += 1;
        self.stats.updates += 1;
        if u.jitter {
            self.stats.jitter_events += 1;
        }
        self.nis_log.push(NisRecord {
            run: ctx.run,
            t_s: m.t_s,
            track_id: id,
            meas_id: m.meas_id,
            tx: m.tx,
            rx: m.rx,
            nis: u.innovation.nis,
        });
        updated.insert(id);
    }

    /// JPDA (docs/model.md §6.8): each track with gated measurements is updated with every one
    /// of them and the posteriors are mixed with the association probabilities.
    fn soft_updates(
        &mut self,
        ctx: &DwellContext,
        hyps: Hypotheses,
        caches: &mut [PredCache],
        probs: &AssociationProbabilities,
        updated: &mut BTreeSet<u64>,
    ) {
        let Hypotheses { list, ids, table } = hyps;
        let n_m = list.len();
        let filter = &*self.c.filter;
        for (i, id) in ids.iter().enumerate() {
            let Some(row) = probs.beta.get(i) else { continue };
            // The most probable measurement sets the update time; measurements of the channel
            // at another time (rare) are left out and the rest renormalized.
            let Some(best) =
                (0..n_m).filter(|&j| row[j] > 0.0).max_by(|&a, &b| row[a].total_cmp(&row[b]).then(b.cmp(&a)))
            else {
                continue;
            };
            let t_s = list[best].t_s;
            let Some(track) = self.tracks.get(id) else { continue };
            let iterations =
                if track.n_updates < self.config.iekf_first_updates { self.config.iekf_iterations } else { 1 };
            let pred = caches[i].get(filter, track, t_s).clone();
            let mut posteriors = Vec::new();
            let mut jitter = false;
            for j in (0..n_m).filter(|&j| row[j] > 0.0 && list[j].t_s == t_s) {
                let m = &list[j];
                if let Ok(u) = filter.update(&pred, m.observation(), iterations)
                    && u.state.is_finite()
                {
                    jitter |= u.jitter;
                    posteriors.push((row[j], u.state));
                }
            }
            if posteriors.is_empty() {
                self.stats.failed_updates += 1;
                continue;
            }
            let total: f64 = row[n_m] + posteriors.iter().map(|p| p.0).sum::<f64>();
            let beta0 = row[n_m] / total;
            posteriors.iter_mut().for_each(|p| p.0 /= total);
            let state = combine(&pred, beta0, &posteriors);
            if !state.is_finite() {
                self.stats.failed_updates += 1;
                continue;
            }
            let nis = table.get(i, best).map_or(f64::NAN, |h| h.nis);
            let m = &list[best];
            let Some(track) = self.tracks.get_mut(id) else { continue };
            track.state = state;
            track.t_s = t_s;
            track.n_updates += 1;
            track.last_meas_id = Some(m.meas_id);
            track.last_face = Some((m.rx, m.rx_face));
            if nis.is_finite() {
                track.nis_sum += nis;
                track.nis_count += 1;
            }
            self.stats.updates += 1;
            if jitter {
                self.stats.jitter_events += 1;
            }
            self.nis_log.push(NisRecord {
                run: ctx.run,
                t_s,
                track_id: *id,
                meas_id: m.meas_id,
                tx: m.tx,
                rx: m.rx,
                nis,
            });
            updated.insert(*id);
        }
    }
}

/// With `share_merged`, each track left without a measurement takes the gated `merged`
/// measurement of smallest NIS (which another track already has). Returns which tracks did.
fn share_merged(list: &[PreparedMeasurement], table: &HypothesisTable, assign: &mut [Option<usize>]) -> Vec<bool> {
    let n_m = list.len();
    let mut shared = vec![false; assign.len()];
    for (i, a) in assign.iter_mut().enumerate() {
        if a.is_some() {
            continue;
        }
        let best = (0..n_m)
            .filter(|&j| list[j].merged)
            .filter_map(|j| table.get(i, j).map(|h| (j, h.nis)))
            .min_by(|x, y| x.1.total_cmp(&y.1).then(x.0.cmp(&y.0)));
        if let Some((j, _)) = best {
            *a = Some(j);
            shared[i] = true;
        }
    }
    shared
}
