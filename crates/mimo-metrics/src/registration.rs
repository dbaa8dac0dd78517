//! The registration error (docs/design.md §6, "Registration error"): per run and radar, a test
//! article's last estimate of the radar's biases minus the biases drawn for it, and that error's
//! NEES under the estimate's own 4 × 4 covariance block. With biases off, or a test article that
//! reports no estimate, there is nothing to score and nothing is written.

use crate::results::{RegistrationErrorRow, RegistrationSummary};
use mimo_core::records::{BiasRow, RegistrationRow};
use std::collections::BTreeMap;

/// The registration error of every (run, radar) that has both a drawn bias and an estimate, by
/// run then radar. Of a radar's estimates the last (largest `t_s`, the later row on a tie)
/// counts.
pub fn registration_errors(biases: &[BiasRow], estimates: &[RegistrationRow]) -> Vec<RegistrationErrorRow> {
    let mut last: BTreeMap<(u32, mimo_core::ids::RadarId), &RegistrationRow> = BTreeMap::new();
    for e in estimates {
        let slot = last.entry((e.run, e.radar)).or_insert(e);
        if e.t_s >= slot.t_s {
            *slot = e;
        }
    }
    let truth: BTreeMap<_, _> = biases.iter().map(|b| ((b.run, b.radar), b)).collect();
    last.into_iter()
        .filter_map(|(key, e)| {
            let b = truth.get(&key)?;
            let err = [e.range_m - b.range_m, e.u - b.u, e.v - b.v, e.heading_deg - b.heading_deg];
            Some(RegistrationErrorRow {
                run: key.0,
                radar: key.1.to_string(),
                t_s: e.t_s,
                looks: e.looks,
                range_error_m: err[0],
                u_error: err[1],
                v_error: err[2],
                heading_error_deg: err[3],
                nees: nees4(&e.covariance(), &err),
            })
        })
        .collect()
}

/// `eᵀ P⁻¹ e` by Cholesky; `None` if `p` is not positive definite.
fn nees4(p: &[[f64; 4]; 4], e: &[f64; 4]) -> Option<f64> {
    // Scale to unit diagonal first: the units (m, sine, deg) differ by orders of magnitude.
    let d: Vec<f64> = (0..4).map(|i| p[i][i].sqrt()).collect();
    if d.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
        return None;
    }
    let mut l = [[0.0f64; 4]; 4];
    for i in 0..4 {
        for j in 0..=i {
            let s = p[i][j] / (d[i] * d[j]) - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if s.is_nan() || s <= 1e-12 {
                    return None;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    // Forward substitution: L y = e / d; NEES = |y|².
    let mut y = [0.0f64; 4];
    for i in 0..4 {
        y[i] = (e[i] / d[i] - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
    }
    Some(y.iter().map(|v| v * v).sum())
}

/// The summary of the registration errors: RMS of each component over every (run, radar), and
/// the mean NEES (4 if the estimates are consistent). `None` when there are none.
pub fn registration_summary(rows: &[RegistrationErrorRow]) -> Option<RegistrationSummary> {
    if rows.is_empty() {
        return None;
    }
    let n = rows.len() as f64;
    let rms = |f: fn(&RegistrationErrorRow) -> f64| (rows.iter().map(|r| f(r).powi(2)).sum::<f64>() / n).sqrt();
    let nees: Vec<f64> = rows.iter().filter_map(|r| r.nees).collect();
    Some(RegistrationSummary {
        estimates: rows.len() as u32,
        range_error_rms_m: rms(|r| r.range_error_m),
        u_error_rms: rms(|r| r.u_error),
        v_error_rms: rms(|r| r.v_error),
        heading_error_rms_deg: rms(|r| r.heading_error_deg),
        nees_mean: (!nees.is_empty()).then(|| nees.iter().sum::<f64>() / nees.len() as f64),
        nees_dof: 4,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::ids::RadarId;

    fn estimate(run: u32, radar: u8, t_s: f64, range_m: f64, var_range_m2: f64) -> RegistrationRow {
        RegistrationRow {
            run,
            t_s,
            radar: RadarId(radar),
            range_m,
            u: 1e-3,
            v: 0.0,
            heading_deg: 0.1,
            var_range_m2,
            var_u: 1e-6,
            var_v: 1e-6,
            var_heading_deg2: 0.01,
            cov_range_u_m: 0.0,
            cov_range_v_m: 0.0,
            cov_range_heading_m_deg: 0.0,
            cov_u_v: 0.0,
            cov_u_heading_deg: 0.0,
            cov_v_heading_deg: 0.0,
            looks: 7,
        }
    }

    fn truth(run: u32, radar: u8, range_m: f64) -> BiasRow {
        BiasRow { run, radar: RadarId(radar), range_m, u: 0.0, v: 2e-3, heading_deg: 0.0 }
    }

    #[test]
    fn the_last_estimate_is_scored_against_its_own_radar_and_run() {
        let biases = [truth(0, 0, 10.0), truth(0, 1, -5.0), truth(1, 0, 0.0)];
        let estimates = [
            estimate(0, 0, 50.0, 0.0, 4.0),
            estimate(0, 0, 100.0, 12.0, 4.0), // the last: counts
            estimate(0, 1, 100.0, -5.0, 4.0),
            estimate(2, 0, 100.0, 0.0, 4.0), // no truth for run 2: left out
        ];
        let rows = registration_errors(&biases, &estimates);
        assert_eq!(rows.len(), 2);
        let r = &rows[0];
        assert_eq!((r.run, r.radar.as_str(), r.t_s), (0, "R1", 100.0));
        assert!((r.range_error_m - 2.0).abs() < 1e-12 && (r.u_error - 1e-3).abs() < 1e-15);
        assert!((r.v_error + 2e-3).abs() < 1e-15 && (r.heading_error_deg - 0.1).abs() < 1e-15);
        // Hand-made: (2/2)² + (1e-3/1e-3)² + (2e-3/1e-3)² + (0.1/0.1)² = 1 + 1 + 4 + 1.
        assert!((r.nees.expect("nees") - 7.0).abs() < 1e-9, "{:?}", r.nees);
        let s = registration_summary(&rows).expect("summary");
        assert_eq!(s.estimates, 2);
        assert!((s.range_error_rms_m - (4.0f64 / 2.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_correlated_covariance_is_inverted_whole_and_a_singular_one_gives_no_nees() {
        // Range and heading correlated at 0.8: with errors along the correlation the NEES is
        // smaller than the diagonal's.
        let mut e = estimate(0, 0, 1.0, 2.0, 4.0);
        (e.u, e.v, e.heading_deg) = (0.0, 0.0, 0.1);
        e.cov_range_heading_m_deg = 0.8 * 2.0 * 0.1;
        let rows = registration_errors(&[BiasRow { v: 0.0, ..truth(0, 0, 0.0) }], &[e.clone()]);
        // e = (1, 0, 0, 1) in σ units, correlation 0.8: eᵀC⁻¹e = 2 (1 − 0.8) / (1 − 0.64) = 10/9.
        assert!((rows[0].nees.expect("nees") - 10.0 / 9.0).abs() < 1e-9, "{:?}", rows[0].nees);
        e.cov_range_heading_m_deg = 2.0 * 0.1;
        let rows = registration_errors(&[truth(0, 0, 0.0)], &[e]);
        assert_eq!(rows[0].nees, None);
    }
}
