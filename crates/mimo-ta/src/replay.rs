//! Offline re-runs (`mimo track`): a test article over a recording, in time order, without
//! re-simulating.
//!
//! The recording's dwell schedule is fixed, so a re-run is open loop: the test article gets a
//! `start` event with `closed_loop = false`, then a `dwell_ended` event for every recorded dwell
//! its subscription asks for, in the order the closed loop delivered them (by end time, then
//! group id), and `finish`; its requests are ignored (and counted). Dwell reports are rebuilt
//! from the dwells table and the scenario's ships exactly as the engine builds them, so the
//! default test article reproduces the closed loop's tracks bit for bit from measurements. From
//! primitives, measurements are first re-formed per dwell group with
//! `mimo_radar::measurements_from_primitives` and the group's own id base, which reproduces the
//! recorded measurements exactly. Truth never reaches the test article: `target_hint` is
//! cleared before delivery. [`replay_selected`] needs only the dwells table's keys up front and
//! loads whole rows for the groups delivered alone (a few percent of the table).

use mimo_core::ids::RadarId;
use mimo_core::records::{DwellRow, MeasurementRow, PrimitiveRow, Requester, Role, TrackRow};
use mimo_core::sink::{RunSink, SinkError};
use mimo_core::time::SimTime;
use mimo_sim::engine::{Engine, EngineError};
use mimo_sim::messages::{DwellReport, PartReport, Reply, Subscription};
use mimo_sim::test_article::{TaFault, TestArticle};
use mimo_sim::{EngineConfig, World};

mod grouped;
use grouped::{GroupedRows, by_group};

/// What a re-run starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReplayFrom {
    /// Re-form measurements from the recorded primitives.
    Primitives,
    /// Use the recorded measurements.
    Measurements,
}

/// Errors of a re-run.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    /// A row refers to a dwell the dwells table does not hold.
    #[error("{table} row refers to dwell_id {dwell_id}, which the dwells table does not hold")]
    UnknownDwell {
        /// The table of the row.
        table: &'static str,
        /// The dwell id it names.
        dwell_id: u64,
    },
    /// A part names a radar or face the scenario does not have.
    #[error("dwells row {dwell_id} names radar {radar} face {face}, which the scenario does not have")]
    UnknownFace {
        /// The dwell part.
        dwell_id: u64,
        /// Its radar.
        radar: String,
        /// Its face.
        face: u8,
    },
    /// The test article failed or the sink could not take the rows, as in a closed-loop run.
    #[error("{0}")]
    Run(#[from] EngineError),
    /// The whole dwells rows of the groups delivered could not be loaded.
    #[error("{0}")]
    DwellRows(Box<dyn std::error::Error + Send + Sync>),
}

impl From<SinkError> for ReplayError {
    fn from(e: SinkError) -> ReplayError {
        ReplayError::Run(EngineError::Sink(e))
    }
}

/// Counters of a re-run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReplayStats {
    /// Dwell reports delivered.
    pub dwells: u64,
    /// Measurements delivered.
    pub measurements: u64,
    /// Requests the test article made (ignored: the schedule is the recording's).
    pub ignored_requests: u64,
    /// Track rows whose covariance was slightly indefinite and was repaired (docs/design.md §7).
    pub repaired_covariances: u64,
    /// The most negative smallest-to-largest eigenvalue ratio among them (0 if none).
    pub worst_covariance_ratio: f64,
}

/// The columns of a dwells row a re-run needs before it knows which groups it delivers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DwellKey {
    /// `run`.
    pub run: u32,
    /// `dwell_id`.
    pub dwell_id: u64,
    /// `group_id`.
    pub group_id: u64,
    /// `radar`.
    pub radar: RadarId,
    /// `face`.
    pub face: u8,
    /// `requested_by`.
    pub requested_by: Requester,
}

/// The dwells table's key columns, one value per row in each (a longer column's extra values are
/// ignored). A view: the reader's columns are the replay's keys, held once.
#[derive(Debug, Clone, Copy, Default)]
pub struct DwellKeyColumns<'a> {
    /// `run`.
    pub run: &'a [u32],
    /// `dwell_id`.
    pub dwell_id: &'a [u64],
    /// `group_id`.
    pub group_id: &'a [u64],
    /// `radar`.
    pub radar: &'a [RadarId],
    /// `face`.
    pub face: &'a [u8],
    /// `requested_by`.
    pub requested_by: &'a [Requester],
}

impl DwellKeyColumns<'_> {
    /// Number of rows (the shortest column's length).
    pub fn len(&self) -> usize {
        [
            self.run.len(),
            self.dwell_id.len(),
            self.group_id.len(),
            self.radar.len(),
            self.face.len(),
            self.requested_by.len(),
        ]
        .into_iter()
        .min()
        .unwrap_or(0)
    }

    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The key of row `i` (`i < len()`).
    pub fn get(&self, i: usize) -> DwellKey {
        DwellKey {
            run: self.run[i],
            dwell_id: self.dwell_id[i],
            group_id: self.group_id[i],
            radar: self.radar[i],
            face: self.face[i],
            requested_by: self.requested_by[i],
        }
    }
}

/// Key columns built from whole rows (for [`replay`], which is given the rows).
#[derive(Debug, Clone, Default, PartialEq)]
struct OwnedKeyColumns {
    run: Vec<u32>,
    dwell_id: Vec<u64>,
    group_id: Vec<u64>,
    radar: Vec<RadarId>,
    face: Vec<u8>,
    requested_by: Vec<Requester>,
}

impl OwnedKeyColumns {
    /// The key columns of `rows`.
    fn of(rows: &[DwellRow]) -> OwnedKeyColumns {
        OwnedKeyColumns {
            run: rows.iter().map(|d| d.run).collect(),
            dwell_id: rows.iter().map(|d| d.dwell_id).collect(),
            group_id: rows.iter().map(|d| d.group_id).collect(),
            radar: rows.iter().map(|d| d.radar).collect(),
            face: rows.iter().map(|d| d.face).collect(),
            requested_by: rows.iter().map(|d| d.requested_by).collect(),
        }
    }

    /// The columns as a view.
    fn view(&self) -> DwellKeyColumns<'_> {
        DwellKeyColumns {
            run: &self.run,
            dwell_id: &self.dwell_id,
            group_id: &self.group_id,
            radar: &self.radar,
            face: &self.face,
            requested_by: &self.requested_by,
        }
    }
}

/// Whole dwells rows by position in the key list (positions ascending, rows in that order); the
/// error is returned as [`ReplayError::DwellRows`].
pub type DwellLoader<'a> = dyn FnMut(&[usize]) -> Result<Vec<DwellRow>, Box<dyn std::error::Error + Send + Sync>> + 'a;

/// Re-run test article `ta` over one run's dwells and primitives or measurements. Track rows
/// (and, from primitives, the re-formed measurements) go to `sink`.
#[allow(clippy::too_many_arguments)] // the recording's tables, the test article and the sink
pub fn replay(
    world: &World,
    cfg: &EngineConfig,
    ta: &mut dyn TestArticle,
    run: u32,
    dwells: &[DwellRow],
    primitives: &[PrimitiveRow],
    measurements: &[MeasurementRow],
    from: ReplayFrom,
    sink: &mut dyn RunSink,
) -> Result<ReplayStats, ReplayError> {
    let keys = OwnedKeyColumns::of(dwells);
    let mut load = |at: &[usize]| -> Result<Vec<DwellRow>, Box<dyn std::error::Error + Send + Sync>> {
        Ok(at.iter().map(|&i| dwells[i].clone()).collect())
    };
    let primitives = primitives.iter().filter(|p| p.run == run).cloned().collect();
    let measurements = measurements.iter().filter(|m| m.run == run).cloned().collect();
    let recording = Recording { run, keys: keys.view(), load: &mut load, primitives, measurements, from };
    replay_selected(world, cfg, ta, recording, sink)
}

/// One run's recording as [`replay_selected`] reads it.
pub struct Recording<'r, 'l> {
    /// The run re-run.
    pub run: u32,
    /// The dwells table's key columns, every row.
    pub keys: DwellKeyColumns<'r>,
    /// The loader of whole dwells rows, asked once for the rows of the groups delivered.
    pub load: &'r mut DwellLoader<'l>,
    /// The primitives table's rows (rows of other runs are dropped).
    pub primitives: Vec<PrimitiveRow>,
    /// The measurements table's rows (rows of other runs are dropped).
    pub measurements: Vec<MeasurementRow>,
    /// What the re-run starts from.
    pub from: ReplayFrom,
}

/// [`replay`] from the dwells table's keys (`rec.keys`, every row) and a loader of whole rows,
/// asked once for the rows of the groups delivered: a reader can skip decoding the rest of the
/// table (`mimo_store::dwell_keys`). The result is [`replay`]'s.
pub fn replay_selected(
    world: &World,
    cfg: &EngineConfig,
    ta: &mut dyn TestArticle,
    rec: Recording<'_, '_>,
    sink: &mut dyn RunSink,
) -> Result<ReplayStats, ReplayError> {
    let Recording { run, keys, load, primitives, measurements, from } = rec;
    let parts = Parts::of_run(world, keys, run)?;
    let (meas_by_group, prims_by_group) = by_group(&parts, run, primitives, measurements, from, sink)?;

    let start = Engine::start_info(world, run, cfg, false);
    let mut stats = ReplayStats::default();
    let mut taker =
        Taker { run, ta_name: ta.name().to_string(), track_check: Default::default(), n_radars: world.n_radars() };
    let reply = ta.on_start(&start).map_err(|f| ta_fault(ta, f))?;
    taker.take(reply, &mut stats, sink)?;
    let sub = ta.subscription();

    let wanted_parts = parts.wanted_groups(&meas_by_group, &sub);
    // Whole rows of the wanted groups' parts only, by position in the keys.
    let mut needed: Vec<usize> =
        wanted_parts.iter().flat_map(|(_, ks)| ks.clone().map(|k| parts.part_row(k))).collect();
    needed.sort_unstable();
    needed.dedup();
    let full = load_rows(load, &needed)?;
    let row_at = |i: usize| needed.binary_search(&i).ok().map(|p| &full[p]);
    let mut wanted: Vec<(SimTime, u64, std::ops::Range<usize>)> = Vec::with_capacity(wanted_parts.len());
    for (gid, ks) in wanted_parts {
        let Some(first) = row_at(parts.part_row(ks.start)) else { continue };
        let t_end = SimTime::from_secs(first.t_s).plus_secs(first.duration_s);
        wanted.push((t_end, gid, ks));
    }
    // Delivery order of the engine: end time, then group id.
    wanted.sort_by_key(|w| (w.0, w.1));
    for (end, gid, ks) in wanted {
        let Some(g) = row_at(parts.part_row(ks.start)) else { continue };
        let t_mid = g.t_s + 0.5 * g.duration_s;
        let group_rows = ks.filter_map(|k| row_at(parts.part_row(k)));
        let reports = part_reports(world, group_rows, t_mid)?;
        let mut ms = meas_by_group.cloned(gid);
        ms.iter_mut().for_each(|m| m.target_hint = None);
        let mut ps = if sub.primitives { prims_by_group.cloned(gid) } else { Vec::new() };
        ps.iter_mut().for_each(|p| p.target_hint = None);
        stats.dwells += 1;
        stats.measurements += ms.len() as u64;
        let report = DwellReport {
            run,
            group_id: gid,
            kind: g.kind,
            requested_by: g.requested_by,
            t_s: t_mid,
            duration_s: g.duration_s,
            end_s: end.as_secs(),
            aim_ecef: mimo_core::DVec3::new(g.aim_x_m, g.aim_y_m, g.aim_z_m),
            tag: Vec::new(),
            parts: reports,
            measurements: ms,
            primitives: ps,
        };
        let reply = ta.on_dwell(&report).map_err(|f| ta_fault(ta, f))?;
        taker.take(reply, &mut stats, sink)?;
    }
    let reply = ta.on_finish(cfg.duration_s).map_err(|f| ta_fault(ta, f))?;
    taker.take(reply, &mut stats, sink)?;
    Ok(stats)
}

/// The replay error of a test article's fault.
fn ta_fault(ta: &dyn TestArticle, fault: TaFault) -> ReplayError {
    ReplayError::Run(EngineError::ta(ta.name(), fault))
}

/// Takes the test article's replies: counts the ignored requests, checks the tracks and sends them on.
struct Taker {
    /// The run re-run (stamped on every track row).
    run: u32,
    /// The test article's name, for its faults.
    ta_name: String,
    /// The track rows' check across the run.
    track_check: mimo_sim::track_check::TrackRowCheck,
    /// The scenario's radars (for the registration rows' check).
    n_radars: usize,
}

impl Taker {
    /// Take one reply.
    fn take(&mut self, reply: Reply, stats: &mut ReplayStats, sink: &mut dyn RunSink) -> Result<(), ReplayError> {
        stats.ignored_requests += reply.requests.len() as u64;
        let mut rows: Vec<TrackRow> = reply.tracks;
        self.track_check.check(&mut rows).map_err(|fault| ReplayError::Run(EngineError::ta(&self.ta_name, fault)))?;
        stats.repaired_covariances = self.track_check.repaired();
        stats.worst_covariance_ratio = self.track_check.worst_ratio();
        rows.iter_mut().for_each(|r| r.run = self.run);
        if !rows.is_empty() {
            sink.tracks(rows)?;
        }
        let mut registration = reply.registration;
        if !registration.is_empty() {
            mimo_sim::registration_check::check_registration(&mut registration, self.n_radars, self.run)
                .map_err(|fault| ReplayError::Run(EngineError::ta(&self.ta_name, fault)))?;
            sink.registration(registration)?;
        }
        Ok(())
    }
}

/// The run's dwell parts in dwell_id order, as positions in the keys, and their order by group.
/// Four bytes a part beside the keys (eight when groups are not numbered in dwell_id order).
struct Parts<'k> {
    /// The dwells table's key columns, every row.
    keys: DwellKeyColumns<'k>,
    /// Positions in `keys` of the run's parts, in dwell_id order (equal ids keep file order).
    rows: Vec<u32>,
    /// Indices into `rows` ordered by (group_id, dwell_id), when that is not `rows`' own order.
    by_group: Option<Vec<u32>>,
}

impl<'k> Parts<'k> {
    /// The run's parts, each checked to name a face its ship has (cheaply, for every part; frames
    /// are computed only for the groups delivered).
    fn of_run(world: &World, keys: DwellKeyColumns<'k>, run: u32) -> Result<Parts<'k>, ReplayError> {
        let n = keys.len();
        if u32::try_from(n).is_err() {
            return Err(ReplayError::DwellRows(format!("{n} dwells rows: more than one run can hold").into()));
        }
        let mut rows: Vec<u32> = (0..n as u32).filter(|&i| keys.run[i as usize] == run).collect();
        // Ids come a few rows out of place (docs/design.md §3); the sort runs over them.
        if !rows.windows(2).all(|w| keys.dwell_id[w[0] as usize] <= keys.dwell_id[w[1] as usize]) {
            rows.sort_unstable_by_key(|&i| (keys.dwell_id[i as usize], i));
        }
        for &i in &rows {
            let d = keys.get(i as usize);
            let n_faces = world.scenario.ships.get(d.radar.index()).map_or(0, |s| s.radar.face_azimuths_deg.len());
            if usize::from(d.face) >= n_faces {
                return Err(ReplayError::UnknownFace {
                    dwell_id: d.dwell_id,
                    radar: d.radar.to_string(),
                    face: d.face,
                });
            }
        }
        let by_group = Self::group_order(keys, &rows);
        Ok(Parts { keys, rows, by_group })
    }

    /// The group of a dwell id (binary search), if the run has that dwell.
    fn group_of(&self, dwell_id: u64) -> Option<u64> {
        let keys = self.keys;
        let at = self.rows.binary_search_by_key(&dwell_id, |&i| keys.dwell_id[i as usize]).ok()?;
        Some(keys.group_id[self.rows[at] as usize])
    }

    /// Indices into `rows` ordered by (group_id, dwell_id), so each group's parts are contiguous
    /// and in dwell_id order; none when groups are numbered in dwell_id order already (the usual
    /// case: `rows` is that order).
    fn group_order(keys: DwellKeyColumns<'_>, rows: &[u32]) -> Option<Vec<u32>> {
        let group = |i: u32| keys.group_id[i as usize];
        if rows.windows(2).all(|w| group(w[0]) <= group(w[1])) {
            return None;
        }
        let mut by_group: Vec<u32> = (0..rows.len() as u32).collect();
        by_group.sort_by_key(|&k| (group(rows[k as usize]), keys.dwell_id[rows[k as usize] as usize]));
        Some(by_group)
    }

    /// Number of parts.
    fn len(&self) -> usize {
        self.rows.len()
    }

    /// The position in the keys of the `k`-th part in group order.
    fn part_row(&self, k: usize) -> usize {
        let at = self.by_group.as_ref().map_or(k, |o| o[k] as usize);
        self.rows[at] as usize
    }

    /// The groups the subscription wants, as ranges of parts in group order. A group's kind,
    /// requester, start, duration and aim are its first part's.
    fn wanted_groups(
        &self,
        meas_by_group: &GroupedRows<MeasurementRow>,
        sub: &Subscription,
    ) -> Vec<(u64, std::ops::Range<usize>)> {
        let keys = self.keys;
        let mut wanted_parts = Vec::new();
        let mut k = 0;
        while k < self.len() {
            let first = keys.get(self.part_row(k));
            let mut end = k + 1;
            while end < self.len() && keys.group_id[self.part_row(end)] == first.group_id {
                end += 1;
            }
            let n_meas = meas_by_group.group(first.group_id).len();
            if sub.wants(first.requested_by, n_meas) {
                wanted_parts.push((first.group_id, k..end));
            }
            k = end;
        }
        wanted_parts
    }
}

/// Whole dwells rows at the positions `needed`, checked to be one per position.
fn load_rows(load: &mut DwellLoader<'_>, needed: &[usize]) -> Result<Vec<DwellRow>, ReplayError> {
    let full = load(needed).map_err(ReplayError::DwellRows)?;
    if full.len() != needed.len() {
        return Err(ReplayError::DwellRows(
            format!("{} dwells rows loaded for {} asked for", full.len(), needed.len()).into(),
        ));
    }
    Ok(full)
}

/// A group's part reports at mid-dwell `t_mid`, with the engine's own (interpolated) face
/// frames, so reports match the closed loop's.
fn part_reports<'a>(
    world: &World,
    group_rows: impl Iterator<Item = &'a DwellRow>,
    t_mid: f64,
) -> Result<Vec<PartReport>, ReplayError> {
    let mut reports = Vec::new();
    for d in group_rows {
        let frame = world.face_at(d.radar, d.face, t_mid).ok_or_else(|| ReplayError::UnknownFace {
            dwell_id: d.dwell_id,
            radar: d.radar.to_string(),
            face: d.face,
        })?;
        reports.push(PartReport {
            radar: d.radar,
            dwell_id: d.dwell_id,
            transmits: d.role.transmits(),
            receives: matches!(d.role, Role::Rx | Role::Txrx),
            face: d.face,
            beam_u: d.beam_u,
            beam_v: d.beam_v,
            n_pulses: d.n_pulses,
            site_ecef: frame.origin_ecef,
            face_from_ecef: PartReport::rows_of(&frame),
        });
    }
    Ok(reports)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hand-made run: rows in file order with ids out of place, groups not numbered in id
    /// order, a part of another run; plus the ships-only world of standard scenario 7.
    fn hand_made() -> (World, OwnedKeyColumns) {
        let mut s = mimo_scenario::load_standard(7).expect("standard scenario");
        s.duration_s = 10.0;
        let world = World::ships_only(s);
        // (run, dwell_id, group_id) by file row.
        let rows = [(3, 12, 5), (3, 10, 7), (4, 11, 1), (3, 11, 5), (3, 14, 2), (3, 13, 7), (3, 15, 9)];
        let n = rows.len();
        let keys = OwnedKeyColumns {
            run: rows.iter().map(|r| r.0).collect(),
            dwell_id: rows.iter().map(|r| r.1).collect(),
            group_id: rows.iter().map(|r| r.2).collect(),
            radar: vec![RadarId(0); n],
            face: vec![0; n],
            requested_by: vec![Requester::Radar; n],
        };
        (world, keys)
    }

    /// The run's parts come in dwell_id order, group order puts each group's parts together in
    /// dwell_id order, and a dwell id finds its group; the other run's part is left out.
    #[test]
    fn parts_in_id_order_and_in_group_order() {
        let (world, keys) = hand_made();
        let parts = Parts::of_run(&world, keys.view(), 3).expect("parts");
        // File rows of ids 10, 11, 12, 13, 14, 15 (row 2 is run 4's).
        assert_eq!(parts.rows, vec![1, 3, 0, 5, 4, 6]);
        let by_group: Vec<(u64, u64)> =
            (0..parts.len()).map(|k| parts.part_row(k)).map(|i| (keys.group_id[i], keys.dwell_id[i])).collect();
        assert_eq!(by_group, vec![(2, 14), (5, 11), (5, 12), (7, 10), (7, 13), (9, 15)]);
        assert_eq!([10, 11, 15, 16].map(|id| parts.group_of(id)), [Some(7), Some(5), Some(9), None]);
        let meas = GroupedRows::<MeasurementRow> { rows: Vec::new() };
        let all = Subscription { dwells: mimo_sim::messages::DwellFilter::All, ..Subscription::default() };
        let groups: Vec<(u64, std::ops::Range<usize>)> = parts.wanted_groups(&meas, &all);
        assert_eq!(groups, vec![(2, 0..1), (5, 1..3), (7, 3..5), (9, 5..6)]);
        // Numbered in id order, no group order is built.
        let (mut ids, mut bad_face) = (keys.clone(), keys.clone());
        ids.group_id = ids.dwell_id.clone();
        assert!(Parts::of_run(&world, ids.view(), 3).expect("parts").by_group.is_none());
        bad_face.face[4] = 9;
        match Parts::of_run(&world, bad_face.view(), 3) {
            Err(ReplayError::UnknownFace { dwell_id: 14, face: 9, .. }) => {}
            other => panic!("expected an unknown face, got {:?}", other.map(|p| p.rows)),
        }
    }
}
