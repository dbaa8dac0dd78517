//! The engine's hooks for registration biases (docs/model.md §5.5): a run's biases drawn at its
//! start and written to the `biases` table, beams steered through them, and every primitive of a
//! dwell given its radars' biases before measurements are formed. With biases off none of this
//! runs, and a run is byte-identical to one without the feature.

use super::group::{Group, Part};
use mimo_core::face::FaceFrame;
use mimo_core::records::{BiasRow, PrimitiveRow};
use mimo_core::registration::RadarBias;
use mimo_radar::registration::{bias_primitives, physical_beam, up_in_face};

/// Every radar's biases in run `run` (`None` when the scenario's `[biases]` is off).
pub(super) fn run_biases(world: &crate::world::World, seed: u64, run: u32) -> Option<Vec<RadarBias>> {
    let b = &world.scenario.biases;
    (!b.is_off()).then(|| b.draw(seed, run, world.n_radars()))
}

/// The `biases` table's rows of run `run`.
pub(super) fn bias_rows(run: u32, biases: &[RadarBias]) -> Vec<BiasRow> {
    biases
        .iter()
        .enumerate()
        .map(|(i, b)| BiasRow {
            run,
            radar: mimo_core::ids::RadarId(i as u8),
            range_m: b.range_m,
            u: b.u,
            v: b.v,
            heading_deg: b.heading_deg,
        })
        .collect()
}

/// The direction part `p` physically steers to on `frame`: its ordered beam, through its radar's
/// biases when there are any.
pub(super) fn steered_beam(biases: Option<&[RadarBias]>, p: &Part, frame: &FaceFrame) -> (f64, f64) {
    match biases.and_then(|b| b.get(p.radar.index())) {
        Some(b) if !b.is_zero() => physical_beam(p.beam_u, p.beam_v, up_in_face(frame), b),
        _ => (p.beam_u, p.beam_v),
    }
}

/// Give group `g`'s primitives (its parts on `frames`) the biases of their radars, and the beam
/// each receiver was ordered to (the radar model records the physical one).
pub(super) fn bias_dwell(biases: &[RadarBias], g: &Group, frames: &[FaceFrame], primitives: &mut Vec<PrimitiveRow>) {
    let part_of = |rx: mimo_core::ids::RadarId| g.parts.iter().position(|p| p.radar == rx && p.receives());
    bias_primitives(primitives, biases, |rx, face| {
        let i = part_of(rx)?;
        (g.parts[i].face == face).then(|| up_in_face(&frames[i]))
    });
    for p in primitives.iter_mut() {
        if let Some(i) = part_of(p.rx) {
            (p.beam_u, p.beam_v) = (g.parts[i].beam_u, g.parts[i].beam_v);
        }
    }
}
