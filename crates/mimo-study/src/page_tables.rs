//! The study tables as `report.html` reads them back from a study directory
//! (docs/decisions/0310-study-report-page.md): each file must be Parquet, its metadata must name
//! the table, and every column the page needs must be there with its type. A column the page
//! can do without (a metric added to the tables after the study was made, such as the shipped
//! stability study's first-track times) reads as null, as `crates/mimo-study/tests/shipped_studies.rs`
//! reads such studies; the schema version is not required to be this mimo's for the same reason.
//! Anything else — a missing file, a file that is not Parquet, another table, a needed column
//! missing or of another type — is a [`PageError`] naming the file.

use arrow::array::{Array, AsArray, RecordBatch};
use arrow::datatypes::{DataType, Float64Type, UInt32Type};
use mimo_store::layout::StudyDir;
use mimo_store::schema::{META_TABLE, TableSpec};
use parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder;
use std::path::{Path, PathBuf};

/// Why the page cannot be made from a study directory (the page is then not written).
#[derive(Debug, thiserror::Error)]
pub enum PageError {
    /// A table or `report.md` is missing.
    #[error("{}: missing: the study page is made from the study's tables (merge the study first)", path.display())]
    Missing {
        /// The file looked for.
        path: PathBuf,
    },
    /// A file cannot be read as the table it should hold.
    #[error("{}: {why}", path.display())]
    Damaged {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// Reading or writing failed for a reason of the system.
    #[error("{}: {why}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        why: String,
    },
}

impl PageError {
    /// Whether the input is at fault (exit 2) rather than the system (exit 1).
    pub fn is_input(&self) -> bool {
        !matches!(self, PageError::Io { .. })
    }
}

/// One study table read whole.
pub struct Table {
    path: PathBuf,
    batches: Vec<RecordBatch>,
}

fn damaged(path: &Path, why: impl Into<String>) -> PageError {
    PageError::Damaged { path: path.to_path_buf(), why: why.into() }
}

impl Table {
    /// Read table `spec` of the study at `dir`; `Ok(None)` when it is optional and absent.
    pub fn read(dir: &Path, spec: &TableSpec, optional: bool) -> Result<Option<Table>, PageError> {
        let path = StudyDir::new(dir).table(spec);
        let file = match std::fs::File::open(&path) {
            Ok(f) => f,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return if optional { Ok(None) } else { Err(PageError::Missing { path }) };
            }
            Err(e) => return Err(PageError::Io { path, why: e.to_string() }),
        };
        let builder =
            ParquetRecordBatchReaderBuilder::try_new(file).map_err(|e| damaged(&path, format!("not Parquet: {e}")))?;
        match builder.schema().metadata().get(META_TABLE) {
            Some(t) if t == spec.name => {}
            Some(t) => return Err(damaged(&path, format!("holds table '{t}', expected '{}'", spec.name))),
            None => return Err(damaged(&path, format!("has no '{META_TABLE}' metadata: not written by mimo"))),
        }
        let reader = builder.build().map_err(|e| damaged(&path, e.to_string()))?;
        let batches = reader.collect::<Result<Vec<_>, _>>().map_err(|e| damaged(&path, e.to_string()))?;
        Ok(Some(Table { path, batches }))
    }

    /// The file read.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Rows.
    pub fn len(&self) -> usize {
        self.batches.iter().map(RecordBatch::num_rows).sum()
    }

    /// Whether the table has no row.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn column<T>(
        &self,
        name: &str,
        required: bool,
        ty: &str,
        get: impl Fn(&dyn Array, usize) -> Option<Option<T>>,
    ) -> Result<Vec<Option<T>>, PageError> {
        let mut out = Vec::with_capacity(self.len());
        for b in &self.batches {
            let Some(c) = b.column_by_name(name) else {
                if required {
                    return Err(damaged(&self.path, format!("no column '{name}'")));
                }
                out.extend((0..b.num_rows()).map(|_| None));
                continue;
            };
            for i in 0..b.num_rows() {
                let v = get(c.as_ref(), i).ok_or_else(|| {
                    damaged(&self.path, format!("column '{name}' is {}, expected {ty}", c.data_type()))
                })?;
                out.push(v);
            }
        }
        Ok(out)
    }

    /// A float64 column (null where a value is null, or everywhere when optional and absent).
    pub fn f64s(&self, name: &str, required: bool) -> Result<Vec<Option<f64>>, PageError> {
        self.column(name, required, "float64", |c, i| {
            let a = c.as_primitive_opt::<Float64Type>()?;
            Some(a.is_valid(i).then(|| a.value(i)))
        })
    }

    /// A uint32 column.
    pub fn u32s(&self, name: &str, required: bool) -> Result<Vec<Option<u32>>, PageError> {
        self.column(name, required, "uint32", |c, i| {
            let a = c.as_primitive_opt::<UInt32Type>()?;
            Some(a.is_valid(i).then(|| a.value(i)))
        })
    }

    /// A text column.
    pub fn texts(&self, name: &str, required: bool) -> Result<Vec<Option<String>>, PageError> {
        self.column(name, required, "utf8", |c, i| {
            let a = c.as_string_opt::<i32>()?;
            Some(a.is_valid(i).then(|| a.value(i).to_string()))
        })
    }

    /// A boolean column.
    pub fn bools(&self, name: &str, required: bool) -> Result<Vec<Option<bool>>, PageError> {
        self.column(name, required, "bool", |c, i| {
            if c.data_type() != &DataType::Boolean {
                return None;
            }
            let a = c.as_boolean();
            Some(a.is_valid(i).then(|| a.value(i)))
        })
    }
}
