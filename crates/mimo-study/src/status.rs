//! `mimo study PLAN --out DIR --status`: how far a study is — items done in all and per shard
//! (the shard count is the one its shards recorded, `crate::shard_log`), what each shard was last
//! seen doing, which items' methods failed, and whether it has been merged. It reads the item
//! records and the shard files and writes nothing.

use crate::grid::{self, Shard};
use crate::plan::Plan;
use crate::record::{ItemRecord, record_path};
use crate::runner::{StudyError, cell_dirs};
use crate::shard_log::{ShardState, latest_n, read_all};
use crate::study_dir::{DirError, read_mark};
use mimo_store::layout::StudyDir;
use std::fmt::Write;
use std::path::Path;

/// One shard's progress.
#[derive(Debug, Clone, PartialEq)]
pub struct ShardProgress {
    /// The shard.
    pub shard: Shard,
    /// Its items.
    pub items: usize,
    /// Of those, items with a record.
    pub done: usize,
    /// What it last wrote about itself (`None`: it never started).
    pub state: Option<ShardState>,
}

/// An item whose method failed.
#[derive(Debug, Clone, PartialEq)]
pub struct MethodFailure {
    /// The cell's directory under `runs/`.
    pub cell: String,
    /// The run.
    pub run: u32,
    /// Why.
    pub why: String,
}

/// A study's state.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyStatus {
    /// Cells.
    pub cells: usize,
    /// Items.
    pub items: usize,
    /// Items with a record.
    pub done: usize,
    /// Per shard of the latest split (empty when no shard ever ran).
    pub shards: Vec<ShardProgress>,
    /// Finished items whose method failed.
    pub failures: Vec<MethodFailure>,
    /// Whether the study tables exist.
    pub merged: bool,
}

/// "shard 2/3: 4, shard 0/3: 1" for the missing items (indices into the item list), by the
/// shard count the study's shards recorded; empty when none did.
pub fn missing_by_shard(out: &Path, missing: &[usize]) -> String {
    let Some(n) = latest_n(&read_all(out)) else { return String::new() };
    let mut per = vec![0usize; n];
    for i in missing {
        per[i % n] += 1;
    }
    let parts: Vec<String> =
        per.iter().enumerate().filter(|(_, m)| **m > 0).map(|(k, m)| format!("shard {k}/{n}: {m}")).collect();
    format!("; missing by shard: {}", parts.join(", "))
}

/// The state of the study of `plan` in `out`.
pub fn study_status(plan: &Plan, plan_text: &str, out: &Path) -> Result<StudyStatus, StudyError> {
    let refused = |why: &str| StudyError::Dir(DirError::Refused { path: out.to_path_buf(), why: why.into() });
    match read_mark(out)? {
        None => return Err(refused("not a mimo study (no study.json): nothing to report")),
        Some(m) if m.plan != plan_text => {
            return Err(refused("holds a study of another plan (its plan.toml differs from the one given)"));
        }
        Some(_) => {}
    }
    let cells = grid::cells(plan);
    let dirs = cell_dirs(plan, &cells, out);
    let runs = plan.runs as usize;
    let items = cells.len() * runs;
    let mut done_at = vec![false; items];
    let mut failures = Vec::new();
    for (i, done) in done_at.iter_mut().enumerate() {
        let (dir, run) = (&dirs[i / runs], (i % runs) as u32);
        if let Some(r) = ItemRecord::read(&record_path(dir, run))? {
            *done = true;
            if let Some(why) = r.failure {
                let cell = dir.strip_prefix(StudyDir::new(out).runs()).unwrap_or(dir).display().to_string();
                failures.push(MethodFailure { cell, run, why });
            }
        }
    }
    let states = read_all(out);
    let shards = match latest_n(&states) {
        None => Vec::new(),
        Some(n) => (0..n)
            .map(|k| ShardProgress {
                shard: Shard { k, n },
                items: (k..items).step_by(n).count(),
                done: (k..items).step_by(n).filter(|&i| done_at[i]).count(),
                state: states.iter().find(|s| s.n == n && s.k == k).cloned(),
            })
            .collect(),
    };
    Ok(StudyStatus {
        cells: cells.len(),
        items,
        done: done_at.iter().filter(|d| **d).count(),
        shards,
        failures,
        merged: StudyDir::new(out).table(&mimo_store::schema::STUDY_RESULTS).is_file(),
    })
}

fn shard_line(p: &ShardProgress) -> String {
    let Shard { k, n } = p.shard;
    let head = format!("shard {k}/{n}: {} of {} items done", p.done, p.items);
    let Some(s) = &p.state else { return format!("{head}; never started") };
    match (&s.error, s.stopped_unix_s) {
        (Some(e), _) => format!("{head}; stopped on an error on {} (pid {}): {e}", s.host, s.pid),
        (None, Some(_)) if p.done == p.items => format!("{head}; finished on {}", s.host),
        (None, Some(_)) => format!("{head}; stopped on {} before its items were done", s.host),
        (None, None) => format!(
            "{head}; started on {} (pid {}) {} s ago and not stopped: running, or killed (see its log)",
            s.host,
            s.pid,
            crate::shard_log::now_unix_s().saturating_sub(s.started_unix_s)
        ),
    }
}

impl StudyStatus {
    /// The report a person reads.
    pub fn text(&self, out: &Path) -> String {
        let mut o = String::new();
        let _ = writeln!(o, "{}: {} of {} items done ({} cells)", out.display(), self.done, self.items, self.cells);
        for p in &self.shards {
            let _ = writeln!(o, "{}", shard_line(p));
        }
        let _ = writeln!(o, "{} finished items failed (the method, not the machine)", self.failures.len());
        for f in self.failures.iter().take(20) {
            let _ = writeln!(o, "  {} run {}: {}", f.cell, f.run, f.why);
        }
        if self.failures.len() > 20 {
            let _ =
                writeln!(o, "  … and {} more (results.parquet `failure` after the merge)", self.failures.len() - 20);
        }
        let merged = match (self.merged, self.done == self.items) {
            (true, true) => "merged (results.parquet, summary.parquet, report.md)",
            (true, false) => "an earlier merge is there, but items are missing now: run them, then --merge again",
            (false, true) => "every item is done: not merged yet (--merge)",
            (false, false) => "not merged: run the unfinished shards (or --resume), then --merge",
        };
        let _ = writeln!(o, "{merged}");
        o
    }
}
