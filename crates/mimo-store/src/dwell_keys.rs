//! The dwells table read in two passes, for re-runs (`mimo track`, docs/design.md §2).
//!
//! A re-run delivers only the dwell groups its test article subscribes to (by default those
//! with a detection or ordered by the test article: a few percent of the rows). The first pass,
//! [`read_dwell_keys`], decodes with the dwells table's one reader ([`crate::dwell_chunks`]) the
//! columns that decide which rows those are (run, ids, radar, face, requester) and `t_s`, for
//! every row, and checks the table's rules on them
//! (docs/design.md §7: unique `dwell_id`, times ordered per radar, one run per file) exactly as
//! [`crate::read_table`] does; it keeps the key columns only (about 23 bytes a row, sized once
//! from the file's row count). The second, [`read_dwell_rows`], decodes whole rows only for the
//! rows asked for, with the same column checks (types, nulls, finite values, categories) on
//! those rows.

use crate::cell::Cell;
use crate::dwell_chunks::{DwellChunk, DwellChunks, DwellField};
use crate::rows::{Batch, TableRow};
use crate::{StoreError, invariants, schema};
use arrow::array::BooleanArray;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellColumns, DwellKind, DwellRow, Requester, Role};
use mimo_core::table_rules::{Key2, runs_match, times_ordered_per_key, unique};
use parquet::arrow::ProjectionMask;
use parquet::arrow::arrow_reader::{ParquetRecordBatchReaderBuilder, RowSelection, RowSelectionPolicy};
use std::fs::File;
use std::path::Path;

/// The key columns of every row of a dwells file, in file order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DwellKeys {
    /// `run`.
    pub run: Vec<u32>,
    /// `dwell_id`.
    pub dwell_id: Vec<u64>,
    /// `group_id`.
    pub group_id: Vec<u64>,
    /// `radar`.
    pub radar: Vec<RadarId>,
    /// `face`.
    pub face: Vec<u8>,
    /// `requested_by`.
    pub requested_by: Vec<Requester>,
}

impl DwellKeys {
    /// Empty columns with room for `n_rows` rows (a file's claimed count: room is taken only
    /// while it can be had, and columns grow past it as rows come).
    fn with_capacity(n_rows: usize) -> DwellKeys {
        let mut k = DwellKeys::default();
        let _ = (k.run.try_reserve_exact(n_rows), k.dwell_id.try_reserve_exact(n_rows));
        let _ = (k.group_id.try_reserve_exact(n_rows), k.radar.try_reserve_exact(n_rows));
        let _ = (k.face.try_reserve_exact(n_rows), k.requested_by.try_reserve_exact(n_rows));
        k
    }

    /// Number of rows.
    pub fn len(&self) -> usize {
        self.run.len()
    }

    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.run.is_empty()
    }
}

/// Gaps of at most this many rows between rows asked for are read and dropped rather than
/// skipped (a skip and a new read cost about as much as decoding a few rows in every column).
const READ_THROUGH_GAP_ROWS: usize = 16;

/// The dwells table's column names (from its declaration).
const C: DwellColumns = DwellRow::COLUMNS;
/// The columns [`DwellKeys`] holds.
const KEY_COLUMNS: [&str; 6] = [C.run, C.dwell_id, C.group_id, C.radar, C.face, C.requested_by];
/// The fields the first pass reads (with the dwells table's one reader): the keys, and `t_s`
/// for the rule on times (checked, then dropped: the second pass reads it again for the rows
/// asked for).
const FIRST_PASS_FIELDS: [DwellField; 7] = [
    DwellField::Run,
    DwellField::DwellId,
    DwellField::GroupId,
    DwellField::Radar,
    DwellField::Face,
    DwellField::RequestedBy,
    DwellField::TS,
];

/// The columns of a dwells row that are not keys, in file order.
fn rest_columns() -> impl Iterator<Item = &'static str> {
    DwellRow::COLUMN_NAMES.iter().copied().filter(|c| !KEY_COLUMNS.contains(c))
}

/// The dwells file opened and its whole schema checked against the table's spec.
fn open_checked(
    path: &Path,
) -> Result<(ParquetRecordBatchReaderBuilder<File>, &'static schema::TableSpec), StoreError> {
    let builder = crate::open_table::<DwellRow>(path)?;
    let spec = schema::table(DwellRow::SPEC.name)
        .ok_or_else(|| StoreError::Arrow(format!("unknown table {}", DwellRow::SPEC.name)))?;
    // Every column present with its type (checked by `open_table`); the values are checked as
    // they are read.
    Ok((builder, spec))
}

fn parquet_err(path: &Path) -> impl Fn(parquet::errors::ParquetError) -> StoreError + '_ {
    move |e| StoreError::Parquet { path: path.to_path_buf(), why: e.to_string() }
}

/// Read the key columns of every row of one dwells file and check the table's rules on them.
/// The columns are sized once from the file's row count, so a re-run holds them and nothing
/// beside them.
pub fn read_dwell_keys(path: &Path) -> Result<DwellKeys, StoreError> {
    let mut reader = DwellChunks::open(path, &FIRST_PASS_FIELDS)?;
    let n_rows = reader.num_rows();
    let mut k = DwellKeys::with_capacity(n_rows);
    let mut t_s: Vec<f64> = Vec::new();
    let _ = t_s.try_reserve_exact(n_rows);
    let mut c = DwellChunk::default();
    while reader.next_chunk(&mut c)? {
        k.run.extend_from_slice(&c.run);
        k.dwell_id.extend_from_slice(&c.dwell_id);
        k.group_id.extend_from_slice(&c.group_id);
        let radars = reader.radars();
        k.radar.extend(c.radar.iter().map(|&r| radars[usize::from(r)]));
        k.face.extend_from_slice(&c.face);
        k.requested_by.extend_from_slice(&c.requested_by);
        t_s.extend_from_slice(&c.t_s);
    }
    // The rules of `invariants` for `DwellRow`, on the same values.
    let to_err = |v: mimo_core::table_rules::Violation| StoreError::BadRow {
        file: path.to_path_buf(),
        column: v.column,
        row: v.row,
        why: v.why,
    };
    if let Some(run) = invariants::file_run(path) {
        runs_match(&k.run, run).map_err(to_err)?;
    }
    ids_unique(&k).map_err(to_err)?;
    times_ordered_per_key(k.run.iter().zip(&k.radar).map(|(&r, &d)| Key2(r, d)), &t_s, false, C.radar)
        .map_err(to_err)?;
    Ok(k)
}

/// The rule that (`run`, `dwell_id`) is unique, at four bytes a row: file positions sorted by
/// key and neighbours compared. A repeat is named by [`unique`], the rule's own check, so the
/// message is `read_table`'s.
fn ids_unique(k: &DwellKeys) -> Result<(), mimo_core::table_rules::Violation> {
    let n = k.len().min(k.dwell_id.len());
    let key = |i: usize| (k.run[i], k.dwell_id[i]);
    if (1..n).all(|i| key(i - 1) < key(i)) {
        return Ok(());
    }
    let repeats = match u32::try_from(n) {
        Ok(n32) => {
            let mut order: Vec<u32> = (0..n32).collect();
            order.sort_unstable_by_key(|&i| key(i as usize));
            order.windows(2).any(|w| key(w[0] as usize) == key(w[1] as usize))
        }
        Err(_) => true,
    };
    if repeats {
        unique(k.run.iter().zip(&k.dwell_id).map(|(&r, &d)| Key2(r, d)), C.dwell_id)?;
    }
    Ok(())
}

/// The file positions `rows` (of a file of `n_rows` rows) as ranges to read; a short gap between
/// two positions is read through and its rows dropped after the read (decoding a few rows costs
/// less than a skip and a new read in every column). Errors ([`StoreError::BadRow`]) on a
/// position past the end or out of order.
fn read_ranges(path: &Path, rows: &[usize], n_rows: usize) -> Result<Vec<std::ops::Range<usize>>, StoreError> {
    let bad = |row: usize, why: &str| StoreError::BadRow {
        file: path.to_path_buf(),
        column: C.dwell_id,
        row,
        why: why.to_string(),
    };
    if let Some(w) = rows.windows(2).find(|w| w[1] <= w[0]) {
        return Err(bad(w[1], "rows asked for out of order"));
    }
    if let Some(&last) = rows.last()
        && last >= n_rows
    {
        return Err(bad(last, "row asked for past the end of the file"));
    }
    let mut ranges: Vec<std::ops::Range<usize>> = Vec::new();
    for &r in rows {
        match ranges.last_mut() {
            Some(last) if r <= last.end + READ_THROUGH_GAP_ROWS => last.end = r + 1,
            _ => ranges.push(r..r + 1),
        }
    }
    Ok(ranges)
}

/// Read whole rows of one dwells file: the rows at the given file positions (ascending), in file
/// order. `keys` are the file's keys ([`read_dwell_keys`]); only the other columns are decoded.
/// Errors ([`StoreError::BadRow`]) on a position past the end or out of order.
pub fn read_dwell_rows(path: &Path, keys: &DwellKeys, rows: &[usize]) -> Result<Vec<DwellRow>, StoreError> {
    let (builder, spec) = open_checked(path)?;
    let n_rows = usize::try_from(builder.metadata().file_metadata().num_rows()).unwrap_or(0);
    let ranges = read_ranges(path, rows, n_rows.min(keys.len()))?;
    // The file positions of the rows the reader returns, in order, and which were asked for.
    let mut positions = ranges.clone().into_iter().flatten();
    let mut asked = rows.iter().peekable();
    let selection = RowSelection::from_consecutive_ranges(ranges.into_iter(), n_rows);
    // Selectors (skip runs of rows), not a mask over decoded rows: the rows asked for are few.
    let mask = ProjectionMask::columns(builder.parquet_schema(), rest_columns());
    let reader = builder
        .with_projection(mask)
        .with_row_selection(selection)
        .with_row_selection_policy(RowSelectionPolicy::Selectors)
        .build()
        .map_err(parquet_err(path))?;
    let mut out = Vec::with_capacity(rows.len());
    let mut at = rows.iter();
    for batch in reader {
        let batch = batch.map_err(|e| StoreError::Parquet { path: path.to_path_buf(), why: e.to_string() })?;
        let keep: Vec<bool> = (0..batch.num_rows())
            .map(|_| {
                let p = positions.next();
                let wanted = p.is_some() && asked.peek().copied().copied() == p;
                if wanted {
                    asked.next();
                }
                wanted
            })
            .collect();
        // Only the rows asked for are checked and delivered, as if the gaps had been skipped.
        let batch = if keep.iter().all(|&k| k) {
            batch
        } else {
            arrow::compute::filter_record_batch(&batch, &BooleanArray::from(keep))
                .map_err(|e| StoreError::Parquet { path: path.to_path_buf(), why: e.to_string() })?
        };
        let b = Batch::check_values_at(&batch, path, spec, &rows[out.len()..])?;
        // The checks of `DwellRow::from_batch`, column by column, on the rows read.
        let (role, kind, t) = (Role::read(&b, C.role)?, DwellKind::read(&b, C.kind)?, f64::read(&b, C.t_s)?);
        let (dur, pw, np) = (f64::read(&b, C.duration_s)?, f64::read(&b, C.pulse_width_s)?, u32::read(&b, C.n_pulses)?);
        let (pp, e, wf) = (f64::read(&b, C.peak_power_w)?, f64::read(&b, C.energy_j)?, u32::read(&b, C.waveform)?);
        let (bu, bv) = (f64::read(&b, C.beam_u)?, f64::read(&b, C.beam_v)?);
        let (ax, ay, az) = (f64::read(&b, C.aim_x_m)?, f64::read(&b, C.aim_y_m)?, f64::read(&b, C.aim_z_m)?);
        for i in 0..role.len() {
            let Some(&k) = at.next() else { break };
            out.push(DwellRow {
                run: keys.run[k],
                dwell_id: keys.dwell_id[k],
                group_id: keys.group_id[k],
                radar: keys.radar[k],
                role: role[i],
                kind: kind[i],
                requested_by: keys.requested_by[k],
                t_s: t[i],
                duration_s: dur[i],
                pulse_width_s: pw[i],
                n_pulses: np[i],
                peak_power_w: pp[i],
                energy_j: e[i],
                waveform: wf[i],
                face: keys.face[k],
                beam_u: bu[i],
                beam_v: bv[i],
                aim_x_m: ax[i],
                aim_y_m: ay[i],
                aim_z_m: az[i],
            });
        }
    }
    if out.len() != rows.len() {
        return Err(StoreError::Parquet {
            path: path.to_path_buf(),
            why: format!("{} dwell rows read for {} asked for", out.len(), rows.len()),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(i: u64) -> DwellRow {
        DwellRow {
            run: 0,
            dwell_id: 100 + i,
            group_id: 50 + i / 2,
            radar: RadarId::parse(if i.is_multiple_of(3) { "R1" } else { "R2" }).expect("radar"),
            role: Role::Txrx,
            kind: DwellKind::Search,
            requested_by: if i.is_multiple_of(4) { Requester::Ta } else { Requester::Radar },
            t_s: i as f64 * 0.5,
            duration_s: 0.01,
            pulse_width_s: 1e-5,
            n_pulses: 1 + i as u32,
            peak_power_w: 1e5,
            energy_j: 1.0,
            waveform: 0,
            face: (i % 4) as u8,
            beam_u: 0.01 * i as f64,
            beam_v: -0.02 * i as f64,
            aim_x_m: 1.0,
            aim_y_m: 2.0,
            aim_z_m: i as f64,
        }
    }

    /// Keys and selected rows round-trip what was written, across row groups.
    #[test]
    fn keys_and_selected_rows_round_trip() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        let n = crate::ROW_GROUP_ROWS as u64 + 300;
        let rows: Vec<DwellRow> = (0..n).map(row).collect();
        crate::write_table(&path, &rows).expect("write");
        let k = read_dwell_keys(&path).expect("keys");
        assert_eq!(k.len(), rows.len());
        for (i, r) in rows.iter().enumerate() {
            assert_eq!(
                (k.run[i], k.dwell_id[i], k.group_id[i], k.radar[i], k.face[i], k.requested_by[i]),
                (r.run, r.dwell_id, r.group_id, r.radar, r.face, r.requested_by)
            );
        }
        let pick: Vec<usize> = vec![0, 1, 2, 7, 1000, 1001, crate::ROW_GROUP_ROWS - 1, crate::ROW_GROUP_ROWS + 5];
        let got = read_dwell_rows(&path, &k, &pick).expect("rows");
        let want: Vec<DwellRow> = pick.iter().map(|&i| rows[i].clone()).collect();
        assert_eq!(got, want);
        assert!(read_dwell_rows(&path, &k, &[3, 2]).is_err());
        assert!(read_dwell_rows(&path, &k, &[n as usize]).is_err());
    }

    /// Rows asked for across read-through gaps (shorter than `READ_THROUGH_GAP_ROWS`), skipped
    /// gaps and batch and row-group boundaries come back exactly, and only they.
    #[test]
    fn rows_across_read_through_gaps_round_trip() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        let n = crate::ROW_GROUP_ROWS + 3000;
        let rows: Vec<DwellRow> = (0..n as u64).map(row).collect();
        crate::write_table(&path, &rows).expect("write");
        let k = read_dwell_keys(&path).expect("keys");
        let gap = READ_THROUGH_GAP_ROWS;
        // Every third row for a while, then gaps at and just past the read-through length.
        let mut pick: Vec<usize> = (0..3000).step_by(3).collect();
        pick.extend([3000 + gap, 3001 + 2 * gap, 3003 + 3 * gap + 1, n - 2000, n - 1]);
        let got = read_dwell_rows(&path, &k, &pick).expect("rows");
        let want: Vec<DwellRow> = pick.iter().map(|&i| rows[i].clone()).collect();
        assert_eq!(got, want);
    }

    /// Ids a few rows out of place (as dwells are written in end order) pass the rule on unique
    /// ids; a repeat far from its first row is named as `read_table` names it.
    #[test]
    fn ids_out_of_place_are_unique_and_a_far_repeat_is_named() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        let mut rows: Vec<DwellRow> = (0..3000).map(row).collect();
        for i in (0..2990).step_by(7) {
            let (a, b) = (rows[i].dwell_id, rows[i + 3].dwell_id);
            (rows[i].dwell_id, rows[i + 3].dwell_id) = (b, a);
        }
        crate::write_table(&path, &rows).expect("write");
        let k = read_dwell_keys(&path).expect("unique ids out of place");
        assert_eq!(k.dwell_id, rows.iter().map(|r| r.dwell_id).collect::<Vec<_>>());
        rows[2900].dwell_id = rows[15].dwell_id;
        rows[2950].dwell_id = rows[10].dwell_id;
        crate::write_table(&path, &rows).expect("write");
        let a = read_dwell_keys(&path).expect_err("repeated id").to_string();
        let b = crate::read_table::<DwellRow>(&path).expect_err("repeated id").to_string();
        assert_eq!(a, b);
        assert!(a.contains("row 2900"), "{a}");
    }

    /// The keys pass refuses what `read_table` refuses, with the same message.
    #[test]
    fn keys_check_the_table_rules() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        let mut rows: Vec<DwellRow> = (0..10).map(row).collect();
        rows[4].dwell_id = rows[2].dwell_id;
        crate::write_table(&path, &rows).expect("write");
        let a = read_dwell_keys(&path).expect_err("repeated id").to_string();
        let b = crate::read_table::<DwellRow>(&path).expect_err("repeated id").to_string();
        assert_eq!(a, b);
        assert!(a.contains("row 4"), "{a}");
        let mut rows: Vec<DwellRow> = (0..10).map(row).collect();
        rows[6].t_s = 0.0;
        crate::write_table(&path, &rows).expect("write");
        let a = read_dwell_keys(&path).expect_err("time back").to_string();
        let b = crate::read_table::<DwellRow>(&path).expect_err("time back").to_string();
        assert_eq!(a, b);
    }
}
