//! Every table mimo writes is read by polars, as users analyse them (docs/design.md §3): a short
//! run is simulated, re-tracked and scored, and Python's polars reads each Parquet file of the
//! run directory and of its score, finding the row count in the file's footer and the columns of
//! the table's schema file (`schemas/*.json`).
//!
//! mimo itself does not link polars (docs/decisions/0100-a-small-build-graph.md), so this test is
//! what keeps the promise. It needs `python3` with polars: without it it fails, saying so
//! (`.ci/run` installs it).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..").canonicalize().expect("repository root")
}

fn mimo(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_mimo")).args(args).current_dir(repo()).output().expect("run mimo")
}

fn ok(o: Output, what: &str) {
    assert!(o.status.success(), "{what} failed: {}", String::from_utf8_lossy(&o.stderr));
}

/// The Python check: for every Parquet file under the directory, polars reads it; its height is
/// the footer's row count, and when the table has a schema file its columns are the schema's.
const CHECK: &str = r#"
import json, pathlib, sys
import polars as pl
import pyarrow.parquet as pq
root, schemas = pathlib.Path(sys.argv[1]), pathlib.Path(sys.argv[2])
by_table = {}
for f in schemas.glob("*.json"):
    d = json.loads(f.read_text())
    if "table" in d:
        by_table[d["table"]] = [c["name"] for c in d["columns"]]
files = sorted(root.rglob("*.parquet"))
assert files, "no Parquet files"
for f in files:
    df = pl.read_parquet(f)
    rows = pq.ParquetFile(f).metadata.num_rows
    assert df.height == rows, f"{f}: polars read {df.height} rows, the footer says {rows}"
    table = f.parent.name if f.parent.name != "score" else "score_" + f.stem
    if table in by_table:
        assert df.columns == by_table[table], f"{f}: columns {df.columns} != {by_table[table]}"
print(len(files))
"#;

#[test]
fn polars_reads_every_table_of_a_run_and_its_score() {
    let has = |module: &str| {
        Command::new("python3").args(["-c", &format!("import {module}")]).status().map(|s| s.success()).unwrap_or(false)
    };
    assert!(
        has("polars") && has("pyarrow"),
        "this test needs python3 with polars and pyarrow (`python3 -m pip install polars pyarrow`; .ci/run \
         installs them)"
    );
    let dir = tempfile::tempdir().expect("tempdir");
    let run = dir.path().join("run");
    let run_s = run.to_str().expect("utf-8");
    ok(
        mimo(&["simulate", "--scenario", "1", "--runs", "2", "--duration", "60", "--out", run_s, "--quiet"]),
        "simulate",
    );
    ok(mimo(&["score", run_s, "--no-charts", "--quiet"]), "score");
    let schemas = repo().join("schemas");
    let o = Command::new("python3")
        .args(["-c", CHECK, run_s, schemas.to_str().expect("utf-8")])
        .output()
        .expect("python3 runs");
    assert!(o.status.success(), "polars could not read a table: {}", String::from_utf8_lossy(&o.stderr));
    let n: usize = String::from_utf8_lossy(&o.stdout).trim().parse().expect("file count");
    // Every Parquet file of the run and its score was read: the run tables of both runs (truth,
    // dwells, tracks and the rest) and every score table.
    fn count(dir: &Path) -> usize {
        std::fs::read_dir(dir)
            .expect("read_dir")
            .map(|e| e.expect("entry").path())
            .map(|p| if p.is_dir() { count(&p) } else { usize::from(p.extension().is_some_and(|e| e == "parquet")) })
            .sum()
    }
    assert_eq!(n, count(&run));
    assert!(n >= 2 * 3 + mimo_store::score_schema::SCORE_TABLES.len(), "only {n} Parquet files read");
}
