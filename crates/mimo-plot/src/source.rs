//! The run to plot: its manifest, scenario and the tables of one Monte Carlo run
//! (docs/design.md §2), following the `parent` link of a `mimo track` output for truth, dwells
//! and (when the re-run did not re-form them) measurements.

use crate::PlotError;
use crate::dwell_digest::DwellDigest;
use crate::truth_samples::TruthSamples;
use mimo_core::records::{MeasurementRow, TrackRow};
use mimo_scenario::Scenario;
use mimo_store::layout::RunDir;
use mimo_store::manifest::Manifest;
use mimo_store::{StoreError, read_table};
use std::path::{Path, PathBuf};

/// A run directory opened for plotting.
#[derive(Debug, Clone)]
pub struct RunSource {
    /// The run directory given (its tracks are plotted).
    pub run_dir: PathBuf,
    /// Its manifest.
    pub manifest: Manifest,
    /// The resolved scenario of the manifest.
    pub scenario: Scenario,
    /// The run directory holding truth and dwells: `run_dir`, or the end of its parent chain.
    pub source_dir: PathBuf,
}

/// The tables of one Monte Carlo run.
#[derive(Debug, Clone, Default)]
pub struct RunTables {
    /// Truth samples, by target (read chunk by chunk into 56 bytes a sample).
    pub truth: TruthSamples,
    /// What the page keeps of the dwell parts (read chunk by chunk).
    pub dwells: DwellDigest,
    /// Measurements.
    pub measurements: Vec<MeasurementRow>,
    /// Track rows.
    pub tracks: Vec<TrackRow>,
    /// The files read, for messages: truth, dwells, measurements, tracks.
    pub files: [PathBuf; 4],
}

/// The manifest's resolved scenario, validated.
fn scenario_of(run_dir: &Path, m: &Manifest) -> Result<Scenario, PlotError> {
    let file = RunDir::new(run_dir).manifest();
    let s: Scenario = serde_json::from_value(m.scenario.resolved.clone())
        .map_err(|e| PlotError::Scenario { file: file.clone(), why: e.to_string() })?;
    s.validate().map_err(|e| PlotError::Scenario { file, why: e.to_string() })?;
    Ok(s)
}

/// Follow `parent` links to the run that holds truth and dwells (checked, cycles refused:
/// `mimo_store::lineage`).
fn source_dir(run_dir: &Path, m: &Manifest) -> Result<PathBuf, PlotError> {
    Ok(mimo_store::lineage::source_dir(run_dir, m)?)
}

impl RunSource {
    /// Open a run directory: manifest, scenario, parent chain.
    pub fn open(run_dir: &Path) -> Result<RunSource, PlotError> {
        let manifest = Manifest::read(run_dir)?;
        let scenario = scenario_of(run_dir, &manifest)?;
        let source_dir = source_dir(run_dir, &manifest)?;
        Ok(RunSource { run_dir: run_dir.to_path_buf(), manifest, scenario, source_dir })
    }

    /// Check that run `run` exists.
    pub fn check_run(&self, run: u32) -> Result<(), PlotError> {
        if run >= self.manifest.runs {
            return Err(PlotError::NoSuchRun {
                dir: self.run_dir.clone(),
                run,
                last: self.manifest.runs.saturating_sub(1),
            });
        }
        Ok(())
    }

    /// The file of `table` for `run` in `dir`.
    pub fn file(dir: &Path, table: &str, run: u32) -> PathBuf {
        RunDir::new(dir).table_file(table, run)
    }

    /// Read the tables of run `run`. Measurements come from the run directory when it has them
    /// (a simulation, or a re-run from primitives), otherwise from the source run. A missing or
    /// empty tracks file is a run without tracks (`--tracker none`): its truth, measurements
    /// and beams are still worth a look.
    pub fn read(&self, run: u32) -> Result<RunTables, PlotError> {
        self.check_run(run)?;
        let truth_f = Self::file(&self.source_dir, "truth", run);
        let dwells_f = Self::file(&self.source_dir, "dwells", run);
        let own_meas = Self::file(&self.run_dir, "measurements", run);
        let meas_f = if own_meas.is_file() { own_meas } else { Self::file(&self.source_dir, "measurements", run) };
        let tracks_f = Self::file(&self.run_dir, "tracks", run);
        let tracks = match read_table::<TrackRow>(&tracks_f) {
            Ok(t) => t,
            Err(StoreError::Missing { .. }) => Vec::new(),
            Err(e) => return Err(e.into()),
        };
        Ok(RunTables {
            truth: TruthSamples::read(&truth_f)?,
            dwells: DwellDigest::read(&dwells_f)?,
            measurements: read_table(&meas_f)?,
            tracks,
            files: [truth_f, dwells_f, meas_f, tracks_f],
        })
    }
}
