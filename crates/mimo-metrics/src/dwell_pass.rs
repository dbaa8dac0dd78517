//! The one read of the dwells table a score makes (docs/design.md §6): each file read once by
//! the dwells table's streaming reader ([`crate::dwell_file::file_pass`], over
//! `mimo_store::dwell_chunks`: from the pages of the store's layout, with the Arrow reader for
//! any other) into both the usage sums ([`crate::dwell_sums`]) and the usage by purpose's rows
//! ([`crate::purpose`]), the latter classified in the same worker. A file whose values break a
//! check is read again by the checked readers of each ([`crate::load::dwell_file_sums`],
//! [`crate::purpose::read_rows`]), so that an error names the same file, column and row as
//! ever, and in the same order: every usage-sum error (in file order) before the usage by
//! purpose's (docs/decisions/0299-one-pass-dwell-reader.md,
//! docs/decisions/0322-one-streaming-reader-of-the-dwells-table.md).

use crate::MetricsError;
use crate::dwell_sums::{DWELL_SLICE_ROWS, DwellSums};
use crate::purpose::{FilePurposeSums, PurposeInput, PurposeSums, TruthFiles};
use mimo_core::records::DwellRow;
use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// One file's results: its usage sums, and its sums by purpose unless the usage sums failed (or
/// the truth files could not be read).
type FileResult = (Result<DwellSums, MetricsError>, Option<Result<FilePurposeSums, MetricsError>>);

/// The dwells read once: per file, its usage sums and sums by purpose.
pub(crate) struct DwellPass {
    paths_given: bool,
    per_file: Vec<FileResult>,
    truth_files: Result<TruthFiles, MetricsError>,
}

impl DwellPass {
    /// Read every dwells file of `input` (by `input.threads` workers, one file each at a time)
    /// for the runs `runs`.
    pub(crate) fn run(input: &PurposeInput<'_>, runs: &BTreeSet<u32>) -> DwellPass {
        let truth_files = crate::purpose::truth_files(input);
        let per_file = crate::parallel::parallel(input.dwells, input.threads, &|path: &PathBuf| {
            file(path, runs, input, truth_files.as_ref().ok())
        });
        DwellPass { paths_given: !input.dwells.is_empty(), per_file, truth_files }
    }

    /// One run's dwells reduced in memory ([`crate::dwell_rows`]) in place of its files: the
    /// same sums, classified with the truth files of `input` as a file's rows are.
    pub(crate) fn from_rows(input: &PurposeInput<'_>, rows: crate::dwell_rows::DwellRows) -> DwellPass {
        let truth_files = crate::purpose::truth_files(input);
        let result: FileResult = match rows.finish() {
            Ok((sums, rows)) => {
                let purpose = truth_files.as_ref().ok().map(|truth| crate::purpose::classify(rows, input, truth));
                (Ok(sums), purpose)
            }
            Err(e) => (Err(e), None),
        };
        DwellPass { paths_given: true, per_file: vec![result], truth_files }
    }

    /// The dwells table reduced to what the usage figures need: the transmit sums per run, radar
    /// and scoring interval ([`DwellSums`]), and every radar named in it (any role).
    ///
    /// Each file is checked and reduced to its sums in one pass ([`crate::dwell_sums`]), in
    /// slices of [`DWELL_SLICE_ROWS`] rows; the results are taken in file order, so the first bad
    /// file in that order is the one named. The per-file sums are summed again by key, so a run
    /// split over several files gives the same figures (to rounding). The groups come out in the
    /// order a single pass over all dwells would give (order of first appearance); a sum whose
    /// interval straddles two slices may differ from that pass's in the last bit (measured: 16 of
    /// 8 000 per-interval values of a 2000-s scenario-7 run, at most 2.2e-16 relative).
    pub(crate) fn usage_sums(&mut self) -> Result<(DwellSums, BTreeSet<String>), MetricsError> {
        if !self.paths_given {
            return Err(crate::load::no_dwells());
        }
        let mut sums = DwellSums::default();
        for (file_sums, _) in &mut self.per_file {
            sums.add(std::mem::replace(file_sums, Ok(DwellSums::default()))?);
        }
        let radars = sums.radars();
        Ok((sums, radars))
    }

    /// The sums by purpose of every file summed by key in file order (after
    /// [`Self::usage_sums`], whose errors come first).
    pub(crate) fn purpose_sums(self) -> Result<PurposeSums, MetricsError> {
        self.truth_files?;
        let per_file = self.per_file.into_iter().map(|(_, purpose)| {
            // Only missing when the usage sums or the truth files failed, each reported before.
            purpose.unwrap_or_else(|| Err(crate::load::no_dwells()))
        });
        crate::purpose::merge(per_file.collect())
    }
}

/// One dwells file read once; read again by each checked reader when the pass gives up.
fn file(path: &Path, runs: &BTreeSet<u32>, input: &PurposeInput<'_>, truth: Option<&TruthFiles>) -> FileResult {
    if let Err(e) = crate::read::file_rows(DwellRow::TABLE, path) {
        return (Err(e), None);
    }
    let of_file = crate::load::runs_of_file(path, runs);
    let runs_here = of_file.as_ref().unwrap_or(runs);
    if let Some((sums, rows)) = crate::dwell_file::file_pass(path, runs_here, input.interval_s, DWELL_SLICE_ROWS) {
        return (Ok(sums), truth.map(|truth| crate::purpose::classify(rows, input, truth)));
    }
    let sums = crate::load::dwell_file_sums(path, runs, input.interval_s);
    let purpose = match (&sums, truth) {
        (Ok(_), Some(truth)) => Some(
            crate::purpose::read_rows(path, input.interval_s)
                .and_then(|rows| crate::purpose::classify(rows, input, truth)),
        ),
        _ => None,
    };
    (sums, purpose)
}
