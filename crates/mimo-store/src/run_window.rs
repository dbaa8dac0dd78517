//! The time window of the run a table file belongs to (docs/design.md §3, §7): every `t_s` of
//! a run's tables (truth samples, dwell starts, detections, track states) lies in
//! `[0, duration_s]` of its manifest. The lower bound is the tables' column rule; the upper one
//! needs the run, found beside the file as `RUN/TABLE/run-K.parquet` → `RUN/manifest.json`
//! (the same layout that gives a file its run id). A file outside a finished run (no manifest
//! there yet: a run being written, a table on its own) is checked against the lower bound only.

use crate::manifest::{MANIFEST_FILE, MAX_MANIFEST_BYTES};
use std::cell::RefCell;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// Rounding allowed past the run's end (s): times are whole nanoseconds of the simulation clock.
pub const END_TOLERANCE_S: f64 = 1e-6;

/// A manifest as it was when read: path, length and modification time.
type Stamp = (PathBuf, u64, SystemTime);

thread_local! {
    /// The last manifest read on this thread and its `duration_s`: a file's batches read it once.
    static LAST: RefCell<Option<(Stamp, Option<f64>)>> = const { RefCell::new(None) };
}

/// Only the field wanted of a manifest (the others are the manifest reader's to check).
#[derive(serde::Deserialize)]
struct Duration {
    duration_s: f64,
}

/// The `duration_s` of the finished run holding the table file `path`, if it is a run's
/// `run-K.parquet` beside a readable manifest.
pub fn run_end_s(path: &Path) -> Option<f64> {
    crate::invariants::file_run(path)?;
    let manifest = path.parent()?.parent()?.join(MANIFEST_FILE);
    let meta = std::fs::metadata(&manifest).ok()?;
    if !meta.is_file() || meta.len() > MAX_MANIFEST_BYTES {
        return None;
    }
    let stamp: Stamp = (manifest, meta.len(), meta.modified().ok()?);
    if let Some(end) = LAST.with_borrow(|last| last.as_ref().filter(|(s, _)| *s == stamp).map(|(_, end)| *end)) {
        return end;
    }
    let end = std::fs::read(&stamp.0)
        .ok()
        .and_then(|bytes| serde_json::from_slice::<Duration>(&bytes).ok())
        .map(|d| d.duration_s)
        .filter(|d| d.is_finite());
    LAST.set(Some((stamp, end)));
    end
}

/// The first of `t_s` (file rows from `first_row`) after the run's end `end_s`, as its file row
/// and value.
pub fn first_after_end(t_s: &[f64], end_s: f64, first_row: usize) -> Option<(usize, f64)> {
    t_s.iter().position(|&t| t > end_s + END_TOLERANCE_S).map(|i| (first_row + i, t_s[i]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_files_run_end_is_its_manifests_duration() {
        let tmp = tempfile::tempdir().expect("tmp");
        let file = tmp.path().join("truth/run-0000.parquet");
        assert_eq!(run_end_s(&file), None, "no manifest: no upper bound");
        std::fs::create_dir_all(tmp.path().join("truth")).expect("mkdir");
        std::fs::write(tmp.path().join(MANIFEST_FILE), r#"{"duration_s": 60.0, "runs": 1}"#).expect("write");
        assert_eq!(run_end_s(&file), Some(60.0));
        assert_eq!(run_end_s(&tmp.path().join("truth/other.parquet")), None, "not a run's file");
        // A rewritten manifest is read again.
        std::fs::write(tmp.path().join(MANIFEST_FILE), r#"{"duration_s": 120.5, "runs": 2}"#).expect("write");
        assert_eq!(run_end_s(&file), Some(120.5));
        assert_eq!(first_after_end(&[0.0, 60.0, 60.0000005, 61.0], 60.0, 10), Some((13, 61.0)));
        assert_eq!(first_after_end(&[0.0, 60.0], 60.0, 0), None);
    }
}
