//! A run's tables written as the engine makes their rows (docs/design.md §2, §8): the
//! [`RunSink`] of `mimo simulate` and of `mimo track`'s re-runs. Each table of the run is a [`TableWriter`] into the run
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

/// The tables of one Monte Carlo run, written as they come. A table the sink does not write
/// (voltages unless recorded; a re-run's truth, dwells and primitives) drops its rows.
pub struct ParquetRunSink {
    truth: Option<Open<TruthRow>>,
    dwells: Option<Open<DwellRow>>,
    primitives: Option<Open<PrimitiveRow>>,
    measurements: Option<Open<MeasurementRow>>,
    tracks: Open<TrackRow>,
    voltages: Option<Open<VoltageRow>>,
}

/// Open a table's file if `on`.
fn open_if<R: TableRow>(
    on: bool,
    dir: &RunDirWriter,
    table: &'static str,
    run: u32,
) -> Result<Option<Open<R>>, StoreError> {
    if on { Ok(Some(Open::new(dir, table, run)?)) } else { Ok(None) }
}

impl ParquetRunSink {
    /// Open run `run`'s files in `dir` (the voltages table only with `record_voltages`).
    pub fn create(dir: &RunDirWriter, run: u32, record_voltages: bool) -> Result<ParquetRunSink, StoreError> {
        Ok(ParquetRunSink {
            truth: open_if(true, dir, "truth", run)?,
            dwells: open_if(true, dir, "dwells", run)?,
            primitives: open_if(true, dir, "primitives", run)?,
            measurements: open_if(true, dir, "measurements", run)?,
            tracks: Open::new(dir, "tracks", run)?,
            voltages: open_if(record_voltages, dir, "voltages", run)?,
        })
    }

    /// Open the files of a re-run of a recording (`mimo track`): tracks, and measurements when
    /// the re-run forms them again (`with_measurements`); the recording's other tables are its
    /// parent's and are not written again.
    pub fn for_rerun(dir: &RunDirWriter, run: u32, with_measurements: bool) -> Result<ParquetRunSink, StoreError> {
        Ok(ParquetRunSink {
            truth: None,
            dwells: None,
            primitives: None,
            measurements: open_if(with_measurements, dir, "measurements", run)?,
            tracks: Open::new(dir, "tracks", run)?,
            voltages: None,
        })
    }

    /// Close every file of the run; returns the manifest entries by table name.
    pub fn finish(self) -> Result<Vec<(&'static str, TableFile)>, StoreError> {
        let mut out = Vec::new();
        for t in [self.truth.map(Open::finish), self.dwells.map(Open::finish), self.primitives.map(Open::finish)] {
            out.extend(t.transpose()?);
        }
        out.extend(self.measurements.map(Open::finish).transpose()?);
        out.push(self.tracks.finish()?);
        out.extend(self.voltages.map(Open::finish).transpose()?);
        Ok(out)
    }
}

/// Hand rows to a table's writer, or drop them if the table is not written.
fn put<R: TableRow>(table: &mut Option<Open<R>>, rows: Vec<R>) -> Result<(), SinkError> {
    match table {
        Some(t) => t.writer.extend(rows).map_err(sink_err),
        None => Ok(()),
    }
}

impl RunSink for ParquetRunSink {
    fn truth(&mut self, rows: Vec<TruthRow>) -> Result<(), SinkError> {
        put(&mut self.truth, rows)
    }
    fn dwell(&mut self, row: DwellRow) -> Result<(), SinkError> {
        match &mut self.dwells {
            Some(t) => t.writer.push(row).map_err(sink_err),
            None => Ok(()),
        }
    }
    fn voltages(&mut self, rows: Vec<VoltageRow>) -> Result<(), SinkError> {
        put(&mut self.voltages, rows)
    }
    fn primitives(&mut self, rows: Vec<PrimitiveRow>) -> Result<(), SinkError> {
        put(&mut self.primitives, rows)
    }
    fn measurements(&mut self, rows: Vec<MeasurementRow>) -> Result<(), SinkError> {
        put(&mut self.measurements, rows)
    }
    fn tracks(&mut self, rows: Vec<TrackRow>) -> Result<(), SinkError> {
        self.tracks.writer.extend(rows).map_err(sink_err)
    }
}
