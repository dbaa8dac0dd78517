//! Fixtures for the tests of this crate and of the crates that read its tables (hidden from the
//! docs: not part of the store's interface).

use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, Role};

/// Dwells of run `run` at times `t_s` (one row a time) whose every column a reader of the
/// dwells decodes varies: four radars in turn (so a radar's times are ordered when `t_s` is),
/// every role, kind and requester, and durations, energies, pulse counts and faces that are not
/// multiples of one step, so that sums taken in another order round differently.
pub fn varied_dwell_rows(run: u32, t_s: &[f64]) -> Vec<DwellRow> {
    t_s.iter()
        .enumerate()
        .map(|(i, &t_s)| DwellRow {
            run,
            dwell_id: i as u64,
            group_id: i as u64,
            radar: RadarId((i % 4) as u8),
            role: Role::ALL[i % Role::ALL.len()],
            kind: DwellKind::ALL[(i / 3) % DwellKind::ALL.len()],
            requested_by: Requester::ALL[(i / 5) % Requester::ALL.len()],
            t_s,
            duration_s: 0.001 + 1e-4 * ((i * 31) % 17) as f64,
            pulse_width_s: 1e-5,
            n_pulses: 1 + (i % 3) as u32,
            peak_power_w: 1e5,
            energy_j: 10.0 + 0.37 * ((i * 53) % 29) as f64,
            waveform: 0,
            face: (i % 3) as u8,
            beam_u: 0.0,
            beam_v: 0.0,
            aim_x_m: 1.0,
            aim_y_m: 2.0,
            aim_z_m: 3.0,
        })
        .collect()
}
