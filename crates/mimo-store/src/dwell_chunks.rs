//! The dwells table read as typed, checked column chunks, one row group at a time: the one
//! streaming reader of the dwells table for the readers that need some columns of every row —
//! the scorer's usage sums and usage by purpose (`mimo-metrics`) and the key pass of `mimo track`
//! ([`crate::dwell_keys`]). Its memory is one chunk (a row group, [`crate::ROW_GROUP_ROWS`]
//! rows), whatever the run's length.
//!
//! Each chunk holds the columns asked for ([`DwellField`]) as typed values: labels parsed to
//! their enumerations ([`Role`], [`DwellKind`], [`Requester`]), radars as indices into
//! [`DwellChunks::radars`] (in order of first appearance in the file), numbers as they are
//! stored. Every value given has kept its column's rule (docs/design.md §3, §7): the spec's rule
//! (finite, non-negative, one of the labels, a radar id), every `run` the file's run, every
//! `t_s` within the run ([`crate::run_window`]).
//!
//! Two decoders give the same chunks:
//!
//! * the page decoder ([`crate::page_columns`]) for the layout the store's writer gives: no Arrow
//!   array, one zstd context for the whole file, each label recognised from its stored bytes in
//!   one comparison;
//! * the Arrow reader, with the checks of every typed read ([`crate::rows::Batch::check_values`]),
//!   for any other layout, and from the first row group the page decoder does not take or whose
//!   values break a rule on: so every refusal is the checked read's, naming the file, the column
//!   and the row (docs/decisions/0322-one-streaming-reader-of-the-dwells-table.md).
//!
//! The rules between rows (unique ids, times ordered per radar) are the reader's caller's: each
//! checks those it relies on as the rows stream by.

use crate::cell::Cell;
use crate::page_columns::{PageFile, PageRowGroup};
use crate::rows::Batch;
use crate::schema::{Rule, TableSpec};
use crate::stored_labels::{KeyCache, labels};
use crate::{StoreError, checked};
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellColumns, DwellKind, DwellRow, Requester, Role};
use parquet::arrow::ProjectionMask;
use parquet::arrow::arrow_reader::ParquetRecordBatchReader;
use std::path::{Path, PathBuf};

/// The dwells table's column names (from its declaration).
const D: DwellColumns = DwellRow::COLUMNS;

/// A column (or, for the aim point, three) of the dwells table a [`DwellChunks`] reader decodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DwellField {
    /// `run`.
    Run,
    /// `dwell_id`.
    DwellId,
    /// `group_id`.
    GroupId,
    /// `radar`, as an index into [`DwellChunks::radars`].
    Radar,
    /// `role`.
    Role,
    /// `kind`.
    Kind,
    /// `requested_by`.
    RequestedBy,
    /// `t_s`.
    TS,
    /// `duration_s`.
    DurationS,
    /// `energy_j`.
    EnergyJ,
    /// `face`.
    Face,
    /// `beam_u`.
    BeamU,
    /// `beam_v`.
    BeamV,
    /// `aim_x_m`, `aim_y_m`, `aim_z_m`.
    AimM,
}

impl DwellField {
    /// The table's columns the field is.
    fn columns(self) -> &'static [&'static str] {
        match self {
            DwellField::Run => &[D.run],
            DwellField::DwellId => &[D.dwell_id],
            DwellField::GroupId => &[D.group_id],
            DwellField::Radar => &[D.radar],
            DwellField::Role => &[D.role],
            DwellField::Kind => &[D.kind],
            DwellField::RequestedBy => &[D.requested_by],
            DwellField::TS => &[D.t_s],
            DwellField::DurationS => &[D.duration_s],
            DwellField::EnergyJ => &[D.energy_j],
            DwellField::Face => &[D.face],
            DwellField::BeamU => &[D.beam_u],
            DwellField::BeamV => &[D.beam_v],
            DwellField::AimM => &[D.aim_x_m, D.aim_y_m, D.aim_z_m],
        }
    }
}

/// Some consecutive rows of a dwells file: the columns asked for, each as long as the chunk
/// ([`DwellChunk::len`]); the others empty.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct DwellChunk {
    /// Index in the file of the chunk's first row.
    pub first_row: usize,
    /// `run`.
    pub run: Vec<u32>,
    /// `dwell_id`.
    pub dwell_id: Vec<u64>,
    /// `group_id`.
    pub group_id: Vec<u64>,
    /// `radar`: the index of each row's radar in [`DwellChunks::radars`].
    pub radar: Vec<u8>,
    /// `role`.
    pub role: Vec<Role>,
    /// `kind`.
    pub kind: Vec<DwellKind>,
    /// `requested_by`.
    pub requested_by: Vec<Requester>,
    /// `t_s` (s).
    pub t_s: Vec<f64>,
    /// `duration_s` (s).
    pub duration_s: Vec<f64>,
    /// `energy_j` (J).
    pub energy_j: Vec<f64>,
    /// `face`.
    pub face: Vec<u8>,
    /// `beam_u`.
    pub beam_u: Vec<f64>,
    /// `beam_v`.
    pub beam_v: Vec<f64>,
    /// `aim_x_m`, `aim_y_m`, `aim_z_m` (ECEF, m).
    pub aim_m: [Vec<f64>; 3],
    /// Rows in the chunk.
    len: usize,
}

impl DwellChunk {
    /// Rows in the chunk.
    pub fn len(&self) -> usize {
        self.len
    }

    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Row `r` appended to every column (a run's rows chunked in memory, as a reader of their
    /// file would give them), its radar as index `radar`. Inlined: a study run calls it for
    /// every dwell it makes, from another crate.
    #[inline]
    pub fn push(&mut self, r: &DwellRow, radar: u8) {
        self.run.push(r.run);
        self.dwell_id.push(r.dwell_id);
        self.group_id.push(r.group_id);
        self.radar.push(radar);
        self.role.push(r.role);
        self.kind.push(r.kind);
        self.requested_by.push(r.requested_by);
        self.t_s.push(r.t_s);
        self.duration_s.push(r.duration_s);
        self.energy_j.push(r.energy_j);
        self.face.push(r.face);
        self.beam_u.push(r.beam_u);
        self.beam_v.push(r.beam_v);
        self.aim_m[0].push(r.aim_x_m);
        self.aim_m[1].push(r.aim_y_m);
        self.aim_m[2].push(r.aim_z_m);
        self.len += 1;
    }

    /// Every column emptied, its capacity kept.
    pub fn clear(&mut self) {
        for v in [&mut self.group_id, &mut self.dwell_id] {
            v.clear();
        }
        for v in [&mut self.radar, &mut self.face] {
            v.clear();
        }
        for v in [&mut self.t_s, &mut self.duration_s, &mut self.energy_j, &mut self.beam_u, &mut self.beam_v] {
            v.clear();
        }
        for v in &mut self.aim_m {
            v.clear();
        }
        self.run.clear();
        self.role.clear();
        self.kind.clear();
        self.requested_by.clear();
        self.len = 0;
    }

    /// Whether every column asked for holds `n` rows.
    fn lengths_are(&self, fields: &[DwellField], n: usize) -> bool {
        fields.iter().all(|f| match f {
            DwellField::Run => self.run.len() == n,
            DwellField::DwellId => self.dwell_id.len() == n,
            DwellField::GroupId => self.group_id.len() == n,
            DwellField::Radar => self.radar.len() == n,
            DwellField::Role => self.role.len() == n,
            DwellField::Kind => self.kind.len() == n,
            DwellField::RequestedBy => self.requested_by.len() == n,
            DwellField::TS => self.t_s.len() == n,
            DwellField::DurationS => self.duration_s.len() == n,
            DwellField::EnergyJ => self.energy_j.len() == n,
            DwellField::Face => self.face.len() == n,
            DwellField::BeamU => self.beam_u.len() == n,
            DwellField::BeamV => self.beam_v.len() == n,
            DwellField::AimM => self.aim_m.iter().all(|v| v.len() == n),
        })
    }
}

/// The decoder in use.
enum Decoder {
    /// Pages of row groups from `next` on.
    Pages { file: PageFile, next: usize },
    /// The Arrow reader, batch by batch.
    Arrow(ParquetRecordBatchReader),
    /// Every row given.
    Done,
}

/// A dwells file read chunk by chunk ([`DwellChunks::next_chunk`]).
pub struct DwellChunks {
    path: PathBuf,
    spec: &'static TableSpec,
    fields: Vec<DwellField>,
    /// The columns read, in file order of the fields asked for.
    names: Vec<&'static str>,
    decoder: Decoder,
    first_row: usize,
    radars: Vec<RadarId>,
    /// The radar labels seen, by stored key: their index in `radars`.
    radar_keys: KeyCache<u8>,
    /// The file's run and the run's end (s), when the file is a run's.
    file_run: Option<u32>,
    end_s: Option<f64>,
    /// Whether the Arrow reader has given rows.
    arrow_used: bool,
    /// The rows the file's footer claims.
    num_rows: usize,
}

impl DwellChunks {
    /// Open the dwells file `path` for reading `fields`, after the checks of every reader
    /// ([`checked::open`]: the table's name and schema version, every column with its type).
    pub fn open(path: &Path, fields: &[DwellField]) -> Result<DwellChunks, StoreError> {
        let spec = checked::spec(DwellRow::TABLE)?;
        // The checks of every reader, before the first value is decoded.
        let num_rows = usize::try_from(checked::open(path, spec)?.metadata().file_metadata().num_rows()).unwrap_or(0);
        let mut fields = fields.to_vec();
        fields.dedup();
        let names: Vec<&'static str> = fields.iter().flat_map(|f| f.columns().iter().copied()).collect();
        let decoder = match PageFile::open(path, &names) {
            Some(file) => Decoder::Pages { file, next: 0 },
            None => Decoder::Arrow(arrow_reader(path, spec, &names, 0)?),
        };
        Ok(DwellChunks {
            path: path.to_path_buf(),
            spec,
            fields,
            names,
            decoder,
            first_row: 0,
            radars: Vec::new(),
            radar_keys: KeyCache::default(),
            file_run: crate::invariants::file_run(path),
            end_s: crate::run_window::run_end_s(path),
            arrow_used: false,
            num_rows,
        })
    }

    /// The rows the file's footer claims (for sizing what is kept of them; the chunks give
    /// the rows there are).
    pub fn num_rows(&self) -> usize {
        self.num_rows
    }

    /// The radars named so far, in order of first appearance: a chunk's `radar` indexes them.
    pub fn radars(&self) -> &[RadarId] {
        &self.radars
    }

    /// Whether the rows so far came from the page decoder alone (for tests of the layouts).
    pub fn pages_only(&self) -> bool {
        !self.arrow_used
    }

    /// The next rows into `chunk` (its columns cleared first, their capacity kept); `false` when
    /// every row has been given. An error names the file, the column and the row.
    pub fn next_chunk(&mut self, chunk: &mut DwellChunk) -> Result<bool, StoreError> {
        chunk.clear();
        loop {
            match std::mem::replace(&mut self.decoder, Decoder::Done) {
                Decoder::Done => return Ok(false),
                Decoder::Pages { file, next } => {
                    if next >= file.num_row_groups() {
                        continue;
                    }
                    let radars_before = self.radars.len();
                    let decoded = file.row_group(next).and_then(|rg| self.page_chunk(&rg, chunk));
                    if decoded.is_some() {
                        self.decoder = Decoder::Pages { file, next: next + 1 };
                        chunk.first_row = self.first_row;
                        self.first_row += chunk.len;
                        return Ok(true);
                    }
                    // The checked read from this row group on: it names what broke, or takes
                    // a layout the page decoder does not.
                    self.radars.truncate(radars_before);
                    self.radar_keys = KeyCache::default();
                    chunk.clear();
                    self.decoder = Decoder::Arrow(arrow_reader(&self.path, self.spec, &self.names, next)?);
                }
                Decoder::Arrow(mut reader) => {
                    let Some(batch) = reader.next() else { continue };
                    self.decoder = Decoder::Arrow(reader);
                    self.arrow_used = true;
                    let batch = batch.map_err(|e| parquet_err(&self.path, e))?;
                    let b = Batch::check_values(&batch, &self.path, self.spec, self.first_row)?;
                    arrow_chunk(&b, &self.fields, &mut self.radars, chunk)?;
                    chunk.len = batch.num_rows();
                    chunk.first_row = self.first_row;
                    self.first_row += chunk.len;
                    return Ok(true);
                }
            }
        }
    }

    /// One row group's columns from its pages, checked; `None` when a page is not of the
    /// layout decoded or a value breaks a rule.
    fn page_chunk(&mut self, rg: &PageRowGroup<'_>, chunk: &mut DwellChunk) -> Option<()> {
        let n = rg.num_rows()?;
        let mut col = 0;
        for i in 0..self.fields.len() {
            let f = self.fields[i];
            match f {
                DwellField::Run => {
                    rg.u32s(col, &mut chunk.run)?;
                    if let Some(run) = self.file_run
                        && chunk.run.iter().any(|&r| r != run)
                    {
                        return None;
                    }
                }
                DwellField::DwellId => rg.u64s(col, &mut chunk.dwell_id)?,
                DwellField::GroupId => rg.u64s(col, &mut chunk.group_id)?,
                DwellField::Face => rg.u8s(col, &mut chunk.face)?,
                DwellField::Radar => self.radar_labels(rg, col, &mut chunk.radar)?,
                DwellField::Role => labels(rg, col, &mut chunk.role)?,
                DwellField::Kind => labels(rg, col, &mut chunk.kind)?,
                DwellField::RequestedBy => labels(rg, col, &mut chunk.requested_by)?,
                DwellField::TS => {
                    self.f64s(rg, col, &mut chunk.t_s)?;
                    if let Some(end) = self.end_s
                        && crate::run_window::first_after_end(&chunk.t_s, end, 0).is_some()
                    {
                        return None;
                    }
                }
                DwellField::DurationS => self.f64s(rg, col, &mut chunk.duration_s)?,
                DwellField::EnergyJ => self.f64s(rg, col, &mut chunk.energy_j)?,
                DwellField::BeamU => self.f64s(rg, col, &mut chunk.beam_u)?,
                DwellField::BeamV => self.f64s(rg, col, &mut chunk.beam_v)?,
                DwellField::AimM => {
                    for (k, aim) in chunk.aim_m.iter_mut().enumerate() {
                        self.f64s(rg, col + k, aim)?;
                    }
                }
            }
            col += f.columns().len();
        }
        chunk.lengths_are(&self.fields, n).then_some(())?;
        chunk.len = n;
        Some(())
    }

    /// A float column's values, kept to its column's rule.
    fn f64s(&self, rg: &PageRowGroup<'_>, col: usize, out: &mut Vec<f64>) -> Option<()> {
        rg.f64s(col, out)?;
        let rule = self.spec.columns.iter().find(|c| Some(&c.name) == self.names.get(col)).map(|c| c.rule)?;
        let min = match rule {
            Rule::Any => return Some(()),
            Rule::Finite => f64::NEG_INFINITY,
            Rule::NonNegative => 0.0,
            Rule::Positive => f64::MIN_POSITIVE,
            _ => return None,
        };
        // Finite and at least `min` (NaN fails both comparisons); folded without a branch.
        let mut bad = false;
        for x in out.iter() {
            bad |= !((*x >= min) & (*x < f64::INFINITY));
        }
        (!bad).then_some(())
    }

    /// The radar column as indices into `radars` (a new radar appended; at most 255).
    fn radar_labels(&mut self, rg: &PageRowGroup<'_>, col: usize, out: &mut Vec<u8>) -> Option<()> {
        out.clear();
        let (radars, cache) = (&mut self.radars, &mut self.radar_keys);
        rg.keyed_strs(col, |key, bytes| {
            let index = match key.and_then(|k| cache.get(k)) {
                Some(index) => index,
                None => {
                    let id = RadarId::parse(std::str::from_utf8(bytes).ok()?)?;
                    let index = match radars.iter().position(|r| *r == id) {
                        Some(i) => i,
                        None => {
                            radars.push(id);
                            radars.len() - 1
                        }
                    };
                    let index = u8::try_from(index).ok()?;
                    if let Some(k) = key {
                        cache.insert(k, index);
                    }
                    index
                }
            };
            out.push(index);
            Some(())
        })
    }
}

/// A checked batch's columns into `chunk`.
fn arrow_chunk(
    b: &Batch<'_>,
    fields: &[DwellField],
    radars: &mut Vec<RadarId>,
    chunk: &mut DwellChunk,
) -> Result<(), StoreError> {
    for &f in fields {
        match f {
            DwellField::Run => chunk.run = u32::read(b, D.run)?,
            DwellField::DwellId => chunk.dwell_id = u64::read(b, D.dwell_id)?,
            DwellField::GroupId => chunk.group_id = u64::read(b, D.group_id)?,
            DwellField::Face => chunk.face = u8::read(b, D.face)?,
            DwellField::Radar => {
                let ids = RadarId::read(b, D.radar)?;
                chunk.radar.clear();
                for id in ids {
                    let index = match radars.iter().position(|r| *r == id) {
                        Some(i) => i,
                        None => {
                            radars.push(id);
                            radars.len() - 1
                        }
                    };
                    let index = u8::try_from(index).map_err(|_| StoreError::BadColumn {
                        file: b.file.to_path_buf(),
                        column: D.radar.to_string(),
                        why: "names more than 255 radars".to_string(),
                    })?;
                    chunk.radar.push(index);
                }
            }
            DwellField::Role => chunk.role = Role::read(b, D.role)?,
            DwellField::Kind => chunk.kind = DwellKind::read(b, D.kind)?,
            DwellField::RequestedBy => chunk.requested_by = Requester::read(b, D.requested_by)?,
            DwellField::TS => chunk.t_s = f64::read(b, D.t_s)?,
            DwellField::DurationS => chunk.duration_s = f64::read(b, D.duration_s)?,
            DwellField::EnergyJ => chunk.energy_j = f64::read(b, D.energy_j)?,
            DwellField::BeamU => chunk.beam_u = f64::read(b, D.beam_u)?,
            DwellField::BeamV => chunk.beam_v = f64::read(b, D.beam_v)?,
            DwellField::AimM => {
                for (aim, name) in chunk.aim_m.iter_mut().zip([D.aim_x_m, D.aim_y_m, D.aim_z_m]) {
                    *aim = f64::read(b, name)?;
                }
            }
        }
    }
    Ok(())
}

fn parquet_err(path: &Path, e: impl std::fmt::Display) -> StoreError {
    StoreError::Parquet { path: path.to_path_buf(), why: e.to_string() }
}

/// The Arrow reader of columns `names` of `path`, from row group `first_group` on.
fn arrow_reader(
    path: &Path,
    spec: &'static TableSpec,
    names: &[&'static str],
    first_group: usize,
) -> Result<ParquetRecordBatchReader, StoreError> {
    let builder = checked::open(path, spec)?;
    let groups: Vec<usize> = (first_group..builder.metadata().num_row_groups()).collect();
    let mask = ProjectionMask::columns(builder.parquet_schema(), names.iter().copied());
    builder
        .with_projection(mask)
        .with_row_groups(groups)
        .with_batch_size(crate::ROW_GROUP_ROWS)
        .build()
        .map_err(|e| parquet_err(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::varied_dwell_rows;

    const ALL: [DwellField; 14] = [
        DwellField::Run,
        DwellField::DwellId,
        DwellField::GroupId,
        DwellField::Radar,
        DwellField::Role,
        DwellField::Kind,
        DwellField::RequestedBy,
        DwellField::TS,
        DwellField::DurationS,
        DwellField::EnergyJ,
        DwellField::Face,
        DwellField::BeamU,
        DwellField::BeamV,
        DwellField::AimM,
    ];

    /// Every chunk of `path` read with `fields`, the rows rebuilt from them with the radars
    /// named, and whether the pages alone gave them.
    fn read_all(path: &Path, fields: &[DwellField]) -> Result<(Vec<DwellChunk>, Vec<RadarId>, bool), StoreError> {
        let mut r = DwellChunks::open(path, fields)?;
        let mut out = Vec::new();
        let mut c = DwellChunk::default();
        while r.next_chunk(&mut c)? {
            out.push(c.clone());
        }
        Ok((out, r.radars().to_vec(), r.pages_only()))
    }

    fn rows(n: usize) -> Vec<DwellRow> {
        let t: Vec<f64> = (0..n).map(|i| 0.0137 * i as f64).collect();
        varied_dwell_rows(0, &t)
    }

    /// The store's own file decodes from its pages to the rows written, chunk by chunk and
    /// row group by row group.
    #[test]
    fn the_stores_file_round_trips_through_its_pages() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        let rows = rows(2 * crate::ROW_GROUP_ROWS + 300);
        crate::write_table(&path, &rows).expect("write");
        let (chunks, radars, pages) = read_all(&path, &ALL).expect("read");
        assert!(pages, "the store's layout is decoded from its pages");
        assert_eq!(chunks.len(), 3);
        assert_eq!(chunks.iter().map(|c| c.len()).sum::<usize>(), rows.len());
        let mut i = 0;
        for c in &chunks {
            assert_eq!(c.first_row, i);
            for k in 0..c.len() {
                let r = &rows[i];
                assert_eq!((c.run[k], c.dwell_id[k], c.group_id[k]), (r.run, r.dwell_id, r.group_id));
                assert_eq!(radars[usize::from(c.radar[k])], r.radar);
                assert_eq!((c.role[k], c.kind[k], c.requested_by[k]), (r.role, r.kind, r.requested_by));
                assert_eq!((c.t_s[k], c.duration_s[k], c.energy_j[k]), (r.t_s, r.duration_s, r.energy_j));
                assert_eq!((c.face[k], c.beam_u[k], c.beam_v[k]), (r.face, r.beam_u, r.beam_v));
                assert_eq!([c.aim_m[0][k], c.aim_m[1][k], c.aim_m[2][k]], [r.aim_x_m, r.aim_y_m, r.aim_z_m]);
                i += 1;
            }
        }
        // Only the fields asked for are filled.
        let (some, _, _) = read_all(&path, &[DwellField::TS]).expect("read t_s");
        assert!(some[0].run.is_empty() && some[0].t_s.len() == some[0].len());
    }

    /// A file of another layout (dictionary pages, other page sizes) gives the same chunks'
    /// values through the Arrow reader.
    #[test]
    fn another_layout_gives_the_same_values() {
        use parquet::arrow::ArrowWriter;
        use parquet::file::properties::WriterProperties;
        let dir = tempfile::tempdir().expect("tempdir");
        let rows = rows(5000);
        let ours = dir.path().join("run-0000.parquet");
        crate::write_table(&ours, &rows).expect("write");
        let batch = crate::rows::to_batch(&rows).expect("batch");
        let schema = std::sync::Arc::new(crate::schema::DWELLS.arrow_schema());
        let batch = arrow::record_batch::RecordBatch::try_new(schema.clone(), batch.columns().to_vec()).expect("b");
        let other_dir = dir.path().join("other");
        std::fs::create_dir_all(&other_dir).expect("dir");
        let other = other_dir.join("run-0000.parquet");
        let props = WriterProperties::builder().set_dictionary_enabled(true).set_max_row_group_row_count(Some(999));
        let mut w = ArrowWriter::try_new(std::fs::File::create(&other).expect("f"), schema, Some(props.build()))
            .expect("writer");
        w.write(&batch).expect("write");
        w.close().expect("close");
        let (a, ra, pages_a) = read_all(&ours, &ALL).expect("ours");
        let (b, rb, pages_b) = read_all(&other, &ALL).expect("other");
        assert!(pages_a && !pages_b);
        assert_eq!(ra, rb);
        let flat = |cs: &[DwellChunk]| {
            let mut all = DwellChunk::default();
            for c in cs {
                all.t_s.extend(&c.t_s);
                all.radar.extend(&c.radar);
                all.role.extend(&c.role);
                all.kind.extend(&c.kind);
                all.dwell_id.extend(&c.dwell_id);
                all.aim_m[2].extend(&c.aim_m[2]);
            }
            all
        };
        assert_eq!(flat(&a), flat(&b));
    }

    /// A value that breaks a rule is refused with the checked read's error: file, column, row.
    #[test]
    fn a_broken_value_is_named_by_file_column_and_row() {
        let dir = tempfile::tempdir().expect("tempdir");
        let path = dir.path().join("run-0000.parquet");
        let mut rows = rows(crate::ROW_GROUP_ROWS + 50);
        rows[crate::ROW_GROUP_ROWS + 7].energy_j = -1.0;
        crate::write_table(&path, &rows).expect("write");
        let e = read_all(&path, &ALL).map(|_| ()).expect_err("negative energy").to_string();
        let row = crate::ROW_GROUP_ROWS + 7;
        assert!(e.contains("energy_j") && e.contains(&format!("row {row}")), "{e}");
        // A row of another run in run 0's file.
        let mut other = self::rows(100);
        let path = dir.path().join("run-0001.parquet");
        other.iter_mut().enumerate().for_each(|(i, r)| r.run = if i == 30 { 2 } else { 1 });
        crate::write_table(&path, &other).expect("write");
        let e = read_all(&path, &[DwellField::Run]).map(|_| ()).expect_err("another run").to_string();
        assert!(e.contains("run") && e.contains("row 30"), "{e}");
        // Not read at all: a beam that is not finite, when the beams are not asked for.
        let mut beams = self::rows(100);
        beams[3].beam_u = f64::NAN;
        let path = dir.path().join("run-0002.parquet");
        beams.iter_mut().for_each(|r| r.run = 2);
        crate::write_table(&path, &beams).expect("write");
        assert!(read_all(&path, &[DwellField::TS]).is_ok());
        let e = read_all(&path, &ALL).map(|_| ()).expect_err("NaN beam").to_string();
        assert!(e.contains("beam_u") && e.contains("row 3"), "{e}");
    }
}
