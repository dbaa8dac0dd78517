//! The study directory and who may write into it.
//!
//! `DIR/study.json` marks a directory as a mimo study and records the plan's text; it is written
//! first. A study directory is continued (`--resume`), shared by shards (`--shard K/N`) and
//! merged (`--merge`) only for the same plan; `--force` replaces a study directory, and nothing
//! replaces a directory that is not one.
//!
//! ```text
//! DIR/study.json                   the mark: mimo version, plan file and text
//! DIR/plan.toml                    a copy of the plan
//! DIR/runs/method=…/scenario=…/…/  one run directory per cell (hive-style partitions)
//!     .items/run-0000.json         the record of each finished (cell, run) item
//! DIR/results.parquet, costs.parquet, summary.parquet, charts/, report.md   (after the merge)
//! ```

use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The mark file.
pub const STUDY_FILE: &str = "study.json";

/// What `study.json` holds.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyMark {
    /// Version of mimo that started the study.
    pub mimo_version: String,
    /// The plan file as given.
    pub plan_file: String,
    /// The plan's text (the study's identity).
    pub plan: String,
}

/// How the directory is to be used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Access {
    /// Continue a study of the same plan.
    pub resume: bool,
    /// Replace a study directory.
    pub force: bool,
    /// Only merge: the directory must hold the study.
    pub merge: bool,
}

/// Why the directory cannot be used.
#[derive(Debug, thiserror::Error)]
pub enum DirError {
    /// The user's choice of directory or flags (exit 2).
    #[error("{}: {why}", path.display())]
    Refused {
        /// The directory.
        path: PathBuf,
        /// Why.
        why: String,
    },
    /// The file system failed (exit 1).
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> DirError + '_ {
    move |source| DirError::Io { path: path.to_path_buf(), source }
}

fn refused(path: &Path, why: impl Into<String>) -> DirError {
    DirError::Refused { path: path.to_path_buf(), why: why.into() }
}

/// Read a directory's mark, if it has one.
pub fn read_mark(dir: &Path) -> Result<Option<StudyMark>, DirError> {
    let path = dir.join(STUDY_FILE);
    match std::fs::read_to_string(&path) {
        Ok(t) => serde_json::from_str(&t).map(Some).map_err(|e| refused(&path, format!("not a study mark ({e})"))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(io(&path)(e)),
    }
}

fn is_empty_dir(dir: &Path) -> Result<bool, DirError> {
    Ok(std::fs::read_dir(dir).map_err(io(dir))?.next().is_none())
}

fn create(dir: &Path, mark: &StudyMark) -> Result<(), DirError> {
    std::fs::create_dir_all(dir.join("runs")).map_err(io(dir))?;
    let write = |name: &str, text: &str| -> Result<(), DirError> {
        let path = dir.join(name);
        let tmp = dir.join(format!(".{name}.tmp-{}", std::process::id()));
        std::fs::write(&tmp, text).map_err(io(&tmp))?;
        std::fs::rename(&tmp, &path).map_err(io(&path))
    };
    write("plan.toml", &mark.plan)?;
    let json = serde_json::to_string_pretty(mark).map_err(|e| refused(dir, e.to_string()))?;
    write(STUDY_FILE, &(json + "\n"))
}

/// Make `dir` ready for the study `mark` under `access`. Returns whether it was created (or
/// replaced) rather than continued.
pub fn open(dir: &Path, mark: &StudyMark, access: Access) -> Result<bool, DirError> {
    if !dir.exists() {
        if access.merge {
            return Err(refused(dir, "no such study directory to merge (run the study or its shards first)"));
        }
        create(dir, mark)?;
        return Ok(true);
    }
    if !dir.is_dir() {
        return Err(refused(dir, "exists and is not a directory"));
    }
    let Some(found) = read_mark(dir)? else {
        if !access.merge && is_empty_dir(dir)? {
            create(dir, mark)?;
            return Ok(true);
        }
        return Err(refused(
            dir,
            format!("exists and is not a mimo study (no {STUDY_FILE}); refusing to write into it, even with --force"),
        ));
    };
    let same = found.plan == mark.plan;
    if same && (access.resume || access.merge) {
        return Ok(false);
    }
    if access.force && !access.merge {
        let old = dir.with_file_name(format!(
            ".{}.old-{}",
            dir.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default(),
            std::process::id()
        ));
        std::fs::rename(dir, &old).map_err(io(dir))?;
        std::fs::remove_dir_all(&old).map_err(io(&old))?;
        create(dir, mark)?;
        return Ok(true);
    }
    if same {
        Err(refused(dir, "already holds this study: --resume continues it, --force starts it over"))
    } else {
        Err(refused(
            dir,
            format!(
                "holds a study of another plan ({}; its plan.toml differs): use another --out, or --force to replace it",
                found.plan_file
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mark(plan: &str) -> StudyMark {
        StudyMark { mimo_version: "x".into(), plan_file: "p.toml".into(), plan: plan.into() }
    }
    const NEW: Access = Access { resume: false, force: false, merge: false };

    #[test]
    fn who_may_write_where() {
        let tmp = tempfile::tempdir().expect("tmp");
        let dir = tmp.path().join("study");
        // Merging nothing is refused; a new directory is created with its mark and plan copy.
        assert!(open(&dir, &mark("a"), Access { merge: true, ..NEW }).is_err());
        assert!(open(&dir, &mark("a"), NEW).expect("create"));
        assert_eq!(std::fs::read_to_string(dir.join("plan.toml")).expect("plan"), "a");
        // Again: refused unless resumed (same plan) or forced.
        assert!(matches!(open(&dir, &mark("a"), NEW), Err(DirError::Refused { .. })));
        assert!(!open(&dir, &mark("a"), Access { resume: true, ..NEW }).expect("resume"));
        std::fs::write(dir.join("runs/keep"), "x").expect("write");
        assert!(open(&dir, &mark("b"), Access { resume: true, ..NEW }).is_err(), "another plan cannot resume");
        assert!(open(&dir, &mark("b"), Access { force: true, ..NEW }).expect("force"));
        assert!(!dir.join("runs/keep").exists(), "forced: the old study is gone");
        // A directory that is not a study is never touched, even with --force; an empty one is used.
        let other = tmp.path().join("mine");
        std::fs::create_dir_all(&other).expect("mkdir");
        assert!(open(&other, &mark("a"), NEW).expect("empty dir"));
        let precious = tmp.path().join("precious");
        std::fs::create_dir_all(&precious).expect("mkdir");
        std::fs::write(precious.join("thesis.tex"), "x").expect("write");
        let e = open(&precious, &mark("a"), Access { force: true, ..NEW }).expect_err("refused");
        assert!(e.to_string().contains("not a mimo study"), "{e}");
        assert!(precious.join("thesis.tex").exists());
    }
}
