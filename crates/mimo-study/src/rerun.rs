//! Re-running one item of a study into a run directory of its own (docs/studies.md, "The
//! page"): the same plan, seed, cell and run index, through the same code as the study
//! ([`crate::item::do_item`]), with the tables kept, so that `mimo plot` opens the run and its
//! tables are byte for byte the ones the study wrote for that item (with `keep_runs = true`).
//!
//! A cell is named by its path under the study's `runs/` (`method=mimo@4/scenario=7`), as
//! `report.html` shows it. A method the plan lists is found by name; a point a refinement round
//! added (`mimo@1.625`, `mimo@held_share:0.05,power_budget_w:4`) is rebuilt from its family's
//! entry and the values its name carries, so no record of the study is needed.

use crate::grid::Cell;
use crate::item::{ItemError, do_item};
use crate::merge::{CellFiles, cell_manifest};
use crate::plan::{Ctx, Method, Plan, PlanError};
use crate::prepare::prepare;
use crate::record::record_path;
use crate::runner::StudyError;
use mimo_store::StoreError;
use mimo_store::rundir::RunDirWriter;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Why an item cannot be re-run.
#[derive(Debug, thiserror::Error)]
pub enum RerunError {
    /// The plan names no such cell.
    #[error("{plan}: the study has no cell '{cell}' (a cell is its path under the study's runs/, e.g. '{example}')")]
    NoCell {
        /// The plan file.
        plan: String,
        /// The cell asked for.
        cell: String,
        /// A cell the plan has.
        example: String,
    },
    /// The run index is outside the plan's runs.
    #[error("--run: {plan}: the plan has runs 0 to {last}, got {run}")]
    NoRun {
        /// The plan file.
        plan: String,
        /// The run asked for.
        run: u32,
        /// The plan's last run.
        last: u32,
    },
    /// The plan cannot be prepared, or the refined point does not fit its family.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// Running the item failed (a system fault).
    #[error(transparent)]
    Item(#[from] ItemError),
    /// Writing the run directory failed, or it may not be written.
    #[error(transparent)]
    Store(#[from] StoreError),
    /// Building the manifest failed.
    #[error(transparent)]
    Study(#[from] Box<StudyError>),
}

impl RerunError {
    /// Whether the user's input is at fault (exit 2) rather than the system (exit 1).
    pub fn is_input(&self) -> bool {
        match self {
            RerunError::NoCell { .. } | RerunError::NoRun { .. } | RerunError::Plan(_) => true,
            RerunError::Store(e) => e.is_input_error(),
            RerunError::Item(_) | RerunError::Study(_) => false,
        }
    }
}

/// A word for a POSIX shell: as it is when it holds only characters no shell interprets, else in
/// single quotes.
pub fn quote(s: &str) -> String {
    let plain = |c: char| c.is_ascii_alphanumeric() || "_./=@:,+-%".contains(c);
    if !s.is_empty() && s.chars().all(plain) { s.to_string() } else { format!("'{}'", s.replace('\'', "'\\''")) }
}

/// The path of a cell without its first (`method=…`) segment, as text with `/` separators.
fn place_of(rel: &Path) -> String {
    rel.iter().skip(1).map(|p| p.to_string_lossy()).collect::<Vec<_>>().join("/")
}

/// A refined point of a family: `family@value` (one key) or `family@short:value,…` (a grid).
fn refined_method(plan: &Plan, name: &str) -> Option<Result<Method, PlanError>> {
    let (family, spec) = name.split_once('@')?;
    let entry = plan.methods.iter().position(|m| m.family == family && !m.grid.is_empty())?;
    let base = &plan.methods[entry];
    let keys: Vec<String> = base.grid.iter().map(|(k, _)| k.clone()).collect();
    let values: Vec<f64> = if keys.len() == 1 {
        vec![spec.parse().ok()?]
    } else {
        let mut values = vec![f64::NAN; keys.len()];
        for part in spec.split(',') {
            let (short, v) = part.split_once(':')?;
            let k = keys.iter().position(|k| k == short || k.rsplit('.').next() == Some(short))?;
            values[k] = v.parse().ok()?;
        }
        if values.iter().any(|v| v.is_nan()) {
            return None;
        }
        values
    };
    let file = plan.file.display().to_string();
    let made = crate::method_sweep::method_at(&Ctx { file: &file }, &format!("methods[{entry}]"), base, &keys, &values);
    Some(made.map(|m| Method { refined: true, ..m }).and_then(|m| {
        if m.name == name { Ok(m) } else { Err(Ctx { file: &file }.err("methods", format!("a point named {name}"))) }
    }))
}

/// The plan (with the method appended when refinement made it) and the cell named `rel`.
pub fn find_cell(plan: &Plan, rel: &str) -> Result<(Plan, Cell, Cell), RerunError> {
    let stage0 = crate::grid::cells(plan);
    let example = stage0.first().map(|c| c.rel_dir(plan).display().to_string()).unwrap_or_default();
    let no_cell = || RerunError::NoCell { plan: plan.file.display().to_string(), cell: rel.to_string(), example };
    let rel_path = Path::new(rel.trim_end_matches('/'));
    let name =
        rel_path.iter().next().and_then(|s| s.to_str()).and_then(|s| s.strip_prefix("method=")).map(str::to_string);
    let Some(name) = name else { return Err(no_cell()) };
    let place = place_of(rel_path);
    let Some(at) = stage0.iter().find(|c| place_of(&c.rel_dir(plan)) == place).cloned() else {
        return Err(no_cell());
    };
    let mut plan = plan.clone();
    let method = match plan.methods.iter().position(|m| m.name == name) {
        Some(i) => i,
        None => match refined_method(&plan, &name) {
            Some(m) => {
                plan.methods.push(m?);
                plan.methods.len() - 1
            }
            None => return Err(no_cell()),
        },
    };
    let cell = Cell { method, ..at.clone() };
    Ok((plan, cell, at))
}

/// Re-run item `run` of the cell at `rel` into the run directory `out` (refused if it exists,
/// unless `force` and it is a run directory), its tables kept; returns `out`.
pub fn rerun(plan: &Plan, rel: &str, run: u32, out: &Path, force: bool) -> Result<PathBuf, RerunError> {
    if run >= plan.runs {
        return Err(RerunError::NoRun {
            plan: plan.file.display().to_string(),
            run,
            last: plan.runs.saturating_sub(1),
        });
    }
    let (mut plan, cell, at) = find_cell(plan, rel)?;
    plan.keep_runs = true;
    let prep = prepare(&plan)?;
    let c0 = prep.cells.iter().position(|c| *c == at).ok_or_else(|| RerunError::NoCell {
        plan: plan.file.display().to_string(),
        cell: rel.to_string(),
        example: String::new(),
    })?;
    let world = &prep.worlds[prep.world_of[c0]];
    let writer = RunDirWriter::create(out, force)?;
    let record = do_item(&plan, &cell, world, writer.staging(), run, None)?;
    // The item's record is the study's bookkeeping, not part of a run directory.
    let rec = record_path(writer.staging(), run);
    let _ = std::fs::remove_file(&rec);
    if let Some(dir) = rec.parent() {
        let _ = std::fs::remove_dir(dir);
    }
    let mut tables = BTreeMap::new();
    for (name, tf) in record.tables {
        tables.insert(name, vec![tf]);
    }
    let files = CellFiles { tables, ta: record.ta, wall_s: record.costs.wall_s };
    let manifest = cell_manifest(&plan, &cell, world, files).map_err(Box::new)?;
    Ok(writer.finish(&manifest)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped challenge plan: a point its refinement added (a midpoint of share) is rebuilt
    /// from its name, with the configuration the family's entry gives it.
    #[test]
    fn a_refined_grid_point_is_rebuilt_from_its_name() {
        let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../studies/challenge.toml");
        let plan = Plan::read(&file).expect("plan");
        let rel = "method=mimo@held_share:0,share:0.2/scenario=7";
        let (p, cell, _) = find_cell(&plan, rel).expect("refined cell");
        let m = &p.methods[cell.method];
        assert_eq!(m.name, "mimo@held_share:0,share:0.2");
        assert!(m.refined && cell.method == plan.methods.len());
        assert_eq!(cell.rel_dir(&p).display().to_string(), rel);
        let listed = find_cell(&plan, "method=conventional@held_share:0.1,share:0.3/scenario=7").expect("listed");
        assert!(!listed.0.methods[listed.1.method].refined);
        assert!(matches!(find_cell(&plan, "method=mimo@3/scenario=1"), Err(RerunError::NoCell { .. })));
        assert!(matches!(find_cell(&plan, "method=mimo/scenario=8"), Err(RerunError::NoCell { .. })));
    }

    #[test]
    fn words_are_quoted_only_when_a_shell_would_read_them_otherwise() {
        assert_eq!(
            quote("method=mimo@power_budget_w:1,held_share:0/scenario=1"),
            "method=mimo@power_budget_w:1,held_share:0/scenario=1"
        );
        assert_eq!(quote("my plan.toml"), "'my plan.toml'");
        assert_eq!(quote("it's"), "'it'\\''s'");
    }
}
