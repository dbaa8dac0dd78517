//! The bad-input and fault matrix (docs/design.md §7): every case a user has met or may meet, run
//! against the real binary, with the exit status and a fragment of the one `error:` line it must
//! give, and the check that nothing was left behind (no staging, no lock file, no partial output;
//! inputs untouched). A case is one row of [`CASES`]: add a row for every new failure found.

use mimo_core::records::{DwellRow, MeasurementRow, TrackRow};
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::sync::OnceLock;

const MIMO: &str = env!("CARGO_BIN_EXE_mimo");

/// A scenario small enough to simulate in a moment (one ship, one jet, 60 s).
const SMALL: &str = r#"
name = "small"
duration_s = 60.0

[aircraft_types.jet]
rcs_m2 = 5.0
min_speed_mps = 100.0
max_speed_mps = 300.0
max_accel_g = 3.0

[[ships]]
id = "R1"
lat_deg = 36.0
lon_deg = -70.0
heading_deg = 0.0

[[aircraft]]
id = "X"
type = "jet"
start = { lat_deg = 36.5, lon_deg = -70.0, alt_m = 5000.0 }
heading_deg = 180.0
speed_mps = 200.0
"#;

fn mimo(dir: &Path, args: &[&str]) -> Output {
    Command::new(MIMO).args(args).current_dir(dir).output().expect("mimo runs")
}

/// A template directory holding `small.toml` and a finished run `r` of it (made once).
fn template() -> &'static Path {
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

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    for e in std::fs::read_dir(from).expect("read_dir").flatten() {
        let p = e.path();
        if p.is_dir() {
            copy_dir(&p, &to.join(e.file_name()));
        } else {
            std::fs::copy(&p, to.join(e.file_name())).expect("copy");
        }
    }
}

/// Every path under `dir` (relative), with each file's length.
fn listing(dir: &Path) -> BTreeSet<(PathBuf, u64)> {
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

fn edit_manifest(run: &Path, edit: impl FnOnce(&mut serde_json::Value)) {
    let path = run.join("manifest.json");
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("manifest")).expect("json");
    edit(&mut v);
    std::fs::write(&path, serde_json::to_string_pretty(&v).expect("json")).expect("write");
}

fn edit_table<R: mimo_store::rows::TableRow>(run: &Path, table: &str, edit: impl FnOnce(&mut Vec<R>)) {
    let f = run.join(table).join("run-0000.parquet");
    let mut rows: Vec<R> = mimo_store::read_table(&f).expect("valid table");
    edit(&mut rows);
    mimo_store::write_table(&f, &rows).expect("write");
}

fn ok(dir: &Path, args: &[&str]) {
    let o = mimo(dir, args);
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// One case: what to prepare in the case's directory (holding `small.toml` and the run `r`), the
/// arguments, the exit status and a fragment of the message (stderr; stdout for status 0).
struct Case {
    name: &'static str,
    setup: fn(&Path),
    args: &'static [&'static str],
    code: i32,
    fragment: &'static str,
}

fn none(_: &Path) {}

const CASES: &[Case] = &[
    // ---- parent links and run directories
    Case {
        name: "track onto its own input",
        setup: none,
        args: &["track", "r", "--out", "r", "--force"],
        code: 2,
        fragment: "is the input run directory",
    },
    Case {
        name: "track into its input",
        setup: none,
        args: &["track", "r", "--out", "r/sub"],
        code: 2,
        fragment: "lies inside the input run directory",
    },
    Case {
        name: "track onto a directory holding its input",
        setup: |d| copy_dir(&d.join("r"), &d.join("w/r")),
        args: &["track", "w/r", "--out", "w", "--force"],
        code: 2,
        fragment: "holds the input run directory",
    },
    Case {
        name: "a run that is its own parent",
        setup: |d| edit_manifest(&d.join("r"), |m| m["parent"] = ".".into()),
        args: &["score", "r", "--no-charts"],
        code: 2,
        fragment: "form a cycle",
    },
    Case {
        name: "two runs that are each other's parent",
        setup: |d| {
            copy_dir(&d.join("r"), &d.join("a"));
            copy_dir(&d.join("r"), &d.join("b"));
            edit_manifest(&d.join("a"), |m| m["parent"] = "../b".into());
            edit_manifest(&d.join("b"), |m| m["parent"] = "../a".into());
        },
        args: &["score", "a", "--no-charts"],
        code: 2,
        fragment: "form a cycle",
    },
    Case {
        name: "a re-tracked run scored from another directory",
        setup: |d| {
            ok(d, &["track", "r", "--out", "runs/t", "--quiet"]);
            std::fs::create_dir(d.join("elsewhere")).expect("mkdir");
            ok(d, &["score", "runs/t", "--no-charts", "--quiet"]);
        },
        args: &["score", "../runs/t", "--no-charts"],
        code: 0,
        fragment: "completeness",
    },
    Case {
        name: "a parent moved away",
        setup: |d| {
            ok(d, &["track", "r", "--out", "t", "--quiet"]);
            std::fs::rename(d.join("r"), d.join("moved")).expect("mv");
        },
        args: &["score", "t", "--no-charts"],
        code: 2,
        fragment: "not found",
    },
    Case {
        name: "a parent replaced by another scenario's run",
        setup: |d| {
            ok(d, &["track", "r", "--out", "t", "--quiet"]);
            ok(d, &["simulate", "--scenario", "small.toml", "--seed", "7", "--out", "r", "--force", "--quiet"]);
        },
        args: &["score", "t", "--no-charts"],
        code: 2,
        fragment: "tracked from scenario 'small' seed",
    },
    Case {
        name: "a parent re-simulated since",
        setup: |d| {
            ok(d, &["track", "r", "--out", "t", "--quiet"]);
            ok(d, &["simulate", "--scenario", "small.toml", "--out", "r", "--force", "--quiet"]);
        },
        args: &["score", "t", "--no-charts"],
        code: 2,
        fragment: "was replaced since",
    },
    Case {
        name: "runs: 0 in a manifest",
        setup: |d| edit_manifest(&d.join("r"), |m| m["runs"] = 0.into()),
        args: &["track", "r", "--out", "t"],
        code: 2,
        fragment: "field 'runs'",
    },
    Case {
        name: "a bad scenario in a manifest names the manifest",
        setup: |d| edit_manifest(&d.join("r"), |m| m["scenario"]["resolved"]["ships"][0]["lat_deg"] = 95.0.into()),
        args: &["score", "r"],
        code: 2,
        fragment: "manifest.json: field 'scenario.resolved'",
    },
    // ---- tables that are inconsistent but well-formed
    Case {
        name: "tracks with times reversed",
        setup: |d| {
            edit_table::<TrackRow>(&d.join("r"), "tracks", |rows| {
                let t: Vec<f64> = rows.iter().rev().map(|r| r.t_s).collect();
                rows.iter_mut().zip(t).for_each(|(r, t)| r.t_s = t);
            })
        },
        args: &["score", "r"],
        code: 2,
        fragment: "column `t_s` row",
    },
    Case {
        name: "a tracks row of another run",
        setup: |d| edit_table::<TrackRow>(&d.join("r"), "tracks", |rows| rows[0].run = 5),
        args: &["score", "r"],
        code: 2,
        fragment: "tracks column `run`",
    },
    Case {
        name: "dwells with times reversed",
        setup: |d| {
            edit_table::<DwellRow>(&d.join("r"), "dwells", |rows| {
                let t: Vec<f64> = rows.iter().rev().map(|r| r.t_s).collect();
                rows.iter_mut().zip(t).for_each(|(r, t)| r.t_s = t);
            })
        },
        args: &["track", "r", "--out", "t"],
        code: 2,
        fragment: "column 't_s' row",
    },
    Case {
        name: "a repeated dwell id",
        setup: |d| edit_table::<DwellRow>(&d.join("r"), "dwells", |rows| rows[1].dwell_id = rows[0].dwell_id),
        args: &["track", "r", "--out", "t"],
        code: 2,
        fragment: "column 'dwell_id' row 1",
    },
    Case {
        name: "a repeated measurement id",
        setup: |d| edit_table::<MeasurementRow>(&d.join("r"), "measurements", |rows| rows[1].meas_id = rows[0].meas_id),
        args: &["track", "r", "--from", "measurements", "--out", "t"],
        code: 2,
        fragment: "column 'meas_id' row 1",
    },
    Case {
        name: "a manifest listing a file of a run it does not have",
        setup: |d| edit_manifest(&d.join("r"), |m| m["tables"]["tracks"][0]["file"] = "tracks/run-0003.parquet".into()),
        args: &["score", "r"],
        code: 2,
        fragment: "field 'tables.tracks'",
    },
    // ---- runaway options
    Case {
        name: "--interval 1e-9",
        setup: none,
        args: &["score", "r", "--interval", "1e-9"],
        code: 2,
        fragment: "--interval: 0.000000001 s gives",
    },
    Case {
        name: "--interval 1e-300",
        setup: none,
        args: &["score", "r", "--interval", "1e-300"],
        code: 2,
        fragment: "at most 1e7",
    },
    Case {
        name: "--interval 0",
        setup: none,
        args: &["score", "r", "--interval", "0"],
        code: 2,
        fragment: "--interval:",
    },
    Case { name: "--gate 1e300", setup: none, args: &["score", "r", "--gate", "1e300"], code: 2, fragment: "--gate:" },
    Case {
        name: "--ospa-p 500",
        setup: none,
        args: &["score", "r", "--ospa-p", "500"],
        code: 2,
        fragment: "--ospa-p:",
    },
    Case { name: "--threads 0", setup: none, args: &["score", "r", "--threads", "0"], code: 2, fragment: "--threads:" },
    Case {
        name: "--runs 1000000",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--runs", "1000000", "--out", "big"],
        code: 2,
        fragment: "--runs: 1000000 is above the limit of 100000",
    },
    Case {
        name: "--runs 2000 without --many-runs",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--runs", "2000", "--out", "big"],
        code: 2,
        fragment: "add --many-runs",
    },
    Case {
        name: "--search-pulses 1e6",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--search-pulses", "1000000", "--out", "o"],
        code: 2,
        fragment: "--search-pulses:",
    },
    Case {
        name: "peak_power_w = 1e308",
        setup: |d| {
            let text = SMALL.replace("heading_deg = 0.0\n", "heading_deg = 0.0\nradar = { peak_power_w = 1e308 }\n");
            std::fs::write(d.join("hot.toml"), text).expect("write")
        },
        args: &["simulate", "--scenario", "hot.toml", "--out", "o"],
        code: 2,
        fragment: "peak_power_w: expected at most 1e8 W (plausible range, docs/model.md §3.4)",
    },
    Case {
        name: "a 9 g turn names the scenario file",
        setup: |d| {
            let turn = "speed_mps = 200.0\nmanoeuvres = [{ kind = \"turn\", at_s = 10.0, turn_deg = 90.0, load_factor = 9.0 }]";
            std::fs::write(d.join("turn.toml"), SMALL.replace("speed_mps = 200.0", turn)).expect("write")
        },
        args: &["simulate", "--scenario", "turn.toml", "--out", "o"],
        code: 2,
        fragment: "turn.toml: target X leaves its flight envelope",
    },
    // ---- user files
    Case {
        name: "--map onto an existing file",
        setup: |d| std::fs::write(d.join("map.png"), "mine").expect("write"),
        args: &["scenarios", "--map", "map.png"],
        code: 2,
        fragment: "already exists (use --force",
    },
    Case {
        name: "--map with an unknown extension",
        setup: none,
        args: &["scenarios", "--map", "x.txt"],
        code: 2,
        fragment: "--map: x.txt: expected a .png or .svg",
    },
    Case {
        name: "--force onto a user's folder",
        setup: |d| {
            std::fs::create_dir(d.join("thesis")).expect("mkdir");
            std::fs::write(d.join("thesis/thesis.tex"), "\\documentclass{book}").expect("write");
        },
        args: &["simulate", "--scenario", "small.toml", "--out", "thesis", "--force"],
        code: 2,
        fragment: "not a mimo run directory (no manifest.json); refusing to replace it, even with --force",
    },
    Case {
        name: "simulate --force onto a plain file",
        setup: |d| std::fs::write(d.join("FILE"), "mine").expect("write"),
        args: &["simulate", "--scenario", "small.toml", "--out", "FILE", "--force"],
        code: 2,
        fragment: "exists and is not a directory",
    },
    Case {
        name: "plot onto an existing page",
        setup: |d| std::fs::write(d.join("view.html"), "mine").expect("write"),
        args: &["plot", "r", "--out", "view.html"],
        code: 2,
        fragment: "already exists (use --force",
    },
    Case {
        name: "simulate without --force onto a run",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--out", "r"],
        code: 2,
        fragment: "already exists (use --force",
    },
    // ---- leftovers and locks
    Case {
        name: "stale staging of a killed writer is removed",
        setup: |d| {
            std::fs::create_dir_all(d.join(".o.partial-999999/truth")).expect("mkdir");
            std::fs::create_dir_all(d.join("r/.score.partial-999999/charts")).expect("mkdir");
            ok(d, &["score", "r", "--no-charts", "--quiet"]);
            assert!(!d.join("r/.score.partial-999999").exists(), "stale score staging removed");
        },
        args: &["simulate", "--scenario", "small.toml", "--out", "o", "--quiet"],
        code: 0,
        fragment: "",
    },
    // ---- system faults
    Case {
        name: "an output under a plain file cannot be written",
        setup: |d| std::fs::write(d.join("plain"), "x").expect("write"),
        args: &["simulate", "--scenario", "small.toml", "--out", "plain/o"],
        code: 1,
        fragment: "plain",
    },
    Case {
        name: "power budget zero",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--set", "resource_manager.power_budget_w=0", "--out", "pb"],
        code: 2,
        fragment: "--set: key 'resource_manager.power_budget_w': a power in watts, positive and finite, got 0",
    },
    Case {
        name: "power budget negative",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--set", "resource_manager.power_budget_w=-4", "--out", "pb"],
        code: 2,
        fragment: "--set: key 'resource_manager.power_budget_w': a power in watts, positive and finite, got -4",
    },
    Case {
        name: "power budget infinite",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--set", "resource_manager.power_budget_w=inf", "--out", "pb"],
        code: 2,
        fragment: "--set: key 'resource_manager.power_budget_w': expected a finite number, got inf",
    },
    Case {
        name: "power budget not a number",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--set", "resource_manager.power_budget_w=nan", "--out", "pb"],
        code: 2,
        fragment: "--set: key 'resource_manager.power_budget_w': expected a finite number, got NaN",
    },
    Case {
        name: "power budget text",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--set", "resource_manager.power_budget_w=four", "--out", "pb"],
        code: 2,
        fragment: "--set: key 'resource_manager.power_budget_w': a power in watts, positive and finite, got \"four\"",
    },
];

/// Run one case in a fresh copy of the template; returns what went wrong, if anything.
fn run_case(c: &Case) -> Result<(), String> {
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

#[test]
fn every_bad_input_and_fault_is_answered_and_leaves_nothing() {
    let failures: Vec<String> =
        CASES.iter().filter_map(|c| run_case(c).err().map(|e| format!("{}: {e}", c.name))).collect();
    assert!(failures.is_empty(), "{} of {} cases failed:\n{}", failures.len(), CASES.len(), failures.join("\n"));
}

#[test]
fn a_second_writer_fails_at_once() {
    let tmp = tempfile::tempdir().expect("tmp");
    let d = tmp.path();
    copy_dir(template(), d);
    // Hold the lock of output `o` as a running writer would.
    let lock = std::fs::File::create(d.join(".o.lock")).expect("lock file");
    lock.try_lock().expect("lock");
    let o = mimo(d, &["simulate", "--scenario", "small.toml", "--out", "o"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(err.starts_with("error: ") && err.contains("another mimo process is writing this output"), "{err}");
    assert!(!d.join("o").exists());
}

#[test]
fn a_closed_stdout_is_not_a_panic() {
    let d = template();
    for args in [&["scenarios"][..], &["score", "r", "--no-charts"][..]] {
        let mut child = Command::new(MIMO)
            .args(args)
            .current_dir(d)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("spawn");
        drop(child.stdout.take()); // `| head -0`: the reader is gone before anything is written
        let o = child.wait_with_output().expect("wait");
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}

#[cfg(unix)]
#[test]
fn an_interrupted_simulation_leaves_nothing() {
    let tmp = tempfile::tempdir().expect("tmp");
    let d = tmp.path();
    let child = Command::new(MIMO)
        .args(["simulate", "--scenario", "7", "--runs", "4", "--out", "o", "--quiet"])
        .current_dir(d)
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    // Wait until it is writing (its staging directory exists), then interrupt it.
    let staging = d.join(format!(".o.partial-{}", child.id()));
    let t0 = std::time::Instant::now();
    while !staging.exists() && t0.elapsed().as_secs() < 120 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    assert!(staging.exists(), "the simulation started writing");
    let killed = Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("kill");
    assert!(killed.success());
    let o = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    let left: Vec<_> = listing(d).into_iter().collect();
    assert!(left.is_empty(), "left behind: {left:?}");
}
