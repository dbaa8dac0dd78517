//! Offline re-runs (`mimo track`): run a tracker over a recording in time order, without
//! re-simulating.
//!
//! The recording's dwell schedule is fixed, so a re-run is open loop: the tracker sees every
//! dwell the closed loop ran (search and TA-requested), in the order the engine delivered them
//! (by end time, then group id), with the dwell context built from the dwells table by the same
//! [`dwell_context`](crate::default_ta::dwell_context) the closed loop uses. From measurements,
//! the default tracker therefore reproduces the closed loop's tracks bit for bit; from
//! primitives, measurements are first re-formed per dwell group with
//! `mimo_radar::measurements_from_primitives` and the group's own id base, which reproduces the
//! recorded measurements exactly.

use crate::default_ta::dwell_context;
use crate::engine::first_meas_id;
use crate::ta::PartReport;
use crate::world::World;
use mimo_core::records::{DwellKind, DwellRow, MeasurementRow, PrimitiveRow, Role, TrackRow};
use mimo_core::time::SimTime;
use mimo_track::{MultiTargetTracker, TrackerConfig, TrackerKind};
use std::collections::BTreeMap;

/// What a re-run starts from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ReplayFrom {
    Primitives,
    Measurements,
}

/// A dwell group of a recording.
#[derive(Debug, Clone)]
struct GroupRec {
    kind: DwellKind,
    t0_s: f64,
    duration_s: f64,
    parts: Vec<PartReport>,
}

/// Errors of a re-run: inconsistent recordings.
#[derive(Debug, thiserror::Error)]
pub enum ReplayError {
    #[error("unknown tracker '{0}'")]
    UnknownTracker(String),
    #[error("{table} row refers to dwell_id {dwell_id}, which the dwells table does not hold")]
    UnknownDwell { table: &'static str, dwell_id: u64 },
}

/// The output of a re-run of one Monte Carlo run.
#[derive(Debug, Clone, Default)]
pub struct ReplayOutput {
    /// Re-formed measurements (from primitives only).
    pub measurements: Vec<MeasurementRow>,
    pub tracks: Vec<TrackRow>,
    /// Measurements the tracker processed.
    pub n_measurements: u64,
}

/// Re-run tracker `tracker` over one run's dwells and primitives or measurements.
pub fn replay(
    world: &World,
    tracker: &str,
    run: u32,
    dwells: &[DwellRow],
    primitives: &[PrimitiveRow],
    measurements: &[MeasurementRow],
    from: ReplayFrom,
) -> Result<ReplayOutput, ReplayError> {
    let kind = TrackerKind::parse(tracker).ok_or_else(|| ReplayError::UnknownTracker(tracker.to_string()))?;
    let mut mtt = MultiTargetTracker::new(TrackerConfig::for_kind(kind), world.scenario.centre());

    // Groups from the dwells table, parts in dwell_id order.
    let mut rows: Vec<&DwellRow> = dwells.iter().filter(|d| d.run == run).collect();
    rows.sort_by_key(|d| d.dwell_id);
    let mut groups: BTreeMap<u64, GroupRec> = BTreeMap::new();
    let mut group_of: BTreeMap<u64, u64> = BTreeMap::new();
    for d in rows {
        group_of.insert(d.dwell_id, d.group_id);
        let g = groups.entry(d.group_id).or_insert_with(|| GroupRec {
            kind: d.kind,
            t0_s: d.t_s,
            duration_s: d.duration_s,
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
        });
    }

    // Measurements per group.
    let mut out = ReplayOutput::default();
    let mut meas_by_group: BTreeMap<u64, Vec<MeasurementRow>> = BTreeMap::new();
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
            let mut prims: BTreeMap<u64, Vec<PrimitiveRow>> = BTreeMap::new();
            for p in primitives.iter().filter(|p| p.run == run) {
                let gid = *group_of
                    .get(&p.dwell_id)
                    .ok_or(ReplayError::UnknownDwell { table: "primitives", dwell_id: p.dwell_id })?;
                prims.entry(gid).or_default().push(p.clone());
            }
            for (gid, ps) in prims {
                let ms = mimo_radar::measurements_from_primitives(&ps, first_meas_id(gid));
                out.measurements.extend(ms.iter().cloned());
                meas_by_group.insert(gid, ms);
            }
        }
    }

    // Delivery order of the engine: end time, then group id.
    let mut order: Vec<(SimTime, u64)> =
        groups.iter().map(|(&gid, g)| (SimTime::from_secs(g.t0_s).plus_secs(g.duration_s), gid)).collect();
    order.sort();
    let empty = Vec::new();
    for (_, gid) in order {
        let g = &groups[&gid];
        let ms = meas_by_group.get(&gid).unwrap_or(&empty);
        out.n_measurements += ms.len() as u64;
        let t_mid = g.t0_s + 0.5 * g.duration_s;
        let ctx = dwell_context(run, gid, g.kind, t_mid, &g.parts);
        out.tracks.extend(mtt.process_dwell(&ctx, ms, world));
    }
    out.measurements.sort_by_key(|m| m.meas_id);
    Ok(out)
}
