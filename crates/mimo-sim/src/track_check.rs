//! The track rows a test article returns, checked as they arrive (docs/design.md §7) by the
//! tracks table's own rules: finite states at times from 0 on, covariances the table accepts
//! (`mimo_core::covariance`: finite, positive variances, positive semi-definite or slightly
//! indefinite within the bound, the latter repaired in the row and counted), and no row further
//! back in time than the out-of-sequence window ([`TRACK_OUT_OF_SEQUENCE_S`]) behind the same
//! track's latest earlier row. The tables' readers refuse such rows later anyway; refusing them
//! here stops the run at the reply that broke the rule, with the test article named, instead of
//! after a whole simulation.

use crate::test_article::TaFault;
use mimo_core::covariance::{Accepted, check};
use mimo_core::records::TrackRow;
use mimo_core::table_rules::TRACK_OUT_OF_SEQUENCE_S;
use std::collections::BTreeMap;

/// The latest time seen of every track of one run, and the covariances repaired so far.
#[derive(Debug, Default)]
pub struct TrackRowCheck {
    latest_s: BTreeMap<u64, f64>,
    repaired: u64,
    worst_ratio: f64,
}

impl TrackRowCheck {
    /// Rows whose covariance was repaired so far.
    pub fn repaired(&self) -> u64 {
        self.repaired
    }

    /// The most negative smallest-to-largest eigenvalue ratio among the repaired (0 if none).
    pub fn worst_ratio(&self) -> f64 {
        self.worst_ratio
    }

    /// Check `rows` (one reply's, in order) against each other and everything seen before; a
    /// slightly indefinite covariance is replaced by its repair.
    pub fn check(&mut self, rows: &mut [TrackRow]) -> Result<(), TaFault> {
        for r in rows {
            let finite = [r.t_s, r.x_m, r.y_m, r.z_m, r.vx_mps, r.vy_mps, r.vz_mps].iter().all(|x| x.is_finite());
            if !finite || r.t_s < 0.0 {
                return Err(TaFault::InvalidRequest(format!(
                    "track {} at t = {} s has a non-finite state or a negative time",
                    r.track_id, r.t_s
                )));
            }
            let accepted = check(&r.cov).map_err(|why| {
                TaFault::InvalidRequest(format!("track {} at t = {} s: covariance {why}", r.track_id, r.t_s))
            })?;
            if let Accepted::Repaired { cov, min_eigenvalue, max_eigenvalue } = accepted {
                r.cov = cov;
                self.repaired += 1;
                self.worst_ratio = self.worst_ratio.min(min_eigenvalue / max_eigenvalue);
            }
            let latest = self.latest_s.entry(r.track_id).or_insert(r.t_s);
            if r.t_s < *latest - TRACK_OUT_OF_SEQUENCE_S {
                return Err(TaFault::InvalidRequest(format!(
                    "track {} has a row at t = {} s, {:.3} s before its row at t = {} s \
                     (rows may step back at most {TRACK_OUT_OF_SEQUENCE_S} s, an out-of-sequence update)",
                    r.track_id,
                    r.t_s,
                    *latest - r.t_s,
                    *latest
                )));
            }
            *latest = latest.max(r.t_s);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn identity() -> [[f64; 6]; 6] {
        std::array::from_fn(|i| std::array::from_fn(|j| if i == j { 1.0 } else { 0.0 }))
    }

    fn row(track_id: u64, t_s: f64) -> TrackRow {
        TrackRow {
            run: 0,
            t_s,
            track_id,
            status: mimo_core::records::TrackStatus::Confirmed,
            x_m: 0.0,
            y_m: 0.0,
            z_m: 0.0,
            vx_mps: 0.0,
            vy_mps: 0.0,
            vz_mps: 0.0,
            cov: mimo_core::records::pack_cov(&identity()),
            n_updates: 1,
            last_meas_id: None,
        }
    }

    #[test]
    fn an_out_of_sequence_update_passes_and_a_step_back_beyond_the_window_does_not() {
        let mut c = TrackRowCheck::default();
        c.check(&mut [row(1, 100.0), row(2, 10.0)]).expect("first rows");
        c.check(&mut [row(1, 99.95), row(1, 100.2)]).expect("50 ms back is an out-of-sequence update");
        // The window is measured from the latest time, not the last row's.
        let e = c.check(&mut [row(1, 70.0)]).expect_err("30 s back");
        assert!(e.to_string().contains("track 1 has a row at t = 70 s, 30.200 s before its row at t = 100.2 s"), "{e}");
        // Another track keeps its own clock.
        c.check(&mut [row(2, 10.5)]).expect("track 2");
    }

    #[test]
    fn a_covariance_the_tracks_table_refuses_is_refused_at_once() {
        let mut c = TrackRowCheck::default();
        let mut m = identity();
        m[0][0] = -1.0;
        let e =
            c.check(&mut [TrackRow { cov: mimo_core::records::pack_cov(&m), ..row(3, 5.0) }]).expect_err("negative");
        assert!(e.to_string().contains("track 3 at t = 5 s: covariance variance 0 (diagonal) is -1"), "{e}");
        let mut m = identity();
        (m[0][1], m[1][0]) = (2.0, 2.0);
        let e = c.check(&mut [TrackRow { cov: mimo_core::records::pack_cov(&m), ..row(3, 5.0) }]).expect_err("not PSD");
        assert!(e.to_string().contains("is not positive semi-definite"), "{e}");
        let e = c.check(&mut [row(4, -1.0)]).expect_err("negative time");
        assert!(e.to_string().contains("negative time"), "{e}");
        assert_eq!(c.repaired(), 0);
    }

    /// A correlation of 1 + 1e-7 (smallest eigenvalue -1e-7 of the largest, 2): repaired in the
    /// row, counted, and the row is then valid.
    #[test]
    fn a_slightly_indefinite_covariance_is_repaired_and_counted() {
        let mut c = TrackRowCheck::default();
        let mut m = identity();
        (m[0][1], m[1][0]) = (1.0 + 2e-7, 1.0 + 2e-7);
        let mut rows = [TrackRow { cov: mimo_core::records::pack_cov(&m), ..row(5, 1.0) }, row(6, 1.0)];
        c.check(&mut rows).expect("within the bound");
        assert_eq!(c.repaired(), 1);
        assert!((c.worst_ratio() + 1e-7).abs() < 1e-9, "{}", c.worst_ratio());
        assert_eq!(mimo_core::covariance::check(&rows[0].cov), Ok(Accepted::Valid));
        assert_eq!(rows[1].cov, mimo_core::records::pack_cov(&identity()), "a valid row is untouched");
    }
}
