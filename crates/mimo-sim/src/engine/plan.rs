//! Planning a requested dwell: which radars take part, on which face and beam, with how many
//! pulses and which waveforms, and how long the group occupies them (docs/design.md §5).

use super::group::{Group, Part};
use crate::messages::DwellRequest;
use crate::world::World;
use mimo_core::ids::RadarId;
use mimo_core::records::{Requester, Role};
use mimo_radar::energy::dwell_duration_s;
use mimo_radar::geometry::beam_point;

/// The group for a request whose radars are known to exist, evaluated with the faces at `t_s`.
/// A participant that cannot steer at the aim point is left out; `None` when no transmitter or
/// no receiver is left. Transmitters get waveforms 0, 1, … in the order listed; the group lasts
/// as long as its longest transmission.
pub(crate) fn plan(world: &World, t_s: f64, req: &DwellRequest) -> Option<Group> {
    if req.transmitters.is_empty() || req.receivers.is_empty() {
        return None;
    }
    let mut parts: Vec<Part> = Vec::new();
    let mut waveform = 0u32;
    let mut duration_s: f64 = 0.0;
    let add = |radar: RadarId, tx: Option<u32>, rx: bool, parts: &mut Vec<Part>| -> Option<()> {
        let params = world.params(radar);
        let faces = world.faces_at(radar, t_s);
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
            let p = world.params(tx.radar);
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
    if !parts.iter().any(Part::receives) {
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
