//! Scoring the truth and tracks tables part by part, so that memory follows one run, not the
//! recording.
//!
//! The track metrics of a run need that run's truth and tracks only. The tables' files are
//! grouped into *parts*: sets of truth and tracks files connected by the runs they name (a part
//! is the smallest set of files that holds every row of its runs). A standard recording (one file
//! per run and table) has one part per run; a table written as one file for all runs makes a
//! single part, which is scored as the whole recording always was. The parts are loaded, checked
//! and scored by `threads` workers, each holding one part at a time, and the per-run results are
//! put back in run order, so the outputs are those of scoring everything at once.
//!
//! Errors are reported by the whole-recording path ([`crate::score`] falls back to it when
//! anything here fails), so a bad file is named exactly as before, whatever its part.

use crate::MetricsError;
use crate::load::{Truth, load_tracks, load_truth};
use crate::read::{Check, col as rcol, read_file};
use crate::track_metrics::{RunOutput, TargetTally};
use mimo_core::records::{TrackRow, TruthRow};
use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

/// Files whose runs connect them.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct Part {
    /// Truth files, in the order given.
    pub truth: Vec<PathBuf>,
    /// Tracks files, in the order given.
    pub tracks: Vec<PathBuf>,
}

/// The runs named in one file's `run` column.
fn file_runs(table: &'static str, path: &std::path::Path) -> Result<BTreeSet<u32>, MetricsError> {
    let run = TruthRow::COLUMNS.run;
    let df = read_file(table, path, &[rcol(run, Check::Any)])?;
    let runs = df.u32s(run)?;
    Ok(runs.iter().copied().collect())
}

/// Union–find root with path halving.
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// Group files into parts from the runs each names (`truth_runs[i]` for `truth[i]`, …). Files
/// that name no run (empty files) join the first part, so that they are still read and checked.
/// `None` when the split would not be exact: a tracks file naming a run that no truth file has
/// (an input error the whole read reports), or fewer than two parts (nothing to gain).
pub(crate) fn group(
    truth: &[PathBuf],
    truth_runs: &[BTreeSet<u32>],
    tracks: &[PathBuf],
    tracks_runs: &[BTreeSet<u32>],
) -> Option<Vec<Part>> {
    let known: BTreeSet<u32> = truth_runs.iter().flatten().copied().collect();
    if tracks_runs.iter().flatten().any(|r| !known.contains(r)) {
        return None;
    }
    let n = truth.len() + tracks.len();
    let mut parent: Vec<usize> = (0..n).collect();
    let mut first_file_of_run: BTreeMap<u32, usize> = BTreeMap::new();
    let all_runs = truth_runs.iter().chain(tracks_runs);
    for (file, runs) in all_runs.enumerate() {
        for &run in runs {
            let other = *first_file_of_run.entry(run).or_insert(file);
            let (a, b) = (root(&mut parent, file), root(&mut parent, other));
            parent[a.max(b)] = a.min(b);
        }
    }
    // Parts in the order of their smallest run; files keep their given order inside a part.
    let mut part_of_root: BTreeMap<usize, usize> = BTreeMap::new();
    let mut roots_by_run: Vec<usize> = Vec::new();
    for &file in first_file_of_run.values() {
        let r = root(&mut parent, file);
        if let std::collections::btree_map::Entry::Vacant(e) = part_of_root.entry(r) {
            e.insert(roots_by_run.len());
            roots_by_run.push(r);
        }
    }
    if roots_by_run.len() < 2 {
        return None;
    }
    let mut parts = vec![Part::default(); roots_by_run.len()];
    let runs_of = |file: usize| if file < truth.len() { &truth_runs[file] } else { &tracks_runs[file - truth.len()] };
    for file in 0..n {
        let p = if runs_of(file).is_empty() { 0 } else { part_of_root[&root(&mut parent, file)] };
        if file < truth.len() {
            parts[p].truth.push(truth[file].clone());
        } else {
            parts[p].tracks.push(tracks[file - truth.len()].clone());
        }
    }
    Some(parts)
}

/// A recording's parts and every run its truth table names.
pub(crate) struct Split {
    /// The parts, in the order of their smallest run.
    pub parts: Vec<Part>,
    /// Every run of the truth table.
    pub truth_runs: BTreeSet<u32>,
}

/// Read the `run` column of every truth and tracks file and group the files into parts
/// ([`group`]); `None` when the recording is not worth splitting or cannot be split exactly.
pub(crate) fn split(truth: &[PathBuf], tracks: &[PathBuf]) -> Result<Option<Split>, MetricsError> {
    // No tracks file at all is an input error the whole read reports.
    if truth.len() < 2 || tracks.is_empty() {
        return Ok(None);
    }
    let truth_runs = truth.iter().map(|p| file_runs(TruthRow::TABLE, p)).collect::<Result<Vec<_>, _>>()?;
    let tracks_runs = tracks.iter().map(|p| file_runs(TrackRow::TABLE, p)).collect::<Result<Vec<_>, _>>()?;
    Ok(group(truth, &truth_runs, tracks, &tracks_runs)
        .map(|parts| Split { parts, truth_runs: truth_runs.into_iter().flatten().collect() }))
}

/// One part scored: its runs' outputs, with each run's tally keyed by target name.
pub(crate) struct PartOutput {
    /// (run, output, tally by target name) in run order.
    pub runs: Vec<(u32, RunOutput, BTreeMap<String, TargetTally>)>,
}

/// Scores the runs of a part's truth against its tracks.
pub(crate) type ScoreRuns<'a> =
    dyn Fn(&Truth, &BTreeMap<u32, Vec<crate::track_metrics::TrackLife>>) -> Vec<RunOutput> + Sync + 'a;

/// Load one part and score its runs with `score_runs` (which gets the part's truth and tracks).
pub(crate) fn score_part(
    part: &Part,
    all_runs: &BTreeSet<u32>,
    check_truth: &(dyn Fn(&Truth) -> Result<(), MetricsError> + Sync),
    score_runs: &ScoreRuns<'_>,
) -> Result<PartOutput, MetricsError> {
    let truth = load_truth(&part.truth)?;
    check_truth(&truth)?;
    let tracks = if part.tracks.is_empty() { BTreeMap::new() } else { load_tracks(&part.tracks, all_runs)? };
    let outputs = score_runs(&truth, &tracks);
    let runs = truth
        .runs
        .iter()
        .zip(outputs)
        .map(|(&run, mut out)| {
            let tally: BTreeMap<String, TargetTally> =
                truth.target_names.iter().cloned().zip(std::mem::take(&mut out.tally)).collect();
            (run, out, tally)
        })
        .collect();
    Ok(PartOutput { runs })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn paths(prefix: &str, n: usize) -> Vec<PathBuf> {
        (0..n).map(|i| PathBuf::from(format!("{prefix}{i}"))).collect()
    }
    fn runs(v: &[&[u32]]) -> Vec<BTreeSet<u32>> {
        v.iter().map(|r| r.iter().copied().collect()).collect()
    }

    #[test]
    fn one_file_per_run_gives_one_part_per_run() {
        let (t, k) = (paths("t", 3), paths("k", 3));
        let parts = group(&t, &runs(&[&[0], &[1], &[2]]), &k, &runs(&[&[0], &[1], &[2]])).expect("split");
        assert_eq!(parts.len(), 3);
        for (i, p) in parts.iter().enumerate() {
            assert_eq!(p.truth, vec![t[i].clone()]);
            assert_eq!(p.tracks, vec![k[i].clone()]);
        }
    }

    #[test]
    fn files_sharing_runs_are_one_part_in_their_order() {
        // Truth of runs 0 and 2 in one file, run 1 alone; one tracks file for runs 1 and 3.
        let (t, k) = (paths("t", 3), paths("k", 2));
        let parts = group(&t, &runs(&[&[0, 2], &[1], &[3]]), &k, &runs(&[&[2], &[1, 3]])).expect("split");
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0], Part { truth: vec![t[0].clone()], tracks: vec![k[0].clone()] });
        assert_eq!(parts[1], Part { truth: vec![t[1].clone(), t[2].clone()], tracks: vec![k[1].clone()] });
    }

    #[test]
    fn empty_files_join_the_first_part() {
        let (t, k) = (paths("t", 3), paths("k", 3));
        let parts = group(&t, &runs(&[&[5], &[], &[4]]), &k, &runs(&[&[], &[4], &[5]])).expect("split");
        assert_eq!(parts.len(), 2);
        // Run 4 comes first (parts in the order of their smallest run).
        assert_eq!(parts[0].truth, vec![t[1].clone(), t[2].clone()]);
        assert_eq!(parts[0].tracks, vec![k[0].clone(), k[1].clone()]);
        assert_eq!(parts[1], Part { truth: vec![t[0].clone()], tracks: vec![k[2].clone()] });
    }

    #[test]
    fn no_split_for_an_unknown_run_or_a_single_part() {
        let (t, k) = (paths("t", 2), paths("k", 2));
        assert!(group(&t, &runs(&[&[0], &[1]]), &k, &runs(&[&[0], &[7]])).is_none());
        assert!(group(&t, &runs(&[&[0, 1], &[1]]), &k, &runs(&[&[0], &[1]])).is_none());
    }
}
