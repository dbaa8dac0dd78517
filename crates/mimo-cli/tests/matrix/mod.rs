//! The bad-input and fault matrix's machinery (docs/design.md §7), shared by `bad_input.rs` and
//! `bad_input_limits.rs`: a template run of a small scenario, one fresh copy of it per case, the
//! real binary run in it, and the checks that the answer is the promised exit status and one
//! `error:` line and that nothing was left behind or changed.
#![allow(dead_code)]

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

pub const MIMO: &str = env!("CARGO_BIN_EXE_mimo");

#[path = "../common/mod.rs"]
mod common;

/// A scenario small enough to simulate in a moment (one ship, one jet, 60 s).
pub use common::SMALL;

pub fn mimo(dir: &Path, args: &[&str]) -> Output {
    Command::new(MIMO).args(args).current_dir(dir).output().expect("mimo runs")
}

/// A template directory holding `small.toml` and a finished run `r` of it (made once).
pub fn template() -> &'static Path {
    static T: OnceLock<tempfile::TempDir> = OnceLock::new();
    T.get_or_init(|| {
        let t = tempfile::tempdir().expect("tmp");
        std::fs::write(t.path().join("small.toml"), SMALL).expect("write");
        let o = mimo(t.path(), &["simulate", "--scenario", "small.toml", "--out", "r", "--quiet"]);
        assert!(o.status.success(), "template run: {}", String::from_utf8_lossy(&o.stderr));
        t
    })
    .path()
}

/// Copy the directory tree `from` to `to`.
pub use common::copy_dir;

/// Every path under `dir` (relative), with each file's length.
pub fn listing(dir: &Path) -> BTreeSet<(PathBuf, u64)> {
    fn walk(root: &Path, d: &Path, out: &mut BTreeSet<(PathBuf, u64)>) {
        for e in std::fs::read_dir(d).into_iter().flatten().flatten() {
            let p = e.path();
            let len = if p.is_dir() { 0 } else { p.metadata().map(|m| m.len()).unwrap_or(0) };
            out.insert((p.strip_prefix(root).expect("under root").to_path_buf(), len));
            if p.is_dir() {
                walk(root, &p, out);
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(dir, dir, &mut out);
    out
}

pub fn edit_manifest(run: &Path, edit: impl FnOnce(&mut serde_json::Value)) {
    let path = run.join("manifest.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("manifest")).expect("json");
    edit(&mut v);
    std::fs::write(&path, serde_json::to_string_pretty(&v).expect("json")).expect("write");
}

pub fn edit_table<R: mimo_store::rows::TableRow>(run: &Path, table: &str, edit: impl FnOnce(&mut Vec<R>)) {
    let f = run.join(table).join("run-0000.parquet");
    let mut rows: Vec<R> = mimo_store::read_table(&f).expect("valid table");
    edit(&mut rows);
    mimo_store::write_table(&f, &rows).expect("write");
}

pub fn ok(dir: &Path, args: &[&str]) {
    let o = mimo(dir, args);
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// One case: what to prepare in the case's directory (holding `small.toml` and the run `r`), the
/// arguments, the exit status and a fragment of the message (stderr; stdout for status 0).
pub struct Case {
    pub name: &'static str,
    pub setup: fn(&Path),
    pub args: &'static [&'static str],
    pub code: i32,
    pub fragment: &'static str,
}

pub fn none(_: &Path) {}

/// Run one case in a fresh copy of the template; returns what went wrong, if anything.
pub fn run_case(c: &Case) -> Result<(), String> {
    let tmp = tempfile::tempdir().map_err(|e| e.to_string())?;
    let d = tmp.path();
    copy_dir(template(), d);
    (c.setup)(d);
    let before = listing(d);
    let cwd = if c.name.contains("another directory") { d.join("elsewhere") } else { d.to_path_buf() };
    let o = mimo(&cwd, c.args);
    let code = o.status.code().unwrap_or(-1);
    let (out, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    if code != c.code {
        return Err(format!("exit {code}, expected {}: {err}", c.code));
    }
    if c.code == 0 {
        if !out.contains(c.fragment) {
            return Err(format!("stdout lacks {:?}: {out}", c.fragment));
        }
    } else {
        let lines: Vec<&str> = err.lines().collect();
        if lines.len() != 1 || !lines[0].starts_with("error: ") {
            return Err(format!("expected one `error:` line, got {err:?}"));
        }
        if !lines[0].contains(c.fragment) {
            return Err(format!("message lacks {:?}: {}", c.fragment, lines[0]));
        }
        // Nothing written, nothing removed, nothing changed.
        let after = listing(d);
        if after != before {
            let added: Vec<_> = after.difference(&before).collect();
            let gone: Vec<_> = before.difference(&after).collect();
            return Err(format!("files changed: added {added:?}, removed or changed {gone:?}"));
        }
    }
    // Never a staging directory or a lock file left, whatever the outcome.
    let left: Vec<_> = listing(d)
        .into_iter()
        .filter(|(p, _)| {
            let n = p.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
            n.contains(".partial-") || n.contains(".old-") || n.ends_with(".lock") || n.ends_with(".tmp")
        })
        .collect();
    if !left.is_empty() {
        return Err(format!("left behind: {left:?}"));
    }
    Ok(())
}

/// Run every case; fail with the list of cases that went wrong.
pub fn run_matrix(cases: &[Case]) {
    let failures: Vec<String> =
        cases.iter().filter_map(|c| run_case(c).err().map(|e| format!("{}: {e}", c.name))).collect();
    assert!(failures.is_empty(), "{} of {} cases failed:\n{}", failures.len(), cases.len(), failures.join("\n"));
}
