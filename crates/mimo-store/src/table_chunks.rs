//! A run table read as typed, checked rows, a chunk at a time: the one reader of every run table
//! (`R` is the table's row record, [`TableRow`], generated from its declaration in
//! `mimo_core::records`). [`crate::read_table`] is this reader's rows collected; `mimo track`,
//! `mimo plot` and `mimo score` read the tables through it (the dwells of the score's usage pass
//! and of re-runs' key pass through their column reader, [`crate::dwell_chunks`]).
//!
//! What a chunk holds has passed every check of a typed read, in this order:
//!
//! 1. when the file is opened ([`checked::open`]): the table name and schema version in its
//!    metadata, its column chunks, every column of the spec with exactly its type;
//! 2. each chunk's values ([`Batch::check_from`]): nulls, the column's rule, `run` the file's
//!    run, times within the run;
//! 3. each chunk's rows against the table's rules ([`crate::invariants`]) after the rows before
//!    them: unique ids, ordered times.
//!
//! Errors name the file, the column and the row in the file; the rows of a chunk are given only
//! when all of them passed. Memory is one chunk ([`crate::ROW_GROUP_ROWS`] rows) plus what the
//! rules keep (each unique key, each key's latest time), whatever the file's length.

use crate::rows::{Batch, TableRow};
use crate::schema::TableSpec;
use crate::{ROW_GROUP_ROWS, StoreError, checked};
use arrow::array::RecordBatch;
use parquet::arrow::arrow_reader::ParquetRecordBatchReader;
use std::path::{Path, PathBuf};

/// One file of a run table, read chunk by chunk ([`TableChunks::next_chunk`]).
pub struct TableChunks<R: TableRow> {
    path: PathBuf,
    spec: &'static TableSpec,
    reader: ParquetRecordBatchReader,
    num_rows: usize,
    rows_read: usize,
    rules: R::Rules,
}

fn parquet_err(path: &Path, e: impl std::fmt::Display) -> StoreError {
    StoreError::Parquet { path: path.to_path_buf(), why: e.to_string() }
}

impl<R: TableRow> TableChunks<R> {
    /// Open `path` as a file of `R`'s table, checked (step 1 above).
    pub fn open(path: &Path) -> Result<TableChunks<R>, StoreError> {
        let spec = crate::schema::table(R::SPEC.name)
            .ok_or_else(|| StoreError::Arrow(format!("unknown table {}", R::SPEC.name)))?;
        let builder = checked::open(path, spec)?;
        let rows = builder.metadata().file_metadata().num_rows();
        let num_rows = usize::try_from(rows).map_err(|_| parquet_err(path, format!("the footer gives {rows} rows")))?;
        let reader = builder.with_batch_size(ROW_GROUP_ROWS).build().map_err(|e| parquet_err(path, e))?;
        Ok(TableChunks { path: path.to_path_buf(), spec, reader, num_rows, rows_read: 0, rules: R::Rules::default() })
    }

    /// The file's rows, from its footer.
    pub fn num_rows(&self) -> usize {
        self.num_rows
    }

    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The next rows of the file, checked; `None` after the last.
    pub fn next_chunk(&mut self) -> Result<Option<Vec<R>>, StoreError> {
        let Some(batch) = self.next_batch()? else {
            return Ok(None);
        };
        Ok(Some(R::from_batch(&self.view(&batch))?))
    }

    /// The next rows of the file as a checked Arrow batch (every check of
    /// [`TableChunks::next_chunk`], no row built): for a reader that wants columns, through
    /// [`TableChunks::view`]. `None` after the last.
    pub fn next_batch(&mut self) -> Result<Option<RecordBatch>, StoreError> {
        let Some(batch) = self.reader.next() else {
            return Ok(None);
        };
        let batch = batch.map_err(|e| parquet_err(&self.path, e))?;
        let b = Batch::check_from(&batch, &self.path, self.spec, self.rows_read)?;
        R::check_chunk(&mut self.rules, self.rows_read, &b)?;
        self.rows_read += b.num_rows();
        Ok(Some(batch))
    }

    /// A batch given by [`TableChunks::next_batch`] with its typed accessors ([`Batch`]'s
    /// `f64_values`, `utf8`, …).
    pub fn view<'a>(&'a self, batch: &'a RecordBatch) -> Batch<'a> {
        Batch { batch, file: &self.path, spec: self.spec }
    }

    /// Every remaining row, checked.
    pub fn rest(mut self) -> Result<Vec<R>, StoreError> {
        let mut out = Vec::with_capacity(self.num_rows.saturating_sub(self.rows_read));
        while let Some(rows) = self.next_chunk()? {
            out.extend(rows);
        }
        Ok(out)
    }
}

impl<R: TableRow> Iterator for TableChunks<R> {
    type Item = Result<Vec<R>, StoreError>;

    fn next(&mut self) -> Option<Self::Item> {
        self.next_chunk().transpose()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::records::{DwellRow, TruthRow};

    fn truth(n: usize) -> Vec<TruthRow> {
        (0..n)
            .map(|i| TruthRow {
                run: 0,
                t_s: (i / 3) as f64,
                target: format!("F{}", i % 3),
                x_m: i as f64,
                y_m: 2.0,
                z_m: 3.0,
                vx_mps: 200.0,
                vy_mps: 0.0,
                vz_mps: 0.0,
                lat_deg: 10.0,
                lon_deg: 20.0,
                alt_m: 1000.0,
                rcs_m2: 5.0,
            })
            .collect()
    }

    /// A file of several chunks comes back as written, chunk by chunk, each at most a row group.
    #[test]
    fn chunks_return_the_rows_written() {
        let dir = tempfile::tempdir().expect("tmp");
        let path = dir.path().join("run-0000.parquet");
        let rows = truth(ROW_GROUP_ROWS * 2 + 7);
        crate::write_table(&path, &rows).expect("write");
        let mut chunks = TableChunks::<TruthRow>::open(&path).expect("open");
        assert_eq!(chunks.num_rows(), rows.len());
        let mut back = Vec::new();
        let mut n_chunks = 0;
        while let Some(c) = chunks.next_chunk().expect("chunk") {
            assert!(!c.is_empty() && c.len() <= ROW_GROUP_ROWS);
            back.extend(c);
            n_chunks += 1;
        }
        assert_eq!(n_chunks, 3);
        assert_eq!(back, rows);
        assert_eq!(crate::read_table::<TruthRow>(&path).expect("read"), rows);
    }

    /// A rule broken across chunks — an id repeated a row group later, a target's time running
    /// back at the first row of the next chunk — is named at its row in the file.
    #[test]
    fn a_rule_broken_across_chunks_names_its_row() {
        let dir = tempfile::tempdir().expect("tmp");
        let path = dir.path().join("run-0000.parquet");
        let t: Vec<f64> = (0..ROW_GROUP_ROWS + 100).map(|i| i as f64 * 0.01).collect();
        let mut dwells = crate::testing::varied_dwell_rows(0, &t);
        let at = ROW_GROUP_ROWS + 50;
        dwells[at].dwell_id = 3;
        crate::write_table(&path, &dwells).expect("write");
        let e = TableChunks::<DwellRow>::open(&path).expect("open").rest().expect_err("repeat").to_string();
        assert!(e.contains(&format!("row {at}")) && e.contains("repeats row 3") && e.contains("dwell_id"), "{e}");

        let mut rows = truth(ROW_GROUP_ROWS + 30);
        rows[ROW_GROUP_ROWS].t_s = 0.0;
        crate::write_table(&path, &rows).expect("write");
        let mut chunks = TableChunks::<TruthRow>::open(&path).expect("open");
        assert_eq!(chunks.next_chunk().expect("first chunk is sound").map(|c| c.len()), Some(ROW_GROUP_ROWS));
        let e = chunks.next_chunk().expect_err("time back").to_string();
        assert!(e.contains(&format!("row {}", ROW_GROUP_ROWS)) && e.contains("t_s"), "{e}");
    }
}
