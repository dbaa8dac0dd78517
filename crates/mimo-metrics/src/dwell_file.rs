//! One dwells file reduced in one pass over its rows, as the dwells table's one reader gives them
//! ([`mimo_store::dwell_chunks`]: typed, checked, a row group at a time): the usage sums
//! ([`crate::dwell_sums`]) and, when asked, the usage by purpose's rows ([`crate::purpose`]).
//! The reader decodes the store's own files from their pages and any other layout with the
//! Arrow reader. A file whose values break a check gives `None`, and the caller reads it again
//! with the checked readers ([`crate::load`], [`crate::purpose`]), which name the file, column
//! and row in their documented order (docs/decisions/0299-one-pass-dwell-reader.md).

use crate::dwell_sums::{DwellSums, FilePass, Rows};
use crate::purpose::{FileRows, PurposeCols};
use mimo_store::dwell_chunks::{DwellChunk, DwellChunks, DwellField};
use std::collections::BTreeSet;
use std::path::Path;

/// The fields read, in this order: the usage sums' eight (`kind` only for its check), then the
/// usage by purpose's.
const FIELDS: [DwellField; 13] = [
    DwellField::Run,
    DwellField::Radar,
    DwellField::Role,
    DwellField::Kind,
    DwellField::RequestedBy,
    DwellField::TS,
    DwellField::DurationS,
    DwellField::EnergyJ,
    DwellField::GroupId,
    DwellField::Face,
    DwellField::BeamU,
    DwellField::BeamV,
    DwellField::AimM,
];

/// Fields the usage sums read (the first of [`FIELDS`]).
const SUMS_FIELDS: usize = 8;

/// The usage sums' columns of a chunk.
pub(crate) fn sums_rows(c: &DwellChunk) -> Rows<'_> {
    Rows {
        run: &c.run,
        radar: &c.radar,
        role: &c.role,
        requested_by: &c.requested_by,
        t_s: &c.t_s,
        duration_s: &c.duration_s,
        energy_j: &c.energy_j,
    }
}

/// The usage by purpose's columns of a chunk, its radars as indices in `radar_index`.
pub(crate) fn purpose_cols<'a>(c: &'a DwellChunk, radar_index: &'a [usize]) -> PurposeCols<'a> {
    PurposeCols {
        first_row: c.first_row,
        run: &c.run,
        group: &c.group_id,
        radar: radar_index,
        role: &c.role,
        kind: &c.kind,
        t_s: &c.t_s,
        duration_s: &c.duration_s,
        energy_j: &c.energy_j,
        face: &c.face,
        beam_u: &c.beam_u,
        beam_v: &c.beam_v,
        aim_m: [&c.aim_m[0], &c.aim_m[1], &c.aim_m[2]],
    }
}

/// One dwells file checked and reduced to its usage sums, the sums split every `slice_rows`
/// rows; `None` when a check fails.
pub(crate) fn file_sums(path: &Path, runs: &BTreeSet<u32>, interval_s: f64, slice_rows: usize) -> Option<DwellSums> {
    pass(path, runs, interval_s, slice_rows, None).map(|(sums, _)| sums)
}

/// [`file_sums`] and the file's rows for the usage by purpose, from one read.
pub(crate) fn file_pass(
    path: &Path,
    runs: &BTreeSet<u32>,
    interval_s: f64,
    slice_rows: usize,
) -> Option<(DwellSums, FileRows)> {
    let (sums, rows) = pass(path, runs, interval_s, slice_rows, Some(FileRows::default()))?;
    let mut rows = rows?;
    rows.set_radars(sums.radar_names.clone());
    Some((sums, rows))
}

/// The pass over the chunks of `path`: the usage sums, and the purpose rows if asked.
fn pass(
    path: &Path,
    runs: &BTreeSet<u32>,
    interval_s: f64,
    slice_rows: usize,
    mut purposes: Option<FileRows>,
) -> Option<(DwellSums, Option<FileRows>)> {
    let fields = if purposes.is_some() { &FIELDS[..] } else { &FIELDS[..SUMS_FIELDS] };
    let mut reader = DwellChunks::open(path, fields).ok()?;
    let mut pass = FilePass::new(runs, interval_s, slice_rows);
    let mut chunk = DwellChunk::default();
    let mut radar_index: Vec<usize> = Vec::new();
    while reader.next_chunk(&mut chunk).ok()? {
        pass.rows(&sums_rows(&chunk))?;
        if let Some(p) = &mut purposes {
            radar_index.clear();
            radar_index.extend(chunk.radar.iter().map(|&r| usize::from(r)));
            p.add(&purpose_cols(&chunk, &radar_index), interval_s);
        }
    }
    let names = reader.radars().iter().map(|r| r.to_string()).collect();
    Some((pass.finish(names), purposes))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use mimo_core::records::DwellRow;

    /// Dwells of run 3 across several row groups, every column the pass reads varied.
    pub(crate) fn rows(n: usize) -> Vec<DwellRow> {
        let t_s: Vec<f64> = (0..n).map(|i| 0.0137 * i as f64).collect();
        let mut rows = mimo_store::testing::varied_dwell_rows(3, &t_s);
        for (i, r) in rows.iter_mut().enumerate() {
            r.group_id = (i / 3) as u64 * 7;
            r.beam_u = 0.01 * ((i * 13) % 11) as f64 - 0.05;
            r.beam_v = -0.003 * ((i * 7) % 5) as f64;
            r.aim_x_m = 3.1e6 + 17.0 * i as f64;
            r.aim_y_m = -2.2e5;
            r.aim_z_m = 5.3e6 - 3.0 * i as f64;
        }
        rows
    }

    /// The one pass gives, bit for bit, the usage sums of the sums-only page pass and the purpose
    /// rows (search sums and kept parts) of the checked Arrow read, across pages and row groups
    /// of the store's own file.
    #[test]
    fn one_pass_equals_the_two_reads() {
        let dir = tempfile::tempdir().expect("tempdir");
        let rows = rows(2 * mimo_store::ROW_GROUP_ROWS + 700);
        let path = dir.path().join("run-0003.parquet");
        mimo_store::write_table(&path, &rows).expect("write");
        let runs = BTreeSet::from([3]);
        let (sums, fused) = file_pass(&path, &runs, 1.0, 5000).expect("the store's file takes the pass");
        let alone = file_sums(&path, &runs, 1.0, 5000).expect("sums alone");
        assert_eq!(format!("{sums:?}"), format!("{alone:?}"));
        let arrow = crate::purpose::read_rows(&path, 1.0).expect("checked read");
        assert_eq!(fused.view(), arrow.view());
        assert!(fused.view().contains("Track"), "non-search parts were kept");
    }

    /// A non-finite aim point, which only the usage by purpose reads, makes the pass give up, and
    /// the checked read names it.
    #[test]
    fn a_non_finite_aim_point_is_left_to_the_checked_read() {
        let dir = tempfile::tempdir().expect("tempdir");
        let mut rows = rows(3000);
        rows[2001].aim_y_m = f64::INFINITY;
        let path = dir.path().join("run-0003.parquet");
        mimo_store::write_table(&path, &rows).expect("write");
        let runs = BTreeSet::from([3]);
        assert!(file_sums(&path, &runs, 1.0, 5000).is_some(), "the usage sums do not read it");
        assert!(file_pass(&path, &runs, 1.0, 5000).is_none());
        let err = crate::purpose::read_rows(&path, 1.0).map(|_| ()).expect_err("non-finite");
        assert!(err.to_string().contains("aim_y_m"), "{err}");
    }
}
