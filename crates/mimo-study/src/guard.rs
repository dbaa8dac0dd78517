//! The sink a study run writes through: it keeps the run's rows and stops the run when the
//! method has failed in a way the engine does not see — a covariance that is not positive
//! definite, more tracks than the plan allows, or a run past its wall-time limit.

use mimo_core::records::{
    DwellRow, MeasurementRow, PrimitiveRow, RunTables, TrackRow, TruthRow, VoltageRow, unpack_cov,
};
use mimo_core::sink::{RunSink, SinkError};
use std::collections::BTreeSet;
use std::time::Instant;

/// Why a run failed, as the results table says it (a short reason).
pub const FAIL_NOT_PD: &str = "covariance not positive definite";
/// See [`FAIL_NOT_PD`].
pub const FAIL_TRACKS: &str = "track count ran away";
/// See [`FAIL_NOT_PD`].
pub const FAIL_TIME: &str = "time limit";

/// Is a symmetric 6×6 matrix positive definite (Cholesky succeeds)?
pub fn positive_definite(m: &[[f64; 6]; 6]) -> bool {
    let mut l = [[0.0f64; 6]; 6];
    for i in 0..6 {
        for j in 0..=i {
            let s = m[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>();
            if i == j {
                if !(s > 0.0 && s.is_finite()) {
                    return false;
                }
                l[i][i] = s.sqrt();
            } else {
                l[i][j] = s / l[j][j];
            }
        }
    }
    true
}

/// Keeps a run's rows and checks them.
pub struct Guarded {
    /// The rows so far.
    pub tables: RunTables,
    tracks: BTreeSet<u64>,
    max_tracks: u64,
    deadline: Instant,
    /// The reason the run was stopped, if it was.
    pub failure: Option<String>,
}

impl Guarded {
    /// A sink allowing `max_tracks` tracks and running until `deadline`.
    pub fn new(max_tracks: u64, deadline: Instant) -> Guarded {
        Guarded { tables: RunTables::default(), tracks: BTreeSet::new(), max_tracks, deadline, failure: None }
    }

    fn fail(&mut self, why: String) -> SinkError {
        self.failure = Some(why.clone());
        SinkError(why)
    }
}

impl RunSink for Guarded {
    fn truth(&mut self, rows: Vec<TruthRow>) -> Result<(), SinkError> {
        self.tables.truth(rows)
    }
    fn dwell(&mut self, row: DwellRow) -> Result<(), SinkError> {
        if Instant::now() > self.deadline {
            return Err(self.fail(format!("{FAIL_TIME} (at t = {:.1} s of the run)", row.t_s)));
        }
        self.tables.dwell(row)
    }
    fn voltages(&mut self, rows: Vec<VoltageRow>) -> Result<(), SinkError> {
        self.tables.voltages(rows)
    }
    fn primitives(&mut self, rows: Vec<PrimitiveRow>) -> Result<(), SinkError> {
        self.tables.primitives(rows)
    }
    fn measurements(&mut self, rows: Vec<MeasurementRow>) -> Result<(), SinkError> {
        self.tables.measurements(rows)
    }
    fn tracks(&mut self, rows: Vec<TrackRow>) -> Result<(), SinkError> {
        for r in &rows {
            if !positive_definite(&unpack_cov(&r.cov)) {
                return Err(self.fail(format!("{FAIL_NOT_PD} (track {} at t = {:.1} s)", r.track_id, r.t_s)));
            }
            self.tracks.insert(r.track_id);
        }
        if self.tracks.len() as u64 > self.max_tracks {
            let n = self.max_tracks;
            return Err(self.fail(format!("{FAIL_TRACKS} (more than {n} tracks)")));
        }
        self.tables.tracks(rows)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cholesky_tells_positive_definite_matrices() {
        let mut m = [[0.0; 6]; 6];
        for (i, row) in m.iter_mut().enumerate() {
            row[i] = 1.0 + i as f64;
        }
        m[0][1] = 0.5;
        m[1][0] = 0.5;
        assert!(positive_definite(&m));
        m[0][1] = 2.0;
        m[1][0] = 2.0; // |off-diagonal| > sqrt(1 · 2): indefinite
        assert!(!positive_definite(&m));
        let mut z = [[0.0; 6]; 6];
        assert!(!positive_definite(&z));
        z[0][0] = f64::NAN;
        assert!(!positive_definite(&z));
    }
}
