//! Unresolved partners (docs/model.md §6.5): a track that GNN left without a measurement, whose
//! prediction sits inside the resolution cell of another track that GNN gave a measurement, is
//! taken to be the other aircraft of an unresolved pair whose one return went to its partner.
//! In `shift` mode it shares that measurement (if gated) and moves by its partner's correction
//! (see [`crate::group`]), whether or not the measurement is flagged `merged`; in `excuse` mode
//! it keeps its prediction and the look is not counted as its miss, so that two tracks on a pair
//! whose dominant return alternates between the aircraft are not deleted and restarted.

use crate::association::{Hypothesis, HypothesisTable};
use serde::{Deserialize, Serialize};

/// What a track inside the resolution cell of a track that got a measurement does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PartnerMode {
    /// Share the measurement, if it is inside the track's gate, and move by the partner's
    /// correction (the group update). Default.
    #[default]
    Shift,
    /// Keep the prediction, but do not count the look as a miss: the pair's one return came
    /// from the other aircraft (whichever dominates an unresolved pair changes from look to
    /// look). No gate test.
    Excuse,
}

/// When an unassigned track shares its partner's measurement. Off by default (`range_sum_m = 0`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PartnerUpdate {
    /// Share and shift, or only excuse the miss. Default `shift`.
    pub mode: PartnerMode,
    /// Largest difference of the two tracks' predicted bistatic range sum R_B = 2ρ (m, the first
    /// measurement coordinate) for them to be one unresolved pair; 0 (the default) disables the
    /// partner update. 120 m is two range cells (ΔR = 30 m of ρ).
    pub range_sum_m: f64,
    /// Largest difference of the two tracks' predicted (u, v), as a fraction of the beamwidth
    /// (`revisit.beamwidth`). Default 0.5 (inside the half-power beam).
    pub beam_fraction: f64,
}

impl Default for PartnerUpdate {
    fn default() -> Self {
        PartnerUpdate { mode: PartnerMode::Shift, range_sum_m: 0.0, beam_fraction: 0.5 }
    }
}

impl PartnerUpdate {
    /// Whether the partner update is on.
    pub fn enabled(&self) -> bool {
        self.range_sum_m > 0.0
    }

    /// For every track GNN left without a measurement (`assign[i] = None`), the measurement of
    /// its unresolved partner it shares, if any: a measurement `j` assigned to another track `p`,
    /// inside track `i`'s gate (`shift` mode only), with the predicted measurements `zp(i, j)` and `zp(p, j)`
    /// (R_B, u, v under `j`'s model) within `range_sum_m` in R_B and `beam_fraction · beamwidth` in
    /// (u, v). Among several, the one of smallest NIS (then lowest index). Tracks GNN assigned
    /// get `None`.
    pub fn partners(
        &self,
        table: &HypothesisTable,
        assign: &[Option<usize>],
        beamwidth: f64,
        zp: &mut dyn FnMut(usize, usize) -> Option<[f64; 3]>,
    ) -> Vec<Option<usize>> {
        let n_t = table.n_tracks.min(assign.len());
        let mut out = vec![None; assign.len()];
        if !self.enabled() {
            return out;
        }
        let uv_max = self.beam_fraction * beamwidth;
        // Which track each measurement went to.
        let mut owner = vec![None; table.n_meas];
        for (p, a) in assign.iter().enumerate().take(n_t) {
            if let Some(j) = a.filter(|&j| j < table.n_meas) {
                owner[j] = Some(p);
            }
        }
        for i in 0..n_t {
            if assign[i].is_some() {
                continue;
            }
            let mut best: Option<(usize, f64)> = None;
            for (j, own) in owner.iter().enumerate() {
                let Some(p) = *own else { continue };
                let h = match (self.mode, table.get(i, j)) {
                    (_, Some(h)) => h,
                    (PartnerMode::Excuse, None) => Hypothesis { nis: f64::INFINITY, ln_det_2pi_s: 0.0 },
                    (PartnerMode::Shift, None) => continue,
                };
                let (Some(zi), Some(zpp)) = (zp(i, j), zp(p, j)) else { continue };
                let (dr, du, dv) = (zi[0] - zpp[0], zi[1] - zpp[1], zi[2] - zpp[2]);
                let inside = dr.abs() <= self.range_sum_m && du * du + dv * dv <= uv_max * uv_max;
                if inside && best.is_none_or(|(_, nis)| h.nis < nis) {
                    best = Some((j, h.nis));
                }
            }
            out[i] = best.map(|(j, _)| j);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gated(n_t: usize, n_m: usize, nis: &[(usize, usize, f64)]) -> HypothesisTable {
        let mut t = HypothesisTable::new(n_t, n_m);
        for &(i, j, x) in nis {
            t.set(i, j, Some(Hypothesis { nis: x, ln_det_2pi_s: 0.0 }));
        }
        t
    }

    #[test]
    fn a_track_inside_its_partners_cell_shares_the_measurement() {
        // Tracks 0 and 1 sit 40 m apart in ρ on one unresolved pair; track 2 is 300 m away.
        // GNN gave measurement 0 to track 0 and measurement 1 to nobody; tracks 1 and 2 gate
        // measurement 0. Only track 1 is its partner.
        let table = gated(3, 2, &[(0, 0, 1.0), (1, 0, 6.0), (2, 0, 9.0)]);
        let assign = vec![Some(0), None, None];
        let rho = [100_000.0, 100_040.0, 100_300.0];
        let mut zp = |i: usize, _j: usize| Some([rho[i], 0.1, 0.2]);
        let pu = PartnerUpdate { mode: PartnerMode::Shift, range_sum_m: 120.0, beam_fraction: 0.5 };
        assert_eq!(pu.partners(&table, &assign, 0.025, &mut zp), vec![None, Some(0), None]);
        // Off by default.
        assert_eq!(PartnerUpdate::default().partners(&table, &assign, 0.025, &mut zp), vec![None; 3]);
    }

    #[test]
    fn a_partner_must_gate_the_measurement_and_be_inside_the_beam_cell() {
        // Track 1 is inside the range cell but a beamwidth away in u; track 2 is inside the
        // cell but outside its own gate. Neither shares.
        let table = gated(3, 1, &[(0, 0, 1.0), (1, 0, 2.0)]);
        let assign = vec![Some(0), None, None];
        let z = [[100_000.0, 0.10, 0.0], [100_010.0, 0.125, 0.0], [100_010.0, 0.10, 0.0]];
        let mut zp = |i: usize, _j: usize| Some(z[i]);
        let pu = PartnerUpdate { mode: PartnerMode::Shift, range_sum_m: 120.0, beam_fraction: 0.5 };
        assert_eq!(pu.partners(&table, &assign, 0.025, &mut zp), vec![None; 3]);
    }

    #[test]
    fn excuse_needs_no_gate_but_the_cell() {
        // Track 1 lies 37 m from track 0 in ρ (the other aircraft of the pair) and does not gate
        // the measurement; track 2 is 200 m away. Excuse picks track 1 only; shift picks none.
        let table = gated(3, 1, &[(0, 0, 1.0)]);
        let assign = vec![Some(0), None, None];
        let rho = [100_000.0, 100_037.0, 100_200.0];
        let mut zp = |i: usize, _j: usize| Some([rho[i], 0.1, 0.2]);
        let excuse = PartnerUpdate { mode: PartnerMode::Excuse, range_sum_m: 120.0, beam_fraction: 0.5 };
        assert_eq!(excuse.partners(&table, &assign, 0.025, &mut zp), vec![None, Some(0), None]);
        let shift = PartnerUpdate { mode: PartnerMode::Shift, ..excuse };
        assert_eq!(shift.partners(&table, &assign, 0.025, &mut zp), vec![None; 3]);
    }

    #[test]
    fn the_nearest_of_two_partners_measurements_wins() {
        // Track 2 lies in the cells of both assigned tracks; it takes the lower-NIS measurement.
        let table = gated(3, 2, &[(0, 0, 1.0), (1, 1, 1.0), (2, 0, 8.0), (2, 1, 3.0)]);
        let assign = vec![Some(0), Some(1), None];
        let mut zp = |_i: usize, _j: usize| Some([50_000.0, 0.0, 0.0]);
        let pu = PartnerUpdate { mode: PartnerMode::Shift, range_sum_m: 120.0, beam_fraction: 0.5 };
        assert_eq!(pu.partners(&table, &assign, 0.025, &mut zp), vec![None, None, Some(1)]);
    }
}
