//! The check of a test article's registration estimates (docs/model.md §6.9), shared by the
//! engine and the re-run of a recording: each of a radar the scenario has, every number finite
//! and every variance positive. Rows that pass are stamped with the run.

use crate::test_article::TaFault;
use mimo_core::records::RegistrationRow;

/// Check `rows` against a scenario of `n_radars` radars and stamp them with `run`; the first
/// bad row is the test article's fault.
pub fn check_registration(rows: &mut [RegistrationRow], n_radars: usize, run: u32) -> Result<(), TaFault> {
    for r in rows.iter_mut() {
        if r.radar.index() >= n_radars {
            return Err(TaFault::InvalidRequest(format!(
                "registration row for unknown radar {} (the scenario has R1…R{n_radars})",
                r.radar
            )));
        }
        let c = r.covariance();
        let numbers = [r.t_s, r.range_m, r.u, r.v, r.heading_deg].into_iter().chain(c.into_iter().flatten());
        if numbers.into_iter().any(|x| !x.is_finite()) {
            return Err(TaFault::InvalidRequest(format!(
                "registration row of {} has a number that is not finite",
                r.radar
            )));
        }
        if (0..4).any(|k| c[k][k] <= 0.0) {
            return Err(TaFault::InvalidRequest(format!(
                "registration row of {} has a variance that is not positive",
                r.radar
            )));
        }
        r.run = run;
    }
    Ok(())
}
