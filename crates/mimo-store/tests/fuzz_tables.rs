//! Property tests of the table readers (docs/design.md §7): any bytes, or a valid file with bytes
//! changed, read as a table or as a one-line error — never a panic; rows that keep the table
//! rules read back as written. The cargo-fuzz target `table_reader` (fuzz/) runs the same reader
//! for longer.

use mimo_core::records::{TrackRow, TrackStatus};
use mimo_store::{read_table, write_table};
use proptest::prelude::*;

fn tracks(times: &[(u64, f64)]) -> Vec<TrackRow> {
    times
        .iter()
        .map(|&(id, t)| TrackRow {
            run: 0,
            t_s: t,
            track_id: id,
            status: TrackStatus::Confirmed,
            x_m: 1.0e6 + t,
            y_m: -4.0e6,
            z_m: 3.7e6,
            vx_mps: 1.0,
            vy_mps: 2.0,
            vz_mps: 3.0,
            cov: [0.5; 21],
            n_updates: 3,
            last_meas_id: if id % 2 == 0 { Some(id) } else { None },
        })
        .collect()
}

/// Rows that keep the rules: for each track, strictly increasing times.
fn valid_rows() -> impl Strategy<Value = Vec<TrackRow>> {
    prop::collection::vec((0u64..5, 0.0f64..1.0e4), 0..40).prop_map(|mut v| {
        v.sort_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
        v.dedup();
        tracks(&v)
    })
}

fn no_panic(path: &std::path::Path) {
    if let Err(e) = read_table::<TrackRow>(path) {
        assert!(!e.to_string().contains('\n'), "one line: {e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 128, ..ProptestConfig::default() })]

    #[test]
    fn valid_rows_round_trip(rows in valid_rows()) {
        let tmp = tempfile::tempdir().expect("tmp");
        let f = tmp.path().join("run-0000.parquet");
        write_table(&f, &rows).expect("write");
        prop_assert_eq!(read_table::<TrackRow>(&f).expect("read"), rows);
    }

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..2000)) {
        let tmp = tempfile::tempdir().expect("tmp");
        let f = tmp.path().join("run-0000.parquet");
        std::fs::write(&f, &bytes).expect("write");
        no_panic(&f);
    }

    #[test]
    fn mutated_files_never_panic(rows in valid_rows(), flips in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8)) {
        let tmp = tempfile::tempdir().expect("tmp");
        let f = tmp.path().join("run-0000.parquet");
        write_table(&f, &rows).expect("write");
        let mut bytes = std::fs::read(&f).expect("read");
        for (i, b) in flips {
            let i = i.index(bytes.len());
            bytes[i] = b;
        }
        std::fs::write(&f, &bytes).expect("write");
        no_panic(&f);
    }

    #[test]
    fn rows_out_of_order_are_refused(rows in valid_rows().prop_filter("two rows of one track", |r| {
        r.iter().any(|a| r.iter().filter(|b| b.track_id == a.track_id).count() > 1)
    })) {
        let mut rows = rows;
        rows.reverse();
        let tmp = tempfile::tempdir().expect("tmp");
        let f = tmp.path().join("run-0000.parquet");
        write_table(&f, &rows).expect("write");
        let e = read_table::<TrackRow>(&f).expect_err("out of order");
        prop_assert!(e.to_string().contains("column 't_s' row"), "{}", e);
    }
}
