//! Where a run's rows go as they are produced.
//!
//! The simulation engine and the offline replay push rows into a [`RunSink`] as they make them,
//! one Monte Carlo run per sink. They never build Arrow arrays and never hold more of a run than
//! the sink keeps: [`RunTables`] keeps everything in memory (tests, small runs), while
//! `mimo-store`'s Parquet sink writes row groups as they fill, so memory stays flat however long
//! the run (docs/design.md §8).

use crate::records::{
    BiasRow, DwellRow, MeasurementRow, PrimitiveRow, RegistrationRow, RunTables, TrackRow, TruthRow, VoltageRow,
};
use std::fmt;

/// A sink failed to take rows (a write error, typically). The message says what and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SinkError(pub String);

impl fmt::Display for SinkError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for SinkError {}

/// Receives the rows of one Monte Carlo run, table by table, in the order they are made.
pub trait RunSink {
    /// Truth samples, in time order, in one or more blocks at the start of a run.
    fn truth(&mut self, rows: Vec<TruthRow>) -> Result<(), SinkError>;
    /// One radar's part in one dwell.
    fn dwell(&mut self, row: DwellRow) -> Result<(), SinkError>;
    /// Voltages of one dwell (only when they are recorded).
    fn voltages(&mut self, rows: Vec<VoltageRow>) -> Result<(), SinkError>;
    /// Detection primitives of one dwell.
    fn primitives(&mut self, rows: Vec<PrimitiveRow>) -> Result<(), SinkError>;
    /// Measurements of one dwell.
    fn measurements(&mut self, rows: Vec<MeasurementRow>) -> Result<(), SinkError>;
    /// Track rows, as the test article hands them over.
    fn tracks(&mut self, rows: Vec<TrackRow>) -> Result<(), SinkError>;
    /// The run's registration biases, once at its start (only when biases are on,
    /// docs/model.md §5.5).
    fn biases(&mut self, rows: Vec<BiasRow>) -> Result<(), SinkError>;
    /// A test article's registration estimates, as it reports them (docs/model.md §6.9).
    fn registration(&mut self, rows: Vec<RegistrationRow>) -> Result<(), SinkError>;
}

/// The in-memory sink: every row of the run, kept.
impl RunSink for RunTables {
    fn truth(&mut self, mut rows: Vec<TruthRow>) -> Result<(), SinkError> {
        self.truth.append(&mut rows);
        Ok(())
    }
    fn dwell(&mut self, row: DwellRow) -> Result<(), SinkError> {
        self.dwells.push(row);
        Ok(())
    }
    fn voltages(&mut self, mut rows: Vec<VoltageRow>) -> Result<(), SinkError> {
        self.voltages.append(&mut rows);
        Ok(())
    }
    fn primitives(&mut self, mut rows: Vec<PrimitiveRow>) -> Result<(), SinkError> {
        self.primitives.append(&mut rows);
        Ok(())
    }
    fn measurements(&mut self, mut rows: Vec<MeasurementRow>) -> Result<(), SinkError> {
        self.measurements.append(&mut rows);
        Ok(())
    }
    fn tracks(&mut self, mut rows: Vec<TrackRow>) -> Result<(), SinkError> {
        self.tracks.append(&mut rows);
        Ok(())
    }
    fn biases(&mut self, mut rows: Vec<BiasRow>) -> Result<(), SinkError> {
        self.biases.append(&mut rows);
        Ok(())
    }
    fn registration(&mut self, mut rows: Vec<RegistrationRow>) -> Result<(), SinkError> {
        self.registration.append(&mut rows);
        Ok(())
    }
}
