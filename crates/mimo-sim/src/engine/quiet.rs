//! Background-search dwells at the cost of their false-alarm draw (docs/model.md §4.4, §4.7).
//!
//! A search dwell that no target reaches and whose false-alarm count is zero produces one dwell
//! row and nothing else. [`quiet_search_row`] recognises it with
//! [`mimo_radar::quiet::QuietRadar::is_quiet`] (same gates, same random stream as the full model) and
//! returns that row without building the dwell's vectors (and, when the beam is far from a
//! ball holding each target over the current epoch, without the targets' exact positions:
//! [`mimo_radar::quiet::QuietRadar::beam_clear`]; the radar's constant part of both tests is made
//! once per run, [`quiet_radars`]); any other dwell goes through
//! [`super::execute::execute`], so the recorded tables are byte-identical either way.

use super::execute::{RunKeys, receiver, transmitter};
use super::group::{Group, Part};
use crate::world::World;
use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::records::DwellRow;
use mimo_radar::energy::dwell_energy_j;
use mimo_radar::quiet::{QuietRadar, TargetBall};

/// The aim of a search beam: its direction at half the instrumented range.
pub(super) fn search_aim(world: &World, g: &Group, frame: &FaceFrame) -> DVec3 {
    let p = &g.parts[0];
    let w = (1.0 - p.beam_u * p.beam_u - p.beam_v * p.beam_v).max(0.0).sqrt();
    let d = frame.face_from_ecef.transpose() * DVec3::new(p.beam_u, p.beam_v, w);
    frame.origin_ecef + d * (0.5 * world.params(p.radar).instrumented_range_m)
}

/// The dwells-table row of part `i` of group `gid`, started at `t0_s` and aimed at `aim`.
pub(super) fn dwell_row(world: &World, run: u32, gid: u64, g: &Group, i: usize, t0_s: f64, aim: DVec3) -> DwellRow {
    let p: &Part = &g.parts[i];
    let params = world.params(p.radar);
    let tx = p.role.transmits();
    DwellRow {
        run,
        dwell_id: gid + i as u64,
        group_id: gid,
        radar: p.radar,
        role: p.role,
        kind: g.kind,
        requested_by: g.requested_by,
        t_s: t0_s,
        duration_s: g.duration_s,
        pulse_width_s: params.pulse_width_s,
        n_pulses: p.n_pulses,
        peak_power_w: if tx { params.peak_power_w } else { 0.0 },
        energy_j: if tx { dwell_energy_j(params, p.n_pulses) } else { 0.0 },
        waveform: p.waveform,
        face: p.face,
        beam_u: p.beam_u,
        beam_v: p.beam_v,
        aim_x_m: aim.x,
        aim_y_m: aim.y,
        aim_z_m: aim.z,
    }
}

/// Every radar's [`QuietRadar`] (indexed by radar), made once per run.
pub(super) fn quiet_radars(world: &World) -> Vec<QuietRadar> {
    world.radar_ids().into_iter().map(|r| QuietRadar::new(world.params(r), world.scenario.fidelity.pattern)).collect()
}

/// The one row of search group `gid` (started at `t0_s`) when the dwell is quiet; `None` when it
/// must be evaluated in full (a target may be in the beam, a false alarm was drawn, or the group
/// is not a one-radar search dwell). `radars` are [`quiet_radars`].
pub(super) fn quiet_search_row<'w>(
    world: &'w World,
    radars: &[QuietRadar],
    keys: &RunKeys,
    gid: u64,
    g: &Group,
    t0_s: f64,
    targets: &mut Vec<mimo_radar::Target<'w>>,
) -> Option<DwellRow> {
    let [p] = g.parts.as_slice() else { return None };
    if g.aim.is_some() || g.window_half_m.is_some() || !p.role.transmits() || !p.receives() {
        return None;
    }
    let quiet_radar = radars.get(p.radar.index())?;
    let t_mid = t0_s + 0.5 * g.duration_s;
    let frame = world.face_at(p.radar, p.face, t_mid)?;
    let aim = search_aim(world, g, &frame);
    // The transmitter, receiver and stream keys `execute` builds for this group.
    let tx = transmitter(world, keys, p, frame);
    let rx = receiver(world, keys, g, p, gid, frame, aim);
    let stream_keys = [u64::from(keys.run), gid];
    let dwell = keys.radar_dwell(world, t_mid, &stream_keys, std::slice::from_ref(&tx), std::slice::from_ref(&rx));
    // A beam far from every target's ball gates every target out whatever its exact position:
    // the positions are then not computed (the answer and the random draws are the same).
    let clear = world.target_balls_at(t_mid).is_some_and(|balls| {
        quiet_radar
            .beam_clear(&dwell, balls.iter().map(|b| TargetBall { center_ecef: b.center_ecef, radius_m: b.radius_m }))
    });
    let quiet = if clear {
        quiet_radar.is_quiet(&dwell, &[])
    } else {
        world.radar_targets_into(t_mid, targets);
        quiet_radar.is_quiet(&dwell, targets)
    };
    if !quiet {
        return None;
    }
    Some(dwell_row(world, keys.run, gid, g, 0, t0_s, aim))
}
