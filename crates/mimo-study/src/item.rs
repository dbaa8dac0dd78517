//! One (cell, run) item from start to record: the closed-loop run ([`crate::execute`]), its
//! tables streamed into the cell's run directory as their rows come (the run sink of
//! `mimo simulate`: a run in flight holds a chunk of rows per table, not the run), the run scored
//! from those files on its own (completed runs only), its tables deleted once scored unless the
//! plan keeps them (`keep_runs`; a failed run's stay for a post-mortem), and the [`ItemRecord`]
//! written last.

use crate::execute::run_item;
use crate::grid::Cell;
use crate::plan::Plan;
use crate::record::{ItemCosts, ItemRecord, RecordError, record_path};
use crate::run_usage::RunUsage;
use mimo_metrics::{DwellRows, MetricsError, Purpose, Score, ScoreInput, ScoreOptions};
use mimo_sim::World;
use mimo_store::StoreError;
use mimo_store::layout::RunDir;
use mimo_store::manifest::TableFile;
use mimo_store::run_sink::{ParquetRunSink, ScratchRunDir};
use mimo_store::schema::STUDY_METRICS;
use std::collections::BTreeMap;
use std::path::Path;

/// A system fault while doing an item (the study stops: the disk, not the method, failed).
#[derive(Debug, thiserror::Error)]
pub enum ItemError {
    /// Writing a table failed.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// Writing the record failed.
    #[error(transparent)]
    Record(#[from] RecordError),
    /// Writing a run's rows as they came failed (the sink's message names the file).
    #[error("{0}")]
    Sink(String),
    /// Scoring a completed run failed (its own tables could not be read back).
    #[error("scoring {}: {source}", dir.display())]
    Score {
        /// The cell directory.
        dir: std::path::PathBuf,
        /// The cause.
        source: Box<MetricsError>,
    },
}

/// Delete a scored run's table files (a file already gone is no error: an item redone after an
/// interruption between the deletion and its record).
fn delete_tables(cell_dir: &Path, tables: &BTreeMap<String, TableFile>) -> Result<(), StoreError> {
    for tf in tables.values() {
        let path = RunDir::new(cell_dir).listed(&tf.file);
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(StoreError::Io { path, source: e }),
            _ => {}
        }
    }
    Ok(())
}

/// Remove the table directories of a cell that deleting its runs' tables left empty.
pub fn remove_empty_table_dirs(cell_dir: &Path) {
    for name in crate::plan::TABLES {
        // Only an empty directory is removed; one that holds kept or failed runs' files stays.
        let _ = std::fs::remove_dir(RunDir::new(cell_dir).table_dir(name));
    }
}

/// Score one run from its files, or from its dwells reduced as the run made them
/// (`dwell_rows`: its dwells file is then not read, and need not exist).
pub fn score_run(
    world: &World,
    cell_dir: &Path,
    run: u32,
    dwell_rows: Option<DwellRows>,
) -> Result<Score, MetricsError> {
    let file = |t: &str| vec![RunDir::new(cell_dir).table_file(t, run)];
    let ships = world.scenario.ships.clone();
    let input = ScoreInput {
        truth: file("truth"),
        dwells: if dwell_rows.is_some() { Vec::new() } else { file("dwells") },
        tracks: file("tracks"),
        scorable: Box::new(move |t, pos, alt| ships.iter().any(|s| s.sees(t, pos, alt))),
        beams: crate::beams::beam_geometry(&world.scenario),
    };
    let opts = ScoreOptions {
        scenario: world.scenario.name.clone(),
        radars: world.scenario.ships.iter().map(|s| s.id.to_string()).collect(),
        threads: 1,
        ..ScoreOptions::default()
    };
    match dwell_rows {
        Some(rows) => mimo_metrics::score_with_dwell_rows(&input, &opts, rows),
        None => mimo_metrics::score(&input, &opts),
    }
}

/// The study metrics of a one-run score and the run's usage, by name.
pub fn metrics_of(score: &Score, usage: &RunUsage) -> BTreeMap<String, Option<f64>> {
    let mut m: BTreeMap<String, Option<f64>> = STUDY_METRICS.iter().map(|(n, _, _)| (n.to_string(), None)).collect();
    let Some(r) = score.summary.per_run.first() else { return m };
    let n_scorable: Vec<u32> = score.track_metrics.iter().map(|t| t.n_scorable).collect();
    let per_object = |i: usize| usage.per_object(i, &n_scorable);
    let reg = score.summary.registration.as_ref();
    let values = [
        ("completeness", r.track.completeness),
        ("redundant_ratio", r.track.redundant_ratio),
        ("spurious_ratio", r.track.spurious_ratio),
        ("breaks", Some(f64::from(r.track.breaks))),
        ("switches", Some(f64::from(r.track.switches))),
        ("position_rmse_m", r.track.position_rmse_m),
        ("velocity_rmse_mps", r.track.velocity_rmse_mps),
        ("ospa_m", r.ospa_m),
        ("gospa_m", r.gospa_m),
        ("gospa_localisation_m", r.gospa_localisation_m),
        ("gospa_missed", r.gospa_missed),
        ("gospa_false", r.gospa_false),
        ("energy_j", Some(usage.totals[1])),
        ("dwell_time_s", Some(usage.totals[0])),
        ("ta_energy_j", Some(usage.totals[3])),
        ("ta_dwell_time_s", Some(usage.totals[2])),
        ("energy_per_object_j", per_object(1)),
        ("ta_energy_per_object_j", per_object(3)),
        ("ta_dwell_time_per_object_s", per_object(2)),
        ("dwell_time_per_object_s", per_object(0)),
        ("first_track_mean_s", r.first_track.mean_s),
        ("first_track_max_s", r.first_track.max_s),
        ("never_tracked", Some(f64::from(r.first_track.never_tracked))),
        ("registration_range_error_rms_m", reg.map(|g| g.range_error_rms_m)),
        ("registration_heading_error_rms_deg", reg.map(|g| g.heading_error_rms_deg)),
        ("registration_nees", reg.and_then(|g| g.nees_mean)),
    ];
    let purposes = Purpose::ALL.map(|p| (p.as_str(), r.usage.by_purpose.get(p)));
    for (name, pair) in purposes {
        m.insert(format!("energy_{name}_j"), Some(pair.energy_j));
        m.insert(format!("dwell_time_{name}_s"), Some(pair.dwell_time_s));
    }
    for (k, v) in values {
        m.insert(k.to_string(), v);
    }
    m
}

/// Do item `run` of `cell` (directory `cell_dir`) and write its record, with `kf_cycle_s` the
/// reference Kalman-filter cycle of this machine ([`crate::kfu`]). A failure of the method is
/// part of the record; an error here is a system fault.
pub fn do_item(
    plan: &Plan,
    cell: &Cell,
    world: &World,
    cell_dir: &Path,
    run: u32,
    kf_cycle_s: Option<f64>,
) -> Result<ItemRecord, ItemError> {
    let (c0, w0) = (crate::cpu::thread_cpu(), std::time::Instant::now());
    // A run the plan does not keep is scored from its dwells reduced as they come, with no
    // dwells file, and from scratch files of its other tables, deleted once it is scored
    // (docs/studies.md, "What a cell keeps").
    let reduce_dwells = !plan.keep_runs;
    let recorded = |t: &str| plan.tables.iter().any(|x| x == t) && !(reduce_dwells && t == "dwells");
    let mut sink = if plan.keep_runs {
        ParquetRunSink::with_tables(&RunDir::new(cell_dir), run, &recorded)?
    } else {
        ParquetRunSink::with_tables(&ScratchRunDir(RunDir::new(cell_dir)), run, &recorded)?
    };
    let mut r = run_item(plan, cell, world, run, &mut sink, ScoreOptions::default().interval_s, reduce_dwells);
    if let Some(fault) = r.fault {
        return Err(ItemError::Sink(fault));
    }
    let mut tables: BTreeMap<String, TableFile> =
        sink.finish()?.into_iter().map(|(name, file)| (name.to_string(), file)).collect();
    let usage = r.usage;
    let metrics = match &r.failure {
        Some(_) => STUDY_METRICS.iter().map(|(n, _, _)| (n.to_string(), None)).collect(),
        None => {
            let mut score = score_run(world, cell_dir, run, r.dwell_rows.take())
                .map_err(|e| ItemError::Score { dir: cell_dir.into(), source: Box::new(e) })?;
            mimo_metrics::attach_registration(&mut score, &r.biases, &r.registration);
            if !plan.keep_runs {
                // Scored: the merge and the charts need only the record (docs/studies.md).
                delete_tables(cell_dir, &tables)?;
                tables.clear();
            }
            metrics_of(&score, &usage)
        }
    };
    let cpu = crate::cpu::thread_cpu().saturating_sub(c0);
    let record = ItemRecord {
        run,
        seed: plan.seed,
        duration_s: world.scenario.duration_s,
        failure: r.failure,
        metrics,
        costs: ItemCosts {
            ta_cpu_s: r.ta_cpu.as_secs_f64(),
            sim_cpu_s: cpu.saturating_sub(r.ta_cpu).as_secs_f64(),
            wall_s: w0.elapsed().as_secs_f64(),
            kf_cycle_s,
        },
        ta: r.ta.map(|t| (t.name, t.config)),
        tables,
    };
    record.write(&record_path(cell_dir, run))?;
    Ok(record)
}
