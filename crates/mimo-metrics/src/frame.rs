//! A [`Frame`]: the columns of one dwells file as Arrow arrays, each of the type its table's spec
//! gives (checked by `crate::read`), looked up by name: the checked read that names a broken
//! rule when the dwells' one-pass reader gives up ([`crate::load`]). Truth and tracks come as
//! typed rows from the store's reader instead (`mimo_store::table_chunks`).

use crate::error::MetricsError;
use arrow::array::{Array, ArrayRef, AsArray, StringArray};
use arrow::datatypes::{Float64Type, UInt32Type};

/// Named columns of equal length.
#[derive(Debug, Clone)]
pub(crate) struct Frame {
    height: usize,
    columns: Vec<(&'static str, ArrayRef)>,
}

fn internal(context: &'static str, detail: impl Into<String>) -> MetricsError {
    MetricsError::Internal { context, detail: detail.into() }
}

impl Frame {
    /// A frame of these columns (all of one length).
    pub(crate) fn new(columns: Vec<(&'static str, ArrayRef)>) -> Result<Frame, MetricsError> {
        let height = columns.first().map_or(0, |(_, c)| c.len());
        if let Some((name, c)) = columns.iter().find(|(_, c)| c.len() != height) {
            return Err(internal("building a frame", format!("column {name} has {} rows, not {height}", c.len())));
        }
        Ok(Frame { height, columns })
    }

    /// The number of rows.
    pub(crate) fn height(&self) -> usize {
        self.height
    }

    /// The column `name`.
    pub(crate) fn column(&self, name: &str) -> Result<&ArrayRef, MetricsError> {
        self.columns
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, c)| c)
            .ok_or_else(|| internal("column", format!("no column {name} was read")))
    }

    /// A uint32 column's values (a null reads as 0: checked columns hold none).
    pub(crate) fn u32s(&self, name: &str) -> Result<&[u32], MetricsError> {
        let c = self.column(name)?;
        c.as_primitive_opt::<UInt32Type>()
            .map(|a| a.values().as_ref())
            .ok_or_else(|| internal("column", format!("{name} is not uint32")))
    }

    /// A float64 column's values.
    pub(crate) fn f64s(&self, name: &str) -> Result<&[f64], MetricsError> {
        f64_values(self.column(name)?)
    }

    /// A utf8 column.
    pub(crate) fn strs(&self, name: &str) -> Result<&StringArray, MetricsError> {
        let c = self.column(name)?;
        c.as_string_opt::<i32>().ok_or_else(|| internal("column", format!("{name} is not utf8")))
    }
}

/// A float64 array's values.
pub(crate) fn f64_values(array: &ArrayRef) -> Result<&[f64], MetricsError> {
    array
        .as_primitive_opt::<Float64Type>()
        .map(|a| a.values().as_ref())
        .ok_or_else(|| internal("column", "not float64"))
}

/// The parts of one column (one per Arrow batch) as one array; an empty column of the wanted type
/// when there are none.
pub(crate) fn concat(mut parts: Vec<ArrayRef>, ty: &arrow::datatypes::DataType) -> Result<ArrayRef, MetricsError> {
    match parts.len() {
        0 => Ok(arrow::array::new_empty_array(ty)),
        1 => parts.pop().ok_or_else(|| internal("reading a column", "no part")),
        _ => {
            let refs: Vec<&dyn Array> = parts.iter().map(|a| a.as_ref()).collect();
            arrow::compute::concat(&refs).map_err(|e| internal("reading a column", e.to_string()))
        }
    }
}
