//! End-to-end tests of the resource-manager role (`--ta-role resource-manager`,
//! docs/ta-protocol.md §7): the built-in default tracker keeps tracking and a process decides the
//! looks. A process that accepts every proposal of the built-in rule gives the built-in default
//! test article's run, table for table, byte for byte; one that refuses them gives another run;
//! bad replies are the protocol's faults.
//!
//! They run the `mimo` binary and `python3` (plain json, no numpy).

mod child_ta;

use child_ta::{completeness, mimo, p, require_python, scored_summary, stderr_of};
use std::path::Path;

const RM: &str = "python3 crates/mimo-cli/tests/fixtures/rule_rm.py";

fn simulate(out: &Path, extra: &[&str]) -> String {
    require_python("json", "python3");
    let mut args = vec!["simulate", "--scenario", "1", "--duration", "20", "--seed", "3", "--quiet", "--out", p(out)];
    args.extend(extra);
    let o = mimo(&args);
    let err = stderr_of(&o);
    assert!(o.status.success(), "simulate {extra:?} failed: {err}");
    err
}

/// Every table file of a run (relative path → bytes), the manifest left out.
fn tables(run: &Path) -> std::collections::BTreeMap<String, Vec<u8>> {
    let mut out = std::collections::BTreeMap::new();
    for dir in std::fs::read_dir(run).expect("run dir") {
        let dir = dir.expect("entry").path();
        if !dir.is_dir() {
            continue;
        }
        for f in std::fs::read_dir(&dir).expect("table dir") {
            let f = f.expect("entry").path();
            if f.extension().is_some_and(|e| e == "parquet") {
                let name = f.strip_prefix(run).expect("inside").display().to_string();
                out.insert(name, std::fs::read(&f).expect("table bytes"));
            }
        }
    }
    out
}

#[test]
fn a_resource_manager_that_defers_to_the_rule_gives_the_built_in_default_run_byte_for_byte() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let (builtin, rm, refuse) = (tmp.path().join("builtin"), tmp.path().join("rm"), tmp.path().join("refuse"));
    simulate(&builtin, &["--tracker", "default"]);
    let cmd = format!("{RM} defer");
    let err = simulate(&rm, &["--ta-cmd", &cmd, "--ta-role", "resource-manager"]);
    let (a, b) = (tables(&builtin), tables(&rm));
    assert!(a.contains_key("tracks/run-0000.parquet") && a.contains_key("dwells/run-0000.parquet"), "{a:?}");
    assert_eq!(a.keys().collect::<Vec<_>>(), b.keys().collect::<Vec<_>>());
    for (name, bytes) in &a {
        assert!(bytes == &b[name], "{name} differs between the built-in default and the deferring resource manager");
    }
    let tracks: Vec<mimo_core::records::TrackRow> =
        mimo_store::read_table(&rm.join("tracks/run-0000.parquet")).expect("tracks");
    assert!(!tracks.is_empty());
    // The process saw every row the built-in tracker wrote.
    assert!(err.contains(&format!("rule_rm.py: {} track rows seen", tracks.len())), "{err}");
    let m = mimo_store::manifest::Manifest::read(&rm).expect("manifest");
    let t = m.tracker.as_ref().expect("tracker");
    assert_eq!(t.name, cmd);
    assert_eq!((t.config["role"].as_str(), t.config["tracker"].as_str()), (Some("resource-manager"), Some("default")));
    assert_eq!(t.config["name"], "rule-rm (defer)");
    // The same score, of course.
    let (sa, sb) = (scored_summary(&builtin), scored_summary(&rm));
    assert_eq!(sa["track"], sb["track"]);
    assert!(completeness(&rm) > 0.0);

    // Refusing every proposal: the built-in tracker still tracks what search finds, but no look
    // of the test article's is made.
    simulate(&refuse, &["--ta-cmd", &format!("{RM} refuse"), "--ta-role", "resource-manager"]);
    let dwells: Vec<mimo_core::records::DwellRow> =
        mimo_store::read_table(&refuse.join("dwells/run-0000.parquet")).expect("dwells");
    assert!(dwells.iter().all(|d| d.requested_by == mimo_core::records::Requester::Radar));
    let before: Vec<mimo_core::records::DwellRow> =
        mimo_store::read_table(&builtin.join("dwells/run-0000.parquet")).expect("dwells");
    assert!(before.iter().any(|d| d.requested_by == mimo_core::records::Requester::Ta));
}

/// Accepting some proposals and adding a look of its own: the accepted looks and the own look
/// are made (the own one reported with its tag), the refused ones are proposed again later.
#[test]
fn a_resource_manager_mixes_accepted_proposals_and_its_own_looks() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("half");
    let err = simulate(&out, &["--ta-cmd", &format!("{RM} half"), "--ta-role", "resource-manager"]);
    // Its own look ran and came back to it with its tag.
    assert!(err.contains("rule_rm.py: own look reported"), "{err}");
    // A refused proposal is proposed again while its track is due.
    let again: u64 = err
        .lines()
        .find_map(|l| l.strip_prefix("rule_rm.py: ")?.strip_suffix(" proposals again after a refusal")?.parse().ok())
        .unwrap_or_else(|| panic!("no count of proposals again: {err}"));
    assert!(again > 0, "{err}");
    let dwells: Vec<mimo_core::records::DwellRow> =
        mimo_store::read_table(&out.join("dwells/run-0000.parquet")).expect("dwells");
    let ta = dwells.iter().filter(|d| d.requested_by == mimo_core::records::Requester::Ta).count();
    assert!(ta > 0, "accepted proposals were made");
}

fn fault(mode: &str) -> String {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let cmd = format!("{RM} {mode}");
    let args = ["simulate", "--scenario", "1", "--duration", "20", "--ta-cmd", &cmd, "--ta-role", "resource-manager"];
    let o = mimo(&[&args[..], &["--quiet", "--out", p(&out)]].concat());
    let err = stderr_of(&o);
    assert_eq!(o.status.code(), Some(1), "{mode}: exit status {:?}, stderr {err}", o.status.code());
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(lines.len(), 1, "{mode}: one error line wanted: {err}");
    assert!(lines[0].starts_with(&format!("error: test article '{cmd}': ")), "{err}");
    assert!(!out.exists(), "{mode}: nothing is kept");
    lines[0].to_string()
}

#[test]
fn bad_replies_of_a_resource_manager_are_the_protocols_faults() {
    let e = fault("bad_index");
    assert!(e.contains("invalid request: accept[0] = ") && e.contains("proposed"), "{e}");
    let e = fault("twice");
    assert!(e.contains("invalid request: accept[1] = 0: proposal 0 accepted twice"), "{e}");
    // Track rows are the built-in tracker's: a resource manager's reply has no `tracks`.
    let e = fault("tracks");
    assert!(e.contains("bad reply: unknown field `tracks`"), "{e}");
}

#[test]
fn the_role_is_checked_on_the_command_line() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let base = ["simulate", "--scenario", "1", "--duration", "5", "--quiet", "--out", p(&out)];
    let run = |extra: &[&str]| {
        let o = mimo(&[&base[..], extra].concat());
        assert_eq!(o.status.code(), Some(2), "{extra:?}: {}", stderr_of(&o));
        stderr_of(&o)
    };
    // --tracker with a whole test article in a process.
    let e = run(&["--ta-cmd", "python3 x.py", "--tracker", "imm"]);
    assert!(e.contains("--tracker"), "{e}");
    // A built-in with no tracker.
    let e = run(&["--ta-cmd", "python3 x.py", "--ta-role", "resource-manager", "--tracker", "none"]);
    assert!(e.contains("--tracker: 'none' has no tracker"), "{e}");
    // The role without a process.
    let e = run(&["--ta-role", "resource-manager"]);
    assert!(e.contains("--ta-cmd"), "{e}");
    assert!(!out.exists());
}
