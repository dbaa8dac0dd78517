//! What mimo wrote, recognised by content (docs/design.md §7): `--force` replaces only outputs
//! that pass these checks, and refuses, naming them, anything else found inside.
//!
//! * A **run directory**: its `manifest.json` parses as a [`Manifest`]; inside it, only the
//!   manifest, the table files the manifest lists, a score directory (below), a study cell's item
//!   records (JSON) and mimo's own hidden lock and staging entries.
//! * A **score directory**: `summary.json` a JSON object with the summary's `challenge` and
//!   `usage`, Parquet files whose metadata names a mimo table, and `charts/` holding only charts
//!   mimo drew (below). A file of mimo's score that was **damaged** (cut short, emptied) is
//!   still recognised, by its name and what is left of its content ([`damaged_in_score_dir`]):
//!   a score table's name with the Parquet magic `PAR1` but no readable footer (or no byte at
//!   all), a `summary.json` that opens as mimo writes one (`{` then `"scenario":`) but does not
//!   parse. `mimo score` replaces it with the rest of the score and says so.
//! * A **page `mimo plot` wrote**: it carries [`PLOT_MARK`] in its head.
//! * An **image `scenarios --map` wrote**: a PNG with a `tEXt` chunk, or an SVG opening with a
//!   comment, holding [`MAP_MARK`] ([`mark_image`]).
//! * A **chart mimo drew** (a score's or a study's): a PNG whose `Software` `tEXt` chunk, or an
//!   SVG whose opening comment, starts with [`CHART_MARK`] (maps included).
//!
//! A file name alone never makes something mimo's: a web project's `manifest.json` is not a
//! mimo manifest, and a user's `notes.txt` inside a run is not a table.

use crate::layout::{RunDir, ScoreDir};
use crate::manifest::{MANIFEST_FILE, Manifest};
use crate::{StoreError, io_err};
use std::io::Read;
use std::path::{Path, PathBuf};

/// The marker in the head of every page `mimo plot` writes.
pub const PLOT_MARK: &str = r#"<meta name="generator" content="mimo plot">"#;
/// The text marking a map `mimo scenarios --map` drew.
pub const MAP_MARK: &str = "mimo scenarios --map";
/// The text marking a chart mimo drew (score and study charts; a map's mark starts with it too).
pub const CHART_MARK: &str = "mimo";
/// The PNG `tEXt` keyword of a mark.
const PNG_KEYWORD: &[u8] = b"Software\0";

/// Most entries named in a refusal.
const NAMED: usize = 5;

/// The first `n` bytes of a file (fewer if it is shorter); empty if it cannot be read.
fn head(path: &Path, n: usize) -> Vec<u8> {
    let mut buf = Vec::with_capacity(n);
    if let Ok(f) = std::fs::File::open(path) {
        let _ = f.take(n as u64).read_to_end(&mut buf);
    }
    buf
}

fn contains(hay: &[u8], needle: &[u8]) -> bool {
    hay.windows(needle.len()).any(|w| w == needle)
}

/// Whether `path` is a Parquet file whose metadata names a mimo table.
pub fn is_mimo_parquet(path: &Path) -> bool {
    let Ok(file) = std::fs::File::open(path) else { return false };
    match parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(file) {
        Ok(b) => b.schema().metadata().contains_key(crate::schema::META_TABLE),
        Err(_) => false,
    }
}

/// Whether `path` is a chart mimo drew: a PNG whose first chunk after the header is the
/// `Software` `tEXt` chunk [`mark_image`] writes, or an SVG opening with its comment, holding
/// [`CHART_MARK`] (or a longer mark starting with it, as a map's).
pub fn is_chart_image(path: &Path) -> bool {
    let h = head(path, 33 + 8 + PNG_KEYWORD.len() + CHART_MARK.len());
    let png = [b"tEXt".as_slice(), PNG_KEYWORD, CHART_MARK.as_bytes()].concat();
    (h.starts_with(b"\x89PNG\r\n\x1a\n") && h.get(37..).is_some_and(|chunk| chunk.starts_with(&png)))
        || h.starts_with(format!("<!-- {CHART_MARK}").as_bytes())
}

/// Whether `path` holds a JSON document.
fn is_json(path: &Path) -> bool {
    std::fs::read(path).is_ok_and(|b| serde_json::from_slice::<serde_json::Value>(&b).is_ok())
}

/// Whether `path` is a page `mimo plot` wrote.
pub fn is_plot_page(path: &Path) -> bool {
    contains(&head(path, 4096), PLOT_MARK.as_bytes())
}

/// Whether `path` is an image `mimo scenarios --map` drew ([`mark_image`]).
pub fn is_map_image(path: &Path) -> bool {
    contains(&head(path, 512), MAP_MARK.as_bytes())
}

/// CRC-32 (ISO-HDLC) of PNG chunks.
fn crc32(bytes: &[u8]) -> u32 {
    let mut c = 0xffff_ffffu32;
    for &b in bytes {
        c ^= u32::from(b);
        for _ in 0..8 {
            c = if c & 1 == 1 { 0xedb8_8320 ^ (c >> 1) } else { c >> 1 };
        }
    }
    !c
}

/// Mark a drawn image as mimo's: a `tEXt` chunk (`Software`) after a PNG's header chunk, or a
/// comment before an SVG's root element, holding `mark` ([`MAP_MARK`], [`CHART_MARK`]).
pub fn mark_image(path: &Path, mark: &str) -> Result<(), StoreError> {
    let write_err = |e: std::io::Error| StoreError::Write { path: path.to_path_buf(), why: e.to_string() };
    let bytes = std::fs::read(path).map_err(write_err)?;
    // Signature (8 bytes), then the IHDR chunk: length 13, type, data, CRC (25 bytes).
    let marked = if bytes.starts_with(b"\x89PNG\r\n\x1a\n") && bytes.len() > 33 {
        let data = [PNG_KEYWORD, mark.as_bytes()].concat();
        let mut chunk = Vec::with_capacity(data.len() + 12);
        chunk.extend_from_slice(&(data.len() as u32).to_be_bytes());
        let typed = [b"tEXt".as_slice(), &data].concat();
        chunk.extend_from_slice(&typed);
        chunk.extend_from_slice(&crc32(&typed).to_be_bytes());
        [&bytes[..33], &chunk, &bytes[33..]].concat()
    } else {
        [format!("<!-- {mark} -->\n").as_bytes(), &bytes].concat()
    };
    std::fs::write(path, marked).map_err(write_err)
}

/// Whether `name` is mimo's own hidden lock, staging or temporary entry (`.score.lock`,
/// `.score.partial-PID`, `.score.old-PID`, `.run-0000.parquet.tmp`): what an interrupted writer
/// leaves for the next one to remove.
fn is_own_hidden(name: &str) -> bool {
    let Some(rest) = name.strip_prefix('.') else { return false };
    rest.ends_with(".lock")
        || rest.ends_with(".tmp")
        || rest.contains(".tmp-")
        || rest.contains(".partial-")
        || rest.contains(".old-")
}

/// The files below `dir` mimo did not write: every file must be mimo's own hidden entry, a
/// Parquet file of a mimo table, a JSON document (a manifest, a record, a log), a chart mimo
/// drew, or one the caller recognises (`ours`). Used inside a directory already recognised as mimo's
/// (a study, by its mark).
pub fn foreign_in_tree(dir: &Path, ours: &dyn Fn(&Path) -> bool) -> Result<Vec<PathBuf>, StoreError> {
    let mut foreign = Vec::new();
    for (name, path) in entries(dir)? {
        let meta = std::fs::symlink_metadata(&path).map_err(io_err(&path))?;
        if meta.is_dir() {
            foreign.extend(foreign_in_tree(&path, ours)?);
        } else if !(meta.is_file()
            && (ours(&path)
                || is_own_hidden(&name)
                || is_mimo_parquet(&path)
                || is_json(&path)
                || is_chart_image(&path)))
        {
            foreign.push(path);
        }
    }
    Ok(foreign)
}

fn entries(dir: &Path) -> Result<Vec<(String, PathBuf)>, StoreError> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).map_err(io_err(dir))? {
        let e = e.map_err(io_err(dir))?;
        out.push((e.file_name().to_string_lossy().to_string(), e.path()));
    }
    out.sort();
    Ok(out)
}

/// Whether `path` is a file of mimo's own score that was damaged: named as one of the score's
/// tables or its summary, and holding what is left of one (module docs).
fn is_damaged_score_file(dir: &ScoreDir, path: &Path) -> bool {
    let Ok(meta) = std::fs::symlink_metadata(path) else { return false };
    if !meta.is_file() {
        return false;
    }
    if path == dir.summary() {
        let text = head(path, 64);
        let opens_as_mimo = text.starts_with(b"{") && {
            let rest = String::from_utf8_lossy(&text[1..]).to_string();
            rest.trim_start().starts_with("\"scenario\":")
        };
        return (meta.len() == 0 || opens_as_mimo) && !is_json(path);
    }
    let named = crate::score_schema::SCORE_TABLES
        .iter()
        .chain(&crate::score_schema::SCORE_OPTIONAL_TABLES)
        .any(|spec| dir.table(spec) == path);
    named && (meta.len() == 0 || (head(path, 4) == b"PAR1" && !is_readable_parquet(path)))
}

/// Whether `path` has a Parquet footer the reader accepts.
fn is_readable_parquet(path: &Path) -> bool {
    std::fs::File::open(path)
        .is_ok_and(|f| parquet::arrow::arrow_reader::ParquetRecordBatchReaderBuilder::try_new(f).is_ok())
}

/// The files of mimo's own score in `dir` that were damaged (module docs): replaced by the
/// next `mimo score`, which names them.
pub fn damaged_in_score_dir(dir: &ScoreDir) -> Result<Vec<PathBuf>, StoreError> {
    if !dir.root().is_dir() {
        return Ok(Vec::new());
    }
    Ok(entries(dir.root())?.into_iter().map(|(_, p)| p).filter(|p| is_damaged_score_file(dir, p)).collect())
}

/// The entries of a score directory mimo did not write (all of it if it is not a score
/// directory at all). Damaged files of mimo's own score are mimo's ([`damaged_in_score_dir`]).
pub fn foreign_in_score_dir(dir: &ScoreDir) -> Result<Vec<PathBuf>, StoreError> {
    let mut foreign = Vec::new();
    for (name, path) in entries(dir.root())? {
        let ours = if path == dir.summary() {
            std::fs::read(&path)
                .ok()
                .and_then(|b| serde_json::from_slice::<serde_json::Value>(&b).ok())
                .is_some_and(|v| v.get("challenge").is_some() && v.get("usage").is_some())
                || is_damaged_score_file(dir, &path)
        } else if path == dir.charts() && path.is_dir() {
            let inside = entries(&path)?;
            foreign.extend(inside.into_iter().filter(|(_, p)| !(p.is_file() && is_chart_image(p))).map(|(_, p)| p));
            true
        } else {
            is_own_hidden(&name) || (path.is_file() && is_mimo_parquet(&path)) || is_damaged_score_file(dir, &path)
        };
        if !ours {
            foreign.push(path);
        }
    }
    Ok(foreign)
}

/// The entries of a run directory mimo did not write, given its manifest.
pub fn foreign_in_run_dir(dir: &Path, m: &Manifest) -> Result<Vec<PathBuf>, StoreError> {
    let run = RunDir::new(dir);
    let mut foreign = Vec::new();
    for (name, path) in entries(dir)? {
        if name == MANIFEST_FILE || is_own_hidden(&name) {
            continue;
        }
        if path == run.score().root() && path.is_dir() {
            foreign.extend(foreign_in_score_dir(&run.score())?);
        } else if let Some(files) = m.tables.get(&name).filter(|_| path.is_dir()) {
            for (file, p) in entries(&path)? {
                if !files.iter().any(|f| f.file == format!("{name}/{file}")) {
                    foreign.push(p);
                }
            }
        } else if name == ".items" && path.is_dir() {
            foreign.extend(entries(&path)?.into_iter().filter(|(_, p)| !is_json(p)).map(|(_, p)| p));
        } else {
            foreign.push(path);
        }
    }
    Ok(foreign)
}

/// Why a directory holding `foreign` entries is refused: every one named (up to a few).
pub fn foreign_why(foreign: &[PathBuf], what: &str) -> String {
    let mut names: Vec<String> = foreign.iter().take(NAMED).map(|p| p.display().to_string()).collect();
    if foreign.len() > NAMED {
        names.push(format!("and {} more", foreign.len() - NAMED));
    }
    format!(
        "holds files mimo did not write ({}); {what} replaces only what mimo wrote: move them out first",
        names.join(", ")
    )
}

/// The refusal for `target` holding `foreign` entries.
pub fn refuse_foreign(target: &Path, foreign: &[PathBuf], what: &str) -> StoreError {
    StoreError::Refused { path: target.to_path_buf(), why: foreign_why(foreign, what) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn damaged_files_of_a_score_are_mimos_and_a_users_are_not() {
        let tmp = tempfile::tempdir().expect("tmp");
        let dir = ScoreDir::new(tmp.path().join("score"));
        std::fs::create_dir_all(dir.root()).expect("mkdir");
        let tm = dir.table(&crate::score_schema::SCORE_TABLES[0]);
        // A score table cut short: the magic, then nothing readable.
        std::fs::write(&tm, b"PAR1\x15\x04\x15").expect("write");
        std::fs::write(dir.summary(), "{\n  \"scenario\": \"7\",\n  \"runs\"").expect("write");
        let damaged = damaged_in_score_dir(&dir).expect("ls");
        assert_eq!(damaged, vec![dir.summary(), tm.clone()]);
        assert!(foreign_in_score_dir(&dir).expect("ls").is_empty());
        // A user's summary (valid JSON without mimo's keys) and a user's file under another name
        // stay foreign; so does a PAR1 file under a name that is not a score table's.
        std::fs::write(dir.summary(), "{}").expect("write");
        std::fs::write(dir.root().join("mine.parquet"), b"PAR1xx").expect("write");
        let foreign = foreign_in_score_dir(&dir).expect("ls");
        assert_eq!(foreign, vec![dir.root().join("mine.parquet"), dir.summary()]);
    }

    #[test]
    fn crc_of_a_known_chunk() {
        // The IEND chunk's CRC, fixed by the PNG specification.
        assert_eq!(crc32(b"IEND"), 0xae42_6082);
    }

    #[test]
    fn marked_images_are_recognised_and_others_are_not() {
        let tmp = tempfile::tempdir().expect("tmp");
        let png = tmp.path().join("m.png");
        let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
        bytes.extend_from_slice(&[0, 0, 0, 13]);
        bytes.extend_from_slice(b"IHDR");
        bytes.extend_from_slice(&[0; 17]);
        bytes.extend_from_slice(b"rest");
        std::fs::write(&png, &bytes).expect("write");
        assert!(!is_map_image(&png) && !is_chart_image(&png));
        mark_image(&png, MAP_MARK).expect("mark");
        let marked = std::fs::read(&png).expect("read");
        assert!(is_map_image(&png) && marked.starts_with(&bytes[..33]) && marked.ends_with(b"rest"));
        assert!(is_chart_image(&png), "a map is a chart mimo drew");
        let chart = tmp.path().join("c.png");
        std::fs::write(&chart, &bytes).expect("write");
        mark_image(&chart, CHART_MARK).expect("mark");
        assert!(is_chart_image(&chart) && !is_map_image(&chart));
        let svg = tmp.path().join("m.svg");
        std::fs::write(&svg, "<svg></svg>").expect("write");
        assert!(!is_chart_image(&svg));
        mark_image(&svg, MAP_MARK).expect("mark");
        assert!(is_map_image(&svg) && is_chart_image(&svg));
        let page = tmp.path().join("p.html");
        std::fs::write(&page, format!("<html><head>{PLOT_MARK}</head></html>")).expect("write");
        assert!(is_plot_page(&page) && !is_plot_page(&svg));
    }
}
