//! SIGINT and SIGTERM (docs/design.md §7): every command exits 130 and leaves nothing, or only
//! what the next writer of the same output removes (and it does). Each test starts the real
//! binary, waits until it has begun writing (a file appears: no fixed sleep), signals it, and
//! checks the status and what is left.
#![cfg(unix)]

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const MIMO: &str = env!("CARGO_BIN_EXE_mimo");

/// A one-cell study of standard scenario 7 with runs long enough to be interrupted midway.
const PLAN: &str =
    "title = \"long\"\nscenarios = [7]\nruns = 4\nduration_s = 300\n[[methods]]\nname = \"m\"\nta = \"default\"\n";

fn spawn(dir: &Path, args: &[&str]) -> Child {
    Command::new(MIMO).args(args).current_dir(dir).stdout(Stdio::null()).stderr(Stdio::piped()).spawn().expect("spawn")
}

/// Wait (up to two minutes) until `ready()`; false if the child ended first.
fn wait_for(child: &mut Child, ready: impl Fn() -> bool) -> bool {
    let t0 = Instant::now();
    while !ready() && t0.elapsed() < Duration::from_secs(120) {
        if child.try_wait().expect("try_wait").is_some() {
            return false;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    ready()
}

/// Signal the child, then its status and standard error.
fn signal(child: Child, sig: &str) -> (Option<i32>, String) {
    let sent = Command::new("kill").args([sig, &child.id().to_string()]).status().expect("kill");
    assert!(sent.success());
    let o = child.wait_with_output().expect("wait");
    (o.status.code(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// Every path under `dir` whose name starts with a dot (staging, locks, temporary files).
fn hidden(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).expect("read_dir").flatten() {
        let p = e.path();
        if e.file_name().to_string_lossy().starts_with('.') {
            out.push(p.clone());
        }
        if p.is_dir() {
            out.extend(hidden(&p));
        }
    }
    out
}

/// How many files the table directory `dir` holds (0 if it does not exist yet).
fn files_in(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |r| r.count())
}

/// Whether some table file is being written in the staging directory `staging`.
fn writing(staging: &Path) -> bool {
    ["truth", "dwells", "tracks"].iter().any(|t| files_in(&staging.join(t)) > 0)
}

#[test]
fn many_short_runs_interrupted_exit_130_and_leave_nothing() {
    for sig in ["-INT", "-TERM"] {
        let tmp = tempfile::tempdir().expect("tmp");
        let d = tmp.path();
        let mut child =
            spawn(d, &["simulate", "--scenario", "7", "--runs", "500", "--duration", "30", "--out", "o", "--quiet"]);
        // Interrupted once dozens of runs are written: removing them takes long enough that the
        // workers, finding their staging directory gone, fail while the handler is still at it
        // (which once ended the command with "write failed" and status 1, leaving a
        // `.o.partial-PID.removing` directory behind).
        let tracks = d.join(format!(".o.partial-{}/tracks", child.id()));
        assert!(wait_for(&mut child, || files_in(&tracks) >= 60), "{sig}: the simulation wrote 60 runs");
        let (code, err) = signal(child, sig);
        assert_eq!(code, Some(130), "{sig}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{sig}: one line: {err}");
        assert!(err.contains("interrupted") && !err.contains("write failed"), "{sig}: {err}");
        let left: Vec<_> = std::fs::read_dir(d).expect("ls").flatten().map(|e| e.path()).collect();
        assert!(left.is_empty(), "{sig}: left behind: {left:?}");
    }
}

#[test]
fn a_track_interrupted_leaves_nothing_and_its_input_is_untouched() {
    let tmp = tempfile::tempdir().expect("tmp");
    let d = tmp.path();
    let o = Command::new(MIMO)
        .args(["simulate", "--scenario", "7", "--runs", "2", "--duration", "120", "--out", "r", "--quiet"])
        .current_dir(d)
        .output()
        .expect("simulate");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut child = spawn(d, &["track", "r", "--out", "t", "--quiet", "--threads", "1"]);
    let staging = d.join(format!(".t.partial-{}", child.id()));
    assert!(wait_for(&mut child, || writing(&staging)), "the re-run started writing");
    let (code, err) = signal(child, "-INT");
    assert_eq!(code, Some(130), "{err}");
    assert!(!d.join("t").exists(), "no output");
    assert!(hidden(d).is_empty(), "left behind: {:?}", hidden(d));
}

#[test]
fn a_study_interrupted_exits_130_and_resumes() {
    let tmp = tempfile::tempdir().expect("tmp");
    let d = tmp.path();
    std::fs::write(d.join("plan.toml"), PLAN).expect("write");
    let mut child = spawn(d, &["study", "plan.toml", "--out", "st", "--quiet", "--threads", "1"]);
    let truth = d.join("st/runs/method=m/scenario=7/truth");
    assert!(wait_for(&mut child, || truth.is_dir()), "the study started its first item");
    let (code, err) = signal(child, "-TERM");
    assert_eq!(code, Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    // What it left (the cell's half-written item) is redone by the next writer.
    let o = Command::new(MIMO)
        .args(["study", "plan.toml", "--out", "st", "--resume", "--quiet", "--threads", "2"])
        .current_dir(d)
        .output()
        .expect("resume");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let partial: Vec<PathBuf> = hidden(&d.join("st"))
        .into_iter()
        .filter(|p| {
            let n = p.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
            n.ends_with(".tmp") || n.ends_with(".lock") || n.contains(".partial-")
        })
        .collect();
    assert!(partial.is_empty(), "no temporary file left: {partial:?}");
}

#[test]
fn staging_an_interrupt_handler_could_not_finish_removing_is_removed_by_the_next_writer() {
    let tmp = tempfile::tempdir().expect("tmp");
    let d = tmp.path();
    std::fs::create_dir_all(d.join(".o.partial-4194303.removing/truth")).expect("mkdir");
    std::fs::write(d.join(".o.partial-4194303.removing/truth/run-0000.parquet"), "x").expect("write");
    let o = Command::new(MIMO)
        .args(["simulate", "--scenario", "7", "--duration", "5", "--out", "o", "--quiet"])
        .current_dir(d)
        .output()
        .expect("simulate");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let names: Vec<String> =
        std::fs::read_dir(d).expect("ls").flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect();
    assert_eq!(names, ["o"], "only the run is left");
}

/// Every `.NAME.tmp` file below `dir` (a table being written).
fn temporaries(dir: &Path) -> Vec<PathBuf> {
    hidden(dir).into_iter().filter(|p| p.file_name().is_some_and(|n| n.to_string_lossy().ends_with(".tmp"))).collect()
}

/// docs/decisions/0303: a study writes its cells in place; interrupted while its items' tables
/// are being written (on one thread and on two), it removes every temporary file of the cells in
/// flight before it exits 130 — with no `--resume` to clean up after it.
#[test]
fn an_interrupted_study_leaves_no_temporary_file_of_its_cells() {
    for (sig, threads) in [("-INT", "1"), ("-TERM", "2")] {
        let tmp = tempfile::tempdir().expect("tmp");
        let d = tmp.path();
        std::fs::write(d.join("plan.toml"), PLAN).expect("write");
        let mut child = spawn(d, &["study", "plan.toml", "--out", "st", "--quiet", "--threads", threads]);
        let st = d.join("st");
        assert!(
            wait_for(&mut child, || st.is_dir() && !temporaries(&st).is_empty()),
            "{sig}: the study started writing a table"
        );
        // Well into the writing of the tables, not at their first bytes.
        std::thread::sleep(Duration::from_millis(300));
        let (code, err) = signal(child, sig);
        assert_eq!(code, Some(130), "{sig}: {err}");
        assert!(err.contains("interrupted"), "{sig}: {err}");
        assert!(temporaries(&st).is_empty(), "{sig}: left behind: {:?}", temporaries(&st));
        let locks: Vec<_> = hidden(d).into_iter().filter(|p| p.to_string_lossy().ends_with(".lock")).collect();
        assert!(locks.is_empty(), "{sig}: locks left: {locks:?}");
    }
}
