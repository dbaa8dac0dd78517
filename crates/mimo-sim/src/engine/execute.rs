//! Executing a dwell group: evaluate the radar model at mid-dwell and produce the group's rows
//! and, when the test article wants it, its report (docs/design.md §5, docs/model.md §4–§5).

use super::group::{Group, Part};
use super::quiet::{dwell_row, search_aim};
use super::registration::{bias_dwell, steered_beam};
use crate::messages::{DwellReport, PartReport};
use crate::world::World;
use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::records::{DwellRow, MeasurementRow, PrimitiveRow, VoltageRow};
use mimo_radar::dwell::RangeWindow;

/// Measurement ids of a dwell group start at `group_id << 12`, so they depend only on the group
/// (offline re-forming of measurements from primitives reproduces them without replaying the
/// engine's order). A dwell yields far fewer than 4096 measurements.
pub fn first_meas_id(group_id: u64) -> u64 {
    group_id << 12
}

/// Everything one executed group produced.
pub(crate) struct Executed {
    pub dwells: Vec<DwellRow>,
    pub primitives: Vec<PrimitiveRow>,
    pub measurements: Vec<MeasurementRow>,
    pub voltages: Vec<VoltageRow>,
    /// The participants' faces at mid-dwell (for the report).
    pub frames: Vec<FaceFrame>,
    /// The aim point actually used.
    pub aim: DVec3,
}

/// What the engine knows of the run when it executes a group.
pub(crate) struct RunKeys<'b> {
    pub seed: u64,
    pub run: u32,
    pub record_voltages: bool,
    /// Every radar's registration biases; `None` when they are off (docs/model.md §5.5).
    pub biases: Option<&'b [mimo_core::registration::RadarBias]>,
}

impl RunKeys<'_> {
    /// The radar model's dwell of a group at its mid-time `t_mid_s`; `stream_keys` are the
    /// group's `[run, gid]`, so the same group always draws the same numbers.
    pub(super) fn radar_dwell<'a>(
        &self,
        world: &'a World,
        t_mid_s: f64,
        stream_keys: &'a [u64; 2],
        transmitters: &'a [mimo_radar::Transmitter<'a>],
        receivers: &'a [mimo_radar::Receiver<'a>],
    ) -> mimo_radar::Dwell<'a> {
        mimo_radar::Dwell {
            run: self.run,
            t_s: t_mid_s,
            seed: self.seed,
            keys: stream_keys,
            transmitters,
            receivers,
            fidelity: &world.scenario.fidelity,
            record_voltages: self.record_voltages,
            simulate_all_cells: false,
        }
    }
}

/// Part `p`'s transmitter on its face `frame` at mid-dwell, its beam steered through its biases.
pub(super) fn transmitter<'w>(
    world: &'w World,
    keys: &RunKeys,
    p: &Part,
    frame: FaceFrame,
) -> mimo_radar::Transmitter<'w> {
    let (beam_u, beam_v) = steered_beam(keys.biases, p, &frame);
    mimo_radar::Transmitter {
        radar: p.radar,
        params: world.params(p.radar),
        frame,
        beam_u,
        beam_v,
        n_pulses: p.n_pulses,
        waveform: p.waveform,
    }
}

/// Part `p`'s receiver (dwell part id `dwell_id`) on its face `frame`: the whole instrumented range
/// for search, `±window_half_m` about the aim's ρ otherwise (docs/model.md §5.2); its beam
/// steered through its biases.
pub(super) fn receiver<'w>(
    world: &'w World,
    keys: &RunKeys,
    g: &Group,
    p: &Part,
    dwell_id: u64,
    frame: FaceFrame,
    aim: DVec3,
) -> mimo_radar::Receiver<'w> {
    let params = world.params(p.radar);
    let window = match g.window_half_m {
        None => RangeWindow::Fixed { rho_min_m: params.min_range_m, rho_max_m: params.instrumented_range_m },
        Some(half) => RangeWindow::AroundAim { aim_ecef: aim, half_width_m: half },
    };
    let (beam_u, beam_v) = steered_beam(keys.biases, p, &frame);
    mimo_radar::Receiver {
        radar: p.radar,
        dwell_id,
        params,
        face: p.face,
        frame,
        beam_u,
        beam_v,
        window,
        predicted_snr: g.predicted_snr,
    }
}

/// Execute group `gid` that starts at `t0_s`.
pub(crate) fn execute<'w>(
    world: &'w World,
    keys: &RunKeys,
    gid: u64,
    g: &Group,
    t0_s: f64,
    targets: &mut Vec<mimo_radar::Target<'w>>,
) -> Executed {
    let t_mid = t0_s + 0.5 * g.duration_s;
    // Participants' faces at mid-dwell (a part's face was chosen from the same frames).
    let frames: Vec<FaceFrame> = g.parts.iter().filter_map(|p| world.face_at(p.radar, p.face, t_mid)).collect();
    let aim = g.aim.unwrap_or_else(|| search_aim(world, g, &frames[0]));
    let txs: Vec<mimo_radar::Transmitter> = g
        .parts
        .iter()
        .zip(&frames)
        .filter(|(p, _)| p.role.transmits())
        .map(|(p, f)| transmitter(world, keys, p, *f))
        .collect();
    let rxs: Vec<mimo_radar::Receiver> = g
        .parts
        .iter()
        .enumerate()
        .zip(&frames)
        .filter(|((_, p), _)| p.receives())
        .map(|((i, p), f)| receiver(world, keys, g, p, gid + i as u64, *f, aim))
        .collect();
    let stream_keys = [u64::from(keys.run), gid];
    let dwell = keys.radar_dwell(world, t_mid, &stream_keys, &txs, &rxs);
    // Only the targets the dwell's beams may reach: the same dwell, at a cost that follows them.
    world.radar_targets_reached_into(t_mid, mimo_radar::reach::DwellReach::new(&dwell).as_ref(), targets);
    let mut out = mimo_radar::evaluate(&dwell, targets);
    if let Some(biases) = keys.biases {
        bias_dwell(biases, g, &frames, &mut out.primitives);
    }
    let measurements = mimo_radar::measurements_from_primitives(&out.primitives, first_meas_id(gid));
    let dwells = (0..g.parts.len()).map(|i| dwell_row(world, keys.run, gid, g, i, t0_s, aim)).collect();
    Executed { dwells, primitives: out.primitives, measurements, voltages: out.voltages, frames, aim }
}

/// The test article's view of an executed group: no truth (`target_hint` cleared); primitives
/// only when asked for.
pub(crate) fn report(
    run: u32,
    gid: u64,
    g: &Group,
    t0_s: f64,
    end_s: f64,
    ex: &Executed,
    with_primitives: bool,
) -> DwellReport {
    let mut measurements = ex.measurements.clone();
    measurements.iter_mut().for_each(|m| m.target_hint = None);
    let primitives = if with_primitives {
        let mut p = ex.primitives.clone();
        p.iter_mut().for_each(|p| p.target_hint = None);
        p
    } else {
        Vec::new()
    };
    let parts = g
        .parts
        .iter()
        .zip(&ex.frames)
        .enumerate()
        .map(|(i, (p, f))| PartReport {
            radar: p.radar,
            dwell_id: gid + i as u64,
            transmits: p.role.transmits(),
            receives: p.receives(),
            face: p.face,
            beam_u: p.beam_u,
            beam_v: p.beam_v,
            n_pulses: p.n_pulses,
            site_ecef: f.origin_ecef,
            face_from_ecef: PartReport::rows_of(f),
        })
        .collect();
    DwellReport {
        run,
        group_id: gid,
        kind: g.kind,
        requested_by: g.requested_by,
        t_s: t0_s + 0.5 * g.duration_s,
        duration_s: g.duration_s,
        end_s,
        aim_ecef: ex.aim,
        tag: g.tag.clone(),
        parts,
        measurements,
        primitives,
    }
}
