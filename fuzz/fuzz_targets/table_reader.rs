//! Any bytes as a Parquet file to every typed table reader: rows or a one-line error, never a
//! panic. Seed the corpus with real files (`cp RUN/*/run-0000.parquet fuzz/corpus/table_reader/`).
#![no_main]

use libfuzzer_sys::fuzz_target;
use mimo_core::records::*;
use mimo_store::read_table;

fuzz_target!(|data: &[u8]| {
    let dir = std::env::temp_dir().join(format!("mimo-fuzz-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let f = dir.join("run-0000.parquet");
    if std::fs::write(&f, data).is_err() {
        return;
    }
    let errs = [
        read_table::<TruthRow>(&f).err().map(|e| e.to_string()),
        read_table::<DwellRow>(&f).err().map(|e| e.to_string()),
        read_table::<PrimitiveRow>(&f).err().map(|e| e.to_string()),
        read_table::<MeasurementRow>(&f).err().map(|e| e.to_string()),
        read_table::<TrackRow>(&f).err().map(|e| e.to_string()),
        read_table::<VoltageRow>(&f).err().map(|e| e.to_string()),
    ];
    for e in errs.into_iter().flatten() {
        assert!(!e.contains('\n'));
    }
});
