//! End-to-end tests of test articles in another process (`--ta-cmd`, docs/ta-protocol.md): the
//! Python examples `python/examples/simple_ta.py` and `search_saver_ta.py` in the closed loop, a
//! Python test article's own search dwells, the faults a child process can commit, and determinism
//! across thread counts.
//!
//! They run the `mimo` binary (so a fault's exit status and stderr are observed as a user sees
//! them) and need `python3` with numpy: without it they fail, saying so (`.ci/run` installs it).

mod child_ta;

use child_ta::{completeness, mimo, p, scored_summary, stderr_of};

fn require_numpy() {
    child_ta::require_python("numpy", "numpy");
}

const SIMPLE_TA: &str = "python3 python/examples/simple_ta.py";

#[test]
fn simple_python_ta_tracks_scenario_1_in_the_closed_loop() {
    require_numpy();
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("s1-py");
    let o =
        mimo(&["simulate", "--scenario", "1", "--duration", "300", "--ta-cmd", SIMPLE_TA, "--quiet", "--out", p(&out)]);
    assert!(o.status.success(), "simulate with simple_ta.py failed: {}", stderr_of(&o));
    let m = mimo_store::manifest::Manifest::read(&out).expect("manifest");
    let tracker = m.tracker.as_ref().expect("tracker in the manifest");
    assert_eq!(tracker.name, SIMPLE_TA);
    assert_eq!(tracker.config["name"], "simple-ta (python)");
    let tracks: Vec<mimo_core::records::TrackRow> =
        mimo_store::read_table(&out.join("tracks/run-0000.parquet")).expect("tracks");
    assert!(tracks.iter().any(|r| r.status == mimo_core::records::TrackStatus::Confirmed));
    // Every track ends with one deleted row.
    let ids: std::collections::BTreeSet<u64> = tracks.iter().map(|r| r.track_id).collect();
    let deleted = tracks.iter().filter(|r| r.status == mimo_core::records::TrackStatus::Deleted).count();
    assert_eq!(deleted, ids.len());
    // Measured 98.00 % on this 300-s run (numpy 2.4), 99.40 % over the full 1000 s
    // (reports/benchmarks-history.md); the bound leaves room for another numpy's rounding.
    let c = completeness(&out);
    assert!(c >= 0.95, "completeness {c}");
}

/// The energy and dwell time a scored run's summary gives to the search purpose (docs/design.md §6):
/// the radars' own background search and the test article's search dwells.
fn search_usage(summary: &serde_json::Value) -> (f64, f64) {
    let search = &summary["usage"]["by_purpose"]["search"];
    (search["energy_j"].as_f64().expect("search energy"), search["dwell_time_s"].as_f64().expect("search time"))
}

/// Issue 36, item 6: the Python example that turns search down once its tracks are held
/// (`search_saver_ta.py`, docs/model.md §7.4) holds 98 % completeness on scenario 1 and spends a
/// fraction of the search energy of the default background search, which the built-in default test
/// article leaves on (it sends no search order) over the same scenario, seed and duration.
///
/// 500 s, not the scenario's 1000 s: measured (release build of main, numpy 2.4) 99.00 % at this
/// seed and 98.25–99.75 % over seeds 1–6; at 300 s it is 98.33 % here but 97.67 % and 97.92 % on
/// two of those seeds (the start's acquisition weighs more in a shorter run). Search energy at
/// 500 s: 68.7 kJ for the example, 467.2 kJ for the default background search (433.2 kJ under
/// `simple_ta.py`, the example's tracker with the radars' own search, too slow to run here).
#[test]
fn the_search_saver_python_ta_holds_98_percent_on_a_fraction_of_the_search_energy() {
    require_numpy();
    let tmp = tempfile::tempdir().expect("tempdir");
    let (saver, default) = (tmp.path().join("saver"), tmp.path().join("default"));
    let cmd = "python3 python/examples/search_saver_ta.py";
    let run = |out: &std::path::Path, ta: &[&str]| {
        let mut args = vec!["simulate", "--scenario", "1", "--duration", "500", "--quiet", "--out", p(out)];
        args.extend(ta);
        let o = mimo(&args);
        assert!(o.status.success(), "simulate {ta:?} failed: {}", stderr_of(&o));
        scored_summary(out)
    };
    let s = run(&saver, &["--ta-cmd", cmd]);
    let d = run(&default, &["--tracker", "default"]);
    let m = mimo_store::manifest::Manifest::read(&saver).expect("manifest");
    assert_eq!(m.tracker.as_ref().expect("tracker").config["name"], "search-saver (python)");

    let c = s["track"]["completeness"].as_f64().expect("completeness");
    assert!(c >= 0.98, "search_saver_ta.py: completeness {c} below 98 %");
    assert_eq!(s["first_track"]["never_tracked"], 0, "every target tracked: {}", s["first_track"]);

    let ((se, st), (de, dt)) = (search_usage(&s), search_usage(&d));
    println!("search energy {se} J vs {de} J, search dwell time {st} s vs {dt} s, completeness {c}");
    assert!(se > 0.0, "the example keeps searching");
    assert!(se < 0.25 * de, "search energy {se} J is not below a quarter of the default's {de} J");
    assert!(st < 0.25 * dt, "search dwell time {st} s is not below a quarter of the default's {dt} s");
    // Every transmit dwell counted (search and the example's own looks) is below the default's
    // search alone.
    let total = s["usage"]["total_energy_j"].as_f64().expect("total energy");
    assert!(total < de, "total energy {total} J against the default's search {de} J");
}

/// A Python test article orders search dwells of its own (docs/ta-protocol.md §3,
/// `TestArticle.request_search_dwell`) with the radars' own search off: the dwells run, monostatic
/// and multistatic, are recorded as `kind = search`, `requested_by = ta`, come back to the test
/// article as such (the fixture raises otherwise), detect the target they are aimed at, and their
/// energy is the test article's and the search purpose's.
#[test]
fn a_python_ta_orders_its_own_search_dwells_monostatic_and_multistatic() {
    use mimo_core::records::{DwellKind, DwellRow, MeasurementRow, Requester, Role};
    require_numpy();
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let cmd = "python3 crates/mimo-cli/tests/fixtures/search_dwell_ta.py";
    let o = mimo(&["simulate", "--scenario", "1", "--duration", "5", "--ta-cmd", cmd, "--out", p(&out)]);
    let err = stderr_of(&o);
    assert!(o.status.success(), "{err}");
    // The fixture's log: both dwells came back as its own search dwells, with detections.
    let logged: Vec<&str> = err.lines().filter(|l| l.starts_with("search dwell ")).collect();
    assert_eq!(logged.len(), 2, "{err}");
    assert!(logged.iter().all(|l| l.contains("kind=search requested_by=ta")), "{err}");

    let dwells: Vec<DwellRow> = mimo_store::read_table(&out.join("dwells/run-0000.parquet")).expect("dwells");
    assert!(dwells.iter().all(|d| d.kind == DwellKind::Search && d.requested_by == Requester::Ta), "{dwells:?}");
    let groups: std::collections::BTreeSet<u64> = dwells.iter().map(|d| d.group_id).collect();
    assert_eq!(groups.len(), 2, "no background search, two dwells of the test article's: {dwells:?}");
    let (mono, multi) = (groups.first().copied().expect("first"), groups.last().copied().expect("second"));
    let parts = |g: u64| dwells.iter().filter(|d| d.group_id == g).collect::<Vec<_>>();
    let mono_parts = parts(mono);
    assert_eq!(mono_parts.len(), 1);
    assert_eq!((mono_parts[0].radar.to_string(), mono_parts[0].role), ("R3".to_string(), Role::Txrx));
    let multi_parts = parts(multi);
    assert_eq!(multi_parts.len(), 4, "R3 transmits, the four radars receive: {multi_parts:?}");
    assert_eq!(multi_parts.iter().filter(|d| d.energy_j > 0.0).count(), 1, "one transmitter");

    // Target C is where they are aimed: the multistatic dwell is heard by other radars than R3.
    let meas: Vec<MeasurementRow> =
        mimo_store::read_table(&out.join("measurements/run-0000.parquet")).expect("measurements");
    let multi_ids: Vec<u64> = multi_parts.iter().map(|d| d.dwell_id).collect();
    assert!(meas.iter().any(|m| m.dwell_id == mono_parts[0].dwell_id), "the monostatic dwell detects C");
    let bistatic = meas.iter().filter(|m| multi_ids.contains(&m.dwell_id) && m.rx != m.tx).count();
    assert!(bistatic >= 1, "the multistatic search dwell is received by other radars: {meas:?}");

    let s = scored_summary(&out);
    let (se, _) = search_usage(&s);
    let (total, ta) =
        (s["usage"]["total_energy_j"].as_f64().expect("total"), s["usage"]["ta_energy_j"].as_f64().expect("ta"));
    let emitted: f64 = dwells.iter().map(|d| d.energy_j).sum();
    assert!(se > 0.0 && (se - total).abs() <= 1e-9 * total && (ta - total).abs() <= 1e-9 * total, "{}", s["usage"]);
    assert!((total - emitted).abs() <= 1.0, "summary {total} J against the dwells table's {emitted} J");
}

#[test]
fn the_same_python_ta_and_seed_give_identical_tables_whatever_the_threads() {
    require_numpy();
    let tmp = tempfile::tempdir().expect("tempdir");
    let run = |threads: &str, name: &str| {
        let out = tmp.path().join(name);
        let o = mimo(&[
            "simulate",
            "--scenario",
            "1",
            "--runs",
            "2",
            "--duration",
            "40",
            "--threads",
            threads,
            "--ta-cmd",
            SIMPLE_TA,
            "--quiet",
            "--out",
            p(&out),
        ]);
        assert!(o.status.success(), "simulate failed: {}", stderr_of(&o));
        out
    };
    let (a, b) = (run("1", "a"), run("2", "b"));
    let mut n = 0;
    for table in ["truth", "dwells", "primitives", "measurements", "tracks"] {
        for r in 0..2 {
            let f = format!("{table}/run-{r:04}.parquet");
            let (x, y) = (std::fs::read(a.join(&f)).expect("read"), std::fs::read(b.join(&f)).expect("read"));
            assert_eq!(x, y, "{f} differs between --threads 1 and 2");
            n += 1;
        }
    }
    assert_eq!(n, 10);
    let tracks: Vec<mimo_core::records::TrackRow> =
        mimo_store::read_table(&a.join("tracks/run-0001.parquet")).expect("tracks");
    assert!(!tracks.is_empty(), "the Python TA wrote no track in 40 s");
}

/// Run the fault fixture in `mode`: exit status 1, one `error:` line naming the command, and
/// nothing left in the output's parent directory. Returns the error line.
fn fault(mode: &str, extra: &[&str]) -> String {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let cmd = format!("python3 crates/mimo-cli/tests/fixtures/fault_ta.py {mode}");
    let mut args =
        vec!["simulate", "--scenario", "1", "--duration", "5", "--ta-cmd", &cmd, "--quiet", "--out", p(&out)];
    args.extend(extra);
    let o = mimo(&args);
    let err = stderr_of(&o);
    assert_eq!(o.status.code(), Some(1), "{mode}: exit status {:?}, stderr {err}", o.status.code());
    let lines: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(lines.len(), 1, "{mode}: one error line wanted: {err}");
    let prefix = format!("error: test article '{cmd}': ");
    assert!(lines[0].starts_with(&prefix), "{mode}: {}", lines[0]);
    let left: Vec<_> =
        std::fs::read_dir(tmp.path()).expect("read tmp").filter_map(|e| e.ok()).map(|e| e.path()).collect();
    assert!(left.is_empty(), "{mode}: left behind {left:?}");
    lines[0].to_string()
}

#[test]
fn a_crashing_ta_stops_the_run() {
    let e = fault("crash", &[]);
    assert!(e.contains("crashed") && e.contains("exit status: 3"), "{e}");
}

#[test]
fn a_hanging_ta_is_caught_after_the_timeout() {
    let t0 = std::time::Instant::now();
    let e = fault("hang", &["--ta-timeout", "1"]);
    assert!(e.contains("no reply within 1 s"), "{e}");
    // The child sleeps 60 s: the run must not have waited for it.
    assert!(t0.elapsed().as_secs() < 50);
}

#[test]
fn a_ta_writing_something_else_than_a_reply_stops_the_run() {
    let e = fault("not_json", &[]);
    assert!(e.contains("bad reply") && e.contains("hello, mimo"), "{e}");
    let e = fault("unknown_key", &[]);
    assert!(e.contains("bad reply") && e.contains("trackz"), "{e}");
    let e = fault("json_array", &[]);
    assert!(e.contains("bad reply: expected a JSON object") && e.contains("`[]`"), "{e}");
    // JSON has no NaN: Python's json.dumps writes `NaN`, which is a bad reply, not a request.
    let e = fault("nan_aim", &[]);
    assert!(e.contains("bad reply") && e.contains("NaN"), "{e}");
}

#[test]
fn a_second_reply_line_stops_the_run_at_once() {
    let e = fault("two_lines", &[]);
    assert!(e.contains("bad reply: a second line in reply to the message at t = "), "{e}");
}

#[test]
fn a_track_row_back_in_time_beyond_the_window_stops_the_run() {
    let e = fault("track_back", &[]);
    assert!(e.contains("invalid request: track 7 has a row at t = 1 s, 30.000 s before its row at t = 31 s"), "{e}");
}

#[test]
fn a_covariance_the_tracks_table_refuses_stops_the_run_at_once() {
    let e = fault("track_negative_variance", &[]);
    assert!(e.contains("invalid request: track 7 at t = 2 s: covariance variance 0 (diagonal) is -1"), "{e}");
    let e = fault("track_not_psd", &[]);
    assert!(e.contains("invalid request: track 7 at t = 2 s: covariance is not positive semi-definite"), "{e}");
    // Beyond the bound of a repair: refused, the eigenvalues named (docs/design.md §7).
    let e = fault("track_far_psd", &[]);
    assert!(e.contains("smallest eigenvalue is -2.000000e-2 against a largest of 2.020000e0"), "{e}");
}

/// A reply whose covariance rounding left slightly indefinite (smallest eigenvalue -1e-6 of the
/// largest) is repaired before its row is written, counted in one warning line, and the table
/// written is valid: its score counts no repair.
#[test]
fn a_slightly_indefinite_covariance_is_repaired_and_counted_not_a_fault() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("out");
    let cmd = "python3 crates/mimo-cli/tests/fixtures/fault_ta.py track_near_psd";
    let o = mimo(&["simulate", "--scenario", "1", "--duration", "5", "--ta-cmd", cmd, "--out", p(&out)]);
    let err = stderr_of(&o);
    assert!(o.status.success(), "{err}");
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("warning:")).collect();
    assert_eq!(warnings.len(), 1, "{err}");
    assert!(warnings[0].contains("1 covariance(s)") && warnings[0].contains("-1.00e-6 of the largest"), "{err}");
    let raw =
        mimo_store::checked::repaired_covariances(&out.join("tracks/run-0000.parquet"), &mimo_store::schema::TRACKS)
            .expect("tracks");
    assert_eq!(raw.rows, 0, "the row written is the repaired one");
    let rows: Vec<mimo_core::records::TrackRow> =
        mimo_store::read_table(&out.join("tracks/run-0000.parquet")).expect("tracks");
    let m = mimo_core::records::unpack_cov(&rows[0].cov);
    assert!((m[0][1] - (1.0 + 2e-6)).abs() < 2e-6, "repaired close to what was sent: {}", m[0][1]);
}

#[test]
fn an_invalid_request_stops_the_run() {
    let e = fault("unknown_radar", &[]);
    assert!(e.contains("invalid request") && e.contains("unknown radar R9"), "{e}");
    let e = fault("start_outside", &[]);
    assert!(e.contains("invalid request") && e.contains("outside the run"), "{e}");
    let e = fault("wake_in_past", &[]);
    assert!(e.contains("invalid request") && e.contains("wake_at 0.5 s"), "{e}");
}
