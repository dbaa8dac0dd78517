//! Helpers of the tests that run the `mimo` binary with a test article in another process
//! (`ta_process.rs`, `stonesoup_ta.rs`, `ta_process_group.rs`): the binary run from the
//! repository root, the Python modules a test needs, and the completeness of a scored run.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root: the child commands are given relative to it.
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("repository root")
}

/// Run the `mimo` binary from the repository root.
pub fn mimo(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mimo")).args(args).current_dir(repo()).output().expect("run mimo")
}

pub fn p(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

pub fn stderr_of(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Fail, saying how to install them, unless `python3` imports `modules` (e.g. "numpy, stonesoup").
pub fn require_python(modules: &str, install: &str) {
    let ok = Command::new("python3")
        .args(["-c", &format!("import {modules}")])
        .status()
        .map(|s| s.success())
        .unwrap_or(false);
    assert!(
        ok,
        "these tests need python3 with {modules} (`python3 -m pip install {install}`; .ci/run installs it): \
         `python3 -c 'import {modules}'` failed"
    );
}

/// Score a run (`mimo score`, no charts) and return its `score/summary.json`.
pub fn scored_summary(run: &Path) -> serde_json::Value {
    let o = mimo(&["score", p(run), "--no-charts", "--quiet"]);
    assert!(o.status.success(), "mimo score failed: {}", stderr_of(&o));
    let text = std::fs::read_to_string(run.join("score/summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("summary is JSON")
}

/// The `completeness` of a scored run's summary.
pub fn completeness(run: &Path) -> f64 {
    let v = scored_summary(run);
    find_number(&v, "completeness").unwrap_or_else(|| panic!("no completeness in {v}"))
}

/// The first number under `key` anywhere in a JSON value.
fn find_number(v: &serde_json::Value, key: &str) -> Option<f64> {
    match v {
        serde_json::Value::Object(m) => {
            m.get(key).and_then(|x| x.as_f64()).or_else(|| m.values().find_map(|x| find_number(x, key)))
        }
        serde_json::Value::Array(a) => a.iter().find_map(|x| find_number(x, key)),
        _ => None,
    }
}
