//! Merging a study: check every item has its record, then read the records one at a time into
//! each cell's manifest and the compact rows of the study tables ([`ResultRow`]), and write the
//! manifests, the tables, the charts and `report.md`. Nothing is written until every record has
//! been read, and the memory held is about 1.5 kB per item (the rows and each cell's list
//! of table files), not the records themselves.

use crate::challenge_table::{family_rows, ratio_rows, write_challenge};
use crate::grid::Cell;
use crate::plan::{MethodTa, Plan};
use crate::prepare::{Prepared, search_of};
use crate::record::{ItemRecord, record_path};
use crate::runner::StudyError;
use crate::status::missing_by_shard;
use crate::tables::{ResultRow, summarize, write_results, write_summary};
use mimo_sim::World;
use mimo_store::StoreError;
use mimo_store::layout::{RunDir, StudyDir};
use mimo_store::manifest::{Manifest, ScenarioInfo, TableFile, TrackerInfo};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// What a merge found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Merged {
    /// Items merged.
    pub items: usize,
    /// Of those, items whose method failed.
    pub failed: usize,
}

/// Every item without a record, as indices into the item list; an error names how many, the
/// first, and which shards they belong to.
fn check_complete(plan: &Plan, dirs: &[PathBuf], out: &Path) -> Result<(), StudyError> {
    let runs = plan.runs as usize;
    let missing: Vec<usize> =
        (0..dirs.len() * runs).filter(|i| !record_path(&dirs[i / runs], (i % runs) as u32).is_file()).collect();
    let Some(&i) = missing.first() else { return Ok(()) };
    let dir = &dirs[i / runs];
    Err(StudyError::Incomplete {
        dir: out.to_path_buf(),
        missing: missing.len(),
        total: dirs.len() * runs,
        first: format!("{} run {}", dir.strip_prefix(out).unwrap_or(dir).display(), i % runs),
        shards: missing_by_shard(out, &missing),
    })
}

/// What the cell manifest needs of its records, gathered while they are read one at a time.
pub(crate) struct CellFiles {
    pub(crate) tables: BTreeMap<String, Vec<TableFile>>,
    pub(crate) ta: Option<(String, serde_json::Value)>,
    pub(crate) wall_s: f64,
}

fn read_cell(plan: &Plan, dir: &Path) -> Result<(Vec<ResultRow>, CellFiles), StudyError> {
    let mut rows = Vec::with_capacity(plan.runs as usize);
    let mut files = CellFiles { tables: BTreeMap::new(), ta: None, wall_s: 0.0 };
    for run in 0..plan.runs {
        let path = record_path(dir, run);
        // Checked just before; a record removed since is a fault of the file system or a user.
        let r: ItemRecord = ItemRecord::read(&path)?.ok_or_else(|| {
            StudyError::Store(StoreError::Io { path: path.clone(), source: std::io::ErrorKind::NotFound.into() })
        })?;
        rows.push(ResultRow::of(&r));
        files.wall_s += r.costs.wall_s;
        if files.ta.is_none() {
            files.ta = r.ta;
        }
        for (name, tf) in r.tables {
            files.tables.entry(name).or_default().push(tf);
        }
    }
    Ok((rows, files))
}

/// The result rows of every cell (each with all its records), in cell order.
pub(crate) fn read_rows(plan: &Plan, dirs: &[PathBuf]) -> Result<Vec<Vec<ResultRow>>, StudyError> {
    dirs.iter().map(|d| read_cell(plan, d).map(|(rows, _)| rows)).collect()
}

/// Whether every item of the cells in `dirs` has its record.
pub(crate) fn all_done(plan: &Plan, dirs: &[PathBuf]) -> bool {
    dirs.iter().all(|d| (0..plan.runs).all(|run| record_path(d, run).is_file()))
}

/// A cell's manifest.
pub(crate) fn cell_manifest(plan: &Plan, cell: &Cell, world: &World, files: CellFiles) -> Result<Manifest, StudyError> {
    let json = |v: serde_json::Result<serde_json::Value>| v.map_err(|e| StudyError::Report(e.to_string()));
    let mut fidelity = json(serde_json::to_value(&world.scenario.fidelity))?;
    let stress: serde_json::Map<String, serde_json::Value> =
        cell.point.iter().map(|(a, v)| (a.name().to_string(), serde_json::json!(v))).collect();
    if let Some(obj) = fidelity.as_object_mut() {
        obj.insert("search".into(), json(serde_json::to_value(search_of(cell)))?);
        obj.insert("stress".into(), serde_json::Value::Object(stress));
        if let Some(a) = cell.swept {
            obj.insert("swept".into(), serde_json::json!(a.name()));
        }
    }
    let method = &plan.methods[cell.method];
    let schedule = match &method.ta {
        MethodTa::Builtin { ta, .. } => mimo_ta::registry::schedule_description(ta),
        MethodTa::Process { cmd, .. } => {
            format!("closed loop: background search plus dwells requested by the test article '{cmd}'")
        }
    };
    let mut timing_s = BTreeMap::new();
    timing_s.insert("runs_wall_sum".to_string(), files.wall_s);
    Ok(Manifest {
        mimo_version: env!("CARGO_PKG_VERSION").to_string(),
        schema_version: mimo_store::schema::SCHEMA_VERSION,
        scenario: ScenarioInfo {
            name: world.scenario.name.clone(),
            resolved: json(serde_json::to_value(&world.scenario))?,
        },
        seed: plan.seed,
        runs: plan.runs,
        duration_s: world.scenario.duration_s,
        fidelity,
        tracker: files.ta.map(|(name, config)| TrackerInfo { name, config }),
        schedule,
        parent: None,
        parent_check: None,
        tables: files.tables,
        timing_s,
    })
}

/// Write `text` to `path` atomically (temporary file, then rename).
pub fn write_atomic(path: &Path, text: &str) -> Result<(), StudyError> {
    let io = |e: std::io::Error| StudyError::Store(StoreError::Io { path: path.to_path_buf(), source: e });
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
    std::fs::write(&tmp, text).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}

/// Merge: every cell's manifest, the study tables, the charts, the report and its page.
pub fn merge(plan: &Plan, prep: &Prepared, dirs: &[PathBuf], out: &Path) -> Result<Merged, StudyError> {
    check_complete(plan, dirs, out)?;
    let mut rows = Vec::with_capacity(dirs.len());
    let mut manifests = Vec::with_capacity(dirs.len());
    for (c, dir) in dirs.iter().enumerate() {
        let (r, files) = read_cell(plan, dir)?;
        rows.push(r);
        manifests.push(cell_manifest(plan, &prep.cells[c], &prep.worlds[prep.world_of[c]], files)?.to_json());
    }
    for (dir, m) in dirs.iter().zip(manifests) {
        write_atomic(&RunDir::new(dir).manifest(), &m)?;
        crate::item::remove_empty_table_dirs(dir);
    }
    write_results(plan, &prep.cells, &rows, out)?;
    let summaries = summarize(&rows);
    write_summary(plan, &prep.cells, &summaries, out)?;
    let families = family_rows(plan, &prep.cells, &rows);
    let ratios = ratio_rows(plan, &prep.cells, &families);
    write_challenge(plan, &prep.cells, &families, &ratios, out)?;
    let failures = crate::failure_table::failure_rows(plan, &prep.cells, &rows);
    crate::failure_table::write_failure_points(plan, &failures, out)?;
    let charts = crate::charts::study_charts(plan, &prep.cells, &summaries, &families, &failures);
    mimo_store::rundir::replace_dir(&StudyDir::new(out).charts(), |d: &Path| -> Result<(), StudyError> {
        mimo_report::study::render_study(&charts, d).map_err(|e| StudyError::Report(e.to_string()))?;
        Ok(())
    })?;
    let study = crate::report::StudyFigures {
        plan,
        cells: &prep.cells,
        summaries: &summaries,
        records: &rows,
        challenge: crate::challenge_report::Challenge { families: &families, ratios: &ratios },
        failures: &failures,
    };
    let report = crate::report::report_md(&study, &charts);
    write_atomic(&StudyDir::new(out).report(), &report)?;
    crate::report_page::write_page(plan, &plan.file.display().to_string(), out)?;
    let failed = summaries.iter().map(|s| s.failed as usize).sum();
    Ok(Merged { items: rows.iter().map(Vec::len).sum(), failed })
}
