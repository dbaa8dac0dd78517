//! Who may write an output path (docs/design.md §7,
//! docs/decisions/0034-force-locks-and-interrupts.md): the one owner of these rules for run
//! directories and for the plain files the commands write (maps, HTML pages).
//!
//! * **`--force` replaces only what mimo made**: a directory holding `manifest.json`, or an empty
//!   directory. Anything else — a user's folder, a plain file — is refused, even with `--force`.
//! * **A lock per output**: `.NAME.lock` beside `NAME`, taken with an exclusive, non-blocking
//!   file lock (`flock` on Unix) before any work, so a second writer of the same output fails at
//!   once. The kernel drops the lock when the process ends, however it ends.
//! * **Stale staging**: with the lock held no other writer of `NAME` is alive, so every
//!   `.NAME.partial-*` and `.NAME.old-*` beside it is left over from a killed process and is
//!   removed.
//! * **Interrupts**: the staging directories and lock files of this process are registered;
//!   [`remove_pending`] (called by the command's SIGINT/SIGTERM handler) removes them.

use crate::StoreError;
use crate::manifest::MANIFEST_FILE;
use std::fs::{File, OpenOptions, TryLockError};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// Paths this process is writing and would leave half-done if interrupted.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Note a staging directory or lock file to remove on interrupt.
pub fn register(path: &Path) {
    if let Ok(mut p) = PENDING.lock() {
        p.push(path.to_path_buf());
    }
}

/// Forget a path (published or removed).
pub fn unregister(path: &Path) {
    if let Ok(mut p) = PENDING.lock() {
        p.retain(|x| x != path);
    }
}

/// Remove everything registered (the interrupt handler's job). Best effort: it runs while the
/// process is being stopped.
pub fn remove_pending() {
    let paths = match PENDING.lock() {
        Ok(mut p) => std::mem::take(&mut *p),
        Err(_) => return,
    };
    for p in paths {
        if p.is_dir() {
            // Renamed first, atomically: the run workers may still be writing, and while
            // `remove_dir_all` walked the tree one of them could create its table directory and
            // file again under the staging path, which was then left behind. After the rename
            // nothing can be created under that path; the renamed tree (`.NAME.partial-*`, so
            // the next writer removes it if this process is killed first) is removed.
            let removing = p.with_file_name(format!(
                "{}.removing",
                p.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default()
            ));
            let doomed = if std::fs::rename(&p, &removing).is_ok() { removing } else { p };
            let _ = std::fs::remove_dir_all(&doomed);
        } else {
            let _ = std::fs::remove_file(&p);
        }
    }
}

/// The name of an output path, for its hidden siblings.
fn name_of(target: &Path) -> Result<String, StoreError> {
    target.file_name().map(|n| n.to_string_lossy().to_string()).ok_or_else(|| StoreError::Refused {
        path: target.to_path_buf(),
        why: "not a usable output path (it names no file or directory)".into(),
    })
}

/// A hidden sibling of `target`: `.NAME.what`.
pub fn sibling(target: &Path, what: &str) -> Result<PathBuf, StoreError> {
    Ok(target.with_file_name(format!(".{}.{what}", name_of(target)?)))
}

/// The exclusive lock on an output path, held until dropped.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
    _file: File,
}

impl OutputLock {
    /// Lock `target` (creating its parent directory if needed), or fail at once if another
    /// process holds it.
    pub fn acquire(target: &Path) -> Result<OutputLock, StoreError> {
        let path = sibling(target, "lock")?;
        if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(crate::io_err(dir))?;
        }
        // A lock file removed and recreated by a finishing writer between our open and our lock
        // would give us a lock on a file nobody else sees: check it is still the file at `path`.
        for _ in 0..8 {
            let file = OpenOptions::new()
                .create(true)
                .truncate(false)
                .write(true)
                .open(&path)
                .map_err(crate::io_err(&path))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    return Err(StoreError::Busy {
                        path: target.to_path_buf(),
                        why: format!(
                            "another mimo process is writing this output (it holds {}); wait for it or choose another output",
                            path.display()
                        ),
                    });
                }
                Err(TryLockError::Error(e)) => return Err(StoreError::Io { path: path.clone(), source: e }),
            }
            if same_file(&file, &path) {
                register(&path);
                return Ok(OutputLock { path, _file: file });
            }
        }
        Err(StoreError::Busy { path: target.to_path_buf(), why: "its lock file keeps changing".into() })
    }
}

#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.ino() == b.ino() && a.dev() == b.dev(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still locked; the lock itself goes with the file handle.
        let _ = std::fs::remove_file(&self.path);
        unregister(&self.path);
    }
}

/// Whether `target` may be written as a run directory: it does not exist, is an empty directory,
/// or (with `force`) holds a mimo manifest. Returns whether something is there to replace.
pub fn check_replaceable(target: &Path, force: bool) -> Result<bool, StoreError> {
    let meta = match std::fs::symlink_metadata(target) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(false),
        Err(e) => return Err(StoreError::Io { path: target.to_path_buf(), source: e }),
    };
    if !meta.is_dir() {
        return Err(StoreError::Refused {
            path: target.to_path_buf(),
            why: "exists and is not a directory; --force replaces only a mimo run directory".into(),
        });
    }
    let empty = std::fs::read_dir(target).map_err(crate::io_err(target))?.next().is_none();
    if empty {
        return Ok(true);
    }
    if !target.join(MANIFEST_FILE).is_file() {
        return Err(StoreError::Refused {
            path: target.to_path_buf(),
            why: format!(
                "exists and is not a mimo run directory (no {MANIFEST_FILE}); refusing to replace it, even with --force"
            ),
        });
    }
    if !force {
        return Err(StoreError::Exists { path: target.to_path_buf() });
    }
    Ok(true)
}

/// Whether `path` may be written as a plain output file (a map, an HTML page): it does not
/// exist, or it is a file and `force` is set. A directory is never replaced.
pub fn check_file_output(path: &Path, force: bool) -> Result<(), StoreError> {
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(StoreError::Io { path: path.to_path_buf(), source: e }),
        Ok(m) if m.is_dir() => Err(StoreError::Refused {
            path: path.to_path_buf(),
            why: "is a directory; expected a file to write".into(),
        }),
        Ok(_) if !force => Err(StoreError::Exists { path: path.to_path_buf() }),
        Ok(_) => Ok(()),
    }
}

/// Remove the staging left beside `target` by writers that are gone: `.NAME.partial-*` and
/// `.NAME.old-*`. Call it with the lock on `target` held (then no other writer is alive).
pub fn remove_stale(target: &Path) -> Result<(), StoreError> {
    let name = name_of(target)?;
    let dir = match target.parent().filter(|p| !p.as_os_str().is_empty()) {
        Some(d) => d.to_path_buf(),
        None => PathBuf::from("."),
    };
    let Ok(entries) = std::fs::read_dir(&dir) else { return Ok(()) };
    let prefixes = [format!(".{name}.partial-"), format!(".{name}.old-")];
    for e in entries.flatten() {
        let n = e.file_name().to_string_lossy().to_string();
        let is_pid =
            |p: &String| n.strip_prefix(p.as_str()).is_some_and(|rest| rest.bytes().all(|b| b.is_ascii_digit()));
        if prefixes.iter().any(is_pid) {
            let p = e.path();
            std::fs::remove_dir_all(&p).map_err(crate::io_err(&p))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn force_replaces_only_mimo_runs_and_empty_dirs() {
        let tmp = tempfile::tempdir().expect("tmp");
        let new = tmp.path().join("new");
        assert!(!check_replaceable(&new, false).expect("new"));
        std::fs::create_dir(&new).expect("mkdir");
        assert!(check_replaceable(&new, false).expect("empty"));
        std::fs::write(new.join("thesis.tex"), "x").expect("write");
        let e = check_replaceable(&new, true).expect_err("user folder");
        assert!(e.to_string().contains("not a mimo run directory"), "{e}");
        std::fs::write(new.join(MANIFEST_FILE), "{}").expect("write");
        assert!(matches!(check_replaceable(&new, false), Err(StoreError::Exists { .. })));
        assert!(check_replaceable(&new, true).expect("run"));
        let file = tmp.path().join("file");
        std::fs::write(&file, "x").expect("write");
        assert!(matches!(check_replaceable(&file, true), Err(StoreError::Refused { .. })));
        assert!(matches!(check_file_output(&file, false), Err(StoreError::Exists { .. })));
        assert!(check_file_output(&file, true).is_ok());
        assert!(matches!(check_file_output(tmp.path(), true), Err(StoreError::Refused { .. })));
    }

    #[test]
    fn one_writer_per_output_and_stale_staging_goes() {
        let tmp = tempfile::tempdir().expect("tmp");
        let target = tmp.path().join("run");
        let stale = tmp.path().join(".run.partial-999999");
        std::fs::create_dir_all(stale.join("truth")).expect("mkdir");
        let other = tmp.path().join(".runner.partial-1");
        std::fs::create_dir_all(&other).expect("mkdir");
        let lock = OutputLock::acquire(&target).expect("first");
        let e = OutputLock::acquire(&target).expect_err("second");
        assert!(matches!(e, StoreError::Busy { .. }), "{e}");
        remove_stale(&target).expect("clean");
        assert!(!stale.exists() && other.exists());
        drop(lock);
        assert!(!tmp.path().join(".run.lock").exists());
        drop(OutputLock::acquire(&target).expect("free again"));
    }
}
