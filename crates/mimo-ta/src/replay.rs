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
use mimo_sim::engine::{Engine, EngineError, first_meas_id};
use mimo_sim::messages::{DwellReport, PartReport, Reply, Subscription};
use mimo_sim::test_article::{TaFault, TestArticle};
use mimo_sim::{EngineConfig, World};
use std::collections::{BTreeMap, HashMap};

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

impl DwellKey {
    /// The key of a whole row.
    pub fn of(d: &DwellRow) -> DwellKey {
        DwellKey {
            run: d.run,
            dwell_id: d.dwell_id,
            group_id: d.group_id,
            radar: d.radar,
            face: d.face,
            requested_by: d.requested_by,
        }
    }

    /// The keys of the dwells table's key columns, row by row (the columns have one length; a
    /// longer column's extra values are ignored). Built here, in an optimised crate, since a
    /// replay does it for every row of the table.
    pub fn from_columns(
        run: &[u32],
        dwell_id: &[u64],
        group_id: &[u64],
        radar: &[RadarId],
        face: &[u8],
        requested_by: &[Requester],
    ) -> Vec<DwellKey> {
        let n = [run.len(), dwell_id.len(), group_id.len(), radar.len(), face.len(), requested_by.len()]
            .into_iter()
            .min()
            .unwrap_or(0);
        (0..n)
            .map(|i| DwellKey {
                run: run[i],
                dwell_id: dwell_id[i],
                group_id: group_id[i],
                radar: radar[i],
                face: face[i],
                requested_by: requested_by[i],
            })
            .collect()
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
    let keys: Vec<DwellKey> = dwells.iter().map(DwellKey::of).collect();
    let mut load = |at: &[usize]| -> Result<Vec<DwellRow>, Box<dyn std::error::Error + Send + Sync>> {
        Ok(at.iter().map(|&i| dwells[i].clone()).collect())
    };
    let recording = Recording { run, keys: &keys, load: &mut load, primitives, measurements, from };
    replay_selected(world, cfg, ta, recording, sink)
}

/// One run's recording as [`replay_selected`] reads it.
pub struct Recording<'r, 'l> {
    /// The run re-run.
    pub run: u32,
    /// The dwells table's keys, every row.
    pub keys: &'r [DwellKey],
    /// The loader of whole dwells rows, asked once for the rows of the groups delivered.
    pub load: &'r mut DwellLoader<'l>,
    /// The primitives table's rows.
    pub primitives: &'r [PrimitiveRow],
    /// The measurements table's rows.
    pub measurements: &'r [MeasurementRow],
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
    let (mut meas_by_group, mut prims_by_group) = by_group(&parts, run, primitives, measurements, from, sink)?;

    let start = Engine::start_info(world, run, cfg, false);
    let mut stats = ReplayStats::default();
    let mut taker = Taker { run, ta_name: ta.name().to_string(), track_check: Default::default() };
    let reply = ta.on_start(&start).map_err(|f| ta_fault(ta, f))?;
    taker.take(reply, &mut stats, sink)?;
    let sub = ta.subscription();

    let by_group = parts.group_order();
    let wanted_parts = parts.wanted_groups(&by_group, &meas_by_group, &sub);
    let rows = parts.rows;
    // Whole rows of the wanted groups' parts only, by position in `keys`.
    let mut needed: Vec<usize> =
        wanted_parts.iter().flat_map(|(_, parts)| by_group[parts.clone()].iter().map(|&k| rows[k as usize])).collect();
    needed.sort_unstable();
    needed.dedup();
    let full = load_rows(load, &needed)?;
    let row_at = |i: usize| needed.binary_search(&i).ok().map(|p| &full[p]);
    let mut wanted: Vec<(SimTime, u64, std::ops::Range<usize>)> = Vec::with_capacity(wanted_parts.len());
    for (gid, parts) in wanted_parts {
        let Some(first) = row_at(rows[by_group[parts.start] as usize]) else { continue };
        let t_end = SimTime::from_secs(first.t_s).plus_secs(first.duration_s);
        wanted.push((t_end, gid, parts));
    }
    // Delivery order of the engine: end time, then group id.
    wanted.sort_by_key(|w| (w.0, w.1));
    for (end, gid, parts) in wanted {
        let Some(g) = row_at(rows[by_group[parts.start] as usize]) else { continue };
        let t_mid = g.t_s + 0.5 * g.duration_s;
        let group_rows = by_group[parts].iter().filter_map(|&i| row_at(rows[i as usize]));
        let reports = part_reports(world, group_rows, t_mid)?;
        let mut ms = meas_by_group.remove(&gid).unwrap_or_default();
        ms.iter_mut().for_each(|m| m.target_hint = None);
        let mut ps = if sub.primitives { prims_by_group.remove(&gid).unwrap_or_default() } else { Vec::new() };
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
}

impl Taker {
    /// Take one reply.
    fn take(&mut self, reply: Reply, stats: &mut ReplayStats, sink: &mut dyn RunSink) -> Result<(), ReplayError> {
        stats.ignored_requests += reply.requests.len() as u64;
        self.track_check
            .check(&reply.tracks)
            .map_err(|fault| ReplayError::Run(EngineError::ta(&self.ta_name, fault)))?;
        let mut rows: Vec<TrackRow> = reply.tracks;
        rows.iter_mut().for_each(|r| r.run = self.run);
        if !rows.is_empty() {
            sink.tracks(rows)?;
        }
        Ok(())
    }
}

/// The run's dwell parts in dwell_id order, as positions in the keys.
struct Parts<'k> {
    /// The dwells table's keys, every row.
    keys: &'k [DwellKey],
    /// Positions in `keys` of the run's parts, in dwell_id order (equal ids keep file order).
    rows: Vec<usize>,
}

impl<'k> Parts<'k> {
    /// The run's parts, each checked to name a face its ship has (cheaply, for every part; frames
    /// are computed only for the groups delivered).
    fn of_run(world: &World, keys: &'k [DwellKey], run: u32) -> Result<Parts<'k>, ReplayError> {
        let mut by_id: Vec<(u64, usize)> =
            (0..keys.len()).filter(|&i| keys[i].run == run).map(|i| (keys[i].dwell_id, i)).collect();
        mimo_core::nearly_sorted::sort_nearly_sorted(&mut by_id);
        let rows: Vec<usize> = by_id.into_iter().map(|(_, i)| i).collect();
        for &i in &rows {
            let d = &keys[i];
            let n_faces = world.scenario.ships.get(d.radar.index()).map_or(0, |s| s.radar.face_azimuths_deg.len());
            if usize::from(d.face) >= n_faces {
                return Err(ReplayError::UnknownFace {
                    dwell_id: d.dwell_id,
                    radar: d.radar.to_string(),
                    face: d.face,
                });
            }
        }
        Ok(Parts { keys, rows })
    }

    /// The group of a dwell id (binary search), if the run has that dwell.
    fn group_of(&self, dwell_id: u64) -> Option<u64> {
        let keys = self.keys;
        self.rows.binary_search_by_key(&dwell_id, |&i| keys[i].dwell_id).ok().map(|k| keys[self.rows[k]].group_id)
    }

    /// Part indices ordered by (group_id, dwell_id), so each group's parts are contiguous and in
    /// dwell_id order. Groups are usually numbered in dwell_id order already: then no sort is needed.
    fn group_order(&self) -> Vec<u32> {
        let (keys, rows) = (self.keys, &self.rows);
        let mut by_group: Vec<u32> = (0..rows.len() as u32).collect();
        if !rows.windows(2).all(|w| keys[w[0]].group_id <= keys[w[1]].group_id) {
            by_group.sort_by_key(|&k| (keys[rows[k as usize]].group_id, keys[rows[k as usize]].dwell_id));
        }
        by_group
    }

    /// The groups the subscription wants, as runs of `by_group`. A group's kind, requester,
    /// start, duration and aim are its first part's.
    fn wanted_groups(
        &self,
        by_group: &[u32],
        meas_by_group: &HashMap<u64, Vec<MeasurementRow>>,
        sub: &Subscription,
    ) -> Vec<(u64, std::ops::Range<usize>)> {
        let (keys, rows) = (self.keys, &self.rows);
        let mut wanted_parts = Vec::new();
        let mut k = 0;
        while k < by_group.len() {
            let first = &keys[rows[by_group[k] as usize]];
            let mut end = k + 1;
            while end < by_group.len() && keys[rows[by_group[end] as usize]].group_id == first.group_id {
                end += 1;
            }
            let n_meas = meas_by_group.get(&first.group_id).map_or(0, Vec::len);
            if sub.wants(first.requested_by, n_meas) {
                wanted_parts.push((first.group_id, k..end));
            }
            k = end;
        }
        wanted_parts
    }
}

/// Measurements by group, and primitives by group.
type ByGroup = (HashMap<u64, Vec<MeasurementRow>>, BTreeMap<u64, Vec<PrimitiveRow>>);

/// The run's measurements (recorded, or re-formed from primitives and sent to `sink`) and
/// primitives, per group.
fn by_group(
    parts: &Parts<'_>,
    run: u32,
    primitives: &[PrimitiveRow],
    measurements: &[MeasurementRow],
    from: ReplayFrom,
    sink: &mut dyn RunSink,
) -> Result<ByGroup, ReplayError> {
    let mut meas_by_group: HashMap<u64, Vec<MeasurementRow>> = HashMap::new();
    let mut prims_by_group: BTreeMap<u64, Vec<PrimitiveRow>> = BTreeMap::new();
    for p in primitives.iter().filter(|p| p.run == run) {
        let gid = parts
            .group_of(p.dwell_id)
            .ok_or(ReplayError::UnknownDwell { table: "primitives", dwell_id: p.dwell_id })?;
        prims_by_group.entry(gid).or_default().push(p.clone());
    }
    match from {
        ReplayFrom::Measurements => {
            for m in measurements.iter().filter(|m| m.run == run) {
                let gid = parts
                    .group_of(m.dwell_id)
                    .ok_or(ReplayError::UnknownDwell { table: "measurements", dwell_id: m.dwell_id })?;
                meas_by_group.entry(gid).or_default().push(m.clone());
            }
        }
        ReplayFrom::Primitives => {
            let mut all = Vec::new();
            for (gid, ps) in &prims_by_group {
                let ms = mimo_radar::measurements_from_primitives(ps, first_meas_id(*gid));
                all.extend(ms.iter().cloned());
                meas_by_group.insert(*gid, ms);
            }
            all.sort_by_key(|m| m.meas_id);
            if !all.is_empty() {
                sink.measurements(all)?;
            }
        }
    }
    Ok((meas_by_group, prims_by_group))
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

    /// Keys built from columns are the keys of the rows the columns came from.
    #[test]
    fn keys_from_columns_are_the_rows_keys() {
        let keys = [
            DwellKey { run: 2, dwell_id: 7, group_id: 3, radar: RadarId(1), face: 2, requested_by: Requester::Radar },
            DwellKey { run: 2, dwell_id: 9, group_id: 4, radar: RadarId(0), face: 0, requested_by: Requester::Ta },
        ];
        let built = DwellKey::from_columns(
            &keys.map(|k| k.run),
            &keys.map(|k| k.dwell_id),
            &keys.map(|k| k.group_id),
            &keys.map(|k| k.radar),
            &keys.map(|k| k.face),
            &keys.map(|k| k.requested_by),
        );
        assert_eq!(built, keys.to_vec());
        assert!(DwellKey::from_columns(&[1], &[], &[], &[], &[], &[]).is_empty());
    }
}
