//! A user's files are never lost (docs/design.md §7): `--force` replaces only what mimo wrote,
//! recognised by content, and refuses — naming it, changing nothing — anything else; one scorer
//! per run, and no `simulate --force` onto a run being scored. Each case runs the real binary and
//! checks the exit status, a fragment of the message, and that nothing of the user's changed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

mod common;

use common::{SMALL, copy_dir};

const MIMO: &str = env!("CARGO_BIN_EXE_mimo");

/// A one-cell, one-run study of standard scenario 1 for 3 s.
const PLAN: &str =
    "title = \"tiny\"\nscenarios = [1]\nruns = 1\nduration_s = 3\n[[methods]]\nname = \"m\"\nta = \"default\"\n";

fn mimo(dir: &Path, args: &[&str]) -> Output {
    Command::new(MIMO).args(args).current_dir(dir).output().expect("mimo runs")
}

fn ok(dir: &Path, args: &[&str]) {
    let o = mimo(dir, args);
    assert!(o.status.success(), "{args:?}: {}", String::from_utf8_lossy(&o.stderr));
}

/// Run `args`, expect exit status `code` and an `error:` line holding every fragment.
fn refused(dir: &Path, args: &[&str], code: i32, fragments: &[&str]) {
    let o = mimo(dir, args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(code), "{args:?}: {err}");
    assert!(err.starts_with("error: ") && err.trim_end().lines().count() == 1, "{args:?}: one error line: {err}");
    for f in fragments {
        assert!(err.contains(f), "{args:?}: expected '{f}' in: {err}");
    }
}

/// Every file under `dir` (relative path) with its bytes.
fn contents(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    fn walk(root: &Path, d: &Path, out: &mut BTreeMap<PathBuf, Vec<u8>>) {
        for e in std::fs::read_dir(d).expect("read_dir").flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                out.insert(p.strip_prefix(root).expect("under root").to_path_buf(), std::fs::read(&p).expect("read"));
            }
        }
    }
    let mut out = BTreeMap::new();
    walk(dir, dir, &mut out);
    out
}

/// A fresh directory holding `small.toml`, `plan.toml` and a scored run `r` (made once, copied).
fn workdir() -> tempfile::TempDir {
    static T: OnceLock<tempfile::TempDir> = OnceLock::new();
    let t = T.get_or_init(|| {
        let t = tempfile::tempdir().expect("tmp");
        std::fs::write(t.path().join("small.toml"), SMALL).expect("write");
        std::fs::write(t.path().join("plan.toml"), PLAN).expect("write");
        ok(t.path(), &["simulate", "--scenario", "small.toml", "--out", "r", "--quiet"]);
        ok(t.path(), &["score", "r", "--quiet"]);
        t
    });
    let d = tempfile::tempdir().expect("tmp");
    copy_dir(t.path(), d.path());
    d
}

/// A web project: its own `manifest.json` and sources.
fn web_project(d: &Path) -> PathBuf {
    let web = d.join("web");
    std::fs::create_dir_all(web.join("src")).expect("mkdir");
    std::fs::write(web.join("manifest.json"), r#"{"name": "My app", "start_url": "/", "display": "standalone"}"#)
        .expect("write");
    std::fs::write(web.join("src/app.js"), "console.log('hello');\n").expect("write");
    web
}

#[test]
fn a_web_project_is_not_a_run_for_any_command() {
    let tmp = workdir();
    let d = tmp.path();
    let web = web_project(d);
    let before = contents(&web);
    let not_a_run = "not a mimo run directory";
    refused(d, &["simulate", "--scenario", "small.toml", "--out", "web", "--force"], 2, &["web", not_a_run]);
    refused(d, &["track", "r", "--out", "web", "--force"], 2, &["web", not_a_run]);
    refused(d, &["plot", "r", "--out", "web", "--force"], 2, &["web", "is a directory"]);
    refused(d, &["study", "plan.toml", "--out", "web", "--force"], 2, &["web", "not a mimo study"]);
    // A manifest a web project names `manifest.json` cannot be scored or plotted as a run either.
    refused(d, &["score", "web"], 2, &["manifest.json"]);
    assert_eq!(contents(&web), before, "the web project is untouched");
}

#[test]
fn plot_never_overwrites_a_file_it_did_not_write() {
    let tmp = workdir();
    let d = tmp.path();
    let run_before = contents(&d.join("r"));
    refused(
        d,
        &["plot", "r", "--out", "r/manifest.json", "--force"],
        2,
        &["manifest.json", "not a page mimo plot wrote"],
    );
    std::fs::write(d.join("mine.html"), "<html>my page</html>").expect("write");
    refused(d, &["plot", "r", "--out", "mine.html", "--force"], 2, &["mine.html", "not a page mimo plot wrote"]);
    assert_eq!(std::fs::read(d.join("mine.html")).expect("read"), b"<html>my page</html>");
    assert_eq!(contents(&d.join("r")), run_before, "the run is untouched");
    // Its own page it replaces with --force, and only with it.
    ok(d, &["plot", "r", "--out", "view.html", "--quiet"]);
    refused(d, &["plot", "r", "--out", "view.html"], 2, &["already exists"]);
    ok(d, &["plot", "r", "--out", "view.html", "--force", "--quiet"]);
    let page = std::fs::read_to_string(d.join("view.html")).expect("page");
    assert!(page.contains(mimo_store::recognise::PLOT_MARK), "the page carries the mark");
    assert!(!d.join(".view.html.tmp").exists() && !d.join(".view.html.lock").exists());
}

#[test]
fn a_users_file_inside_a_run_is_named_and_kept() {
    let tmp = workdir();
    let d = tmp.path();
    for inside in ["r/notes.txt", "r/tracks/notes.txt", "r/score/charts/notes.txt"] {
        std::fs::write(d.join(inside), "my notes").expect("write");
        let before = contents(&d.join("r"));
        refused(
            d,
            &["simulate", "--scenario", "small.toml", "--out", "r", "--force"],
            2,
            &["notes.txt", "did not write", "move them out first"],
        );
        assert_eq!(contents(&d.join("r")), before, "{inside}: the run is untouched");
        std::fs::remove_file(d.join(inside)).expect("rm");
    }
    // Without a user's file the run is replaced.
    ok(d, &["simulate", "--scenario", "small.toml", "--out", "r", "--force", "--quiet"]);
    assert!(!d.join("r/score").exists(), "the old score went with the old run");
}

#[test]
fn a_users_file_in_the_score_directory_is_named_and_kept() {
    let tmp = workdir();
    let d = tmp.path();
    std::fs::write(d.join("r/score/notes.txt"), "my notes").expect("write");
    let before = contents(&d.join("r"));
    refused(d, &["score", "r", "--no-charts"], 2, &["score/notes.txt", "mimo score replaces only what mimo wrote"]);
    assert_eq!(contents(&d.join("r")), before, "the run and its score are untouched");
    std::fs::remove_file(d.join("r/score/notes.txt")).expect("rm");
    ok(d, &["score", "r", "--no-charts", "--quiet"]);
    // A track output holding a user's file is not replaced either.
    ok(d, &["track", "r", "--out", "t", "--quiet"]);
    std::fs::write(d.join("t/README.md"), "mine").expect("write");
    refused(d, &["track", "r", "--out", "t", "--force"], 2, &["README.md"]);
    assert_eq!(std::fs::read(d.join("t/README.md")).expect("read"), b"mine");
}

#[test]
fn a_map_is_replaced_only_if_scenarios_drew_it() {
    let tmp = workdir();
    let d = tmp.path();
    for name in ["m.png", "m.svg"] {
        ok(d, &["scenarios", "--map", name]);
        assert!(mimo_store::recognise::is_map_image(&d.join(name)), "{name} carries the mark");
        refused(d, &["scenarios", "--map", name], 2, &["already exists"]);
        ok(d, &["scenarios", "--map", name, "--force"]);
    }
    // The PNG is still a PNG every decoder reads (the mark is a valid tEXt chunk).
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(d.join("m.png")).expect("open")));
    let reader = decoder.read_info().expect("a valid PNG");
    assert!(reader.info().width > 0);
    std::fs::write(d.join("photo.png"), b"\x89PNG\r\n\x1a\nnot mimo's").expect("write");
    refused(d, &["scenarios", "--map", "photo.png", "--force"], 2, &["photo.png", "not a map"]);
    assert_eq!(std::fs::read(d.join("photo.png")).expect("read"), b"\x89PNG\r\n\x1a\nnot mimo's");
    let left: Vec<_> = std::fs::read_dir(d)
        .expect("ls")
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with('.'))
        .collect();
    assert!(left.is_empty(), "no temporary file left: {left:?}");
}

/// A PNG whose bytes are a real image but carry no mark of mimo's (a user's own chart).
fn users_png(d: &Path) -> Vec<u8> {
    let marked = std::fs::read(d.join("r/score/charts/completeness.png")).expect("a chart");
    // The mark is the chunk after the header (33 bytes): length, type, data, CRC.
    let len = u32::from_be_bytes(marked[33..37].try_into().expect("4 bytes")) as usize;
    [&marked[..33], &marked[33 + 12 + len..]].concat()
}

#[test]
fn charts_are_mimos_by_their_mark_and_a_users_image_among_them_is_kept() {
    let tmp = workdir();
    let d = tmp.path();
    for name in ["completeness.png", "completeness.svg"] {
        let chart = d.join("r/score/charts").join(name);
        assert!(mimo_store::recognise::is_chart_image(&chart), "{name} carries the mark");
    }
    // The marked PNG is still a PNG every decoder reads.
    let file = std::fs::File::open(d.join("r/score/charts/completeness.png")).expect("open");
    let reader = png::Decoder::new(std::io::BufReader::new(file)).read_info().expect("a valid PNG");
    assert_eq!(reader.info().width, 1200);
    let mine = users_png(d);
    for (name, bytes) in
        [("mine.png", mine.clone()), ("mine.svg", b"<svg xmlns=\"http://www.w3.org/2000/svg\"/>".to_vec())]
    {
        let path = d.join("r/score/charts").join(name);
        std::fs::write(&path, &bytes).expect("write");
        let before = contents(&d.join("r"));
        refused(d, &["score", "r"], 2, &[name, "mimo score replaces only what mimo wrote"]);
        refused(d, &["simulate", "--scenario", "small.toml", "--out", "r", "--force"], 2, &[name, "did not write"]);
        assert_eq!(contents(&d.join("r")), before, "{name}: the run and its score are untouched");
        std::fs::remove_file(&path).expect("rm");
    }
    ok(d, &["score", "r", "--quiet"]);
    // In a study, the same.
    ok(d, &["study", "plan.toml", "--out", "st", "--quiet", "--threads", "1"]);
    std::fs::write(d.join("st/mine.png"), &mine).expect("write");
    refused(d, &["study", "plan.toml", "--out", "st", "--force", "--quiet"], 2, &["mine.png", "did not write"]);
    assert_eq!(std::fs::read(d.join("st/mine.png")).expect("read"), mine);
    // A page of the user's own under the study page's name is not mimo's either.
    std::fs::remove_file(d.join("st/mine.png")).expect("rm");
    let page = "<!doctype html><title>my notes</title>";
    std::fs::write(d.join("st/report.html"), page).expect("write");
    refused(d, &["study", "plan.toml", "--out", "st", "--force", "--quiet"], 2, &["report.html", "did not write"]);
    assert_eq!(std::fs::read_to_string(d.join("st/report.html")).expect("read"), page);
}

#[test]
fn a_study_is_replaced_only_if_all_of_it_is_mimos() {
    let tmp = workdir();
    let d = tmp.path();
    ok(d, &["study", "plan.toml", "--out", "st", "--quiet", "--threads", "1"]);
    std::fs::write(d.join("st/runs/notes.txt"), "mine").expect("write");
    let before = contents(&d.join("st"));
    refused(d, &["study", "plan.toml", "--out", "st", "--force", "--quiet"], 2, &["notes.txt", "did not write"]);
    assert_eq!(contents(&d.join("st")), before, "the study is untouched");
    std::fs::remove_file(d.join("st/runs/notes.txt")).expect("rm");
    ok(d, &["study", "plan.toml", "--out", "st", "--force", "--quiet", "--threads", "1"]);
}

#[test]
fn a_method_name_too_long_for_a_directory_is_refused_before_anything_is_written() {
    let tmp = workdir();
    let d = tmp.path();
    let long = "m".repeat(5000);
    std::fs::write(d.join("long.toml"), PLAN.replace("name = \"m\"", &format!("name = \"{long}\""))).expect("write");
    refused(d, &["study", "long.toml", "--out", "st"], 2, &["long.toml", "methods[0].name", "at most 255 bytes"]);
    assert!(!d.join("st").exists(), "nothing written");
}

#[test]
fn one_scorer_per_run_and_no_force_onto_a_run_being_scored() {
    let tmp = workdir();
    let d = tmp.path();
    let score = mimo_store::layout::RunDir::new(d.join("r")).score();
    let before = contents(&d.join("r"));
    // This test process is "the scorer" holding the run's score lock.
    let lock = mimo_store::output::OutputLock::acquire(score.root()).expect("lock");
    let pid = format!("pid {}", std::process::id());
    refused(d, &["score", "r", "--no-charts"], 1, &[".score.lock", &pid]);
    refused(d, &["simulate", "--scenario", "small.toml", "--out", "r", "--force"], 1, &[".score.lock", &pid]);
    drop(lock);
    assert_eq!(contents(&d.join("r")), before, "the run is untouched");
    // A lock left by a process that died (not held, naming a pid that is gone) is stale: taken
    // over and removed.
    std::fs::write(d.join("r/.score.lock"), "mimo 4194303\n").expect("write");
    ok(d, &["score", "r", "--no-charts", "--quiet"]);
    assert!(!d.join("r/.score.lock").exists(), "stale lock removed");
}
