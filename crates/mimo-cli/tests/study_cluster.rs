//! `mimo study` as a batch scheduler runs it, against the real binary: shards that start at the
//! same moment on a new or empty directory (none may be refused), the shard argument's bad
//! input, a merge with items missing (how many, and which shard), `--status`, `--init`, and the
//! Slurm submit script's bad input. The Slurm route itself runs on a real cluster in
//! scripts/slurm_test.sh.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

const MIMO: &str = env!("CARGO_BIN_EXE_mimo");

/// One cell of scenario 1 for a few seconds: a study that costs next to nothing.
fn tiny_plan(dir: &Path, runs: u32) -> PathBuf {
    let path = dir.join("plan.toml");
    let text = format!(
        "title = \"tiny\"\nscenarios = [1]\nruns = {runs}\nduration_s = 3\n[[methods]]\nname = \"m\"\nta = \"default\"\n"
    );
    std::fs::write(&path, text).expect("plan");
    path
}

fn run(args: &[&str]) -> Output {
    Command::new(MIMO).args(args).output().expect("mimo runs")
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// Exit status 2 and exactly one line on stderr, an `error:` line containing `want`.
fn assert_input_error(o: &Output, want: &str) {
    let err = text(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: ") && err.contains(want), "wanted '{want}' in: {err}");
}

fn p(path: &Path) -> &str {
    path.to_str().expect("utf-8 path")
}

#[test]
fn shards_started_together_are_never_refused() {
    const TRIALS: usize = 50;
    const SHARDS: usize = 8;
    let tmp = tempfile::tempdir().expect("tmp");
    let plan = tiny_plan(tmp.path(), 1);
    for trial in 0..TRIALS {
        let out = tmp.path().join(format!("study-{trial}"));
        // Half the trials on a directory that does not exist, half on an empty one.
        if trial % 2 == 1 {
            std::fs::create_dir(&out).expect("mkdir");
        }
        let children: Vec<Child> = (0..SHARDS)
            .map(|k| {
                let shard = format!("{k}/{SHARDS}");
                Command::new(MIMO)
                    .args(["study", p(&plan), "--out", p(&out), "--shard", &shard, "--threads", "1", "--quiet"])
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .spawn()
                    .expect("spawn")
            })
            .collect();
        for (k, c) in children.into_iter().enumerate() {
            let o = c.wait_with_output().expect("wait");
            assert!(o.status.success(), "trial {trial}, shard {k}/{SHARDS} refused: {}", text(&o.stderr));
        }
        let names: Vec<String> = std::fs::read_dir(&out)
            .expect("dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into())
            .collect();
        assert!(names.iter().all(|n| !n.contains(".tmp-")), "trial {trial}: temporary files left: {names:?}");
        assert!(out.join("runs/method=m/scenario=1/.items/run-0000.json").is_file(), "trial {trial}: the item");
        assert_eq!(std::fs::read_dir(out.join("shards")).expect("shards").count(), SHARDS, "trial {trial}");
    }
}

#[test]
fn a_bad_shard_is_refused_before_anything_is_written() {
    let tmp = tempfile::tempdir().expect("tmp");
    let plan = tiny_plan(tmp.path(), 1);
    let out = tmp.path().join("s");
    for (shard, want) in [
        ("3/3", "--shard: expected 0 <= K < N"),
        ("5/3", "got 5/3"),
        ("0/0", "got 0/0"),
        ("x/3", "K in K/N: expected a whole number, got 'x'"),
        ("1/y", "N in K/N: expected a whole number, got 'y'"),
        ("-1/3", "K in K/N: expected a whole number, got '-1'"),
        ("2", "expected K/N"),
    ] {
        let arg = format!("--shard={shard}");
        assert_input_error(&run(&["study", p(&plan), "--out", p(&out), &arg]), want);
        assert!(!out.exists(), "--shard {shard}: nothing written");
    }
}

#[test]
fn status_and_merge_name_the_missing_shard() {
    let tmp = tempfile::tempdir().expect("tmp");
    let plan = tiny_plan(tmp.path(), 4);
    let out = tmp.path().join("s");
    let study = |extra: &[&str]| {
        let mut a = vec!["study", p(&plan), "--out", p(&out)];
        a.extend_from_slice(extra);
        run(&a)
    };
    // --init creates the directory and runs nothing; again, it only checks.
    for _ in 0..2 {
        let o = study(&["--init"]);
        assert!(o.status.success(), "{}", text(&o.stderr));
        assert!(text(&o.stdout).contains("ready for") && text(&o.stdout).contains("(4 runs in 1 cells)"));
    }
    assert!(out.join("study.json").is_file() && !out.join("runs/method=m").exists());
    let o = study(&["--shard", "0/2", "--threads", "1"]);
    assert!(text(&o.stdout).contains("shard 0/2: ran 2 of its 2 runs"), "{}", text(&o.stdout));

    // Items 1 and 3 (shard 1/2) are missing: the merge refuses and says so; nothing is written.
    assert_input_error(&study(&["--merge"]), "2 of 4 runs are not finished");
    assert_input_error(&study(&["--merge"]), "missing by shard: shard 1/2: 2");
    assert!(!out.join("results.parquet").exists());
    let st = text(&study(&["--status"]).stdout);
    assert!(st.contains("2 of 4 items done (1 cells)"), "{st}");
    assert!(st.contains("shard 0/2: 2 of 2 items done; finished on"), "{st}");
    assert!(st.contains("shard 1/2: 0 of 2 items done; never started"), "{st}");
    assert!(st.contains("not merged"), "{st}");

    let o = study(&["--shard", "1/2", "--threads", "1"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = study(&["--merge"]);
    let said = text(&o.stdout);
    assert!(said.starts_with("merged 4 runs of 1 cells (0 failed)"), "{said}");
    let st = text(&study(&["--status"]).stdout);
    assert!(st.contains("4 of 4 items done") && st.contains("shard 1/2: 2 of 2 items done; finished"), "{st}");
    assert!(st.contains("0 finished items failed") && st.contains("\nmerged ("), "{st}");

    // The status of a directory that is not this plan's study is refused.
    let other = tmp.path().join("other.toml");
    std::fs::write(&other, std::fs::read_to_string(&plan).expect("plan").replace("runs = 4", "runs = 5"))
        .expect("write");
    assert_input_error(&run(&["study", p(&other), "--out", p(&out), "--status"]), "another plan");
    assert_input_error(&run(&["study", p(&plan), "--out", p(tmp.path()), "--status"]), "not a mimo study");
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn the_slurm_submit_script_refuses_bad_arguments_and_writes_nothing() {
    let tmp = tempfile::tempdir().expect("tmp");
    let plan = tiny_plan(tmp.path(), 1);
    let submit = repo().join("examples/slurm/submit.sh");
    let cases: [(&[&str], &str); 6] = [
        (&[], "expected PLAN OUT SHARDS"),
        (&[p(&plan), "out"], "expected PLAN OUT SHARDS"),
        (&[p(&plan), "out", "0"], "SHARDS: expected a whole number of at least 1, got '0'"),
        (&[p(&plan), "out", "three"], "got 'three'"),
        (&[p(&plan), "out", "3", "--partition=x"], "sbatch options go after --"),
        (&["missing.toml", "out", "3"], "missing.toml: no such plan file"),
    ];
    for (args, want) in cases {
        let o = Command::new("bash").arg(&submit).args(args).current_dir(tmp.path()).output().expect("bash");
        assert_input_error(&o, want);
        assert!(!tmp.path().join("out").exists(), "{args:?}: nothing written");
    }
    let o = Command::new("bash")
        .arg(&submit)
        .args([p(&plan), "out", "3", "--", "--array=1"])
        .current_dir(tmp.path())
        .output()
        .expect("bash");
    assert_input_error(&o, "submit.sh sets it itself");
}
