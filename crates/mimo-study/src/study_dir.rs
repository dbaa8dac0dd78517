//! The study directory and who may write into it.
//!
//! `DIR/study.json` marks a directory as a mimo study and records the plan's text; it is written
//! first, whole and atomically, so that any number of shards may start at once on a new or empty
//! directory: one creates the study, the others find its mark and join it. A study directory is
//! continued (`--resume`), shared by shards (`--shard K/N`) and merged (`--merge`) only for the
//! same plan; `--force` replaces a study directory, and nothing
//! replaces a directory that is not one.
//!
//! ```text
//! DIR/study.json                   the mark: mimo version, plan file and text
//! DIR/plan.toml                    a copy of the plan
//! DIR/runs/method=…/scenario=…/…/  one run directory per cell (hive-style partitions)
//!     .items/run-0000.json         the record of each finished (cell, run) item
//! DIR/results.parquet, costs.parquet, summary.parquet, charts/, report.md   (after the merge)
//! ```

use mimo_store::layout::StudyDir;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The mark file.
pub use mimo_store::layout::STUDY_FILE;

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
    let path = StudyDir::new(dir).mark();
    match std::fs::read_to_string(&path) {
        Ok(t) => serde_json::from_str(&t).map(Some).map_err(|e| refused(&path, format!("not a study mark ({e})"))),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(None),
        Err(e) => Err(io(&path)(e)),
    }
}

/// Whether `name` is a mark being written (see [`claim`]).
fn is_mark_temp(name: &str) -> bool {
    name.starts_with(&format!(".{STUDY_FILE}.tmp-"))
}

/// Whether `dir` is empty but for marks other processes are writing: a directory that a study
/// may claim.
fn is_fresh(dir: &Path) -> Result<bool, DirError> {
    for e in std::fs::read_dir(dir).map_err(io(dir))? {
        let e = e.map_err(io(dir))?;
        if !is_mark_temp(&e.file_name().to_string_lossy()) {
            return Ok(false);
        }
    }
    Ok(true)
}

/// A name no other process, on this machine or another sharing the directory, writes.
fn unique_suffix() -> String {
    let t = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    format!("{}-{t}", std::process::id())
}

/// Claim `dir` (absent, or fresh) for `mark`: the mark is written whole to a temporary file and
/// hard-linked to `study.json`, which fails if another process linked its own first, so that
/// any number of shards may start at once and every one finds either no mark or a whole one.
/// Returns whether this call created the study (`false`: another process did; judge its mark).
fn claim(dir: &Path, mark: &StudyMark) -> Result<bool, DirError> {
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let json = serde_json::to_string_pretty(mark).map_err(|e| refused(dir, e.to_string()))? + "\n";
    let study = StudyDir::new(dir);
    let path = study.mark();
    let tmp = path.with_file_name(format!(".{STUDY_FILE}.tmp-{}", unique_suffix()));
    // Removed by the interrupt handler if a signal comes before it is linked and removed here:
    // the next writer takes it for another shard's mark being written and leaves it alone.
    mimo_store::output::register(&tmp);
    let linked = std::fs::write(&tmp, &json).map(|()| std::fs::hard_link(&tmp, &path));
    let _ = std::fs::remove_file(&tmp);
    mimo_store::output::unregister(&tmp);
    let linked = linked.map_err(io(&tmp))?;
    let created = match linked {
        Ok(()) => true,
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => false,
        // A file system without hard links: create the mark exclusively; a reader that finds it
        // still empty waits for it (`read_mark_settled`).
        Err(_) => match std::fs::OpenOptions::new().write(true).create_new(true).open(&path) {
            Ok(mut f) => {
                std::io::Write::write_all(&mut f, json.as_bytes()).map_err(io(&path))?;
                true
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => false,
            Err(e) => return Err(io(&path)(e)),
        },
    };
    if created {
        std::fs::create_dir_all(study.runs()).map_err(io(dir))?;
        let plan = study.plan();
        let tmp = plan.with_file_name(format!(".plan.toml.tmp-{}", unique_suffix()));
        mimo_store::output::register(&tmp);
        let copied = std::fs::write(&tmp, &mark.plan)
            .map_err(io(&tmp))
            .and_then(|()| std::fs::rename(&tmp, &plan).map_err(io(&plan)));
        if copied.is_err() {
            let _ = std::fs::remove_file(&tmp);
        }
        mimo_store::output::unregister(&tmp);
        copied?;
    }
    Ok(created)
}

/// [`read_mark`], waiting up to about five seconds for a mark that another process is still
/// writing (only where the file system has no hard links) before calling it bad.
fn read_mark_settled(dir: &Path) -> Result<Option<StudyMark>, DirError> {
    let mut tries = 0;
    loop {
        match read_mark(dir) {
            Err(DirError::Refused { .. }) if tries < 50 => {
                tries += 1;
                std::thread::sleep(std::time::Duration::from_millis(100));
            }
            other => return other,
        }
    }
}

/// The marker in the head of the study page mimo writes (crates/mimo-study/assets/report.html).
const PAGE_MARK: &str = r#"<meta name="generator" content="mimo study">"#;

/// Whether `path` is a study page mimo wrote: its first kilobytes hold [`PAGE_MARK`].
fn page_is_mimos(path: &Path) -> bool {
    use std::io::Read;
    let mut head = Vec::with_capacity(4096);
    std::fs::File::open(path)
        .and_then(|f| f.take(4096).read_to_end(&mut head))
        .is_ok_and(|_| String::from_utf8_lossy(&head).contains(PAGE_MARK))
}

/// Everything in the study directory `dir` (marked `found`) is what mimo wrote, recognised by
/// content: its mark and plan copy, and below them only run directories' tables, records and
/// manifests, shard logs, study tables, charts, the report and its page ([`mimo_store::recognise`]).
/// Anything else is refused, named, and left alone, even with `--force`.
fn check_all_ours(dir: &Path, found: &StudyMark) -> Result<(), DirError> {
    let study = StudyDir::new(dir);
    let plan_copy = std::fs::read_to_string(study.plan()).is_ok_and(|t| t == found.plan);
    let report = std::fs::read_to_string(study.report()).is_ok_and(|t| t.starts_with("# "));
    // The page (docs/studies.md, "The page") carries its generator in its head.
    let page = study.report_html();
    let page_ours = page_is_mimos(&page);
    let ours = |p: &Path| {
        (p == study.plan() && plan_copy)
            || (p == study.report() && report)
            || (p == page.as_path() && page_ours)
            || p == study.mark().as_path()
    };
    let foreign = mimo_store::recognise::foreign_in_tree(dir, &ours).map_err(|e| match e {
        mimo_store::StoreError::Io { path, source } => DirError::Io { path, source },
        e => refused(dir, e.to_string()),
    })?;
    if foreign.is_empty() { Ok(()) } else { Err(refused(dir, mimo_store::recognise::foreign_why(&foreign, "--force"))) }
}

/// Make `dir` ready for the study `mark` under `access`. Returns whether it was created (or
/// replaced) rather than continued.
pub fn open(dir: &Path, mark: &StudyMark, access: Access) -> Result<bool, DirError> {
    if access.merge && !dir.exists() {
        return Err(refused(dir, "no such study directory to merge (run the study or its shards first)"));
    }
    if dir.exists() && !dir.is_dir() {
        return Err(refused(dir, "exists and is not a directory"));
    }
    if !access.merge && (!dir.exists() || is_fresh(dir)?) && claim(dir, mark)? {
        return Ok(true);
    }
    let Some(found) = read_mark_settled(dir)? else {
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
        check_all_ours(dir, &found)?;
        let old = dir.with_file_name(format!(
            ".{}.old-{}",
            dir.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default(),
            std::process::id()
        ));
        std::fs::rename(dir, &old).map_err(io(dir))?;
        std::fs::remove_dir_all(&old).map_err(io(&old))?;
        claim(dir, mark)?;
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
        std::fs::write(dir.join("runs/keep.json"), "{}").expect("write");
        assert!(open(&dir, &mark("b"), Access { resume: true, ..NEW }).is_err(), "another plan cannot resume");
        // A user's file inside is named and nothing is replaced, even with --force.
        std::fs::write(dir.join("runs/notes.txt"), "mine").expect("write");
        let e = open(&dir, &mark("b"), Access { force: true, ..NEW }).expect_err("user file");
        assert!(e.to_string().contains("notes.txt"), "{e}");
        assert!(dir.join("runs/keep.json").exists() && dir.join("runs/notes.txt").exists());
        std::fs::remove_file(dir.join("runs/notes.txt")).expect("rm");
        assert!(open(&dir, &mark("b"), Access { force: true, ..NEW }).expect("force"));
        assert!(!dir.join("runs/keep.json").exists(), "forced: the old study is gone");
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

    #[test]
    fn the_mark_is_claimed_once_and_a_mark_being_written_is_not_a_foreign_file() {
        let tmp = tempfile::tempdir().expect("tmp");
        let dir = tmp.path().join("study");
        assert!(claim(&dir, &mark("a")).expect("first"));
        assert!(!claim(&dir, &mark("b")).expect("second"), "the first mark stays");
        assert_eq!(read_mark(&dir).expect("read"), Some(mark("a")));
        let names: Vec<String> =
            std::fs::read_dir(&dir).expect("dir").map(|e| e.expect("e").file_name().to_string_lossy().into()).collect();
        assert!(names.iter().all(|n| !n.contains(".tmp-")), "{names:?}");
        // A directory holding only another process's mark in the making is claimed, not refused.
        let fresh = tmp.path().join("fresh");
        std::fs::create_dir_all(&fresh).expect("mkdir");
        std::fs::write(fresh.join(".study.json.tmp-99-1"), "{").expect("write");
        assert!(open(&fresh, &mark("a"), Access { resume: true, ..NEW }).expect("claimed"));
        // Shards of the same plan join; another plan is refused.
        assert!(!open(&fresh, &mark("a"), Access { resume: true, ..NEW }).expect("join"));
        assert!(open(&fresh, &mark("b"), Access { resume: true, ..NEW }).is_err());
    }
}
