//! A run's tables written as the engine makes their rows (docs/design.md §2, §8): the
//! [`RunSink`] of `mimo simulate`, of `mimo track`'s re-runs and of a study's items. Each table of
//! the run is a [`TableWriter`], so a run in progress holds a chunk of rows per table and the
//! encoded pages of one row group, whatever its duration; the files get their names when the run
//! finishes ([`ParquetRunSink::finish`]). Where they go is a [`RunFiles`]: a run directory's
//! staging area ([`RunDirWriter`], published only after every run) or a study cell's directory
//! ([`RunDir`], each file named as its run finishes).

use crate::layout::RunDir;
use crate::manifest::TableFile;
use crate::rows::TableRow;
use crate::rundir::RunDirWriter;
use crate::table_writer::TableWriter;
use crate::{StoreError, io_err};
use mimo_core::records::{
    BiasRow, DwellRow, MeasurementRow, PrimitiveRow, RegistrationRow, TrackRow, TruthRow, VoltageRow,
};
use mimo_core::sink::{RunSink, SinkError};

/// Where the table files of a run are written.
pub trait RunFiles {
    /// Start run `run`'s file of `table`: its path relative to the run directory (as the
    /// manifest lists it) and its writer.
    fn open_run_table<R: TableRow>(&self, table: &str, run: u32) -> Result<(String, TableWriter<R>), StoreError>;
}

impl RunFiles for RunDirWriter {
    fn open_run_table<R: TableRow>(&self, table: &str, run: u32) -> Result<(String, TableWriter<R>), StoreError> {
        RunDirWriter::open_run_table(self, table, run)
    }
}

/// A run directory written in place (a study cell): the table's directory is created if need
/// be, and each file appears under its name when its writer finishes.
impl RunFiles for RunDir {
    fn open_run_table<R: TableRow>(&self, table: &str, run: u32) -> Result<(String, TableWriter<R>), StoreError> {
        let dir = self.table_dir(table);
        std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
        Ok((RunDir::table_file_rel(table, run), TableWriter::create(&self.table_file(table, run))?))
    }
}

/// A study cell's directory whose run tables are scratch files ([`crate::WriteMode::Scratch`]):
/// written in place as [`RunDir`] writes them, read back once by the item's score and deleted
/// (a study that does not keep its runs, docs/studies.md).
pub struct ScratchRunDir(pub RunDir);

impl RunFiles for ScratchRunDir {
    fn open_run_table<R: TableRow>(&self, table: &str, run: u32) -> Result<(String, TableWriter<R>), StoreError> {
        let dir = self.0.table_dir(table);
        std::fs::create_dir_all(&dir).map_err(io_err(&dir))?;
        let writer = TableWriter::create_for(&self.0.table_file(table, run), crate::WriteMode::Scratch)?;
        Ok((RunDir::table_file_rel(table, run), writer))
    }
}

/// One table of a run being written, with its path in the run directory.
struct Open<R: TableRow> {
    table: &'static str,
    rel: String,
    writer: TableWriter<R>,
}

impl<R: TableRow> Open<R> {
    fn new(dir: &impl RunFiles, table: &'static str, run: u32) -> Result<Open<R>, StoreError> {
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
/// (voltages unless recorded; a re-run's truth, dwells and primitives; a table a study plan does
/// not record) drops its rows.
pub struct ParquetRunSink {
    truth: Option<Open<TruthRow>>,
    dwells: Option<Open<DwellRow>>,
    primitives: Option<Open<PrimitiveRow>>,
    measurements: Option<Open<MeasurementRow>>,
    tracks: Option<Open<TrackRow>>,
    voltages: Option<Open<VoltageRow>>,
    /// The registration biases, opened by [`ParquetRunSink::with_biases`] only.
    biases: Option<Open<BiasRow>>,
    /// The test article's registration estimates, opened by
    /// [`ParquetRunSink::with_registration`] only.
    registration: Option<Open<RegistrationRow>>,
}

/// Open a table's file if `wanted` says so.
fn open_if<R: TableRow>(
    wanted: &dyn Fn(&str) -> bool,
    dir: &impl RunFiles,
    table: &'static str,
    run: u32,
) -> Result<Option<Open<R>>, StoreError> {
    if wanted(table) { Ok(Some(Open::new(dir, table, run)?)) } else { Ok(None) }
}

impl ParquetRunSink {
    /// Open run `run`'s files in `dir` of the tables `wanted` names (`truth`, `dwells`,
    /// `primitives`, `measurements`, `tracks`, `voltages`), in that order; the others' rows are
    /// dropped.
    pub fn with_tables(
        dir: &impl RunFiles,
        run: u32,
        wanted: &dyn Fn(&str) -> bool,
    ) -> Result<ParquetRunSink, StoreError> {
        Ok(ParquetRunSink {
            truth: open_if(wanted, dir, "truth", run)?,
            dwells: open_if(wanted, dir, "dwells", run)?,
            primitives: open_if(wanted, dir, "primitives", run)?,
            measurements: open_if(wanted, dir, "measurements", run)?,
            tracks: open_if(wanted, dir, "tracks", run)?,
            voltages: open_if(wanted, dir, "voltages", run)?,
            biases: None,
            registration: None,
        })
    }

    /// Also write run `run`'s `biases` table in `dir` (a run whose scenario has registration
    /// biases on, docs/model.md §5.5); without it, the biases' rows are dropped and no file is
    /// made.
    pub fn with_biases(mut self, dir: &impl RunFiles, run: u32) -> Result<ParquetRunSink, StoreError> {
        self.biases = Some(Open::new(dir, "biases", run)?);
        Ok(self)
    }

    /// Also write run `run`'s `registration` table in `dir`: the test article's estimates of the
    /// biases (docs/model.md §6.9), empty if it reports none. Without it, their rows are dropped.
    pub fn with_registration(mut self, dir: &impl RunFiles, run: u32) -> Result<ParquetRunSink, StoreError> {
        self.registration = Some(Open::new(dir, "registration", run)?);
        Ok(self)
    }

    /// Open run `run`'s files in `dir`: every table, the voltages only with `record_voltages`.
    pub fn create(dir: &RunDirWriter, run: u32, record_voltages: bool) -> Result<ParquetRunSink, StoreError> {
        ParquetRunSink::with_tables(dir, run, &|t| t != "voltages" || record_voltages)
    }

    /// Open the files of a re-run of a recording (`mimo track`): tracks, and measurements when
    /// the re-run forms them again (`with_measurements`); the recording's other tables are its
    /// parent's and are not written again.
    pub fn for_rerun(dir: &RunDirWriter, run: u32, with_measurements: bool) -> Result<ParquetRunSink, StoreError> {
        ParquetRunSink::with_tables(dir, run, &|t| t == "tracks" || (with_measurements && t == "measurements"))
    }

    /// Close every file of the run; returns the manifest entries by table name.
    pub fn finish(self) -> Result<Vec<(&'static str, TableFile)>, StoreError> {
        let mut out = Vec::new();
        for t in [self.truth.map(Open::finish), self.dwells.map(Open::finish), self.primitives.map(Open::finish)] {
            out.extend(t.transpose()?);
        }
        for t in [self.measurements.map(Open::finish), self.tracks.map(Open::finish), self.voltages.map(Open::finish)] {
            out.extend(t.transpose()?);
        }
        out.extend(self.biases.map(Open::finish).transpose()?);
        out.extend(self.registration.map(Open::finish).transpose()?);
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
        put(&mut self.tracks, rows)
    }
    fn biases(&mut self, rows: Vec<BiasRow>) -> Result<(), SinkError> {
        put(&mut self.biases, rows)
    }
    fn registration(&mut self, rows: Vec<RegistrationRow>) -> Result<(), SinkError> {
        put(&mut self.registration, rows)
    }
}
