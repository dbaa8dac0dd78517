//! Which rung of the fidelity ladder evaluates a channel (docs/model.md §4.8).
//!
//! * `voltage`: every channel at the voltage level (cells, detection, ML monopulse). A dwell
//!   with `simulate_all_cells` (the reference mode) is at the voltage level whatever the level.
//! * `measurement`: every channel at the measurement level ([`crate::statistical`]).
//! * `auto`: the voltage level where it matters, the measurement level elsewhere. A channel is
//!   evaluated at the voltage level when voltages are recorded, when waveform leakage is modelled, or when two of its returns are within
//!   [`AUTO_RANGE_CELLS`] range cells **and** [`AUTO_BEAMWIDTHS`] beamwidths (in `u` and in `v`) of
//!   each other: there the voltages of close targets interfere (§2.7) and the detector's clusters
//!   and local maxima, which the measurement level only approximates by its one-cell,
//!   one-beamwidth grouping, decide what is reported.

use crate::dwell::{Dwell, Return};
use crate::pattern::Antenna;
use mimo_core::params::FidelityLevel;

/// `auto`: returns closer than this many range cells (and [`AUTO_BEAMWIDTHS`]) need voltages.
pub const AUTO_RANGE_CELLS: f64 = 3.0;
/// `auto`: returns closer than this many beamwidths in `u` and in `v` (and [`AUTO_RANGE_CELLS`])
/// need voltages.
pub const AUTO_BEAMWIDTHS: f64 = 3.0;

/// The rung one channel is evaluated at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rung {
    /// Cells, detection and ML monopulse.
    Voltage,
    /// Drawn from the voltage level's statistics.
    Measurement,
}

/// The rung of the channel `(j → i)` of a dwell whose returns in that channel are `rets`.
pub fn channel_rung(d: &Dwell, i: usize, rets: &[Return]) -> Rung {
    if d.simulate_all_cells {
        // The reference mode simulates every cell: it is the voltage level by definition.
        return Rung::Voltage;
    }
    match d.fidelity.level {
        FidelityLevel::Voltage => Rung::Voltage,
        FidelityLevel::Measurement => Rung::Measurement,
        FidelityLevel::Auto => {
            if d.record_voltages || d.fidelity.waveform_isolation_db.is_some() {
                return Rung::Voltage;
            }
            if rets.len() < 2 {
                return Rung::Measurement;
            }
            let rx = &d.receivers[i];
            let dr = rx.params.range_cell_m();
            let ant = Antenna::new(rx.params, d.fidelity.pattern);
            let (du, dv) = (AUTO_BEAMWIDTHS * ant.theta_u(), AUTO_BEAMWIDTHS * ant.theta_v());
            let close = rets.iter().enumerate().any(|(a, ra)| {
                rets[a + 1..].iter().any(|rb| {
                    (ra.rho_m - rb.rho_m).abs() < AUTO_RANGE_CELLS * dr
                        && (ra.u - rb.u).abs() < du
                        && (ra.v - rb.v).abs() < dv
                })
            });
            if close { Rung::Voltage } else { Rung::Measurement }
        }
    }
}
