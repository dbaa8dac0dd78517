//! `report.html` of a study end to end: a small study (scenario 1, 30 s, a swept MIMO family, a
//! conventional method, an RCS axis, 3 runs, every run's tables kept) is run by the `mimo` binary
//! in a temporary directory; its page is opened in headless Chromium (as `mimo plot`'s is,
//! tests/plot.rs) with the network off, and the page's self-test (`report.html#selftest`) checks
//! that the frontier is drawn, that a click on a point lists its runs with a command each,
//! toggles a family, switches to linear energy and sorts the runs. The command the page shows
//! for the first run listed is then run verbatim by a shell in the same directory, and the tables
//! it writes must be byte-identical to the study's tables of that run; its `mimo plot` page must
//! exist. Bad input: a study directory with a missing or damaged table gets no page, one
//! `error:` line naming the file, exit 2; a study of one point gets a page saying why it has no
//! frontier.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// The `mimo` binary, run as a user runs it (the page's commands say `mimo`).
fn mimo_in(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mimo")).args(args).current_dir(dir).output().expect("run mimo")
}

const PLAN: &str = r#"title = "page test"
scenarios = [1]
runs = 3
duration_s = 30
keep_runs = true

[[methods]]
name = "mimo"
ta = "default"
architecture = "mimo"
sweep = { "resource_manager.power_budget_w" = [0.25, 1.0, 100.0] }

[[methods]]
name = "conventional"
ta = "default"
config = { resource_manager = { mimo = false } }

[axes]
rcs_offset_db = [0, -6]
"#;

/// The small study, run once for the tests of this file.
fn study() -> &'static Path {
    static STUDY: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    let (_, dir) = STUDY.get_or_init(|| {
        let tmp = tempfile::tempdir().expect("tempdir");
        std::fs::write(tmp.path().join("plan.toml"), PLAN).expect("plan");
        let out = mimo_in(tmp.path(), &["study", "plan.toml", "--out", "st", "--quiet", "--threads", "2"]);
        assert!(out.status.success(), "study: {}", String::from_utf8_lossy(&out.stderr));
        let dir = tmp.path().to_path_buf();
        (tmp, dir)
    });
    dir
}

fn chromium() -> PathBuf {
    if let Some(p) = std::env::var_os("MIMO_CHROMIUM") {
        return PathBuf::from(p);
    }
    for c in ["/usr/bin/chromium", "/usr/bin/chromium-browser"] {
        if Path::new(c).is_file() {
            return PathBuf::from(c);
        }
    }
    panic!("Chromium is missing: apt-get install -y chromium, or MIMO_CHROMIUM=/path/to/chromium");
}

/// The page's self-test verdict, from headless Chromium with no network.
fn selftest(page: &Path) -> serde_json::Value {
    let profile = tempfile::tempdir().expect("profile");
    let url = format!("file://{}#selftest", page.canonicalize().expect("page").display());
    let out = Command::new(chromium())
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            "--window-size=1400,1000",
            "--virtual-time-budget=30000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.path().display()))
        .arg(url)
        .output()
        .expect("run chromium");
    let dom = String::from_utf8_lossy(&out.stdout);
    let verdict = dom.split("MIMO-SELFTEST ").nth(1).and_then(|s| s.split('<').next()).unwrap_or_else(|| {
        panic!("no self-test verdict in the DOM; chromium stderr:\n{}", String::from_utf8_lossy(&out.stderr))
    });
    let verdict = verdict.replace("&amp;", "&").replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", "\"");
    serde_json::from_str(&verdict).expect("verdict json")
}

/// Split a command line of the page (words, single quotes, `&&`) into its commands' words.
fn commands(line: &str) -> Vec<Vec<String>> {
    let (mut out, mut words, mut word, mut quoted, mut any) = (Vec::new(), Vec::new(), String::new(), false, false);
    for c in line.chars() {
        match c {
            '\'' => {
                quoted = !quoted;
                any = true;
            }
            ' ' if !quoted => {
                if any {
                    words.push(std::mem::take(&mut word));
                }
                any = false;
            }
            _ => {
                word.push(c);
                any = true;
            }
        }
    }
    if any {
        words.push(word);
    }
    for w in words {
        if w == "&&" {
            out.push(Vec::new());
        } else {
            if out.is_empty() {
                out.push(Vec::new());
            }
            out.last_mut().expect("a command").push(w);
        }
    }
    out
}

#[test]
fn the_page_draws_the_frontier_and_a_click_lists_runs_that_its_command_recreates() {
    let dir = study();
    let page = dir.join("st/report.html");
    let bytes = std::fs::metadata(&page).expect("report.html written by the study").len();
    assert!(bytes < 5 << 20, "{bytes} bytes");
    let v = selftest(&page);
    for check in [
        "frontier_points_drawn",
        "required_line",
        "click_lists_runs",
        "command_shown",
        "toggle_hides_a_family",
        "toggle_restores",
        "linear_energy",
        "runs_sortable",
        "report_tables",
        "failure_curves",
    ] {
        assert_eq!(v["checks"][check], true, "self-test check {check} failed: {v}");
    }
    // In 30 s the swept family's cheapest point beats the others (one frontier point, no line);
    // the shipped challenge study's page draws its frontier lines (docs/studies.md, "The page").
    assert!(v["frontier_line_drawn"].is_boolean(), "{v}");
    assert_eq!(v["errors"], serde_json::json!([]), "console errors: {v}");
    assert_eq!(v["network"], serde_json::json!([]), "network attempts: {v}");
    assert_eq!(v["runs_listed"], 3, "{v}");
    // The page marks its first render (its time is measured by scripts/study_page_open_time.sh,
    // not asserted here: speed is a benchmark's, not a test's).
    let first = v["marks"]["first_render_ms"].as_f64().expect("first render mark");
    assert!(first.is_finite() && first >= 0.0, "first render mark {first}: {v}");

    // The command shown for the first run listed, run verbatim: `mimo study … --rerun CELL --run K
    // --out OUT && mimo plot OUT --run K --out OUT.html`.
    let line = v["command"].as_str().expect("command");
    let cell = v["cell"].as_str().expect("cell");
    let cmds = commands(line);
    assert_eq!(cmds.len(), 2, "{line}");
    for words in &cmds {
        assert_eq!(words[0], "mimo", "{line}");
        let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
        let out = mimo_in(dir, &args);
        assert!(out.status.success(), "{line}: {}", String::from_utf8_lossy(&out.stderr));
    }
    let at = |flag: &str| cmds[0].iter().position(|w| w == flag).map(|i| cmds[0][i + 1].clone()).expect(flag);
    let (run, rerun) = (at("--run").parse::<u32>().expect("run"), dir.join(at("--out")));
    assert!(dir.join(format!("{}.html", at("--out"))).is_file(), "the plot page of the re-run");
    let name = format!("run-{run:04}.parquet");
    let mut compared = 0;
    for table in ["truth", "dwells", "measurements", "tracks"] {
        let (a, b) = (dir.join("st/runs").join(cell).join(table).join(&name), rerun.join(table).join(&name));
        let (a, b) = (std::fs::read(&a).expect("study table"), std::fs::read(&b).expect("re-run table"));
        assert!(a == b, "{table} of {cell} run {run} differs from the study's");
        compared += 1;
    }
    assert_eq!(compared, 4);
}

#[test]
fn a_refined_or_unknown_cell_is_found_or_refused_by_name() {
    let dir = study();
    // A point of the family the plan does not list (as a refinement round would add) is
    // rebuilt from its name; a cell the plan cannot have is refused naming the plan.
    let out = mimo_in(
        dir,
        &["study", "plan.toml", "--rerun", "method=mimo@0.5/scenario=1/rcs_offset_db=0", "--out", "r", "--quiet"],
    );
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(dir.join("r/manifest.json").is_file());
    let out = mimo_in(dir, &["study", "plan.toml", "--rerun", "method=nope/scenario=1/rcs_offset_db=0", "--out", "r2"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("error: plan.toml: the study has no cell 'method=nope"), "{err}");
    assert!(!dir.join("r2").exists());
    let out = mimo_in(
        dir,
        &["study", "plan.toml", "--rerun", "method=mimo@1/scenario=1/rcs_offset_db=0", "--run", "3", "--out", "r3"],
    );
    assert_eq!(out.status.code(), Some(2), "{}", String::from_utf8_lossy(&out.stderr));
}

/// A table's file and how a test damages it.
type Damage = (&'static str, fn(&Path));

/// Copy the study's tables and report (not its runs) into `to`.
fn copy_tables(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).expect("mkdir");
    for e in std::fs::read_dir(from).expect("study").flatten() {
        let name = e.file_name().to_string_lossy().to_string();
        if name.ends_with(".parquet") || name == "report.md" || name == "plan.toml" {
            std::fs::copy(e.path(), to.join(&name)).expect("copy");
        }
    }
}

#[test]
fn missing_or_damaged_tables_get_no_page_and_one_error_line() {
    let dir = study();
    let tmp = tempfile::tempdir().expect("tmp");
    std::fs::copy(dir.join("plan.toml"), tmp.path().join("plan.toml")).expect("plan");
    // A copy of the tables re-renders the page (as the shipped studies' are).
    copy_tables(&dir.join("st"), &tmp.path().join("ok"));
    let out = mimo_in(tmp.path(), &["study", "plan.toml", "--out", "ok", "--page", "--quiet"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(tmp.path().join("ok/report.html").is_file());

    let cases: [Damage; 3] = [
        ("results.parquet", |d| std::fs::remove_file(d.join("results.parquet")).expect("rm")),
        ("challenge.parquet", |d| std::fs::write(d.join("challenge.parquet"), b"not parquet").expect("write")),
        ("failure_points.parquet", |d| {
            std::fs::copy(d.join("summary.parquet"), d.join("failure_points.parquet")).expect("copy");
        }),
    ];
    for (file, damage) in cases {
        let d = tmp.path().join(file.replace('.', "_"));
        copy_tables(&dir.join("st"), &d);
        damage(&d);
        let name = d.file_name().expect("name").to_string_lossy().to_string();
        let out = mimo_in(tmp.path(), &["study", "plan.toml", "--out", &name, "--page"]);
        assert_eq!(out.status.code(), Some(2), "{file}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.starts_with("error: ") && err.contains(file), "{file}: {err}");
        let left: Vec<String> = std::fs::read_dir(&d)
            .expect("dir")
            .flatten()
            .map(|e| e.file_name().to_string_lossy().to_string())
            .filter(|n| n.contains("report.html"))
            .collect();
        assert!(left.is_empty(), "{file}: {left:?} written");
    }
}

#[test]
fn a_study_of_one_point_gets_a_page_saying_why_it_has_no_frontier() {
    let tmp = tempfile::tempdir().expect("tmp");
    let plan = "scenarios = [1]\nruns = 2\nduration_s = 20\n[[methods]]\nname = \"only\"\nta = \"default\"\n";
    std::fs::write(tmp.path().join("one.toml"), plan).expect("plan");
    let out = mimo_in(tmp.path(), &["study", "one.toml", "--out", "st", "--quiet"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let v = selftest(&tmp.path().join("st/report.html"));
    assert_eq!(v["errors"], serde_json::json!([]), "{v}");
    assert_eq!(v["checks"]["click_lists_runs"], true, "{v}");
    assert_eq!(v["runs_listed"], 2, "{v}");
    let why = v["frontier_why"].as_str().expect("why");
    assert!(why.contains("one point: there is no frontier"), "{why}");
    assert!(v["stress_why"].as_str().expect("why").contains("no stress axis"), "{v}");
}

/// A study whose frontiers are built on the test article's energy (`frontier_energy =
/// "test_article"`): the frontier table's flags are the frontier of the points' mean TA energies
/// (not of their totals), the report says which energy it used, and the page draws the TA energy
/// with its own axis title.
#[test]
fn a_study_on_the_test_articles_energy_builds_its_frontier_on_it() {
    use arrow::array::{Array, AsArray};
    use arrow::datatypes::Float64Type;
    use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
    let tmp = tempfile::tempdir().expect("tmp");
    let plan = "scenarios = [1]\nruns = 2\nduration_s = 30\nfrontier_energy = \"test_article\"\n[[methods]]\nname = \
                \"mimo\"\nta = \"default\"\nsweep = { \"resource_manager.power_budget_w\" = [0.1, 1.0, 100.0] }\n";
    std::fs::write(tmp.path().join("ta.toml"), plan).expect("plan");
    let out = mimo_in(tmp.path(), &["study", "ta.toml", "--out", "st", "--quiet", "--threads", "2"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let st = tmp.path().join("st");
    let batch = |name: &str| {
        let f = std::fs::File::open(st.join(name)).expect("table");
        let mut r = ParquetRecordBatchReaderBuilder::try_new(f).expect("parquet").build().expect("reader");
        r.next().expect("a batch").expect("batch")
    };
    let (frontier, summary) = (batch("frontier.parquet"), batch("summary.parquet"));
    let text = |b: &arrow::array::RecordBatch, c: &str| -> Vec<String> {
        let col = b.column_by_name(c).expect(c).as_string::<i32>().clone();
        (0..col.len()).map(|i| col.value(i).to_string()).collect()
    };
    let num = |b: &arrow::array::RecordBatch, c: &str| -> Vec<f64> {
        let col = b.column_by_name(c).expect(c).as_primitive::<Float64Type>().clone();
        (0..col.len()).map(|i| col.value(i)).collect()
    };
    let on: Vec<bool> = {
        let col = frontier.column_by_name("on_frontier").expect("on_frontier").as_boolean().clone();
        (0..col.len()).map(|i| col.value(i)).collect()
    };
    let (f_methods, s_methods) = (text(&frontier, "method"), text(&summary, "method"));
    let (ta, total, done) = (
        num(&summary, "ta_energy_per_object_j_mean"),
        num(&summary, "energy_per_object_j_mean"),
        num(&summary, "completeness_mean"),
    );
    // The frontier by hand: a point is on it when no other reaches at least its completeness for
    // at most its TA energy (and strictly better in one of the two).
    let at = |m: &str| s_methods.iter().position(|s| s == m).expect("summary row");
    for (i, m) in f_methods.iter().enumerate() {
        let k = at(m);
        let beaten = (0..s_methods.len())
            .any(|j| j != k && ta[j] <= ta[k] && done[j] >= done[k] && (ta[j] < ta[k] || done[j] > done[k]));
        assert_eq!(on[i], !beaten, "{m}: TA {} J, completeness {}", ta[k], done[k]);
    }
    // The budget raises the TA's energy from point to point (the frontier's axis here), while the
    // total is not what the flags follow.
    let budget = |b: &str| s_methods.iter().position(|s| s == &format!("mimo@{b}")).expect("point");
    assert!(ta[budget("0.1")] < ta[budget("100")], "{ta:?} (totals {total:?})");
    let md = std::fs::read_to_string(st.join("report.md")).expect("report");
    assert!(md.contains("This study's frontiers are built on the test article's energy"), "{md}");
    assert!(md.contains("x: the test article's energy per scorable object"), "{md}");
    let v = selftest(&st.join("report.html"));
    assert_eq!(v["errors"], serde_json::json!([]), "{v}");
    assert_eq!(v["checks"]["frontier_points_drawn"], true, "{v}");
    let html = std::fs::read_to_string(st.join("report.html")).expect("page");
    assert!(html.contains("\"energy\":\"test_article\""), "the page's data names its energy");
}
