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
//! cleared before delivery.

use mimo_core::records::{DwellKind, DwellRow, MeasurementRow, PrimitiveRow, Requester, Role, TrackRow};
use mimo_core::sink::{RunSink, SinkError};
use mimo_core::time::SimTime;
use mimo_sim::engine::{Engine, first_meas_id};
use mimo_sim::messages::{DwellReport, PartReport, Reply};
use mimo_sim::test_article::{TaFault, TestArticle};
use mimo_sim::{EngineConfig, World};
use std::collections::{BTreeMap, BTreeSet};

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
    /// The test article failed.
    #[error("test article '{name}': {fault}")]
    Ta {
        /// Its name.
        name: String,
        /// What went wrong.
        fault: TaFault,
    },
    /// The sink could not take the rows.
    #[error("{0}")]
    Sink(#[from] SinkError),
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

/// A dwell group of a recording.
struct GroupRec {
    kind: DwellKind,
    requested_by: Requester,
    t0_s: f64,
    duration_s: f64,
    aim: mimo_core::DVec3,
    parts: Vec<PartReport>,
}

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
    let fault = |ta: &dyn TestArticle, fault: TaFault| ReplayError::Ta { name: ta.name().to_string(), fault };
    // The dwells table in dwell_id order; every row must name a face its radar has.
    let mut rows: Vec<&DwellRow> = dwells.iter().filter(|d| d.run == run).collect();
    rows.sort_by_key(|d| d.dwell_id);
    for d in &rows {
        let n_faces = world.scenario.ships.get(d.radar.index()).map_or(0, |s| s.radar.face_azimuths_deg.len());
        if usize::from(d.face) >= n_faces {
            return Err(ReplayError::UnknownFace { dwell_id: d.dwell_id, radar: d.radar.to_string(), face: d.face });
        }
    }
    // The group of every dwell a primitive or measurement names (only those: a run has ~10⁵–10⁶
    // dwells, nearly all without a detection).
    let named: BTreeSet<u64> = primitives
        .iter()
        .filter(|p| p.run == run)
        .map(|p| p.dwell_id)
        .chain(measurements.iter().filter(|m| m.run == run).map(|m| m.dwell_id))
        .collect();
    let group_of: BTreeMap<u64, u64> =
        rows.iter().filter(|d| named.contains(&d.dwell_id)).map(|d| (d.dwell_id, d.group_id)).collect();

    // Measurements (and, when subscribed, primitives) per group.
    let mut meas_by_group: BTreeMap<u64, Vec<MeasurementRow>> = BTreeMap::new();
    let mut prims_by_group: BTreeMap<u64, Vec<PrimitiveRow>> = BTreeMap::new();
    for p in primitives.iter().filter(|p| p.run == run) {
        let gid = *group_of
            .get(&p.dwell_id)
            .ok_or(ReplayError::UnknownDwell { table: "primitives", dwell_id: p.dwell_id })?;
        prims_by_group.entry(gid).or_default().push(p.clone());
    }
    match from {
        ReplayFrom::Measurements => {
            for m in measurements.iter().filter(|m| m.run == run) {
                let gid = *group_of
                    .get(&m.dwell_id)
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

    let start = Engine::start_info(world, run, cfg, false);
    let mut stats = ReplayStats::default();
    let take = |reply: Reply, stats: &mut ReplayStats, sink: &mut dyn RunSink| -> Result<(), ReplayError> {
        stats.ignored_requests += reply.requests.len() as u64;
        let mut rows: Vec<TrackRow> = reply.tracks;
        rows.iter_mut().for_each(|r| r.run = run);
        if !rows.is_empty() {
            sink.tracks(rows)?;
        }
        Ok(())
    };
    let reply = ta.on_start(&start).map_err(|f| fault(ta, f))?;
    take(reply, &mut stats, sink)?;
    let sub = ta.subscription();

    // The groups the test article hears of, parts in dwell_id order.
    let n_meas = |gid: u64| meas_by_group.get(&gid).map_or(0, Vec::len);
    let mut groups: BTreeMap<u64, GroupRec> = BTreeMap::new();
    for d in rows.iter().filter(|d| sub.wants(d.requested_by, n_meas(d.group_id))) {
        let t_mid = d.t_s + 0.5 * d.duration_s;
        let frame =
            world.scenario.ships.get(d.radar.index()).and_then(|s| s.faces_at(t_mid).get(d.face as usize).copied());
        let Some(frame) = frame else {
            return Err(ReplayError::UnknownFace { dwell_id: d.dwell_id, radar: d.radar.to_string(), face: d.face });
        };
        let g = groups.entry(d.group_id).or_insert_with(|| GroupRec {
            kind: d.kind,
            requested_by: d.requested_by,
            t0_s: d.t_s,
            duration_s: d.duration_s,
            aim: mimo_core::DVec3::new(d.aim_x_m, d.aim_y_m, d.aim_z_m),
            parts: Vec::new(),
        });
        g.parts.push(PartReport {
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

    // Delivery order of the engine: end time, then group id.
    let mut order: Vec<(SimTime, u64)> =
        groups.iter().map(|(&gid, g)| (SimTime::from_secs(g.t0_s).plus_secs(g.duration_s), gid)).collect();
    order.sort();
    for (end, gid) in order {
        let g = &groups[&gid];
        let mut ms = meas_by_group.remove(&gid).unwrap_or_default();
        if !sub.wants(g.requested_by, ms.len()) {
            continue;
        }
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
            t_s: g.t0_s + 0.5 * g.duration_s,
            duration_s: g.duration_s,
            end_s: end.as_secs(),
            aim_ecef: g.aim,
            tag: Vec::new(),
            parts: g.parts.clone(),
            measurements: ms,
            primitives: ps,
        };
        let reply = ta.on_dwell(&report).map_err(|f| fault(ta, f))?;
        take(reply, &mut stats, sink)?;
    }
    let reply = ta.on_finish(cfg.duration_s).map_err(|f| fault(ta, f))?;
    take(reply, &mut stats, sink)?;
    Ok(stats)
}
