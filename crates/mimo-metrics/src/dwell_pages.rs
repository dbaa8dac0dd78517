//! The usage columns of a dwells file decoded straight from its Parquet pages, for the one-pass
//! usage sums ([`crate::dwell_sums`]): the tables mimo writes hold them as required columns in
//! plain pages (`run` uint32, the labels utf8, `duration_s` and `energy_j` float64) and
//! byte-stream-split pages (`t_s`). Each label is mapped to its index as its bytes are read, so
//! no string array is built. Any other layout (optional columns, dictionary pages, other
//! encodings or types) gives `None`, and the file is read with the Arrow reader instead
//! ([`crate::dwell_read`]), as is a file whose values break a check.

use crate::dwell_sums::{DwellSums, FilePass, Labels, Rows};
use mimo_core::records::{DwellColumns, DwellRow};
use parquet::basic::{ConvertedType, Encoding, Type as PhysicalType};
use parquet::column::page::Page;
use parquet::file::reader::{FileReader, RowGroupReader};
use parquet::file::serialized_reader::SerializedFileReader;
use std::collections::BTreeSet;
use std::fs::File;
use std::path::Path;

/// The dwells table's column names (from its declaration).
const D: DwellColumns = DwellRow::COLUMNS;

/// The columns read, with the physical and converted type they must have.
const COLUMNS: [(&str, PhysicalType, ConvertedType); 8] = [
    (D.run, PhysicalType::INT32, ConvertedType::UINT_32),
    (D.radar, PhysicalType::BYTE_ARRAY, ConvertedType::UTF8),
    (D.role, PhysicalType::BYTE_ARRAY, ConvertedType::UTF8),
    (D.kind, PhysicalType::BYTE_ARRAY, ConvertedType::UTF8),
    (D.requested_by, PhysicalType::BYTE_ARRAY, ConvertedType::UTF8),
    (D.t_s, PhysicalType::DOUBLE, ConvertedType::NONE),
    (D.duration_s, PhysicalType::DOUBLE, ConvertedType::NONE),
    (D.energy_j, PhysicalType::DOUBLE, ConvertedType::NONE),
];

/// The values of one data page (levels skipped: the columns are required and flat), or `None`
/// for a page this reader does not take.
fn page_values(page: &Page) -> Option<(&[u8], usize, Encoding)> {
    match page {
        Page::DataPage { buf, num_values, encoding, .. } => Some((buf, *num_values as usize, *encoding)),
        Page::DataPageV2 {
            buf, num_values, encoding, num_nulls: 0, def_levels_byte_len, rep_levels_byte_len, ..
        } => {
            let levels = *def_levels_byte_len as usize + *rep_levels_byte_len as usize;
            Some((buf.get(levels..)?, *num_values as usize, *encoding))
        }
        _ => None,
    }
}

/// Every data page of column `col` of a row group, in order, handed to `each`.
fn for_pages(
    rg: &dyn RowGroupReader,
    col: usize,
    mut each: impl FnMut(&[u8], usize, Encoding) -> Option<()>,
) -> Option<()> {
    for page in rg.get_column_page_reader(col).ok()? {
        let page = page.ok()?;
        let (values, n, encoding) = page_values(&page)?;
        each(values, n, encoding)?;
    }
    Some(())
}

/// A plain uint32 column.
fn u32s(rg: &dyn RowGroupReader, col: usize, out: &mut Vec<u32>) -> Option<()> {
    out.clear();
    for_pages(rg, col, |values, n, encoding| {
        if encoding != Encoding::PLAIN || values.len() < 4 * n {
            return None;
        }
        out.extend(values[..4 * n].chunks_exact(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])));
        Some(())
    })
}

/// A float64 column, plain or byte-stream-split.
fn f64s(rg: &dyn RowGroupReader, col: usize, out: &mut Vec<f64>) -> Option<()> {
    out.clear();
    for_pages(rg, col, |values, n, encoding| {
        let values = values.get(..8 * n)?;
        match encoding {
            Encoding::PLAIN => {
                out.extend(values.chunks_exact(8).map(|b| f64::from_le_bytes(b.try_into().unwrap_or([0xff; 8]))))
            }
            // Byte k of value i at k·n + i, written stream by stream into the values' bytes.
            Encoding::BYTE_STREAM_SPLIT => {
                let mut bytes = vec![[0u8; 8]; n];
                for (k, stream) in values.chunks_exact(n.max(1)).take(8).enumerate() {
                    let k = k & 7;
                    for (b, byte) in bytes.iter_mut().zip(stream) {
                        b[k] = *byte;
                    }
                }
                out.extend(bytes.into_iter().map(f64::from_le_bytes));
            }
            _ => return None,
        }
        Some(())
    })
}

/// A plain utf8 column mapped to label indices; `None` on a string `labels` refuses (or that is
/// not UTF-8).
fn labels(rg: &dyn RowGroupReader, col: usize, labels: &mut Labels, out: &mut Vec<u8>) -> Option<()> {
    out.clear();
    for_pages(rg, col, |values, n, encoding| {
        if encoding != Encoding::PLAIN {
            return None;
        }
        let mut pos = 0;
        for _ in 0..n {
            let len = values.get(pos..pos + 4)?;
            let len = u32::from_le_bytes([len[0], len[1], len[2], len[3]]) as usize;
            let bytes = values.get(pos + 4..pos + 4 + len)?;
            pos += 4 + len;
            let key = crate::dwell_sums::short_key(bytes);
            let index = match key.and_then(|k| labels.by_view(k)) {
                Some(index) => index,
                None => labels.index(std::str::from_utf8(bytes).ok()?, key)?,
            };
            out.push(index);
        }
        Some(())
    })
}

/// One dwells file checked and reduced to its usage sums from its pages, the sums split every
/// `slice_rows` rows as [`crate::dwell_read`] splits them; `None` when the file has another
/// layout or a check fails.
pub(crate) fn file_sums(path: &Path, runs: &BTreeSet<u32>, interval_s: f64, slice_rows: usize) -> Option<DwellSums> {
    let reader = SerializedFileReader::new(File::open(path).ok()?).ok()?;
    let schema = reader.metadata().file_metadata().schema_descr();
    let mut index = [0usize; 8];
    for (slot, (name, physical, converted)) in index.iter_mut().zip(&COLUMNS) {
        let i = (0..schema.num_columns()).find(|&i| {
            let c = schema.column(i);
            c.path().parts().len() == 1 && c.name() == *name
        })?;
        let c = schema.column(i);
        if c.physical_type() != *physical
            || c.converted_type() != *converted
            || c.max_def_level() != 0
            || c.max_rep_level() != 0
        {
            return None;
        }
        *slot = i;
    }
    let end_s = mimo_store::run_window::run_end_s(path);
    let mut pass = FilePass::new(runs, interval_s, slice_rows);
    let (mut radar, mut role, mut kind, mut by) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (mut run, mut t_s, mut duration_s, mut energy_j) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for g in 0..reader.num_row_groups() {
        let rg = reader.get_row_group(g).ok()?;
        let rg = rg.as_ref();
        u32s(rg, index[0], &mut run)?;
        labels(rg, index[1], &mut pass.radar, &mut radar)?;
        labels(rg, index[2], &mut pass.role, &mut role)?;
        labels(rg, index[3], &mut pass.kind, &mut kind)?;
        labels(rg, index[4], &mut pass.requested_by, &mut by)?;
        f64s(rg, index[5], &mut t_s)?;
        // A time after the run's end is a check failing: the Arrow reader reports it.
        if end_s.is_some_and(|end| mimo_store::run_window::first_after_end(&t_s, end, 0).is_some()) {
            return None;
        }
        f64s(rg, index[6], &mut duration_s)?;
        f64s(rg, index[7], &mut energy_j)?;
        let n = usize::try_from(rg.metadata().num_rows()).ok()?;
        if run.len() != n || kind.len() != n {
            return None;
        }
        pass.rows(&Rows {
            run: &run,
            radar: &radar,
            role: &role,
            requested_by: &by,
            t_s: &t_s,
            duration_s: &duration_s,
            energy_j: &energy_j,
        })?;
    }
    Some(pass.finish())
}
