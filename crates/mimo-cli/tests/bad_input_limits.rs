//! The bad-input matrix, continued (docs/design.md §7): limits that must be refused before they
//! exhaust memory, inputs that are not text files, manifests and configurations with wrong
//! values named by key, negative numbers given to flags, and a run without tracks that is still
//! plotted. Each case: exit status, a fragment of the one `error:` line, nothing left behind and
//! nothing of the user's changed (the machinery is `matrix/`).

mod matrix;

use matrix::*;
use std::path::Path;

/// `values` numbers from `first` in steps of `step`, as a TOML list.
fn list(first: f64, step: f64, values: usize) -> String {
    let v: Vec<String> = (0..values).map(|i| format!("{:?}", first + step * i as f64)).collect();
    format!("[{}]", v.join(", "))
}

/// A study plan of `small.toml` (or `scenario`) with `runs` runs and the given `[axes]` lines.
fn write_plan(d: &Path, scenario: &str, runs: u32, axes: &str) {
    let text = format!(
        "title = \"limits\"\nscenarios = [{scenario}]\nruns = {runs}\n\n[[methods]]\nname = \"a\"\nta = \"default\"\n\n[axes]\n{axes}\n"
    );
    std::fs::write(d.join("plan.toml"), text).expect("plan");
}

fn write(d: &Path, name: &str, text: &str) {
    std::fs::write(d.join(name), text).expect("write");
}

const LIMITS: &[Case] = &[
    // ---- memory: scoring times, study cells, items and worlds
    Case {
        name: "--interval inside 1e7 scoring times but above the memory budget",
        setup: none,
        args: &["score", "r", "--interval", "6.1e-6"],
        code: 2,
        fragment: "--interval: 0.0000061 s gives 9.836e6 scoring times in each of 1 run(s) of 1 radar(s) and 1 target(s), \
                   about 25.2 GiB to score; the memory budget is 4 GiB (an interval of at least 3.89e-5 s)",
    },
    Case {
        name: "a study grid of 1 024 000 cells",
        setup: |d| {
            let axes = format!(
                "rcs_offset_db = {}\npeak_power_offset_db = {}\npfa = {}\nsearch_pulses = {}",
                list(-40.0, 1.0, 80),
                list(-25.0, 1.0, 50),
                list(1e-9, 1e-9, 16),
                list(1.0, 1.0, 16)
            );
            write_plan(d, "\"small.toml\"", 1, &axes);
        },
        args: &["study", "plan.toml", "--out", "s"],
        code: 2,
        fragment: "plan.toml: axes: at most 10000 cells (methods × scenarios × stress points), got 1 × 1 × 1024000 = 1024000",
    },
    Case {
        name: "a study of more than a million runs",
        setup: |d| write_plan(d, "\"small.toml\"", 10_000, &format!("rcs_offset_db = {}", list(-40.0, 0.4, 200))),
        args: &["study", "plan.toml", "--out", "s"],
        code: 2,
        fragment: "plan.toml: runs: at most 1000000 runs in all (cells × runs), got 200 × 10000 = 2000000",
    },
    Case {
        name: "a study whose worlds do not fit in memory",
        setup: |d| {
            let axes =
                format!("rcs_offset_db = {}\npeak_power_offset_db = {}", list(-15.0, 1.0, 30), list(-15.0, 1.0, 30));
            write_plan(d, "7", 1, &axes);
        },
        args: &["study", "plan.toml", "--out", "s"],
        code: 2,
        fragment: "plan.toml: axes: at most 3072 MiB of worlds in memory: 900 distinct (scenario, stress point) worlds",
    },
    // ---- text inputs: regular files only, 1 MiB at most
    Case {
        name: "a device as a scenario",
        setup: none,
        args: &["simulate", "--scenario", "/dev/zero", "--out", "o"],
        code: 2,
        fragment: "/dev/zero: cannot read scenario file: not a regular file (a character device)",
    },
    Case {
        name: "a device included by a scenario",
        setup: |d| write(d, "inc.toml", &format!("include = [\"/dev/zero\"]\n{SMALL}")),
        args: &["simulate", "--scenario", "inc.toml", "--out", "o"],
        code: 2,
        fragment: "/dev/zero: cannot read scenario file: not a regular file (a character device); expected a text file (included from inc.toml)",
    },
    Case {
        name: "a FIFO as a scenario",
        setup: |d| {
            let made = std::process::Command::new("mkfifo").arg(d.join("fifo.toml")).status().expect("mkfifo");
            assert!(made.success());
        },
        args: &["simulate", "--scenario", "fifo.toml", "--out", "o"],
        code: 2,
        fragment: "fifo.toml: cannot read scenario file: not a regular file (a FIFO)",
    },
    Case {
        name: "a 2 MB scenario",
        setup: |d| write(d, "big.toml", &format!("{SMALL}{}", "# padding\n".repeat(200_000))),
        args: &["simulate", "--scenario", "big.toml", "--out", "o"],
        code: 2,
        fragment: "big.toml: cannot read scenario file: 2000335 bytes is above the limit of 1048576 bytes",
    },
    Case {
        name: "a device as a test-article configuration",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--ta-config", "/dev/zero", "--out", "o"],
        code: 2,
        fragment: "/dev/zero: not a regular file (a character device)",
    },
    Case {
        name: "a directory as a study plan",
        setup: |d| std::fs::create_dir(d.join("plan.toml")).expect("mkdir"),
        args: &["study", "plan.toml", "--out", "s"],
        code: 2,
        fragment: "plan.toml: cannot read the plan: not a regular file (a directory)",
    },
    // ---- manifests: values checked, fields named
    Case {
        name: "duration_s = -1 in a manifest",
        setup: |d| edit_manifest(&d.join("r"), |m| m["duration_s"] = (-1.0).into()),
        args: &["track", "r", "--out", "t"],
        code: 2,
        fragment: "manifest.json: field 'duration_s': expected a positive number of seconds, got -1",
    },
    Case {
        name: "a manifest that is its own parent, re-tracked",
        setup: |d| edit_manifest(&d.join("r"), |m| m["parent"] = ".".into()),
        args: &["track", "r", "--out", "t"],
        code: 2,
        fragment: "field 'parent': 'parent' links form a cycle",
    },
    Case {
        name: "a negative run count in a manifest names the field",
        setup: |d| edit_manifest(&d.join("r"), |m| m["runs"] = (-1).into()),
        args: &["score", "r"],
        code: 2,
        fragment: "manifest.json: field 'runs': invalid value: integer `-1`, expected u32",
    },
    Case {
        name: "a FIFO in place of a run's manifest",
        setup: |d| {
            std::fs::remove_file(d.join("r/manifest.json")).expect("rm manifest");
            let made = std::process::Command::new("mkfifo").arg(d.join("r/manifest.json")).status().expect("mkfifo");
            assert!(made.success());
        },
        args: &["score", "r"],
        code: 2,
        fragment: "manifest.json: field '(file)': not a regular file (a FIFO); expected a text file",
    },
    Case {
        name: "a wrong type deep in a manifest names its path",
        setup: |d| edit_manifest(&d.join("r"), |m| m["tables"]["tracks"][0]["rows"] = "many".into()),
        args: &["score", "r"],
        code: 2,
        fragment: "manifest.json: field 'tables.tracks[0].rows': invalid type: string \"many\", expected u64",
    },
    // ---- TOML and configuration type errors name the key
    Case {
        name: "a scenario value of the wrong type",
        setup: |d| write(d, "s.toml", &SMALL.replace("duration_s = 60.0", "duration_s = \"abc\"")),
        args: &["simulate", "--scenario", "s.toml", "--out", "o"],
        code: 2,
        fragment: "s.toml:3:14: duration_s: invalid type: string \"abc\", expected f64",
    },
    Case {
        name: "a ship's value of the wrong type",
        setup: |d| write(d, "s.toml", &SMALL.replace("lat_deg = 36.0", "lat_deg = \"north\"")),
        args: &["simulate", "--scenario", "s.toml", "--out", "o"],
        code: 2,
        fragment: "ships[0].lat_deg: invalid type: string \"north\", expected f64",
    },
    Case {
        name: "a test-article configuration file value of the wrong type",
        setup: |d| write(d, "c.toml", "[resource_manager]\nmimo = \"yes\"\n"),
        args: &["simulate", "--scenario", "small.toml", "--ta-config", "c.toml", "--out", "o"],
        code: 2,
        fragment: "c.toml / --set: key 'resource_manager.mimo': invalid type: string \"yes\", expected a boolean",
    },
    Case {
        name: "a --set value of the wrong type",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--set", "resource_manager.mimo=maybe", "--out", "o"],
        code: 2,
        fragment: "--set: key 'resource_manager.mimo': invalid type: string \"maybe\", expected a boolean",
    },
    // ---- negative numbers to flags: the flag and its range
    Case {
        name: "--runs -1",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--runs", "-1", "--out", "o"],
        code: 2,
        fragment: "--runs: expected a whole number of runs from 1 to 1000 (to 100000 with --many-runs), got '-1'",
    },
    Case {
        name: "--threads -2",
        setup: none,
        args: &["score", "r", "--threads", "-2"],
        code: 2,
        fragment: "--threads: expected a whole number of threads from 1 to 4096, got '-2'",
    },
    Case {
        name: "--search-pulses -1",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--search-pulses", "-1", "--out", "o"],
        code: 2,
        fragment: "--search-pulses: expected a whole number of pulses from 1 to 1000, got '-1'",
    },
    Case {
        name: "--seed -1",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--seed", "-1", "--out", "o"],
        code: 2,
        fragment: "--seed: expected a whole number from 0 to 18446744073709551615, got '-1'",
    },
    Case {
        name: "plot --run -1",
        setup: none,
        args: &["plot", "r", "--run", "-1", "--out", "v.html"],
        code: 2,
        fragment: "--run: expected a Monte Carlo run id, a whole number from 0, got '-1'",
    },
    Case {
        name: "--duration -5",
        setup: none,
        args: &["simulate", "--scenario", "small.toml", "--duration", "-5", "--out", "o"],
        code: 2,
        fragment: "--duration: expected seconds in (0, 86400], got -5",
    },
    Case {
        name: "--interval -1",
        setup: none,
        args: &["score", "r", "--interval", "-1"],
        code: 2,
        fragment: "--interval: expected a positive number of seconds, got -1",
    },
    Case {
        name: "--gate -5",
        setup: none,
        args: &["score", "r", "--gate", "-5"],
        code: 2,
        fragment: "--gate: expected metres in (0, 1.3e7], got -5",
    },
    Case {
        name: "an unknown flag is one line",
        setup: none,
        args: &["score", "r", "--bogus"],
        code: 2,
        fragment: "unexpected argument '--bogus' found",
    },
    // ---- a run without tracks is still plotted
    Case {
        name: "plot of a search-only run",
        setup: |d| ok(d, &["simulate", "--scenario", "small.toml", "--tracker", "none", "--out", "bare", "--quiet"]),
        args: &["plot", "bare", "--out", "bare.html"],
        code: 0,
        fragment: "wrote bare.html",
    },
];

#[test]
fn limits_inputs_and_messages_are_answered_and_leave_nothing() {
    run_matrix(LIMITS);
}
