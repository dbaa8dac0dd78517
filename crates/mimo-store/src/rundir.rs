//! Run directories: staged writing and atomic publication.
//!
//! [`RunDirWriter::create`] locks the output, refuses an existing one unless `force` is set and
//! it is a mimo run directory (or empty; [`crate::output`]), removes staging left by killed
//! writers, and writes into a hidden staging directory beside the target.
//! [`RunDirWriter::finish`] writes the manifest last and renames the staging directory into place
//! (removing the old one only then, with `force`). If the writer is dropped unfinished (an error
//! or a panic) or the process is interrupted, the staging directory is removed: a failed step
//! leaves nothing that looks like a run.

use crate::StoreError;
use crate::io_err;
use crate::layout::RunDir;
use crate::manifest::{Manifest, TableFile};
use crate::output::{self, OutputLock};
use crate::rows::TableRow;
use crate::table_writer::TableWriter;
use std::path::{Path, PathBuf};

/// A run directory being written.
#[derive(Debug)]
pub struct RunDirWriter {
    target: PathBuf,
    staging: PathBuf,
    force: bool,
    finished: bool,
    // Dropped after `Drop::drop` has removed an unfinished staging directory.
    _lock: OutputLock,
    // The score lock of the run being replaced (`RUN/.score.lock`): no scorer reads it while it
    // is replaced, and it is not replaced while a scorer reads it.
    _score_lock: Option<OutputLock>,
}

fn staging_for(target: &Path, what: &str) -> Result<PathBuf, StoreError> {
    output::sibling(target, &format!("{what}-{}", std::process::id()))
}

/// Swap `staging` into `target`, removing what `target` held.
fn publish(target: &Path, staging: &Path, replace: bool) -> Result<(), StoreError> {
    if replace {
        let old = staging_for(target, "old")?;
        output::register(&old);
        std::fs::rename(target, &old).map_err(io_err(target))?;
        std::fs::rename(staging, target).map_err(io_err(target))?;
        std::fs::remove_dir_all(&old).map_err(io_err(&old))?;
        output::unregister(&old);
    } else {
        if let Some(parent) = target.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent).map_err(io_err(parent))?;
        }
        std::fs::rename(staging, target).map_err(io_err(target))?;
    }
    output::unregister(staging);
    Ok(())
}

impl RunDirWriter {
    /// Start writing `target`: lock it (a second writer fails at once), refuse it if it exists
    /// and is not replaceable ([`output::check_replaceable`]), remove stale staging.
    pub fn create(target: &Path, force: bool) -> Result<RunDirWriter, StoreError> {
        let lock = OutputLock::acquire(target)?;
        let replacing = output::check_replaceable(target, force)?;
        // Only a run has a score to lock: the lock file of an empty directory's would make it
        // a directory that is neither empty nor a run when it is checked again at `finish`.
        let is_run = replacing && RunDir::new(target).manifest().is_file();
        let score_lock = if is_run { Some(OutputLock::acquire(RunDir::new(target).score().root())?) } else { None };
        output::remove_stale(target)?;
        let staging = staging_for(target, "partial")?;
        output::register(&staging);
        std::fs::create_dir_all(&staging).map_err(io_err(&staging))?;
        Ok(RunDirWriter {
            target: target.to_path_buf(),
            staging,
            force,
            finished: false,
            _lock: lock,
            _score_lock: score_lock,
        })
    }

    /// The final path.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The staging directory being written.
    pub fn staging(&self) -> &Path {
        &self.staging
    }

    /// The path of run `run`'s file of a table relative to the run directory, its table
    /// directory created in the staging directory.
    fn run_table_path(&self, table: &str, run: u32) -> Result<String, StoreError> {
        // Not `create_dir_all`: a staging directory removed on interrupt is not re-created.
        let dir = RunDir::new(&self.staging).table_dir(table);
        match std::fs::create_dir(&dir) {
            Err(e) if e.kind() != std::io::ErrorKind::AlreadyExists => return Err(io_err(&dir)(e)),
            _ => {}
        }
        Ok(RunDir::table_file_rel(table, run))
    }

    /// Start run `run`'s file of a table, to be written as its rows come
    /// ([`TableWriter::finish`], then [`TableFile`] with the path returned here).
    pub fn open_run_table<R: TableRow>(&self, table: &str, run: u32) -> Result<(String, TableWriter<R>), StoreError> {
        let rel = self.run_table_path(table, run)?;
        let w = TableWriter::create(&self.staging.join(&rel))?;
        Ok((rel, w))
    }

    /// Write run `run`'s file of a table; returns the manifest entry.
    pub fn write_run_table<R: TableRow>(&self, table: &str, run: u32, rows: &[R]) -> Result<TableFile, StoreError> {
        let rel = self.run_table_path(table, run)?;
        let batch = crate::rows::to_batch(rows)?;
        crate::write_batch_into(&self.staging.join(&rel), &batch)?;
        Ok(TableFile { file: rel, rows: rows.len() as u64 })
    }

    /// Write the manifest and publish the directory.
    pub fn finish(mut self, manifest: &Manifest) -> Result<PathBuf, StoreError> {
        let mpath = RunDir::new(&self.staging).manifest();
        let tmp = output::sibling(&mpath, "tmp")?;
        std::fs::write(&tmp, manifest.to_json()).map_err(io_err(&tmp))?;
        std::fs::rename(&tmp, &mpath).map_err(io_err(&mpath))?;
        // Checked again: something may have appeared at the target while the run was written.
        let replace = output::check_replaceable(&self.target, self.force)?;
        publish(&self.target, &self.staging, replace)?;
        self.finished = true;
        Ok(self.target.clone())
    }
}

impl Drop for RunDirWriter {
    fn drop(&mut self) {
        if !self.finished {
            let _ = std::fs::remove_dir_all(&self.staging);
            output::unregister(&self.staging);
        }
    }
}

/// Replace a derived directory (such as `RUN/score/`) atomically: `build` writes into a staging
/// directory, which then replaces `target`. The target is locked for the duration, and staging
/// left beside it by killed processes is removed first. Returns whether an old directory was
/// replaced.
pub fn replace_dir<E: From<StoreError>>(target: &Path, build: impl FnOnce(&Path) -> Result<(), E>) -> Result<bool, E> {
    let lock = OutputLock::acquire(target)?;
    replace_dir_locked(target, &lock, build)
}

/// [`replace_dir`] under a lock on `target` the caller took before its work began (so that a
/// second writer of the same directory fails at once, not after its work).
pub fn replace_dir_locked<E: From<StoreError>>(
    target: &Path,
    _lock: &OutputLock,
    build: impl FnOnce(&Path) -> Result<(), E>,
) -> Result<bool, E> {
    output::remove_stale(target)?;
    let staging = staging_for(target, "partial")?;
    output::register(&staging);
    std::fs::create_dir_all(&staging).map_err(io_err(&staging))?;
    if let Err(e) = build(&staging) {
        let _ = std::fs::remove_dir_all(&staging);
        output::unregister(&staging);
        return Err(e);
    }
    let replaced = target.exists();
    if let Err(e) = publish(target, &staging, replaced) {
        let _ = std::fs::remove_dir_all(&staging);
        output::unregister(&staging);
        return Err(e.into());
    }
    Ok(replaced)
}
