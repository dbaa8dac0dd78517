//! One table file written as its rows arrive (docs/design.md §8): rows are held until
//! [`CHUNK_ROWS`] have come, then encoded into the open Parquet file, so a writer holds at most a
//! chunk of rows plus the encoded pages of the row group being filled ([`crate::ROW_GROUP_ROWS`]
//! rows at most) — flat in the run's length.
//!
//! The file is written under a temporary name (`.NAME.tmp`) in a directory that must exist (a
//! staging directory removed on interrupt is never re-created) and renamed by [`TableWriter::finish`];
//! a writer dropped unfinished, or whose `finish` failed (a full disk), removes its temporary file,
//! and the temporary file is registered with the interrupt handler (`crate::output`), which
//! removes it on SIGINT/SIGTERM wherever it is (a study writes its cells in place).
//! Chunks are a whole number of the Parquet writer's mini-batches (1024 rows), so the bytes are the
//! ones a single write of all the rows gives.

use crate::rows::{TableRow, to_batch};
use crate::{StoreError, WriteMode, writer_props_for};
use parquet::arrow::ArrowWriter;
use std::fs::File;
use std::path::{Path, PathBuf};

/// Rows a writer holds before encoding them (a multiple of the Parquet writer's 1024-row
/// mini-batch).
pub const CHUNK_ROWS: usize = 8 * 1024;

/// A table file being written, row by row.
pub struct TableWriter<R: TableRow> {
    path: PathBuf,
    tmp: PathBuf,
    writer: ArrowWriter<File>,
    held: Vec<R>,
    rows: u64,
    finished: bool,
}

impl<R: TableRow> TableWriter<R> {
    /// Start writing table `R` at `path` (its directory must exist), to be kept.
    pub fn create(path: &Path) -> Result<TableWriter<R>, StoreError> {
        TableWriter::create_for(path, WriteMode::Kept)
    }

    /// Start writing table `R` at `path` (its directory must exist) for `mode`
    /// ([`WriteMode::Scratch`]: read back once and deleted).
    pub fn create_for(path: &Path, mode: WriteMode) -> Result<TableWriter<R>, StoreError> {
        let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
        let tmp = path.with_file_name(format!(".{name}.tmp"));
        let write_err = |why: String| StoreError::Write { path: path.to_path_buf(), why };
        let schema = std::sync::Arc::new(R::SPEC.arrow_schema());
        let file = crate::output::create_registered(&tmp)?;
        let writer =
            ArrowWriter::try_new(file, schema.clone(), Some(writer_props_for(&schema, mode))).map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                crate::output::unregister(&tmp);
                write_err(e.to_string())
            })?;
        Ok(TableWriter {
            path: path.to_path_buf(),
            tmp,
            writer,
            held: Vec::with_capacity(CHUNK_ROWS),
            rows: 0,
            finished: false,
        })
    }

    fn write_err(&self, why: String) -> StoreError {
        StoreError::Write { path: self.path.clone(), why }
    }

    /// Encode the first `n` held rows.
    fn encode(&mut self, n: usize) -> Result<(), StoreError> {
        let batch = to_batch(&self.held[..n])?;
        self.writer.write(&batch).map_err(|e| self.write_err(e.to_string()))?;
        self.held.drain(..n);
        Ok(())
    }

    /// Encode every whole chunk held.
    fn drain_chunks(&mut self) -> Result<(), StoreError> {
        while self.held.len() >= CHUNK_ROWS {
            self.encode(CHUNK_ROWS)?;
        }
        // A large batch of rows (a run's truth) leaves no large buffer behind.
        if self.held.capacity() > 2 * CHUNK_ROWS {
            self.held.shrink_to(CHUNK_ROWS);
        }
        Ok(())
    }

    /// Add one row.
    pub fn push(&mut self, row: R) -> Result<(), StoreError> {
        self.held.push(row);
        self.rows += 1;
        self.drain_chunks()
    }

    /// Add rows, in order.
    pub fn extend(&mut self, rows: Vec<R>) -> Result<(), StoreError> {
        self.rows += rows.len() as u64;
        self.held.extend(rows);
        self.drain_chunks()
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Encode what is held, close the file and give it its name; returns the number of rows.
    pub fn finish(mut self) -> Result<u64, StoreError> {
        if !self.held.is_empty() {
            self.encode(self.held.len())?;
        }
        self.writer.finish().map_err(|e| self.write_err(e.to_string()))?;
        std::fs::rename(&self.tmp, &self.path).map_err(|e| self.write_err(e.to_string()))?;
        crate::output::unregister(&self.tmp);
        self.finished = true;
        Ok(self.rows)
    }
}

impl<R: TableRow> Drop for TableWriter<R> {
    fn drop(&mut self) {
        if !self.finished {
            let _ = std::fs::remove_file(&self.tmp);
            crate::output::unregister(&self.tmp);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::records::TruthRow;

    #[test]
    fn a_writer_dropped_unfinished_leaves_no_temporary_file() {
        let tmp = tempfile::tempdir().expect("tmp");
        let path = tmp.path().join("run-0000.parquet");
        let w = TableWriter::<TruthRow>::create(&path).expect("create");
        assert!(tmp.path().join(".run-0000.parquet.tmp").exists(), "written under its temporary name");
        drop(w);
        assert_eq!(std::fs::read_dir(tmp.path()).expect("ls").count(), 0, "nothing left");
        let w = TableWriter::<TruthRow>::create(&path).expect("create");
        assert_eq!(w.finish().expect("finish"), 0);
        let names: Vec<_> = std::fs::read_dir(tmp.path()).expect("ls").flatten().map(|e| e.file_name()).collect();
        assert_eq!(names, ["run-0000.parquet"], "only the finished file");
    }
}
