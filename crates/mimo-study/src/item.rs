//! One (cell, run) item from start to record: the closed-loop run ([`crate::execute`]), its
//! tables written into the cell's run directory, the run scored on its own (completed runs only),
//! its tables deleted once scored unless the plan keeps them (`keep_runs`; a failed run's stay
//! for a post-mortem), and the [`ItemRecord`] written last.

use crate::execute::run_item;
use crate::grid::Cell;
use crate::plan::Plan;
use crate::record::{ItemCosts, ItemRecord, RecordError, record_path};
use mimo_core::records::{DwellRow, Requester, Role, RunTables};
use mimo_metrics::{MetricsError, Purpose, Score, ScoreInput, ScoreOptions};
use mimo_sim::World;
use mimo_store::layout::RunDir;
use mimo_store::manifest::TableFile;
use mimo_store::schema::STUDY_METRICS;
use mimo_store::{StoreError, write_table};
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
    /// Scoring a completed run failed (its own tables could not be read back).
    #[error("scoring {}: {source}", dir.display())]
    Score {
        /// The cell directory.
        dir: std::path::PathBuf,
        /// The cause.
        source: Box<MetricsError>,
    },
}

fn write_tables(
    plan: &Plan,
    cell_dir: &Path,
    run: u32,
    t: &RunTables,
) -> Result<BTreeMap<String, TableFile>, StoreError> {
    let mut out = BTreeMap::new();
    for name in &plan.tables {
        let rel = RunDir::table_file_rel(name, run);
        let path = RunDir::new(cell_dir).table_file(name, run);
        let rows = match name.as_str() {
            "truth" => write_table(&path, &t.truth)?,
            "dwells" => write_table(&path, &t.dwells)?,
            "primitives" => write_table(&path, &t.primitives)?,
            "measurements" => write_table(&path, &t.measurements)?,
            "tracks" => write_table(&path, &t.tracks)?,
            "voltages" => write_table(&path, &t.voltages)?,
            _ => continue,
        };
        out.insert(name.clone(), TableFile { file: rel, rows });
    }
    Ok(out)
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

/// Score one run from its files.
pub fn score_run(world: &World, cell_dir: &Path, run: u32) -> Result<Score, MetricsError> {
    let file = |t: &str| vec![RunDir::new(cell_dir).table_file(t, run)];
    let ships = world.scenario.ships.clone();
    let input = ScoreInput {
        truth: file("truth"),
        dwells: file("dwells"),
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
    mimo_metrics::score(&input, &opts)
}

/// A run's transmit usage, summed in dwell order (so the sums never depend on how a dataframe
/// engine splits its work): totals and, per scoring interval, the sums the per-object figures
/// divide (docs/design.md §6: only transmitting participations cost; interval
/// `j = floor(t_s / interval_s) + 1`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunUsage {
    /// Dwell time, energy, TA dwell time, TA energy over the run.
    pub totals: [f64; 4],
    /// The same per interval.
    pub per_interval: BTreeMap<u32, [f64; 4]>,
}

impl RunUsage {
    /// Sum a run's dwell rows.
    pub fn of(dwells: &[DwellRow], interval_s: f64) -> RunUsage {
        let mut u = RunUsage::default();
        for d in dwells.iter().filter(|d| d.role != Role::Rx) {
            let ta = d.requested_by == Requester::Ta;
            let add =
                [d.duration_s, d.energy_j, if ta { d.duration_s } else { 0.0 }, if ta { d.energy_j } else { 0.0 }];
            let j = (d.t_s / interval_s).floor() as u32 + 1;
            let slot = u.per_interval.entry(j).or_default();
            for i in 0..4 {
                u.totals[i] += add[i];
                slot[i] += add[i];
            }
        }
        u
    }

    /// Σ over intervals `j` with `N[j] > 0` of `sum[j][i] / N[j]`, `N[j]` the objects scorable
    /// at the end of interval `j` (`n_scorable[j − 1]`); `None` if no interval has one.
    pub fn per_object(&self, i: usize, n_scorable: &[u32]) -> Option<f64> {
        let mut total = None;
        for (j, n) in n_scorable.iter().enumerate() {
            if *n > 0 {
                let s = self.per_interval.get(&(j as u32 + 1)).map_or(0.0, |v| v[i]);
                *total.get_or_insert(0.0) += s / f64::from(*n);
            }
        }
        total
    }
}

/// The study metrics of a one-run score and the run's usage, by name.
pub fn metrics_of(score: &Score, usage: &RunUsage) -> BTreeMap<String, Option<f64>> {
    let mut m: BTreeMap<String, Option<f64>> = STUDY_METRICS.iter().map(|(n, _, _)| (n.to_string(), None)).collect();
    let Some(r) = score.summary.per_run.first() else { return m };
    let n_scorable: Vec<u32> = score.track_metrics.iter().map(|t| t.n_scorable).collect();
    let per_object = |i: usize| usage.per_object(i, &n_scorable);
    let values = [
        ("completeness", r.completeness),
        ("redundant_ratio", r.redundant_ratio),
        ("spurious_ratio", r.spurious_ratio),
        ("breaks", Some(f64::from(r.breaks))),
        ("switches", Some(f64::from(r.switches))),
        ("position_rmse_m", r.position_rmse_m),
        ("velocity_rmse_mps", r.velocity_rmse_mps),
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
    ];
    let purposes = Purpose::ALL.map(|p| (p.as_str(), r.by_purpose.get(p)));
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
    let r = run_item(plan, cell, world, run);
    let mut tables = write_tables(plan, cell_dir, run, &r.tables)?;
    let usage = RunUsage::of(&r.tables.dwells, ScoreOptions::default().interval_s);
    drop(r.tables);
    let metrics = match &r.failure {
        Some(_) => STUDY_METRICS.iter().map(|(n, _, _)| (n.to_string(), None)).collect(),
        None => {
            let score = score_run(world, cell_dir, run)
                .map_err(|e| ItemError::Score { dir: cell_dir.into(), source: Box::new(e) })?;
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

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::ids::RadarId;

    fn dwell(t_s: f64, role: Role, by: Requester, duration_s: f64, energy_j: f64) -> DwellRow {
        DwellRow {
            run: 0,
            dwell_id: 0,
            group_id: 0,
            radar: RadarId(1),
            role,
            kind: mimo_core::records::DwellKind::Track,
            requested_by: by,
            t_s,
            duration_s,
            pulse_width_s: 1e-6,
            n_pulses: 1,
            peak_power_w: 1.0,
            energy_j,
            waveform: 0,
            face: 0,
            beam_u: 0.0,
            beam_v: 0.0,
            aim_x_m: 0.0,
            aim_y_m: 0.0,
            aim_z_m: 0.0,
        }
    }

    #[test]
    fn usage_counts_transmitters_per_interval() {
        let d = [
            dwell(0.2, Role::Txrx, Requester::Radar, 0.01, 100.0),
            dwell(0.7, Role::Tx, Requester::Ta, 0.02, 300.0),
            dwell(0.7, Role::Rx, Requester::Ta, 0.02, 999.0), // receiving costs nothing
            dwell(1.5, Role::Txrx, Requester::Ta, 0.04, 500.0),
            dwell(2.5, Role::Txrx, Requester::Ta, 0.04, 700.0),
        ];
        let u = RunUsage::of(&d, 1.0);
        let want = [0.11, 1600.0, 0.1, 1500.0];
        assert!(u.totals.iter().zip(want).all(|(a, b)| (a - b).abs() < 1e-12), "{:?}", u.totals);
        // Two objects scorable at 1 s, none at 2 s, four at 3 s.
        let per = u.per_object(1, &[2, 0, 4]).expect("defined");
        assert!((per - (400.0 / 2.0 + 700.0 / 4.0)).abs() < 1e-12, "{per}");
        assert_eq!(u.per_object(1, &[0, 0]), None);
    }
}
