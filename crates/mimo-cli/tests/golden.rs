//! Behaviour guard: the content of a short recorded run, hashed table by table, must not change
//! when the code is only restructured.
//!
//! The hashes cover every column of every row as text (Arrow's display of each value; floats in
//! their shortest round-trip form), so they do not depend on how Parquet encodes the columns.
//! When a change is *meant* to alter the recording (a new physics option made default, a better
//! test article), re-bless with `MIMO_BLESS=1 cargo test -p mimo-cli --test golden` and say in the
//! commit why the numbers moved.

mod common;

use arrow::util::display::{ArrayFormatter, FormatOptions};
use common::mimo;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::collections::BTreeMap;
use std::path::Path;

const GOLDEN: &str = "tests/golden_hashes.json";

/// FNV-1a over the text of every value, column by column in schema order, row by row.
fn content_hash(path: &Path) -> String {
    let file = std::fs::File::open(path).expect("open table");
    let reader = ParquetRecordBatchReaderBuilder::try_new(file).expect("parquet").build().expect("reader");
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for b in bytes {
            h ^= u64::from(*b);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    };
    let mut rows = 0usize;
    let opts = FormatOptions::default().with_null("null");
    for batch in reader {
        let batch = batch.expect("batch");
        let schema = batch.schema();
        let fmts: Vec<ArrayFormatter> =
            batch.columns().iter().map(|c| ArrayFormatter::try_new(c.as_ref(), &opts).expect("formatter")).collect();
        for r in 0..batch.num_rows() {
            for (f, field) in fmts.iter().zip(schema.fields()) {
                eat(field.name().as_bytes());
                eat(b"=");
                eat(f.value(r).to_string().as_bytes());
                eat(b";");
            }
            eat(b"\n");
        }
        rows += batch.num_rows();
    }
    format!("{rows} rows, {h:016x}")
}

fn hashes_of(dir: &Path, label: &str, out: &mut BTreeMap<String, String>) {
    let mut tables: Vec<_> = std::fs::read_dir(dir).expect("run dir").filter_map(|e| e.ok()).collect();
    tables.sort_by_key(|e| e.file_name());
    for t in tables {
        if !t.path().is_dir() || t.file_name().to_string_lossy().starts_with('.') || t.file_name() == "score" {
            continue;
        }
        let mut files: Vec<_> = std::fs::read_dir(t.path()).expect("table dir").filter_map(|e| e.ok()).collect();
        files.sort_by_key(|e| e.file_name());
        for f in files {
            let key = format!("{label}/{}/{}", t.file_name().to_string_lossy(), f.file_name().to_string_lossy());
            out.insert(key, content_hash(&f.path()));
        }
    }
}

#[test]
fn a_short_recording_keeps_its_content() {
    let tmp = tempfile::tempdir().expect("tempdir");
    let sim = tmp.path().join("s7");
    let s = sim.to_str().expect("utf-8");
    assert_eq!(mimo(&["simulate", "--scenario", "7", "--runs", "2", "--duration", "60", "--quiet", "--out", s]), 0);
    let imm = tmp.path().join("s7-imm");
    let i = imm.to_str().expect("utf-8");
    assert_eq!(mimo(&["track", s, "--tracker", "imm", "--quiet", "--out", i]), 0);
    let cued = tmp.path().join("s1-cued");
    let c = cued.to_str().expect("utf-8");
    let args = ["simulate", "--scenario", "1", "--duration", "4", "--tracker", "cued", "--record", "voltages"];
    let mut args = args.to_vec();
    args.extend(["--quiet", "--out", c]);
    assert_eq!(mimo(&args), 0);

    let mut got = BTreeMap::new();
    hashes_of(&sim, "simulate-s7-default", &mut got);
    hashes_of(&imm, "track-s7-imm", &mut got);
    hashes_of(&cued, "simulate-s1-cued", &mut got);

    let golden = Path::new(env!("CARGO_MANIFEST_DIR")).join(GOLDEN);
    if std::env::var_os("MIMO_BLESS").is_some() {
        let text = serde_json::to_string_pretty(&got).expect("json") + "\n";
        std::fs::write(&golden, text).expect("write golden hashes");
        return;
    }
    let want: BTreeMap<String, String> =
        serde_json::from_str(&std::fs::read_to_string(&golden).expect("golden hashes file")).expect("golden json");
    let mut diffs = Vec::new();
    for k in want.keys().chain(got.keys()).collect::<std::collections::BTreeSet<_>>() {
        if want.get(k) != got.get(k) {
            diffs.push(format!("{k}: expected {:?}, got {:?}", want.get(k), got.get(k)));
        }
    }
    assert!(diffs.is_empty(), "recorded content changed:\n{}", diffs.join("\n"));
}
