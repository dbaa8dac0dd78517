//! Run directories: staged writing and atomic publication.
//!
//! [`RunDirWriter::create`] refuses an existing output unless `force` is set, and writes into a
//! hidden staging directory beside the target. [`RunDirWriter::finish`] writes the manifest last
//! and renames the staging directory into place (removing the old one only then, with `force`).
//! If the writer is dropped unfinished (an error or a panic), the staging directory is removed:
//! a failed step leaves nothing that looks like a run.

use crate::manifest::{MANIFEST_FILE, Manifest, TableFile};
use crate::rows::TableRow;
use crate::{StoreError, io_err, run_file_name, write_table};
use std::path::{Path, PathBuf};

/// A run directory being written.
#[derive(Debug)]
pub struct RunDirWriter {
    target: PathBuf,
    staging: PathBuf,
    force: bool,
    finished: bool,
}

fn staging_for(target: &Path, what: &str) -> PathBuf {
    let name = target.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_else(|| "run".into());
    target.with_file_name(format!(".{name}.{what}-{}", std::process::id()))
}

impl RunDirWriter {
    /// Start writing `target`. Fails if it exists and `force` is false.
    pub fn create(target: &Path, force: bool) -> Result<RunDirWriter, StoreError> {
        if target.exists() && !force {
            return Err(StoreError::Exists { path: target.to_path_buf() });
        }
        let staging = staging_for(target, "partial");
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(io_err(&staging))?;
        }
        std::fs::create_dir_all(&staging).map_err(io_err(&staging))?;
        Ok(RunDirWriter { target: target.to_path_buf(), staging, force, finished: false })
    }

    /// The final path.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The staging directory being written.
    pub fn staging(&self) -> &Path {
        &self.staging
    }

    /// Write run `run`'s file of a table; returns the manifest entry.
    pub fn write_run_table<R: TableRow>(&self, table: &str, run: u32, rows: &[R]) -> Result<TableFile, StoreError> {
        let rel = format!("{table}/{}", run_file_name(run));
        let n = write_table(&self.staging.join(&rel), rows)?;
        Ok(TableFile { file: rel, rows: n })
    }

    /// Write the manifest and publish the directory.
    pub fn finish(mut self, manifest: &Manifest) -> Result<PathBuf, StoreError> {
        let mpath = self.staging.join(MANIFEST_FILE);
        let tmp = self.staging.join(".manifest.json.tmp");
        std::fs::write(&tmp, manifest.to_json()).map_err(io_err(&tmp))?;
        std::fs::rename(&tmp, &mpath).map_err(io_err(&mpath))?;
        if self.target.exists() {
            if !self.force {
                return Err(StoreError::Exists { path: self.target.clone() });
            }
            let old = staging_for(&self.target, "old");
            std::fs::rename(&self.target, &old).map_err(io_err(&self.target))?;
            std::fs::rename(&self.staging, &self.target).map_err(io_err(&self.target))?;
            std::fs::remove_dir_all(&old).map_err(io_err(&old))?;
        } else {
            if let Some(parent) = self.target.parent().filter(|p| !p.as_os_str().is_empty()) {
                std::fs::create_dir_all(parent).map_err(io_err(parent))?;
            }
            std::fs::rename(&self.staging, &self.target).map_err(io_err(&self.target))?;
        }
        self.finished = true;
        Ok(self.target.clone())
    }
}

impl Drop for RunDirWriter {
    fn drop(&mut self) {
        if !self.finished {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

/// Replace a derived directory (such as `RUN/score/`) atomically: `build` writes into a staging
/// directory, which then replaces `target`. Returns whether an old directory was replaced.
pub fn replace_dir<E: From<StoreError>>(target: &Path, build: impl FnOnce(&Path) -> Result<(), E>) -> Result<bool, E> {
    let staging = staging_for(target, "partial");
    if staging.exists() {
        std::fs::remove_dir_all(&staging).map_err(io_err(&staging))?;
    }
    std::fs::create_dir_all(&staging).map_err(io_err(&staging))?;
    if let Err(e) = build(&staging) {
        let _ = std::fs::remove_dir_all(&staging);
        return Err(e);
    }
    let replaced = target.exists();
    if replaced {
        let old = staging_for(target, "old");
        std::fs::rename(target, &old).map_err(io_err(target))?;
        std::fs::rename(&staging, target).map_err(io_err(target))?;
        std::fs::remove_dir_all(&old).map_err(io_err(&old))?;
    } else {
        std::fs::rename(&staging, target).map_err(io_err(target))?;
    }
    Ok(replaced)
}
