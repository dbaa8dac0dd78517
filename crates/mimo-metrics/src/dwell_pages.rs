//! The columns of a dwells file decoded straight from its Parquet pages, in one pass that feeds
//! the usage sums ([`crate::dwell_sums`]) and, when asked, the usage by purpose
//! ([`crate::purpose`]), by the store's page decoder ([`mimo_store::page_columns`], which lives
//! beside the writer settings it depends on, is checked against them and decompresses with one
//! zstd context per file). Each label is mapped to its index from its stored bytes' key in one
//! comparison, so no string is built. A file of another layout gives `None`, and it is read with
//! the Arrow reader instead ([`crate::dwell_read`], [`crate::purpose_read`]), as is a file whose
//! values break a check.

use crate::dwell_sums::{DwellSums, FilePass, Labels, Rows};
use crate::purpose::{FileRows, PurposeCols};
use mimo_core::records::{DwellColumns, DwellKind, DwellRow, Role};
use mimo_store::page_columns::{PageFile, PageRowGroup};
use std::collections::BTreeSet;
use std::path::Path;

/// The dwells table's column names (from its declaration).
const D: DwellColumns = DwellRow::COLUMNS;

/// The columns read, in this order: the usage sums' eight, then the usage by purpose's.
const COLUMNS: [&str; 15] = [
    D.run,
    D.radar,
    D.role,
    D.kind,
    D.requested_by,
    D.t_s,
    D.duration_s,
    D.energy_j,
    D.group_id,
    D.face,
    D.beam_u,
    D.beam_v,
    D.aim_x_m,
    D.aim_y_m,
    D.aim_z_m,
];

/// Columns the usage sums read (the first of [`COLUMNS`]).
const SUMS_COLUMNS: usize = 8;

/// A utf8 column mapped to label indices; `None` on a string `labels` refuses (or that is not
/// UTF-8).
fn labels(rg: &PageRowGroup<'_>, col: usize, labels: &mut Labels, out: &mut Vec<u8>) -> Option<()> {
    out.clear();
    let mut last: Option<(u128, u8)> = None;
    rg.keyed_strs(col, |key, bytes| {
        let index = match (key, last) {
            (Some(k), Some((l, index))) if k == l => index,
            _ => {
                let index = match key.and_then(|k| labels.by_view(k)) {
                    Some(index) => index,
                    None => labels.index(std::str::from_utf8(bytes).ok()?, key)?,
                };
                last = key.map(|k| (k, index));
                index
            }
        };
        out.push(index);
        Some(())
    })
}

/// The columns of one row group (or of a chunk of rows in memory, [`crate::dwell_rows`]), reused
/// from row group to row group.
#[derive(Default)]
pub(crate) struct Buffers {
    pub(crate) run: Vec<u32>,
    pub(crate) radar: Vec<u8>,
    pub(crate) role: Vec<u8>,
    pub(crate) kind: Vec<u8>,
    pub(crate) by: Vec<u8>,
    pub(crate) t_s: Vec<f64>,
    pub(crate) duration_s: Vec<f64>,
    pub(crate) energy_j: Vec<f64>,
    pub(crate) group: Vec<u64>,
    pub(crate) face: Vec<u8>,
    pub(crate) beam_u: Vec<f64>,
    pub(crate) beam_v: Vec<f64>,
    pub(crate) aim_m: [Vec<f64>; 3],
    pub(crate) radar_index: Vec<usize>,
    pub(crate) roles: Vec<Role>,
    pub(crate) kinds: Vec<DwellKind>,
}

impl Buffers {
    /// The columns the usage sums read.
    pub(crate) fn sums_rows(&self) -> Rows<'_> {
        Rows {
            run: &self.run,
            radar: &self.radar,
            role: &self.role,
            requested_by: &self.by,
            t_s: &self.t_s,
            duration_s: &self.duration_s,
            energy_j: &self.energy_j,
        }
    }

    /// The columns the usage by purpose reads, the first of them row `first_row` of the file.
    pub(crate) fn purpose_cols(&self, first_row: usize) -> PurposeCols<'_> {
        PurposeCols {
            first_row,
            run: &self.run,
            group: &self.group,
            radar: &self.radar_index,
            role: &self.roles,
            kind: &self.kinds,
            t_s: &self.t_s,
            duration_s: &self.duration_s,
            energy_j: &self.energy_j,
            face: &self.face,
            beam_u: &self.beam_u,
            beam_v: &self.beam_v,
            aim_m: [&self.aim_m[0], &self.aim_m[1], &self.aim_m[2]],
        }
    }

    /// Every column emptied, its capacity kept.
    pub(crate) fn clear(&mut self) {
        for v in [&mut self.radar, &mut self.role, &mut self.kind, &mut self.by, &mut self.face] {
            v.clear();
        }
        for v in [&mut self.t_s, &mut self.duration_s, &mut self.energy_j, &mut self.beam_u, &mut self.beam_v] {
            v.clear();
        }
        for v in &mut self.aim_m {
            v.clear();
        }
        self.run.clear();
        self.group.clear();
        self.radar_index.clear();
        self.roles.clear();
        self.kinds.clear();
    }
}

/// The rows of a row group added to the usage by purpose.
struct Purposes {
    rows: FileRows,
    interval_s: f64,
    /// The role and kind of each label index (the labels' fixed lists).
    roles: Vec<Role>,
    kinds: Vec<DwellKind>,
}

/// One dwells file checked and reduced to its usage sums from its pages, the sums split every
/// `slice_rows` rows as [`crate::dwell_read`] splits them; `None` when the file has another
/// layout or a check fails.
pub(crate) fn file_sums(path: &Path, runs: &BTreeSet<u32>, interval_s: f64, slice_rows: usize) -> Option<DwellSums> {
    pass(path, runs, interval_s, slice_rows, None).map(|(sums, _)| sums)
}

/// [`file_sums`] and the file's rows for the usage by purpose, from one read of its pages (every
/// column the usage by purpose reads checked as its checked read checks it: floats finite).
pub(crate) fn file_pass(
    path: &Path,
    runs: &BTreeSet<u32>,
    interval_s: f64,
    slice_rows: usize,
) -> Option<(DwellSums, FileRows)> {
    let purposes = Purposes {
        rows: FileRows::default(),
        interval_s,
        roles: Role::LABELS.iter().map(|l| Role::parse(l)).collect::<Option<_>>()?,
        kinds: DwellKind::LABELS.iter().map(|l| DwellKind::parse(l)).collect::<Option<_>>()?,
    };
    let (sums, purposes) = pass(path, runs, interval_s, slice_rows, Some(purposes))?;
    let mut rows = purposes?.rows;
    rows.set_radars(sums.radar_names.clone());
    Some((sums, rows))
}

/// The pass over the row groups of `path`: the usage sums, and the purpose rows if asked.
fn pass(
    path: &Path,
    runs: &BTreeSet<u32>,
    interval_s: f64,
    slice_rows: usize,
    mut purposes: Option<Purposes>,
) -> Option<(DwellSums, Option<Purposes>)> {
    let names = if purposes.is_some() { &COLUMNS[..] } else { &COLUMNS[..SUMS_COLUMNS] };
    let file = PageFile::open(path, names)?;
    let end_s = mimo_store::run_window::run_end_s(path);
    let mut pass = FilePass::new(runs, interval_s, slice_rows);
    let mut b = Buffers::default();
    let mut first_row = 0;
    for g in 0..file.num_row_groups() {
        let rg = file.row_group(g)?;
        rg.u32s(0, &mut b.run)?;
        labels(&rg, 1, &mut pass.radar, &mut b.radar)?;
        labels(&rg, 2, &mut pass.role, &mut b.role)?;
        labels(&rg, 3, &mut pass.kind, &mut b.kind)?;
        labels(&rg, 4, &mut pass.requested_by, &mut b.by)?;
        rg.f64s(5, &mut b.t_s)?;
        // A time after the run's end is a check failing: the Arrow reader reports it.
        if end_s.is_some_and(|end| mimo_store::run_window::first_after_end(&b.t_s, end, 0).is_some()) {
            return None;
        }
        rg.f64s(6, &mut b.duration_s)?;
        rg.f64s(7, &mut b.energy_j)?;
        let n = rg.num_rows()?;
        if b.run.len() != n || b.kind.len() != n {
            return None;
        }
        pass.rows(&b.sums_rows())?;
        if let Some(p) = &mut purposes {
            purpose_rows(&rg, &mut b, p, first_row, n)?;
        }
        first_row += n;
    }
    Some((pass.finish(), purposes))
}

/// The purpose columns of a row group (the usage sums' already in `b`) decoded, checked and
/// added to `p`.
fn purpose_rows(rg: &PageRowGroup<'_>, b: &mut Buffers, p: &mut Purposes, first_row: usize, n: usize) -> Option<()> {
    rg.u64s(8, &mut b.group)?;
    rg.u8s(9, &mut b.face)?;
    rg.f64s(10, &mut b.beam_u)?;
    rg.f64s(11, &mut b.beam_v)?;
    for (k, aim) in b.aim_m.iter_mut().enumerate() {
        rg.f64s(12 + k, aim)?;
    }
    let lens = [b.group.len(), b.face.len(), b.beam_u.len(), b.beam_v.len(), b.aim_m[0].len()];
    if lens.iter().chain(&[b.aim_m[1].len(), b.aim_m[2].len()]).any(|&l| l != n) {
        return None;
    }
    // Finite, as the checked read of these columns requires (the others are checked by the
    // usage sums' pass).
    let mut bad = false;
    for v in [&b.beam_u, &b.beam_v, &b.aim_m[0], &b.aim_m[1], &b.aim_m[2]] {
        for x in v.iter() {
            bad |= !x.is_finite();
        }
    }
    if bad {
        return None;
    }
    b.radar_index.clear();
    b.radar_index.extend(b.radar.iter().map(|&r| usize::from(r)));
    b.roles.clear();
    for &r in &b.role {
        b.roles.push(*p.roles.get(usize::from(r))?);
    }
    b.kinds.clear();
    for &k in &b.kind {
        b.kinds.push(*p.kinds.get(usize::from(k))?);
    }
    p.rows.add(&b.purpose_cols(first_row), p.interval_s);
    Some(())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

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
