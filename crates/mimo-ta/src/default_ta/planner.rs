//! Planning one dwell for a due track: which radar transmits, with how many pulses, which radars
//! receive, and the range window (docs/model.md §7.2, §7.5).

use super::config::ResourceConfig;
use super::snapshot::Snapshot;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, TrackStatus};
use mimo_radar::energy::{pointing_loss, pulses_for, required_snr_sw1, straddle_loss};
use mimo_sim::messages::{DwellRequest, TxOrder};
use mimo_track::TrackDue;

/// Immediate re-dwells with doubled energy after a miss before the test article tries another
/// radar (docs/model.md §7.2).
pub const MAX_REDWELLS: u32 = 2;

/// One dwell for track `info` at the instant of the scheduling pass `snap`:
///
/// * radars in `over_budget` (their test-article dwells took more than `max_ta_share` of the
///   recent timeline, docs/model.md §7.3) transmit only when no other radar can, and never
///   receive for another radar's MIMO dwell, so that they keep searching; a confirmed track
///   whose only possible transmitters are over budget gets no dwell now (`None`) and is
///   planned again at the next event;
/// * radars in `tx_starved` (their power budget cannot pay for this look, docs/model.md §7.6)
///   are the last choice of transmitter, and a look whose transmitter would be one of them is not
///   planned (`None`); they still receive;
/// * the transmitter is the radar with the best predicted monostatic SNR for an
///   `assumed_rcs_m2` target at the predicted position; after [`MAX_REDWELLS`] misses in a row
///   the best radar may not see the target at all (a track just above its predicted horizon,
///   say), so the track is handed to the next radar;
/// * pulses are sized for `pd_target` (tentative tracks not yet seen again: `confirm_pd`) with the
///   expected pointing and straddle losses, doubled on each miss up to [`MAX_REDWELLS`] times;
/// * the range window is `ρ̂ ± max(window_sigmas·σ_ρ, min_window_half_m)`;
/// * a confirmed track that other radars can see gets a MIMO dwell: the transmitter also
///   receives, and so does every other radar that can see the aim point, except radars in
///   `busy_rx` (their search has been held off for a while, docs/model.md §7.3);
/// * a track in `trouble` (its last look missed or returned a merged measurement) whose
///   predicted position lies in the same resolution cell, seen from the transmitter, as another
///   track's ([`unresolved_from`]) gets no energy doubling: more pulses cannot split the pair.
///   The returned flag says so, and the caller stretches the track's revisit.
pub fn plan(
    cfg: &ResourceConfig,
    snap: &Snapshot,
    info: &TrackDue,
    over_budget: &[RadarId],
    tx_starved: &[RadarId],
    busy_rx: &[RadarId],
    trouble: bool,
) -> Option<(DwellRequest, bool)> {
    let (id, status, misses, n_updates) = (info.id, info.status, info.consecutive_misses, info.n_updates);
    let (tracker, geom, t_s) = (snap.tracker, snap.geom, snap.t_s);
    // One prediction for the aim point and the range window (`predict`'s position is this
    // prediction's mean in ECEF).
    let pred = tracker.predict_local(id, t_s)?;
    let aim = tracker.frame().to_ecef(pred.pos());
    let candidates = transmitter_candidates(cfg, snap, aim, over_budget, tx_starved);
    if candidates.is_empty() {
        return None;
    }
    let k = (misses / (MAX_REDWELLS + 1)) as usize % candidates.len();
    let (tx, snr1, face) = candidates[k];
    if tx_starved.contains(&tx) {
        return None;
    }
    if over_budget.contains(&tx) && status == TrackStatus::Confirmed {
        // Every radar that could look is over its budget: the look waits until the radar's
        // share drops (docs/model.md §7.3).
        return None;
    }
    let p = geom.params(tx)?;
    let losses = pointing_loss(cfg.pointing_sharpness, cfg.pointing_sharpness, true) * straddle_loss();
    // Until a tentative track is seen again, its looks are cheap (most are false alarms).
    let unconfirmed = status == TrackStatus::Tentative && n_updates <= 1;
    let pd = if unconfirmed { cfg.confirm_pd } else { cfg.pd_target };
    let mut n = pulses_for(required_snr_sw1(pd, p.pfa), snr1, losses, p.max_pulses);
    let unresolved =
        cfg.unresolved_hold && trouble && status == TrackStatus::Confirmed && unresolved_from(cfg, snap, id, aim, tx);
    if !unconfirmed && !unresolved {
        // Re-dwell with doubled energy, up to twice (docs/model.md §7.2).
        n = n.saturating_mul(1 << (misses % (MAX_REDWELLS + 1))).min(p.max_pulses);
    }
    let pm = tracker.predict_measurement_of(&pred, t_s, tx, tx, face, geom);
    let sigma_rho = pm.map(|m| m.sigma_rho_m).unwrap_or(0.0);
    let half = (cfg.window_sigmas * sigma_rho).max(cfg.min_window_half_m);
    let mut receivers = vec![tx];
    if cfg.mimo && status == TrackStatus::Confirmed {
        receivers.extend(other_receivers(cfg, snap, tx, aim, over_budget, busy_rx));
    }
    let kind = match (status, receivers.len() > 1) {
        (TrackStatus::Tentative, _) => DwellKind::Confirm,
        (_, true) => DwellKind::Mimo,
        _ => DwellKind::Track,
    };
    let req = DwellRequest {
        kind,
        earliest_s: t_s,
        aim_ecef: aim,
        transmitters: vec![TxOrder { radar: tx, n_pulses: n }],
        predicted_snr: (receivers.len() == 1).then(|| snr1 * f64::from(n)),
        receivers,
        window_half_m: half,
        tag: vec![id],
    };
    Some((req, unresolved))
}

/// Candidate transmitters of a look at `aim` with their monostatic SNR and face: radars within
/// their budget first (not in `over_budget` nor `tx_starved`), then best predicted SNR first,
/// ties by radar id so the choice is deterministic.
fn transmitter_candidates(
    cfg: &ResourceConfig,
    snap: &Snapshot,
    aim: mimo_core::DVec3,
    over_budget: &[RadarId],
    tx_starved: &[RadarId],
) -> Vec<(RadarId, f64, u8)> {
    let mut candidates: Vec<(RadarId, f64, u8)> = snap
        .ids()
        .iter()
        .filter_map(|&r| snap.pair(r, r, aim, cfg.assumed_rcs_m2).map(|pp| (r, pp.snr1, pp.rx_face)))
        .collect();
    let last = |r: &RadarId| over_budget.contains(r) || tx_starved.contains(r);
    candidates.sort_by(|a, b| {
        (last(&a.0), b.1, a.0).partial_cmp(&(last(&b.0), a.1, b.0)).unwrap_or(std::cmp::Ordering::Equal)
    });
    candidates
}

/// The radars other than `tx` that receive a MIMO look at `aim`: those that can see it, except
/// radars in `over_budget` or `busy_rx`, in radar order.
fn other_receivers(
    cfg: &ResourceConfig,
    snap: &Snapshot,
    tx: RadarId,
    aim: mimo_core::DVec3,
    over_budget: &[RadarId],
    busy_rx: &[RadarId],
) -> Vec<RadarId> {
    snap.ids()
        .iter()
        .copied()
        .filter(|&r| {
            r != tx
                && !over_budget.contains(&r)
                && !busy_rx.contains(&r)
                && snap.pair(tx, r, aim, cfg.assumed_rcs_m2).is_some()
        })
        .collect()
}

/// Whether another live track's predicted position at the pass's instant lies in the same
/// resolution cell as `aim` (track `id`'s) seen from radar `tx`: ranges within
/// `unresolved_range_cells` range cells and directions within `unresolved_beam_fraction` of the
/// narrower beamwidth.
pub fn unresolved_from(cfg: &ResourceConfig, snap: &Snapshot, id: u64, aim: mimo_core::DVec3, tx: RadarId) -> bool {
    let (Some(p), Some(face)) = (snap.geom.params(tx), snap.faces_of(tx).first()) else {
        return false;
    };
    let site = face.origin_ecef;
    let d0 = aim - site;
    let r0 = d0.length();
    if r0 <= 0.0 {
        return false;
    }
    let dr_max = cfg.unresolved_range_cells * p.range_cell_m();
    let da_max = cfg.unresolved_beam_fraction * p.beamwidth_u().min(p.beamwidth_v());
    let u0 = d0 / r0;
    // A point within `dr_max` of range and `da_max` of direction lies within `dr_max + r0·da_max`
    // of `aim`; the metre and the relative part cover rounding.
    let reach_m = dr_max + r0 * da_max + 1.0 + 1e-9 * r0;
    let near = snap.near(aim, reach_m);
    let others = near.into_iter().filter(|&o| o != id).filter_map(|o| snap.tracker.track_due(o));
    others.filter(|o| o.status != TrackStatus::Deleted).any(|o| {
        // A track whose position ball is clear of the cell is not predicted.
        if !snap.may_be_near(&o, site, r0, u0, dr_max, da_max) {
            return false;
        }
        let Some(q) = snap.position(o.id) else { return false };
        let d1 = q - site;
        let r1 = d1.length();
        r1 > 0.0 && (r1 - r0).abs() <= dr_max && (d1 / r1 - d0 / r0).length() <= da_max
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::default_ta::budget::RadarBudget;
    use crate::default_ta::fixture::minute_of_scenario_7;
    use crate::default_ta::radars_at_share;

    /// Search protection (docs/model.md §7.3) on a hand-made load: a radar that spent 4.5 of the
    /// last 8 s on test-article dwells is busy at the default 0.5, one that spent 3.5 s is not,
    /// and the busy radar is left out of a confirmed track's MIMO look while the transmitter
    /// keeps its look; with every other radar busy the look is a monostatic track dwell.
    #[test]
    fn a_busy_radar_is_not_asked_to_receive_and_its_look_stays() {
        let (ta, geom) = minute_of_scenario_7();
        let tracker = ta.tracker().expect("started");
        let (t_s, ids) = (60.4, geom.ids());
        let snap = Snapshot::new(tracker, &geom, &ids, t_s);
        let rm = ResourceConfig::default();
        // A confirmed track whose look is a MIMO dwell with at least two receivers besides the
        // transmitter.
        let (info, tx, receivers) = tracker
            .track_dues()
            .filter(|d| d.status == TrackStatus::Confirmed)
            .find_map(|d| planner_mimo(&rm, &snap, &d).map(|(tx, rx)| (d, tx, rx)))
            .expect("a MIMO look at a confirmed track");
        let busy_one = *receivers.iter().find(|&&r| r != tx).expect("another receiver");
        // The hand-made load: `busy_one` 4.5 s of the last 8 s, every other radar 3.5 s.
        let mut budget = RadarBudget::default();
        for &r in &ids {
            let busy_s = if r == busy_one { 4.5 } else { 3.5 };
            budget.record(r, t_s - 8.0 + 1.0, busy_s);
        }
        let busy = radars_at_share(&budget, &ids, t_s, rm.rx_busy_share, rm.rx_busy_window_s);
        assert_eq!(busy, vec![busy_one]);
        let (req, _) = plan(&rm, &snap, &info, &[], &[], &busy, false).expect("a look");
        assert_eq!(req.transmitters[0].radar, tx);
        let expected: Vec<RadarId> = receivers.iter().copied().filter(|&r| r != busy_one).collect();
        assert_eq!(req.receivers, expected);
        // Every other radar busy: the transmitter looks alone.
        let all_others: Vec<RadarId> = ids.iter().copied().filter(|&r| r != tx).collect();
        let (req, _) = plan(&rm, &snap, &info, &[], &[], &all_others, false).expect("a look");
        assert_eq!((req.kind, req.receivers), (DwellKind::Track, vec![tx]));
        // Off (share 1): nobody is busy, whatever the load.
        assert!(radars_at_share(&budget, &ids, t_s, 1.0, 8.0).is_empty());
    }

    /// The transmitter and receivers of the MIMO look `plan` makes for `d`, if it makes one.
    fn planner_mimo(rm: &ResourceConfig, snap: &Snapshot, d: &TrackDue) -> Option<(RadarId, Vec<RadarId>)> {
        let (req, _) = plan(rm, snap, d, &[], &[], &[], false)?;
        (req.kind == DwellKind::Mimo && req.receivers.len() >= 3).then_some((req.transmitters[0].radar, req.receivers))
    }
}
