//! # mimo-store
//!
//! The only crate that touches Arrow and Parquet. It owns:
//!
//! * [`schema`]: the table specs (name, type, unit, meaning, rule and storage of each column).
//!   Every table is declared once (`mimo_core::table_decl`): the run tables in
//!   `mimo_core::records`, the score tables in [`score_schema`], the study tables in
//!   [`study_schema`], [`challenge_schema`] and [`failure_point_schema`]; [`run_tables`],
//!   [`score_schema`] and the study modules expand those declarations into specs ([`cell`]: what
//!   a Rust type is on disk). The Arrow schemas, the `schemas/*.json` files, the readers' checks
//!   and the Parquet writer's per-column settings derive from the specs.
//! * [`rows`]: row records ⇄ Arrow record batches (the conversions generated in [`run_tables`]);
//!   [`columns`]: tables written column by column (score and study tables, their conversions
//!   generated from their declarations too).
//! * Parquet I/O ([`write_table`], [`read_table`], [`read_table_dir`]): files are written to a
//!   temporary name and renamed, carry the table name and schema version in their key-value
//!   metadata, and are byte-identical for identical rows (no timestamps, row groups of
//!   [`ROW_GROUP_ROWS`] rows, layout fixed by the writer properties).
//! * [`layout`]: every path of a run directory and a study directory (no other crate joins a
//!   table or file name onto a path); [`rundir`]: the run directory of docs/design.md §2 —
//!   staging, atomic publication, and [`manifest::Manifest`]; [`output`]: who may write an output
//!   path (`--force`, the lock, stale staging, clean-up on interrupt), with [`recognise`] telling
//!   what mimo wrote by content; [`lineage`]: `parent` links of `mimo track` outputs.
//! * [`table_writer`]: a table file written as its rows come; [`run_sink::ParquetRunSink`]: a
//!   run's tables written that way, the sink of `mimo simulate`, `mimo track` and a study's runs
//!   (memory flat in the run's length).
//! * [`invariants`]: the rules checked on every typed read (unique ids, ordered times, runs).
//! * [`table_chunks`]: the streaming reader of every run table: typed rows a chunk at a time,
//!   each value and each rule between rows checked as they come ([`read_table`] collects it).
//! * [`dwell_chunks`]: the dwells table's streaming reader: typed, checked column chunks a row
//!   group at a time, from the pages of the store's layout or with the Arrow reader (the score's
//!   one pass over the dwells, the key pass of re-runs).
//! * [`dwell_keys`]: the dwells table read in two passes for re-runs: every row's keys, then
//!   whole rows only where asked.
//! * [`page_columns`]: columns decoded straight from the Parquet pages of the layout
//!   the writer settings give (checked against them by its tests), for one-pass readers.

#![warn(missing_docs)]

pub mod cell;
pub mod challenge_schema;
pub mod checked;
pub mod columns;
pub mod dwell_chunks;
pub mod dwell_keys;
pub mod failure_point_schema;
pub mod invariants;
pub mod layout;
pub mod lineage;
pub mod manifest;
pub mod output;
pub mod page_columns;
mod page_delta;
pub mod recognise;
pub mod rows;
pub mod run_sink;
pub mod run_tables;
pub mod run_window;
pub mod rundir;
pub mod schema;
pub mod score_schema;
mod stored_labels;
pub mod study_schema;
pub mod table_chunks;
pub mod table_writer;
#[doc(hidden)]
pub mod testing;

/// `mimo-core`, for the table generators' expansions in other crates.
#[doc(hidden)]
pub use mimo_core as core_crate;

use arrow::array::RecordBatch;
use parquet::arrow::ArrowWriter;
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use parquet::basic::Compression;
use parquet::file::properties::WriterProperties;
use rows::TableRow;
use std::fs::File;
use std::path::{Path, PathBuf};

/// Errors of the storage layer. Each names the file (and column) concerned.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// An I/O operation other than writing an output failed (opening, reading or listing a file
    /// or directory, taking the output lock): a fault of the system.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or directory the operation was on.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Writing an output failed (disk full, permissions): a fault of the system, not the input.
    #[error("{}: write failed: {why}", path.display())]
    Write {
        /// The file being written.
        path: PathBuf,
        /// What failed (the underlying I/O or Parquet writer error).
        why: String,
    },
    /// A file that should hold a table cannot be read as Parquet (corrupt, truncated, not
    /// Parquet), raised when opening it or decoding its record batches.
    #[error("{}: not a readable Parquet file ({why})", path.display())]
    Parquet {
        /// The file read.
        path: PathBuf,
        /// The Parquet reader's error.
        why: String,
    },
    /// A column of a table file is missing, has the wrong Arrow type, holds nulls where none are
    /// allowed, or holds a NaN or ∞ (docs/design.md §3).
    #[error("{}: column '{column}' {why}", file.display())]
    BadColumn {
        /// The file read.
        file: PathBuf,
        /// The column's name.
        column: String,
        /// What is wrong with it.
        why: String,
    },
    /// A Parquet file holds another table than the one asked for, was not written by mimo (no
    /// `mimo.table` metadata), or has another schema version.
    #[error("{}: {why}", file.display())]
    BadTable {
        /// The file read.
        file: PathBuf,
        /// What is wrong with it.
        why: String,
    },
    /// A row breaks a table rule (docs/design.md §7): duplicate ids, times out of order, a run
    /// other than the file's.
    #[error("{}: column '{column}' row {row}: {why}", file.display())]
    BadRow {
        /// The file read.
        file: PathBuf,
        /// The column whose value breaks the rule.
        column: &'static str,
        /// The offending row's index in the file, from 0.
        row: usize,
        /// The rule broken.
        why: String,
    },
    /// A run directory's `manifest.json` is missing, is not valid JSON of the manifest's layout,
    /// has another schema version, lists runs or files that break the rules of
    /// docs/design.md §2 and §7, or has a `parent` link that cannot be followed or no longer
    /// matches its check.
    #[error("{}: field '{field}': {why}", file.display())]
    BadManifest {
        /// The manifest file.
        file: PathBuf,
        /// The offending key (`(file)` when the file itself is missing).
        field: String,
        /// What is wrong with it.
        why: String,
    },
    /// The output already exists and `--force` was not given.
    #[error("{}: already exists (use --force to replace it)", path.display())]
    Exists {
        /// The existing output.
        path: PathBuf,
    },
    /// A run directory, a table's directory or a table file does not exist (or a table
    /// directory holds no `run-*.parquet` file).
    #[error("{}: no such run directory or table", path.display())]
    Missing {
        /// The path looked for.
        path: PathBuf,
    },
    /// The output is not one `--force` may replace, or overlaps the input.
    #[error("{}: {why}", path.display())]
    Refused {
        /// The output path refused.
        path: PathBuf,
        /// Why it is refused.
        why: String,
    },
    /// Another process is writing the same output.
    #[error("{}: {why}", path.display())]
    Busy {
        /// The output path.
        path: PathBuf,
        /// Which lock is held, or that the lock file keeps changing.
        why: String,
    },
    /// Rows could not be turned into an Arrow record batch (columns of the wrong type or length
    /// for the schema, nulls in a non-nullable column, an unknown table): a fault of mimo, not
    /// the input. Holds the message.
    #[error("arrow: {0}")]
    Arrow(String),
}

impl StoreError {
    /// Whether the error is the user's input (exit status 2) rather than a failure of the system
    /// or of mimo (exit status 1: I/O, a failed write, an internal Arrow error).
    pub fn is_input_error(&self) -> bool {
        !matches!(
            self,
            StoreError::Arrow(_) | StoreError::Io { .. } | StoreError::Write { .. } | StoreError::Busy { .. }
        )
    }
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> StoreError + '_ {
    move |source| StoreError::Io { path: path.to_path_buf(), source }
}

/// The zstd level of every table's pages: −5, one of zstd's fast levels (valid levels run from
/// −131 072 to 22). Against level 1 (the Parquet writer's default) it takes 5.5 % fewer
/// instructions to simulate scenario 7 and 3 % fewer to score it, for 9 % more bytes
/// (docs/decisions/0023-zstd-level-minus-5.md).
const ZSTD_LEVEL: i32 = -5;

/// Writer properties for a table of `schema`: fixed so that identical rows give identical bytes.
///
/// The physical encoding only (docs/design.md §3: the columns and their logical types are the
/// contract): zstd pages at a fast level ([`ZSTD_LEVEL`]); no dictionary on any column, the
/// covariance's list items included (interning each value costs the writer more than zstd spends
/// on the plain values, which it compresses nearly as well: the few distinct strings of `radar`,
/// `kind`, … are runs zstd folds away); page statistics (min/max) only on the integer columns,
/// plain values for every number; and per column what its table's declaration says of its
/// storage ([`schema::Storage`], found by the table name in `schema`'s metadata): delta encoding
/// for ids, the byte-stream split for distinct floats, no compression where zstd cannot shrink the
/// values, page statistics on the float columns a reader may filter on (no reader of mimo uses
/// them; computing them for every float was 2 % of `mimo simulate`)
/// (docs/decisions/0019-plain-values-no-dictionaries.md,
/// docs/decisions/0025-no-float-page-statistics.md). Every Parquet reader (polars, pyarrow,
/// DuckDB, arrow-rs) reads them.
pub(crate) fn writer_props(schema: &arrow::datatypes::Schema) -> WriterProperties {
    writer_props_for(schema, WriteMode::Kept)
}

/// What a table file is written for: to be kept (the settings of [`writer_props`]), or as a
/// scratch file that one reader reads back and deletes (a study's scored run): the same columns,
/// values and layout, with plain floats and no compression of them — on floats zstd and the
/// byte-stream split save a little disk, which a scratch file does not keep, for much of the
/// writer's time; labels and integers keep zstd, which folds their runs of equal values away for
/// little (docs/decisions/0319-scratch-tables-for-scored-study-runs.md). Every reader takes
/// both, the scorer's page decoder included ([`page_columns`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WriteMode {
    /// The files users keep: zstd pages and the declared encodings.
    Kept,
    /// A file read back once and deleted: plain, uncompressed floats.
    Scratch,
}

/// [`writer_props`] for a file written for `mode`.
pub(crate) fn writer_props_for(schema: &arrow::datatypes::Schema, mode: WriteMode) -> WriterProperties {
    use parquet::file::properties::EnabledStatistics;
    use schema::Storage;
    let spec = schema.metadata().get(schema::META_TABLE).and_then(|t| schema::table(t));
    let scratch = mode == WriteMode::Scratch;
    let mut b = WriterProperties::builder()
        .set_compression(Compression::ZSTD(parquet::basic::ZstdLevel::try_new(ZSTD_LEVEL).unwrap_or_default()))
        .set_created_by(format!("mimo {}", env!("CARGO_PKG_VERSION")))
        .set_max_row_group_row_count(Some(ROW_GROUP_ROWS))
        .set_data_page_row_count_limit(PAGE_ROWS)
        .set_dictionary_enabled(false)
        .set_statistics_enabled(EnabledStatistics::None);
    for field in schema.fields() {
        let name = field.name().as_str();
        let path = parquet::schema::types::ColumnPath::from(name);
        let storage = spec.and_then(|s| s.columns.iter().find(|c| c.name == name)).map_or(&[][..], |c| c.storage);
        if is_integer(field.data_type()) || storage.contains(&Storage::PageStats) {
            b = b.set_column_statistics_enabled(path.clone(), EnabledStatistics::Page);
        }
        let float =
            matches!(field.data_type(), arrow::datatypes::DataType::Float64 | arrow::datatypes::DataType::Float32);
        if storage.contains(&Storage::Uncompressed) || (scratch && float) {
            b = b.set_column_compression(path.clone(), Compression::UNCOMPRESSED);
        }
        if storage.contains(&Storage::Delta) {
            b = b.set_column_encoding(path, parquet::basic::Encoding::DELTA_BINARY_PACKED);
        } else if storage.contains(&Storage::Split) && !scratch {
            b = b.set_column_encoding(path, parquet::basic::Encoding::BYTE_STREAM_SPLIT);
        }
    }
    b.build()
}

/// Whether a column of `ty` is an integer (or flag) column, which has page statistics.
fn is_integer(ty: &arrow::datatypes::DataType) -> bool {
    use arrow::datatypes::DataType;
    matches!(
        ty,
        DataType::UInt8 | DataType::UInt32 | DataType::UInt64 | DataType::Int32 | DataType::Int64 | DataType::Boolean
    )
}

/// Most rows per data page. The Parquet writer's default cuts a page at 1 MiB or 20 000 rows,
/// so each column of a sparse table (tracks, measurements: ~20 rows/s) kept a page open for
/// several hundred seconds and its zstd context grew with it: a writer's memory followed the
/// run's length (docs/decisions/0021-small-pages-and-row-groups.md).
pub const PAGE_ROWS: usize = 8192;

/// Rows per Parquet row group (and most rows a table writer holds before writing them). The
/// encoded pages of the row group being filled stay in memory, so this bounds a writer's memory
/// whatever the run's length.
pub const ROW_GROUP_ROWS: usize = 1 << 14;

/// Write rows as one Parquet file, atomically (temporary name, then rename).
pub fn write_table<R: TableRow>(path: &Path, rows: &[R]) -> Result<u64, StoreError> {
    let batch = rows::to_batch(rows)?;
    write_batch(path, &batch)?;
    Ok(rows.len() as u64)
}

pub(crate) fn write_batch(path: &Path, batch: &RecordBatch) -> Result<(), StoreError> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    }
    write_batch_into(path, batch)
}

/// Write into an existing directory (never re-creating one removed meanwhile, e.g. a staging
/// directory removed by the interrupt handler). A write that fails (a full disk) removes its
/// temporary file.
pub(crate) fn write_batch_into(path: &Path, batch: &RecordBatch) -> Result<(), StoreError> {
    let name = path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let tmp = path.with_file_name(format!(".{name}.tmp"));
    let write_err = |why: String| StoreError::Write { path: path.to_path_buf(), why };
    let file = output::create_registered(&tmp)?;
    let written = ArrowWriter::try_new(file, batch.schema(), Some(writer_props(&batch.schema())))
        .and_then(|mut w| w.write(batch).and_then(|()| w.close()))
        .map_err(|e| write_err(e.to_string()))
        .and_then(|_| std::fs::rename(&tmp, path).map_err(|e| write_err(e.to_string())));
    if written.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    output::unregister(&tmp);
    written
}

/// Read one Parquet file of table `R`, checked ([`checked`]: table name, schema version, column
/// types, every value against its column's rule, runs matching the file) and its rows against
/// the table's rules ([`invariants`]): the rows of [`table_chunks::TableChunks`], collected.
pub fn read_table<R: TableRow>(path: &Path) -> Result<Vec<R>, StoreError> {
    table_chunks::TableChunks::<R>::open(path)?.rest()
}

/// Open one Parquet file of table `R` for reading, checked ([`checked::open`]: table name,
/// schema version, column chunks, column types).
pub(crate) fn open_table<R: TableRow>(path: &Path) -> Result<ParquetRecordBatchReaderBuilder<File>, StoreError> {
    checked::open(path, &R::SPEC)
}

/// Refuse a footer whose column chunks lie at negative offsets or lengths (a damaged file): the
/// Parquet reader asserts on them instead of returning an error.
pub(crate) fn check_chunk_ranges(md: &parquet::file::metadata::ParquetMetaData, path: &Path) -> Result<(), StoreError> {
    for rg in md.row_groups() {
        for c in rg.columns() {
            let start = c.dictionary_page_offset().unwrap_or(c.data_page_offset());
            if start < 0 || c.compressed_size() < 0 || c.data_page_offset() < 0 {
                return Err(StoreError::Parquet {
                    path: path.to_path_buf(),
                    why: format!("column chunk '{}' has a negative offset or length", c.column_path()),
                });
            }
        }
    }
    Ok(())
}

/// The files of one table in a run directory, in run order (`TABLE/run-0000.parquet`, …).
pub fn table_files(run_dir: &Path, table: &str) -> Result<Vec<PathBuf>, StoreError> {
    let dir = layout::RunDir::new(run_dir).table_dir(table);
    let rd = std::fs::read_dir(&dir).map_err(|_| StoreError::Missing { path: dir.clone() })?;
    let mut files: Vec<PathBuf> = rd
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension().is_some_and(|x| x == "parquet")
                && p.file_name().is_some_and(|n| n.to_string_lossy().starts_with("run-"))
        })
        .collect();
    files.sort();
    if files.is_empty() {
        return Err(StoreError::Missing { path: dir });
    }
    Ok(files)
}

/// Read every file of a table in a run directory.
pub fn read_table_dir<R: TableRow>(run_dir: &Path, table: &str) -> Result<Vec<R>, StoreError> {
    let mut out = Vec::new();
    for f in table_files(run_dir, table)? {
        out.extend(read_table::<R>(&f)?);
    }
    Ok(out)
}

/// File name of run `k`'s file of a table: `run-0000.parquet` (paths: [`layout::RunDir`]).
pub fn run_file_name(run: u32) -> String {
    format!("run-{run:04}.parquet")
}

#[cfg(test)]
mod tests {
    use super::*;
    use parquet::basic::Encoding;
    use parquet::file::properties::EnabledStatistics;
    use parquet::schema::types::ColumnPath;

    /// The writer's settings per column come from the storage tags of the file's table.
    #[test]
    fn writer_settings_follow_the_declared_storage() {
        let col = |n: &str| ColumnPath::from(n);
        let dwells = writer_props(&schema::DWELLS.arrow_schema());
        assert_eq!(dwells.encoding(&col("dwell_id")), Some(Encoding::DELTA_BINARY_PACKED));
        assert_eq!(dwells.encoding(&col("aim_x_m")), Some(Encoding::BYTE_STREAM_SPLIT));
        assert_eq!(dwells.encoding(&col("energy_j")), None);
        assert_eq!(dwells.statistics_enabled(&col("t_s")), EnabledStatistics::Page);
        assert_eq!(dwells.statistics_enabled(&col("energy_j")), EnabledStatistics::None);
        assert_eq!(dwells.statistics_enabled(&col("run")), EnabledStatistics::Page);
        let zstd = dwells.compression(&col("energy_j"));
        assert!(matches!(zstd, Compression::ZSTD(_)));
        let truth = writer_props(&schema::TRUTH.arrow_schema());
        assert_eq!(truth.compression(&col("x_m")), Compression::UNCOMPRESSED);
        assert_eq!(truth.compression(&col("t_s")), zstd);
        // Storage is declared per table: `range_m` of the voltages is compressed, of the
        // measurements not.
        let voltages = writer_props(&schema::VOLTAGES.arrow_schema());
        assert_eq!(voltages.compression(&col("range_m")), zstd);
        let measurements = writer_props(&schema::MEASUREMENTS.arrow_schema());
        assert_eq!(measurements.compression(&col("range_m")), Compression::UNCOMPRESSED);
        // A schema of no known table takes the defaults, whatever its column names.
        let unknown = arrow::datatypes::Schema::new(schema::DWELLS.arrow_schema().fields().clone());
        assert_eq!(writer_props(&unknown).encoding(&col("dwell_id")), None);
        // A scratch file: the same settings but plain, uncompressed floats.
        let scratch = writer_props_for(&schema::DWELLS.arrow_schema(), WriteMode::Scratch);
        assert_eq!(scratch.encoding(&col("dwell_id")), Some(Encoding::DELTA_BINARY_PACKED));
        assert_eq!(scratch.encoding(&col("aim_x_m")), None);
        assert_eq!(scratch.compression(&col("energy_j")), Compression::UNCOMPRESSED);
        assert_eq!(scratch.compression(&col("t_s")), Compression::UNCOMPRESSED);
        assert_eq!(scratch.compression(&col("radar")), zstd);
        assert_eq!(scratch.statistics_enabled(&col("t_s")), EnabledStatistics::Page);
        assert!(!scratch.dictionary_enabled(&col("radar")));
    }
}
