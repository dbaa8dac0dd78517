//! Who may write an output path (docs/design.md §7,
//! docs/decisions/0034-force-locks-and-interrupts.md): the one owner of these rules for run
//! directories and for the plain files the commands write (maps, HTML pages).
//!
//! * **`--force` replaces only what mimo made**, recognised by content ([`crate::recognise`]): a
//!   run directory whose manifest mimo can read and which holds nothing mimo did not write, an
//!   empty directory, a page `mimo plot` wrote, a map `scenarios --map` drew. Anything else — a
//!   user's folder, a web project with its own `manifest.json`, a `notes.txt` inside a run, a
//!   plain file — is refused and named, and left alone, even with `--force`.
//! * **A lock per output**: `.NAME.lock` beside `NAME`, taken with an exclusive, non-blocking
//!   file lock (`flock` on Unix) before any work, so a second writer of the same output fails at
//!   once. The kernel drops the lock when the process ends, however it ends; the lock file names
//!   its holder (`mimo PID`) for the message of the writer that finds it held.
//! * **Stale staging**: with the lock held no other writer of `NAME` is alive, so every
//!   `.NAME.partial-*` and `.NAME.old-*` beside it is left over from a killed process and is
//!   removed.
//! * **Interrupts**: the staging directories and lock files of this process are registered;
//!   [`remove_pending`] (called by the command's SIGINT/SIGTERM handler) removes them.

use crate::StoreError;
use crate::manifest::{MANIFEST_FILE, Manifest};
use crate::recognise;
use std::fs::{File, OpenOptions, TryLockError};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

/// The suffix of a staging directory being removed on interrupt.
const REMOVING: &str = ".removing";

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

/// Set by [`remove_pending`]: the process is being stopped, and no new temporary file may start.
static CLOSED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Create the temporary file `path` and register it, in one step under the lock
/// [`remove_pending`] holds while it removes: a file is either created before the handler runs
/// (and removed by it) or refused after (an interrupted study's workers start no file that
/// nobody would remove). Unregister it once renamed or removed.
pub fn create_registered(path: &Path) -> Result<File, StoreError> {
    let mut pending = PENDING.lock().map_err(|_| StoreError::Write {
        path: path.to_path_buf(),
        why: "the list of files to remove on interrupt is poisoned".into(),
    })?;
    if CLOSED.load(std::sync::atomic::Ordering::SeqCst) {
        return Err(StoreError::Write { path: path.to_path_buf(), why: "interrupted".into() });
    }
    let file = File::create(path).map_err(|e| StoreError::Write { path: path.to_path_buf(), why: e.to_string() })?;
    pending.push(path.to_path_buf());
    Ok(file)
}

/// Remove everything registered (the interrupt handler's job), holding the list's lock so that
/// no new temporary file starts meanwhile ([`create_registered`]). Best effort: it runs while
/// the process is being stopped.
pub fn remove_pending() {
    let mut pending = match PENDING.lock() {
        Ok(p) => p,
        Err(e) => e.into_inner(),
    };
    CLOSED.store(true, std::sync::atomic::Ordering::SeqCst);
    let paths = std::mem::take(&mut *pending);
    for p in paths {
        if p.is_dir() {
            // Renamed first, atomically: the run workers may still be writing, and while
            // `remove_dir_all` walked the tree one of them could create its table directory and
            // file again under the staging path, which was then left behind. After the rename
            // nothing can be created under that path; the renamed tree (`.NAME.partial-*`, so
            // the next writer removes it if this process is killed first) is removed.
            let removing = p.with_file_name(format!(
                "{}{REMOVING}",
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
    file: File,
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
            let mut file = OpenOptions::new()
                .create(true)
                .truncate(false)
                .write(true)
                .open(&path)
                .map_err(crate::io_err(&path))?;
            match file.try_lock() {
                Ok(()) => {}
                Err(TryLockError::WouldBlock) => {
                    let holder = std::fs::read_to_string(&path).ok().and_then(|t| holder_pid(&t));
                    return Err(StoreError::Busy {
                        path: target.to_path_buf(),
                        why: format!(
                            "another mimo process{} is writing this output (it holds the lock {}); wait for it or choose another output",
                            holder.map(|p| format!(" (pid {p})")).unwrap_or_default(),
                            path.display()
                        ),
                    });
                }
                Err(TryLockError::Error(e)) => return Err(StoreError::Io { path: path.clone(), source: e }),
            }
            if same_file(&file, &path) {
                // Who holds it, for the message of a writer that finds it held. A lock file left
                // by a process that died is not held (the kernel released its lock): it is taken
                // over here and removed when this lock is dropped.
                let _ = file.set_len(0).and_then(|()| writeln!(file, "{LOCK_TAG} {}", std::process::id()));
                register(&path);
                return Ok(OutputLock { path, file });
            }
        }
        Err(StoreError::Busy { path: target.to_path_buf(), why: "its lock file keeps changing".into() })
    }
}

/// The first word of a lock file: `mimo PID`.
const LOCK_TAG: &str = "mimo";

/// The process id a lock file names.
fn holder_pid(text: &str) -> Option<u32> {
    text.trim().strip_prefix(LOCK_TAG)?.trim().parse().ok()
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
        // Removed while still locked; the lock itself goes with the file handle. Only if it is
        // still this lock's file: a directory replaced while locked (`--force`) may hold another
        // process's lock at the same path by now.
        if same_file(&self.file, &self.path) {
            let _ = std::fs::remove_file(&self.path);
        }
        unregister(&self.path);
    }
}

/// Whether the derived directory `dir` (`RUN/score/`) may be replaced: absent, or a score
/// directory holding nothing mimo did not write ([`recognise::foreign_in_score_dir`]).
pub fn check_score_dir(dir: &crate::layout::ScoreDir) -> Result<(), StoreError> {
    let root = dir.root();
    match std::fs::symlink_metadata(root) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(StoreError::Io { path: root.to_path_buf(), source: e }),
        Ok(m) if !m.is_dir() => Err(StoreError::Refused {
            path: root.to_path_buf(),
            why: "exists and is not a directory; mimo score replaces only its own score directory".into(),
        }),
        Ok(_) => {
            let foreign = recognise::foreign_in_score_dir(dir)?;
            if foreign.is_empty() {
                return Ok(());
            }
            let mut why = recognise::foreign_why(&foreign, "mimo score");
            why.push_str(&format!(
                " (a file of a score that is damaged beyond recognition is among them if you did not put it there: \
                 the score is derived, so remove the directory, rm -r '{}', and score again)",
                root.display()
            ));
            Err(StoreError::Refused { path: root.to_path_buf(), why })
        }
    }
}

/// Whether `target` may be written as a run directory: it does not exist, is an empty directory,
/// or (with `force`) is a run directory mimo wrote, recognised by content
/// ([`crate::recognise`]): a manifest mimo can read, and nothing inside that mimo did not write.
/// Returns whether something is there to replace.
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
    let manifest = Manifest::read(target).map_err(|e| StoreError::Refused {
        path: target.to_path_buf(),
        why: format!(
            "exists and is not a mimo run directory (its {MANIFEST_FILE} is not one mimo can read: {e}); \
             refusing to replace it, even with --force"
        ),
    })?;
    if !force {
        return Err(StoreError::Exists { path: target.to_path_buf() });
    }
    let foreign = recognise::foreign_in_run_dir(target, &manifest)?;
    if !foreign.is_empty() {
        return Err(recognise::refuse_foreign(target, &foreign, "--force"));
    }
    Ok(true)
}

/// Whether `path` may be written as a plain output file that a command writes whole (a map, an
/// HTML page): it does not exist, or it is a file this kind of command wrote (`ours`, by content)
/// and `force` is set. A directory, or a file mimo did not write, is never replaced.
pub fn check_file_output(path: &Path, force: bool, ours: fn(&Path) -> bool, what: &str) -> Result<(), StoreError> {
    match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
        Err(e) => Err(StoreError::Io { path: path.to_path_buf(), source: e }),
        Ok(m) if m.is_dir() => Err(StoreError::Refused {
            path: path.to_path_buf(),
            why: "is a directory; expected a file to write".into(),
        }),
        Ok(_) if !force => Err(StoreError::Exists { path: path.to_path_buf() }),
        Ok(_) if !ours(path) => Err(StoreError::Refused {
            path: path.to_path_buf(),
            why: format!("exists and is not {what}; refusing to replace it, even with --force"),
        }),
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
        // `.NAME.partial-PID`, or the same renamed `.NAME.partial-PID.removing` by an interrupt handler that was
        // stopped before it had removed it.
        let is_pid = |p: &String| {
            n.strip_prefix(p.as_str())
                .map(|rest| rest.strip_suffix(REMOVING).unwrap_or(rest))
                .is_some_and(|pid| !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit()))
        };
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
        // A web project's manifest is not a mimo manifest.
        std::fs::write(new.join(MANIFEST_FILE), r#"{"name": "app", "start_url": "/"}"#).expect("write");
        let e = check_replaceable(&new, true).expect_err("web project");
        assert!(e.to_string().contains("not a mimo run directory"), "{e}");
        std::fs::remove_file(new.join("thesis.tex")).expect("rm");
        let m = Manifest {
            mimo_version: "x".into(),
            schema_version: crate::schema::SCHEMA_VERSION,
            scenario: crate::manifest::ScenarioInfo { name: "s".into(), resolved: serde_json::json!({}) },
            seed: 1,
            runs: 1,
            duration_s: 1.0,
            fidelity: serde_json::json!({}),
            tracker: None,
            schedule: String::new(),
            parent: None,
            parent_check: None,
            tables: [(
                "tracks".to_string(),
                vec![crate::manifest::TableFile { file: "tracks/run-0000.parquet".into(), rows: 0 }],
            )]
            .into(),
            timing_s: Default::default(),
        };
        std::fs::write(new.join(MANIFEST_FILE), m.to_json()).expect("write");
        std::fs::create_dir(new.join("tracks")).expect("mkdir");
        std::fs::write(new.join("tracks/run-0000.parquet"), "x").expect("write");
        assert!(matches!(check_replaceable(&new, false), Err(StoreError::Exists { .. })));
        assert!(check_replaceable(&new, true).expect("run"));
        // A file mimo did not list, inside the run: named, and the run is not replaced.
        std::fs::write(new.join("tracks/notes.txt"), "x").expect("write");
        let e = check_replaceable(&new, true).expect_err("notes");
        assert!(e.to_string().contains("notes.txt") && e.to_string().contains("did not write"), "{e}");
        let file = tmp.path().join("file");
        std::fs::write(&file, "x").expect("write");
        assert!(matches!(check_replaceable(&file, true), Err(StoreError::Refused { .. })));
        let ours = |_: &Path| true;
        let theirs = |_: &Path| false;
        assert!(matches!(check_file_output(&file, false, ours, "a page"), Err(StoreError::Exists { .. })));
        assert!(check_file_output(&file, true, ours, "a page").is_ok());
        assert!(matches!(check_file_output(&file, true, theirs, "a page"), Err(StoreError::Refused { .. })));
        assert!(matches!(check_file_output(tmp.path(), true, ours, "a page"), Err(StoreError::Refused { .. })));
    }

    #[test]
    fn one_writer_per_output_and_stale_staging_goes() {
        let tmp = tempfile::tempdir().expect("tmp");
        let target = tmp.path().join("run");
        let stale = tmp.path().join(".run.partial-999999");
        std::fs::create_dir_all(stale.join("truth")).expect("mkdir");
        let removing = tmp.path().join(".run.partial-999998.removing");
        std::fs::create_dir_all(removing.join("truth")).expect("mkdir");
        let other = tmp.path().join(".runner.partial-1");
        std::fs::create_dir_all(&other).expect("mkdir");
        let lock = OutputLock::acquire(&target).expect("first");
        let e = OutputLock::acquire(&target).expect_err("second");
        assert!(matches!(e, StoreError::Busy { .. }), "{e}");
        assert!(e.to_string().contains(&format!("pid {}", std::process::id())), "{e}");
        remove_stale(&target).expect("clean");
        assert!(!stale.exists() && !removing.exists() && other.exists());
        drop(lock);
        assert!(!tmp.path().join(".run.lock").exists());
        drop(OutputLock::acquire(&target).expect("free again"));
    }
}
