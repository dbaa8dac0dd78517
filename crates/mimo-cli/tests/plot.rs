//! `mimo plot` end to end: a short recorded scenario-7 run is plotted, and the page is loaded in
//! headless Chromium (Debian's package) from a file URL with the network off. The page's
//! self-test (`view.html#selftest`) clicks a bistatic measurement through plotly's click event,
//! checks the panel, the sensor lines and the 1σ/3σ ellipsoids, switches a dwell kind and a
//! radar off and on, clicks the linked metrics panel, plays and pauses, moves the slider and
//! writes its verdict into the DOM,
//! which `--dump-dom` returns; errors and network attempts are recorded from the page's first
//! script on. A screenshot must show the scene. Bad input exits 2 with one `error:` line and
//! writes nothing.

mod common;

use common::{mimo, p};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// One 60-s scenario-7 recording, scored, shared by the tests of this file.
fn recording() -> &'static Path {
    static RUN: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    let (_, dir) = RUN.get_or_init(|| {
        let tmp = tempfile::tempdir().expect("tempdir");
        let run = tmp.path().join("s7");
        let code = mimo(&["simulate", "--scenario", "7", "--duration", "60", "--quiet", "--out", p(&run)]);
        assert_eq!(code, 0, "simulate");
        assert_eq!(mimo(&["score", p(&run), "--no-charts", "--quiet"]), 0, "score");
        (tmp, run)
    });
    dir
}

fn chromium() -> PathBuf {
    if let Some(p) = std::env::var_os("MIMO_CHROMIUM") {
        let p = PathBuf::from(p);
        assert!(p.is_file(), "Chromium is missing: MIMO_CHROMIUM={} is not a file", p.display());
        return p;
    }
    for c in ["/usr/bin/chromium", "/usr/bin/chromium-browser"] {
        if Path::new(c).is_file() {
            return PathBuf::from(c);
        }
    }
    panic!(
        "Chromium is missing: the browser test of `mimo plot` needs Debian's chromium package \
         (apt-get install -y chromium; .ci/run installs it) or MIMO_CHROMIUM=/path/to/chromium"
    );
}

/// Headless Chromium with no network: background services off, every host unresolvable.
fn headless(profile: &Path) -> Command {
    let mut c = Command::new(chromium());
    c.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--disable-extensions",
        "--host-resolver-rules=MAP * ~NOTFOUND",
        "--enable-logging=stderr",
        "--v=0",
        "--window-size=1400,1000",
        "--virtual-time-budget=60000",
    ]);
    c.arg(format!("--user-data-dir={}", profile.display()));
    c
}

fn file_url(path: &Path, fragment: &str) -> String {
    format!("file://{}#{fragment}", path.canonicalize().expect("page path").display())
}

#[test]
fn page_works_offline_in_headless_chromium() {
    let run = recording();
    let tmp = tempfile::tempdir().expect("tempdir");
    let page = tmp.path().join("view.html");
    assert_eq!(mimo(&["plot", p(run), "--out", p(&page), "--quiet"]), 0);

    // Self-test: click, panel, sensor lines, slider; errors and network attempts.
    let out = headless(&tmp.path().join("profile-a"))
        .arg("--dump-dom")
        .arg(file_url(&page, "selftest"))
        .output()
        .expect("run chromium");
    let dom = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let verdict = dom
        .split("MIMO-SELFTEST ")
        .nth(1)
        .and_then(|s| s.split('<').next())
        .unwrap_or_else(|| panic!("no self-test verdict in the DOM; chromium stderr:\n{stderr}"));
    let verdict = verdict.replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"");
    let v: serde_json::Value = serde_json::from_str(&verdict).expect("verdict json");
    for check in [
        "has_measurement",
        "scene_has_webgl",
        "measurement_drawn",
        "panel_filled",
        "sensor_lines_join_the_radars",
        "sensor_lines_drawn",
        "ellipsoids_1_and_3_sigma",
        "kind_toggle_hides_its_measurements",
        "radar_toggle_hides_its_measurements",
        "toggles_restore",
        "metrics_click_moves_time",
        "play_then_pause",
        "slider_moves_state",
        "earth_not_uploaded_on_slider_steps",
        "framing_holds_ships_and_targets",
    ] {
        assert_eq!(v["checks"][check], true, "self-test check {check} failed: {v}");
    }
    assert_eq!(v["errors"], serde_json::json!([]), "console errors: {v}");
    assert_eq!(v["network"], serde_json::json!([]), "network attempts: {v}");
    assert_eq!(v["ok"], true, "{v}");
    let console_errors: Vec<&str> =
        stderr.lines().filter(|l| l.contains("CONSOLE") && l.contains("Uncaught")).collect();
    assert!(console_errors.is_empty(), "uncaught errors: {console_errors:?}");
    // The panel shows the clicked measurement's time, SNR and radars.
    let panel = v["panel"].as_str().expect("panel text");
    assert!(panel.contains("transmitter") && panel.contains("receiver") && panel.contains("dB"), "{panel}");

    // Screenshot: the globe and the scene are drawn (many pixels off the background, in
    // several colours) in the 3-D panel.
    let shot = tmp.path().join("shot.png");
    let status = headless(&tmp.path().join("profile-b"))
        .arg(format!("--screenshot={}", shot.display()))
        .arg(file_url(&page, "t=40"))
        .output()
        .expect("run chromium");
    assert!(shot.is_file(), "no screenshot: {}", String::from_utf8_lossy(&status.stderr));
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&shot).expect("png")));
    let mut reader = decoder.read_info().expect("png header");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("png frame");
    let channels = info.color_type.samples();
    let (w, h) = (info.width as usize, info.height as usize);
    // The 3-D scene occupies the left part of the page below the header.
    let mut coloured = 0usize;
    let mut colours = std::collections::BTreeSet::new();
    let mut total = 0usize;
    for y in (h / 8..h / 2).step_by(2) {
        for x in (w / 20..w * 3 / 4).step_by(2) {
            let i = (y * w + x) * channels;
            let px = &buf[i..i + 3];
            total += 1;
            if px.iter().any(|&c| c < 235) {
                coloured += 1;
            }
            colours.insert((px[0] / 16, px[1] / 16, px[2] / 16));
        }
    }
    assert!(coloured * 10 > total, "scene looks blank: {coloured} of {total} pixels coloured");
    assert!(colours.len() >= 8, "scene has only {} colours", colours.len());
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let run = recording();
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("view.html");
    let cases: Vec<Vec<String>> = vec![
        vec!["--run".into(), "5".into()],
        vec!["--from".into(), "100".into(), "--to".into(), "200".into()],
        vec!["--from".into(), "30".into(), "--to".into(), "10".into()],
    ];
    for extra in cases {
        let mut args = vec!["plot".to_string(), p(run).to_string(), "--out".into(), p(&out).to_string()];
        args.extend(extra.clone());
        let refs: Vec<&str> = args.iter().map(String::as_str).collect();
        assert_eq!(mimo(&refs), 2, "{extra:?}");
        assert!(!out.exists(), "{extra:?} wrote a file");
    }
    // A run directory that does not exist.
    assert_eq!(mimo(&["plot", p(&tmp.path().join("nope")), "--out", p(&out)]), 2);
    assert!(!out.exists());
}

#[test]
fn a_run_without_tracks_still_shows_truth_measurements_and_beams() {
    // The search-only test article forms no tracks; the page shows what the radars did.
    let tmp = tempfile::tempdir().expect("tempdir");
    let bare = tmp.path().join("bare");
    let out = tmp.path().join("bare.html");
    let args = ["simulate", "--scenario", "1", "--duration", "20", "--tracker", "none", "--quiet", "--out", p(&bare)];
    assert_eq!(mimo(&args), 0);
    assert_eq!(mimo(&["plot", p(&bare), "--out", p(&out), "--quiet"]), 0);
    let data = page_data(&std::fs::read_to_string(&out).expect("page"));
    let truth: Vec<&str> = data["truth"].as_array().expect("truth").iter().filter_map(|t| t["id"].as_str()).collect();
    assert_eq!(truth, ["F-1", "A", "B", "C"]);
    assert!(!data["meas"]["t"].as_array().expect("measurements").is_empty(), "search detections shown");
    assert!(data["tracks"]["t"].as_array().expect("tracks").is_empty(), "no track drawn");
}

#[test]
fn output_is_replaced_only_with_force() {
    let run = recording();
    let tmp = tempfile::tempdir().expect("tempdir");
    let out = tmp.path().join("view.html");
    std::fs::write(&out, "keep me").expect("write");
    assert_eq!(mimo(&["plot", p(run), "--out", p(&out), "--quiet", "--from", "20", "--to", "40"]), 2);
    assert_eq!(std::fs::read_to_string(&out).expect("read"), "keep me");
    assert_eq!(mimo(&["plot", p(run), "--out", p(&out), "--quiet", "--from", "20", "--to", "40", "--force"]), 0);
    let page = std::fs::read_to_string(&out).expect("read");
    assert!(page.starts_with("<!DOCTYPE html>") && page.contains("\"from_s\":20.0"));
    // No temporary file is left beside it.
    let names: Vec<String> = std::fs::read_dir(tmp.path())
        .expect("dir")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into())
        .collect();
    assert_eq!(names, vec!["view.html".to_string()]);
}

/// The view data embedded in a page.
fn page_data(page: &str) -> serde_json::Value {
    let start = page.find("id=\"mimo-data\">").expect("data element") + "id=\"mimo-data\">".len();
    let end = start + page[start..].find("</script>").expect("end of data");
    serde_json::from_str(&page[start..end].replace("<\\/", "</")).expect("view json")
}

#[test]
fn a_track_output_is_plotted_with_its_parents_truth_and_dwells() {
    let run = recording();
    let tmp = tempfile::tempdir().expect("tempdir");
    let rerun = tmp.path().join("s7-imm");
    assert_eq!(mimo(&["track", p(run), "--tracker", "imm", "--quiet", "--out", p(&rerun)]), 0);
    let out = tmp.path().join("view.html");
    assert_eq!(mimo(&["plot", p(&rerun), "--out", p(&out), "--quiet"]), 0);
    let v = page_data(&std::fs::read_to_string(&out).expect("page"));
    let parent = page_data(&{
        let o = tmp.path().join("parent.html");
        assert_eq!(mimo(&["plot", p(run), "--out", p(&o), "--quiet"]), 0);
        std::fs::read_to_string(&o).expect("page")
    });
    // Truth and beams are the parent's; the tracks are the re-run's own (scored in memory,
    // since the re-run has no score directory).
    assert_eq!(v["truth"], parent["truth"]);
    assert_eq!(v["beams"], parent["beams"]);
    assert!(!v["tracks"]["t"].as_array().expect("tracks").is_empty());
    assert_eq!(v["meta"]["tracker"], "imm");
    assert!(v["metrics"]["source"].as_str().expect("source").contains("computed in memory"));
}
