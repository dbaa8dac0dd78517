//! The sink a study run writes through: it hands the run's rows on to the sink that writes them
//! (the cell's table files, as they come), sums the run's transmit usage as its dwells pass, and
//! stops the run when the method has failed in a way the engine does not see — a covariance that
//! is not positive definite, more tracks than the plan allows, or a run past its wall-time limit.
//! Rows that break a check are not handed on.

use crate::run_usage::RunUsage;
use mimo_core::records::{
    BiasRow, DwellRow, MeasurementRow, PrimitiveRow, RegistrationRow, TrackRow, TruthRow, VoltageRow, unpack_cov,
};
use mimo_core::sink::{RunSink, SinkError};
use mimo_metrics::DwellRows;
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

/// The deadline is checked at every this many dwells.
const CLOCK_EVERY_DWELLS: u64 = 64;

/// Checks a run's rows and hands them on to `inner`.
pub struct Guarded<'s> {
    inner: &'s mut dyn RunSink,
    /// The run's transmit usage, summed over the dwells handed on.
    pub usage: RunUsage,
    interval_s: f64,
    tracks: BTreeSet<u64>,
    max_tracks: u64,
    deadline: Instant,
    /// Dwells handed on so far (the clock is read every [`CLOCK_EVERY_DWELLS`]).
    dwells: u64,
    /// The reason the method failed and the run was stopped, if it was.
    pub failure: Option<String>,
    /// Why `inner` could not take rows (a fault of the system, not the method), if it could not.
    pub fault: Option<String>,
    /// The run's drawn registration biases and the test article's estimates of them
    /// (docs/model.md §5.5, §6.9), kept for the run's registration error.
    pub biases: Vec<BiasRow>,
    /// See [`Guarded::biases`].
    pub registration: Vec<RegistrationRow>,
    /// The run's dwells reduced for its score as they are handed on, when the run is scored
    /// from them rather than from its dwells file ([`Guarded::reducing_dwells`]).
    pub dwell_rows: Option<DwellRows>,
}

impl<'s> Guarded<'s> {
    /// A sink handing rows on to `inner`, allowing `max_tracks` tracks, running until
    /// `deadline` and summing usage per scoring interval of `interval_s`.
    pub fn new(inner: &'s mut dyn RunSink, max_tracks: u64, deadline: Instant, interval_s: f64) -> Guarded<'s> {
        Guarded {
            inner,
            usage: RunUsage::default(),
            interval_s,
            tracks: BTreeSet::new(),
            max_tracks,
            deadline,
            dwells: 0,
            failure: None,
            fault: None,
            biases: Vec::new(),
            registration: Vec::new(),
            dwell_rows: None,
        }
    }

    /// Also reduce run `run`'s dwells for its score as they come (per scoring interval of
    /// `interval_s`; docs/decisions/0321-study-runs-scored-from-their-dwell-rows.md).
    pub fn reducing_dwells(mut self, run: u32, interval_s: f64) -> Guarded<'s> {
        self.dwell_rows = Some(DwellRows::new(run, interval_s));
        self
    }

    fn fail(&mut self, why: String) -> SinkError {
        self.failure = Some(why.clone());
        SinkError(why)
    }

    /// The inner sink's answer, its error noted as a fault.
    fn pass(&mut self, r: Result<(), SinkError>) -> Result<(), SinkError> {
        if let Err(e) = &r {
            self.fault.get_or_insert_with(|| e.0.clone());
        }
        r
    }
}

impl RunSink for Guarded<'_> {
    fn truth(&mut self, rows: Vec<TruthRow>) -> Result<(), SinkError> {
        let r = self.inner.truth(rows);
        self.pass(r)
    }
    fn dwell(&mut self, row: DwellRow) -> Result<(), SinkError> {
        // A 1 000-s run of scenario 7 makes about 650 000 dwells: reading the clock for each cost
        // 3 % of a study item; every 64th (the first included) is well within a second.
        let check_clock = self.dwells.is_multiple_of(CLOCK_EVERY_DWELLS);
        self.dwells += 1;
        if check_clock && Instant::now() > self.deadline {
            return Err(self.fail(format!("{FAIL_TIME} (at t = {:.1} s of the run)", row.t_s)));
        }
        self.usage.add(&row, self.interval_s);
        if let Some(d) = &mut self.dwell_rows {
            d.push(&row);
        }
        let r = self.inner.dwell(row);
        self.pass(r)
    }
    fn voltages(&mut self, rows: Vec<VoltageRow>) -> Result<(), SinkError> {
        let r = self.inner.voltages(rows);
        self.pass(r)
    }
    fn primitives(&mut self, rows: Vec<PrimitiveRow>) -> Result<(), SinkError> {
        let r = self.inner.primitives(rows);
        self.pass(r)
    }
    fn measurements(&mut self, rows: Vec<MeasurementRow>) -> Result<(), SinkError> {
        let r = self.inner.measurements(rows);
        self.pass(r)
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
        let r = self.inner.tracks(rows);
        self.pass(r)
    }
    fn biases(&mut self, rows: Vec<BiasRow>) -> Result<(), SinkError> {
        self.biases.extend(rows.iter().cloned());
        let r = self.inner.biases(rows);
        self.pass(r)
    }
    fn registration(&mut self, rows: Vec<RegistrationRow>) -> Result<(), SinkError> {
        self.registration.extend(rows.iter().cloned());
        let r = self.inner.registration(rows);
        self.pass(r)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::records::RunTables;

    /// The deadline stops a run at the first dwell after it (the clock is read at the first dwell
    /// and every 64th after); before it every dwell is handed on and its usage summed.
    #[test]
    fn a_run_past_its_deadline_fails_on_time_and_one_before_it_goes_on() {
        let rows =
            mimo_store::testing::varied_dwell_rows(0, &(0..200).map(|i| 0.01 * f64::from(i)).collect::<Vec<_>>());
        let mut kept = RunTables::default();
        let late = Instant::now() - std::time::Duration::from_secs(1);
        let mut g = Guarded::new(&mut kept, 10, late, 1.0);
        let e = g.dwell(rows[0].clone()).expect_err("past the deadline");
        assert!(e.0.starts_with(FAIL_TIME), "{e}");
        assert!(g.failure.as_deref().is_some_and(|f| f.starts_with(FAIL_TIME)));
        let mut kept = RunTables::default();
        let soon = Instant::now() + std::time::Duration::from_secs(3600);
        let mut g = Guarded::new(&mut kept, 10, soon, 1.0);
        for r in &rows {
            g.dwell(r.clone()).expect("before the deadline");
        }
        assert_eq!(g.failure, None);
        let want = crate::run_usage::RunUsage::of(&rows, 1.0);
        assert_eq!(g.usage, want);
        assert_eq!(kept.dwells.len(), rows.len());
    }

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
