//! A run's tables written as the engine makes their rows (docs/design.md §2, §8): the
//! [`RunSink`] of `mimo simulate`. Each table of the run is a [`TableWriter`] into the run
//! directory's staging area, so a run in progress holds a chunk of rows per table and the encoded
//! pages of one row group, whatever its duration; the files get their names when the run
//! finishes ([`ParquetRunSink::finish`]) and the run directory is published only after every run.

use crate::StoreError;
use crate::manifest::TableFile;
use crate::rows::TableRow;
use crate::rundir::RunDirWriter;
use crate::table_writer::TableWriter;
use mimo_core::records::{DwellRow, MeasurementRow, PrimitiveRow, TrackRow, TruthRow, VoltageRow};
use mimo_core::sink::{RunSink, SinkError};

/// One table of a run being written, with its path in the run directory.
struct Open<R: TableRow> {
    table: &'static str,
    rel: String,
    writer: TableWriter<R>,
}

impl<R: TableRow> Open<R> {
    fn new(dir: &RunDirWriter, table: &'static str, run: u32) -> Result<Open<R>, StoreError> {
        let (rel, writer) = dir.open_run_table(table, run)?;
        Ok(Open { table, rel, writer })
    }

    fn finish(self) -> Result<(&'static str, TableFile), StoreError> {
        let rows = self.writer.finish()?;
        Ok((self.table, TableFile { file: self.rel, rows }))
    }
}

fn sink_err(e: StoreError) -> SinkError {
    SinkError(e.to_string())
}

/// The tables of one Monte Carlo run, written as they come.
pub struct ParquetRunSink {
    truth: Open<TruthRow>,
    dwells: Open<DwellRow>,
    primitives: Open<PrimitiveRow>,
    measurements: Open<MeasurementRow>,
    tracks: Open<TrackRow>,
    voltages: Option<Open<VoltageRow>>,
}

impl ParquetRunSink {
    /// Open run `run`'s files in `dir` (the voltages table only with `record_voltages`).
    pub fn create(dir: &RunDirWriter, run: u32, record_voltages: bool) -> Result<ParquetRunSink, StoreError> {
        Ok(ParquetRunSink {
            truth: Open::new(dir, "truth", run)?,
            dwells: Open::new(dir, "dwells", run)?,
            primitives: Open::new(dir, "primitives", run)?,
            measurements: Open::new(dir, "measurements", run)?,
            tracks: Open::new(dir, "tracks", run)?,
            voltages: if record_voltages { Some(Open::new(dir, "voltages", run)?) } else { None },
        })
    }

    /// Close every file of the run; returns the manifest entries by table name.
    pub fn finish(self) -> Result<Vec<(&'static str, TableFile)>, StoreError> {
        let mut out = vec![
            self.truth.finish()?,
            self.dwells.finish()?,
            self.primitives.finish()?,
            self.measurements.finish()?,
            self.tracks.finish()?,
        ];
        if let Some(v) = self.voltages {
            out.push(v.finish()?);
        }
        Ok(out)
    }
}

impl RunSink for ParquetRunSink {
    fn truth(&mut self, rows: Vec<TruthRow>) -> Result<(), SinkError> {
        self.truth.writer.extend(rows).map_err(sink_err)
    }
    fn dwell(&mut self, row: DwellRow) -> Result<(), SinkError> {
        self.dwells.writer.push(row).map_err(sink_err)
    }
    fn voltages(&mut self, rows: Vec<VoltageRow>) -> Result<(), SinkError> {
        match &mut self.voltages {
            Some(v) => v.writer.extend(rows).map_err(sink_err),
            None => Ok(()),
        }
    }
    fn primitives(&mut self, rows: Vec<PrimitiveRow>) -> Result<(), SinkError> {
        self.primitives.writer.extend(rows).map_err(sink_err)
    }
    fn measurements(&mut self, rows: Vec<MeasurementRow>) -> Result<(), SinkError> {
        self.measurements.writer.extend(rows).map_err(sink_err)
    }
    fn tracks(&mut self, rows: Vec<TrackRow>) -> Result<(), SinkError> {
        self.tracks.writer.extend(rows).map_err(sink_err)
    }
}
