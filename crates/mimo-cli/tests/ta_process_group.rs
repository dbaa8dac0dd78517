//! A process test article given up on goes with everything it started
//! (docs/decisions/0325-test-article-process-group.md). The test article is a wrapper shell that
//! starts `sleep 60` in the background, writes its pid and never replies:
//! * timed out (`--ta-timeout`), the run fails and the `sleep` ends with the wrapper;
//! * interrupted (SIGINT to `mimo`), the run exits 130 and the `sleep` ends too, although a
//!   child in its own process group does not receive the interrupt itself.

#[allow(dead_code)] // the helpers of the Python test articles are not used here
mod child_ta;

use child_ta::{p, repo};
use std::io::Read;
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The pid the wrapper wrote, once it has written it (within 60 s: the simulation starts first).
fn pid_written(path: &Path) -> u32 {
    let t0 = Instant::now();
    loop {
        if let Ok(text) = std::fs::read_to_string(path)
            && let Ok(pid) = text.trim().parse()
        {
            return pid;
        }
        assert!(t0.elapsed() < Duration::from_secs(60), "the wrapper never wrote {}", path.display());
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// Gone, or a zombie nobody has reaped yet (a container's init may not reap): not running.
fn ended(pid: u32) -> bool {
    match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        // "pid (comm) S …": the state follows the last ')'.
        Ok(stat) => stat.rsplit_once(')').is_some_and(|(_, rest)| rest.trim_start().starts_with(['Z', 'X'])),
        Err(_) => true,
    }
}

fn ends_within_5_s(pid: u32) -> bool {
    let t0 = Instant::now();
    while t0.elapsed() < Duration::from_secs(5) {
        if ended(pid) {
            return true;
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    false
}

/// A shell that starts `sleep 60` in the background, writes its pid to `pid_file` and waits.
fn wrapper(pid_file: &Path) -> String {
    format!("sh -c 'sleep 60 & echo $! > \"{}\"; wait'", p(pid_file))
}

/// `mimo simulate` with the wrapper as its test article (`extra` arguments added), started with
/// its stderr piped.
fn simulate(cmd: &str, out: &Path, extra: &[&str]) -> Child {
    Command::new(env!("CARGO_BIN_EXE_mimo"))
        .args(["simulate", "--scenario", "1", "--duration", "5", "--ta-cmd", cmd, "--quiet", "--out", p(out)])
        .args(extra)
        .current_dir(repo())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn mimo")
}

/// Wait for mimo's exit, not for its stderr to close: the wrapper and its sleep share that pipe,
/// so reading it to the end would wait for the sleep whatever became of it. The sleep must have
/// ended within 5 s of mimo's exit. Returns mimo's exit code and stderr.
fn exit_and_sleep_ended(mut child: Child, sleep_pid: u32, what: &str) -> (Option<i32>, String) {
    let status = child.wait().expect("wait for mimo");
    assert!(ends_within_5_s(sleep_pid), "the wrapper's background sleep outlived the {what}");
    let mut err = String::new();
    child.stderr.take().expect("stderr pipe").read_to_string(&mut err).expect("read stderr");
    (status.code(), err)
}

#[test]
fn a_timed_out_test_article_is_killed_with_what_it_started() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let pid_file = tmp.path().join("sleep.pid");
    let out = tmp.path().join("out");
    let child = simulate(&wrapper(&pid_file), &out, &["--ta-timeout", "1"]);
    let sleep_pid = pid_written(&pid_file);
    let (code, err) = exit_and_sleep_ended(child, sleep_pid, "timed-out test article");
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("no reply within 1 s"), "{err}");
    assert!(!out.exists());
}

#[test]
fn an_interrupted_run_kills_its_test_article_with_what_it_started() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let pid_file = tmp.path().join("sleep.pid");
    let out = tmp.path().join("out");
    let child = simulate(&wrapper(&pid_file), &out, &[]);
    // The wrapper is running (it wrote its sleep's pid) and waits for nothing: interrupt mimo.
    let sleep_pid = pid_written(&pid_file);
    assert!(!ended(sleep_pid), "the background sleep runs before the interrupt");
    let killed = Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill");
    assert!(killed.success());
    let (code, err) = exit_and_sleep_ended(child, sleep_pid, "interrupted run");
    assert_eq!(code, Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    assert!(!out.exists());
}
