//! The bad-input and fault matrix (docs/design.md §7): every case a user has met or may meet, run
//! against the real binary, with the exit status and a fragment of the one `error:` line it must
//! give, and the check that nothing was left behind (no staging, no lock file, no partial output;
//! inputs untouched). A case is one row of [`CASES`]: add a row for every new failure found.

mod matrix;

use matrix::*;
use mimo_core::records::{DwellRow, MeasurementRow, TrackRow};
use std::process::{Command, Stdio};

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
        fragment: "column 't_s' row",
    },
    Case {
        name: "a tracks row of another run",
        setup: |d| edit_table::<TrackRow>(&d.join("r"), "tracks", |rows| rows[0].run = 5),
        args: &["score", "r"],
        code: 2,
        fragment: "tracks/run-0000.parquet: column 'run' row 0: 5 in the file of run 0",
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
        name: "a negative bias scale",
        setup: |d| std::fs::write(d.join("b.toml"), format!("{SMALL}\n[biases]\nscale = -1.0\n")).expect("write"),
        args: &["simulate", "--scenario", "b.toml", "--out", "o"],
        code: 2,
        fragment: "b.toml: biases.scale: expected a number in [0, 100], got -1",
    },
    Case {
        name: "a bias standard deviation that is not finite",
        setup: |d| {
            std::fs::write(d.join("b.toml"), format!("{SMALL}\n[biases]\nsigma_range_m = nan\n")).expect("write")
        },
        args: &["simulate", "--scenario", "b.toml", "--out", "o"],
        code: 2,
        fragment: "b.toml: biases.sigma_range_m: expected a standard deviation in [0, 1000], got NaN",
    },
    Case {
        name: "a bias for a radar the scenario lacks",
        setup: |d| {
            std::fs::write(d.join("b.toml"), format!("{SMALL}\n[biases.radars.R2]\nrange_m = 5.0\n")).expect("write")
        },
        args: &["simulate", "--scenario", "b.toml", "--out", "o"],
        code: 2,
        fragment: "b.toml: biases.radars.R2: expected a radar of the scenario (R1…R1), got `R2`",
    },
    Case {
        name: "a heading bias beyond its bound",
        setup: |d| {
            std::fs::write(d.join("b.toml"), format!("{SMALL}\n[biases.radars.R1]\nheading_deg = 45.0\n"))
                .expect("write")
        },
        args: &["simulate", "--scenario", "b.toml", "--out", "o"],
        code: 2,
        fragment: "b.toml: biases.radars.R1.heading_deg: expected a bias in [-10, 10], got 45",
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
