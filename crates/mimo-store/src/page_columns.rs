//! Columns of a table file decoded straight from its Parquet pages, for a reader that needs a few
//! columns of every row and no Arrow arrays (mimo-metrics' one pass over the dwells: usage sums
//! and usage by purpose).
//!
//! The decoder reads the layout the store's writer gives (`crate::writer_props`): required,
//! flat columns without dictionaries, `uint8`, `uint32` and `utf8` values in plain pages,
//! `float64` values plain or byte-stream split, `uint64` ids delta-encoded
//! ([`crate::page_delta`]), pages zstd-compressed or not. It lives beside the writer settings
//! because it depends on them: [`DECODED_ENCODINGS`] names what it decodes, and the tests check
//! that the writer's settings for every column it can be asked for stay within it and that the
//! writer's own files decode to the values written. Anything else — an optional column, a
//! dictionary page, another encoding, type or codec, a short page — gives `None`, and the caller
//! reads the file with the Arrow reader instead (which takes any layout).
//!
//! Pages are decompressed here, with one zstd context per opened file reused for every page of
//! every column and row group: the Parquet crate's page reader makes a codec (a compression and
//! a decompression context) per column chunk, whose set-up cost more than the decompression of
//! the dwells' small pages (docs/decisions/0299-one-pass-dwell-reader.md).

use parquet::basic::{Compression, ConvertedType, Encoding, Type as PhysicalType};
use parquet::column::page::Page;
use parquet::file::reader::FileReader;
use parquet::file::serialized_reader::{SerializedFileReader, SerializedPageReader};
use std::cell::RefCell;
use std::fs::File;
use std::path::Path;
use std::sync::Arc;

/// The value encodings the decoder takes: plain values (every column), the byte-stream split
/// (`float64` columns) and the delta encoding (`uint64` columns, which may also be plain).
pub const DECODED_ENCODINGS: [Encoding; 3] =
    [Encoding::PLAIN, Encoding::BYTE_STREAM_SPLIT, Encoding::DELTA_BINARY_PACKED];

/// Whether the decoder takes values of `physical` type written with `encoding`.
pub fn decodes(physical: PhysicalType, encoding: Encoding) -> bool {
    match physical {
        PhysicalType::DOUBLE => encoding == Encoding::PLAIN || encoding == Encoding::BYTE_STREAM_SPLIT,
        PhysicalType::INT64 => encoding == Encoding::DELTA_BINARY_PACKED || encoding == Encoding::PLAIN,
        PhysicalType::INT32 | PhysicalType::BYTE_ARRAY => encoding == Encoding::PLAIN,
        _ => false,
    }
}

/// The zstd context of a file and the buffer its pages are decompressed into.
struct Inflate {
    zstd: zstd::bulk::Decompressor<'static>,
    page: Vec<u8>,
}

/// A table file opened for page decoding, with the columns asked for found.
pub struct PageFile {
    reader: SerializedFileReader<File>,
    /// The file again, for the page readers of its column chunks.
    file: Arc<File>,
    /// One decompression context for every page of the file.
    inflate: RefCell<Inflate>,
    /// Leaf index in the file of each column asked for, and its physical and converted type.
    columns: Vec<(usize, PhysicalType, ConvertedType)>,
}

impl PageFile {
    /// Open `path` for decoding the columns `names`, each a required top-level column; `None`
    /// if the file cannot be opened or a column is missing, nested or optional.
    pub fn open(path: &Path, names: &[&str]) -> Option<PageFile> {
        let file = File::open(path).ok()?;
        let reader = SerializedFileReader::new(file.try_clone().ok()?).ok()?;
        let schema = reader.metadata().file_metadata().schema_descr();
        let mut columns = Vec::with_capacity(names.len());
        for name in names {
            let i = (0..schema.num_columns()).find(|&i| {
                let c = schema.column(i);
                c.path().parts().len() == 1 && c.name() == *name
            })?;
            let c = schema.column(i);
            if c.max_def_level() != 0 || c.max_rep_level() != 0 {
                return None;
            }
            columns.push((i, c.physical_type(), c.converted_type()));
        }
        let inflate = RefCell::new(Inflate { zstd: zstd::bulk::Decompressor::new().ok()?, page: Vec::new() });
        Some(PageFile { reader, file: Arc::new(file), inflate, columns })
    }

    /// Row groups in the file.
    pub fn num_row_groups(&self) -> usize {
        self.reader.num_row_groups()
    }

    /// Row group `g`.
    pub fn row_group(&self, g: usize) -> Option<PageRowGroup<'_>> {
        (g < self.num_row_groups()).then_some(PageRowGroup { file: self, g })
    }
}

/// One row group of a [`PageFile`]; columns are named by their position in the names asked for.
pub struct PageRowGroup<'f> {
    file: &'f PageFile,
    g: usize,
}

impl PageRowGroup<'_> {
    /// Rows in the row group.
    pub fn num_rows(&self) -> Option<usize> {
        usize::try_from(self.file.reader.metadata().row_group(self.g).num_rows()).ok()
    }

    /// Column `col`'s leaf index if it has the physical and converted type given.
    fn leaf(&self, col: usize, physical: PhysicalType, converted: ConvertedType) -> Option<usize> {
        let &(i, p, c) = self.file.columns.get(col)?;
        (p == physical && c == converted).then_some(i)
    }

    /// Every data page of leaf `leaf`, in order, handed to `each` with its values' bytes
    /// (decompressed), count and encoding.
    fn for_pages(&self, leaf: usize, mut each: impl FnMut(&[u8], usize, Encoding) -> Option<()>) -> Option<()> {
        let rg = self.file.reader.metadata().row_group(self.g);
        let chunk = rg.columns().get(leaf)?;
        let zstd_chunk = match chunk.compression() {
            Compression::UNCOMPRESSED => false,
            Compression::ZSTD(_) => true,
            _ => return None,
        };
        // The chunk's pages as stored: the page reader is told they are not compressed, so that
        // it makes no codec, and each page is decompressed here with the file's one context.
        let stored = chunk.clone().into_builder().set_compression(Compression::UNCOMPRESSED).build().ok()?;
        let rows = usize::try_from(rg.num_rows()).ok()?;
        let pages = SerializedPageReader::new(Arc::clone(&self.file.file), &stored, rows, None).ok()?;
        let mut inflate = self.file.inflate.borrow_mut();
        let Inflate { zstd: context, page: buf } = &mut *inflate;
        for page in pages {
            let page = page.ok()?;
            let (values, n, encoding, compressed) = page_values(&page)?;
            if zstd_chunk && compressed {
                let size = zstd::zstd_safe::get_frame_content_size(values).ok()??;
                let size = usize::try_from(size).ok()?;
                buf.clear();
                buf.reserve(size);
                if context.decompress_to_buffer(values, buf).ok()? != size {
                    return None;
                }
                each(buf, n, encoding)?;
            } else {
                each(values, n, encoding)?;
            }
        }
        Some(())
    }

    /// A `uint32` column's values into `out` (cleared first).
    pub fn u32s(&self, col: usize, out: &mut Vec<u32>) -> Option<()> {
        let leaf = self.leaf(col, PhysicalType::INT32, ConvertedType::UINT_32)?;
        out.clear();
        self.for_pages(leaf, |values, n, encoding| {
            if encoding != Encoding::PLAIN || values.len() < 4 * n {
                return None;
            }
            out.extend(values[..4 * n].chunks_exact(4).map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]])));
            Some(())
        })
    }

    /// A `uint8` column's values into `out` (cleared first).
    pub fn u8s(&self, col: usize, out: &mut Vec<u8>) -> Option<()> {
        let leaf = self.leaf(col, PhysicalType::INT32, ConvertedType::UINT_8)?;
        out.clear();
        self.for_pages(leaf, |values, n, encoding| {
            if encoding != Encoding::PLAIN || values.len() < 4 * n {
                return None;
            }
            for b in values[..4 * n].chunks_exact(4) {
                out.push(u8::try_from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])).ok()?);
            }
            Some(())
        })
    }

    /// A `uint64` column's values into `out` (cleared first), delta-encoded or plain.
    pub fn u64s(&self, col: usize, out: &mut Vec<u64>) -> Option<()> {
        let leaf = self.leaf(col, PhysicalType::INT64, ConvertedType::UINT_64)?;
        out.clear();
        self.for_pages(leaf, |values, n, encoding| match encoding {
            Encoding::DELTA_BINARY_PACKED => crate::page_delta::decode_u64s(values, n, out),
            Encoding::PLAIN => {
                let values = values.get(..8 * n)?;
                out.extend(values.chunks_exact(8).map(|b| u64::from_le_bytes(b.try_into().unwrap_or([0xff; 8]))));
                Some(())
            }
            _ => None,
        })
    }

    /// A `float64` column's values into `out` (cleared first), plain or byte-stream split.
    pub fn f64s(&self, col: usize, out: &mut Vec<f64>) -> Option<()> {
        let leaf = self.leaf(col, PhysicalType::DOUBLE, ConvertedType::NONE)?;
        out.clear();
        self.for_pages(leaf, |values, n, encoding| {
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

    /// A `utf8` column's values, each value's bytes handed to `each` in row order (no string is
    /// built; `each` may refuse one with `None`). The bytes are not checked to be UTF-8.
    pub fn strs(&self, col: usize, mut each: impl FnMut(&[u8]) -> Option<()>) -> Option<()> {
        self.keyed_strs(col, |_, bytes| each(bytes))
    }

    /// [`Self::strs`] with each value's [`short_key`] (`None` for a value over 12 bytes), taken
    /// from the stored bytes in one load.
    pub fn keyed_strs(&self, col: usize, mut each: impl FnMut(Option<u128>, &[u8]) -> Option<()>) -> Option<()> {
        let leaf = self.leaf(col, PhysicalType::BYTE_ARRAY, ConvertedType::UTF8)?;
        self.for_pages(leaf, |values, n, encoding| {
            if encoding != Encoding::PLAIN {
                return None;
            }
            let mut pos = 0;
            for _ in 0..n {
                // Where 16 bytes are left, one load gives the length and the key.
                let (len, key) = match values.get(pos..pos + 16) {
                    Some(b) => {
                        let all = u128::from_le_bytes(b.try_into().ok()?);
                        let len = all as u32 as usize;
                        (len, KEY_MASKS.get(len).map(|mask| all & mask))
                    }
                    None => {
                        let len = values.get(pos..pos + 4)?;
                        let len = u32::from_le_bytes([len[0], len[1], len[2], len[3]]) as usize;
                        (len, stored_key(&values[pos..], len))
                    }
                };
                let bytes = values.get(pos + 4..pos + 4 + len)?;
                each(key, bytes)?;
                pos += 4 + len;
            }
            Some(())
        })
    }
}

/// The key of a string of at most 12 bytes: its length (4 bytes, little-endian) and its bytes in
/// one integer, zero-padded (the layout of an inline Arrow string view), so that a label is
/// recognised in one comparison; `None` for a longer string.
#[inline]
pub fn short_key(bytes: &[u8]) -> Option<u128> {
    let len = u32::try_from(bytes.len()).ok().filter(|&l| l <= 12)?;
    let mut b = [0u8; 16];
    b[..4].copy_from_slice(&len.to_le_bytes());
    for (d, s) in b[4..].iter_mut().zip(bytes) {
        *d = *s;
    }
    Some(u128::from_le_bytes(b))
}

/// The mask of a stored value's key by its length (0 to 12 bytes): its 4 length bytes and `len`
/// bytes of the value.
const KEY_MASKS: [u128; 13] = {
    let mut masks = [0u128; 13];
    let mut len = 0;
    while len < 13 {
        masks[len] = u128::MAX >> (128 - 8 * (4 + len));
        len += 1;
    }
    masks
};

/// [`short_key`] of the plain-encoded value at the start of `stored` (its 4-byte length, then
/// its bytes), read in one load where 16 bytes are left: the stored layout is the key's.
#[inline]
fn stored_key(stored: &[u8], len: usize) -> Option<u128> {
    if len > 12 {
        return None;
    }
    match stored.get(..16) {
        Some(b) => {
            let all = u128::from_le_bytes(b.try_into().ok()?);
            Some(all & (u128::MAX >> (128 - 8 * (4 + len))))
        }
        None => short_key(stored.get(4..4 + len)?),
    }
}

/// The values of one data page (levels skipped: the columns are required and flat), their
/// count and encoding and whether they are compressed, or `None` for a page this decoder does not
/// take (a dictionary page, a page with nulls, levels inside a compressed version-1 page).
fn page_values(page: &Page) -> Option<(&[u8], usize, Encoding, bool)> {
    match page {
        Page::DataPage { buf, num_values, encoding, .. } => Some((buf, *num_values as usize, *encoding, true)),
        Page::DataPageV2 {
            buf,
            num_values,
            encoding,
            num_nulls: 0,
            def_levels_byte_len,
            rep_levels_byte_len,
            is_compressed,
            ..
        } => {
            let levels = *def_levels_byte_len as usize + *rep_levels_byte_len as usize;
            Some((buf.get(levels..)?, *num_values as usize, *encoding, *is_compressed))
        }
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::records::DwellRow;
    use parquet::file::properties::WriterProperties;

    /// Dwell rows of run 3 whose every decoded column varies (times 13.7 ms apart), ids too:
    /// group ids jump up and down by up to 2^40, dwell ids wrap around `u64::MAX`.
    fn dwells(n: usize) -> Vec<DwellRow> {
        let mut rows = crate::testing::varied_dwell_rows(3, &(0..n).map(|i| 0.0137 * i as f64).collect::<Vec<_>>());
        for (i, r) in rows.iter_mut().enumerate() {
            let i = i as u64;
            r.group_id = (i * i * 7919) % (1 << 40) + (i % 5);
            r.dwell_id = (u64::MAX - 3 * n as u64 / 2).wrapping_add(3 * i);
        }
        rows
    }

    /// The id and face columns of every row group, concatenated; `None` where the decoder gives up.
    fn decode_ids(path: &Path) -> Option<(Vec<u64>, Vec<u64>, Vec<u8>)> {
        let f = PageFile::open(path, &["dwell_id", "group_id", "face"])?;
        let mut all = (Vec::new(), Vec::new(), Vec::new());
        let (mut u, mut b) = (Vec::new(), Vec::new());
        for g in 0..f.num_row_groups() {
            let rg = f.row_group(g)?;
            rg.u64s(0, &mut u)?;
            all.0.extend(&u);
            rg.u64s(1, &mut u)?;
            all.1.extend(&u);
            rg.u8s(2, &mut b)?;
            all.2.extend(&b);
        }
        Some(all)
    }

    const NAMES: [&str; 6] = ["run", "radar", "role", "t_s", "duration_s", "energy_j"];

    /// The decoded columns of every row group, concatenated; `None` where the decoder gives up.
    #[allow(clippy::type_complexity)]
    fn decode(path: &Path) -> Option<(Vec<u32>, Vec<String>, Vec<String>, Vec<f64>, Vec<f64>, Vec<f64>)> {
        let f = PageFile::open(path, &NAMES)?;
        let mut all = (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let (mut u, mut x) = (Vec::new(), Vec::new());
        for g in 0..f.num_row_groups() {
            let rg = f.row_group(g)?;
            rg.u32s(0, &mut u)?;
            all.0.extend(&u);
            rg.strs(1, |b| {
                all.1.push(String::from_utf8(b.to_vec()).ok()?);
                Some(())
            })?;
            rg.strs(2, |b| {
                all.2.push(String::from_utf8(b.to_vec()).ok()?);
                Some(())
            })?;
            for (col, out) in [(3, &mut all.3), (4, &mut all.4), (5, &mut all.5)] {
                rg.f64s(col, &mut x)?;
                out.extend(&x);
            }
        }
        Some(all)
    }

    /// The writer's output, across pages and row groups, decodes to the values written, and as
    /// the writer streams it (the run sink's [`crate::table_writer::TableWriter`]) too, kept or
    /// scratch ([`crate::WriteMode`]).
    #[test]
    fn the_store_writer_output_decodes_to_the_rows_written() {
        let dir = tempfile::tempdir().expect("tempdir");
        let rows = dwells(crate::ROW_GROUP_ROWS + crate::PAGE_ROWS + 100);
        let once = dir.path().join("run-0003.parquet");
        crate::write_table(&once, &rows).expect("write");
        let mut files = vec![once];
        for mode in [crate::WriteMode::Kept, crate::WriteMode::Scratch] {
            let streamed = dir.path().join(format!("streamed-{mode:?}.parquet"));
            let mut w = crate::table_writer::TableWriter::create_for(&streamed, mode).expect("create");
            rows.chunks(977).try_for_each(|c| w.extend(c.to_vec())).expect("extend");
            w.finish().expect("finish");
            files.push(streamed);
        }
        // The scratch file is the one written uncompressed, and the checked typed reader takes it.
        assert!(
            std::fs::metadata(&files[2]).expect("scratch").len()
                > 2 * std::fs::metadata(&files[1]).expect("kept").len()
        );
        assert_eq!(crate::read_table::<DwellRow>(&files[2]).expect("read"), rows);
        for path in &files {
            let got = decode(path).expect("the store's own file takes the page decoder");
            assert_eq!(got.0, rows.iter().map(|r| r.run).collect::<Vec<_>>());
            assert_eq!(got.1, rows.iter().map(|r| r.radar.to_string()).collect::<Vec<_>>());
            assert_eq!(got.2, rows.iter().map(|r| r.role.as_str().to_string()).collect::<Vec<_>>());
            assert_eq!(got.3, rows.iter().map(|r| r.t_s).collect::<Vec<_>>());
            assert_eq!(got.4, rows.iter().map(|r| r.duration_s).collect::<Vec<_>>());
            assert_eq!(got.5, rows.iter().map(|r| r.energy_j).collect::<Vec<_>>());
            let ids = decode_ids(path).expect("the store's ids and faces take the page decoder");
            assert_eq!(ids.0, rows.iter().map(|r| r.dwell_id).collect::<Vec<_>>());
            assert_eq!(ids.1, rows.iter().map(|r| r.group_id).collect::<Vec<_>>());
            assert_eq!(ids.2, rows.iter().map(|r| r.face).collect::<Vec<_>>());
        }
    }

    /// Each value's key from its stored bytes is the key of its string, for values in the middle
    /// of a page (one 16-byte load) and at its end (fewer than 16 bytes left).
    #[test]
    fn stored_keys_are_the_keys_of_the_strings() {
        let dir = tempfile::tempdir().expect("tempdir");
        let rows = dwells(crate::PAGE_ROWS + 100);
        let path = dir.path().join("run-0003.parquet");
        crate::write_table(&path, &rows).expect("write");
        let f = PageFile::open(&path, &["radar", "role", "kind"]).expect("the store's own file");
        let mut values = 0;
        for g in 0..f.num_row_groups() {
            let rg = f.row_group(g).expect("row group");
            for col in 0..3 {
                rg.keyed_strs(col, |key, bytes| {
                    assert_eq!(key, short_key(bytes), "{:?}", std::str::from_utf8(bytes));
                    values += 1;
                    Some(())
                })
                .expect("decoded");
            }
        }
        assert_eq!(values, 3 * rows.len());
    }

    /// The writer's settings for every column of every run table of a type the decoder reads
    /// (`uint8`, `uint32`, `uint64`, `float64`, `utf8`) are settings it decodes: no dictionary, and an encoding of
    /// [`decodes`]. A change of the settings that would turn the fast path off fails here.
    #[test]
    fn the_writer_settings_stay_within_what_the_decoder_takes() {
        use arrow::datatypes::DataType;
        let mut checked = 0;
        for (spec, mode) in
            crate::schema::ALL_TABLES.iter().flat_map(|s| [(s, crate::WriteMode::Kept), (s, crate::WriteMode::Scratch)])
        {
            let schema = spec.arrow_schema();
            let props = crate::writer_props_for(&schema, mode);
            for field in schema.fields() {
                let physical = match field.data_type() {
                    DataType::UInt8 | DataType::UInt32 => PhysicalType::INT32,
                    DataType::UInt64 => PhysicalType::INT64,
                    DataType::Float64 => PhysicalType::DOUBLE,
                    DataType::Utf8 => PhysicalType::BYTE_ARRAY,
                    _ => continue,
                };
                let path = parquet::schema::types::ColumnPath::from(field.name().as_str());
                let what = format!("{}.{}", spec.name, field.name());
                assert!(!props.dictionary_enabled(&path), "{what}: dictionary pages");
                let encoding = props.encoding(&path).unwrap_or(Encoding::PLAIN);
                assert!(decodes(physical, encoding), "{what}: {encoding:?} pages");
                let codec = props.compression(&path);
                assert!(matches!(codec, Compression::UNCOMPRESSED | Compression::ZSTD(_)), "{what}: {codec:?}");
                checked += 1;
            }
        }
        assert!(checked > 80, "{checked} columns checked");
    }

    /// A file written with other settings (dictionary pages, the Parquet writer's defaults) is
    /// not decoded: the decoder gives `None` rather than wrong values.
    #[test]
    fn other_writer_settings_are_refused() {
        let dir = tempfile::tempdir().expect("tempdir");
        let rows = dwells(5000);
        let batch = crate::rows::to_batch(&rows).expect("batch");
        let path = dir.path().join("run-0003.parquet");
        for props in [
            WriterProperties::builder().build(),
            WriterProperties::builder().set_dictionary_enabled(true).build(),
            WriterProperties::builder()
                .set_dictionary_enabled(false)
                .set_column_encoding("run".into(), Encoding::DELTA_BINARY_PACKED)
                .build(),
        ] {
            let file = File::create(&path).expect("create");
            let mut w = parquet::arrow::ArrowWriter::try_new(file, batch.schema(), Some(props)).expect("writer");
            w.write(&batch).expect("write");
            w.close().expect("close");
            assert!(decode(&path).is_none(), "a file of other settings is left to the Arrow reader");
            // Yet it is a well-formed dwells file: the store's checked read takes it.
            assert_eq!(crate::read_table::<DwellRow>(&path).expect("read"), rows);
        }
    }
}
