//! The track metrics of every run, from the truth and tracks tables: read whole, or part by part
//! ([`crate::parts`]). Both give the same rows, in run order.

use crate::load::{Truth, load_tracks, load_truth};
use crate::parts::{self, Part};
use crate::results::{AssignmentRow, TrackMetricsRow};
use crate::track_metrics::{self, RunInput, RunOutput, TargetTally, TargetTruth, TrackLife};
use crate::{MAX_SCORING_TIMES, MetricsError, ScoreInput, ScoreOptions};
use std::collections::{BTreeMap, BTreeSet};

/// Per-run track metrics of a recording, in run order.
pub(crate) struct TrackResults {
    /// The runs of the truth table, ascending.
    pub runs: Vec<u32>,
    /// Every target named in the truth table, sorted.
    pub target_names: Vec<String>,
    /// One row per run and scoring time.
    pub track_metrics: Vec<TrackMetricsRow>,
    /// Truth–track pairs per run and scoring time.
    pub assignments: Vec<AssignmentRow>,
    /// Tallies summed over runs, one per entry of `target_names`.
    pub tally: Vec<TargetTally>,
    /// Scorable truths per run and scoring time.
    pub n_scorable: BTreeMap<u32, Vec<u32>>,
}

/// At most [`MAX_SCORING_TIMES`] scoring times per run.
fn check_scoring_times(truth: &Truth, opts: &ScoreOptions) -> Result<(), MetricsError> {
    if let Some(t_end) = truth.t_end.values().copied().reduce(f64::max)
        && t_end / opts.interval_s > MAX_SCORING_TIMES
    {
        return Err(MetricsError::InvalidOption {
            option: "interval_s",
            value: opts.interval_s.to_string(),
            expected: "at least the run's last truth time / 10^7 (at most 10^7 scoring times per run)",
        });
    }
    Ok(())
}

/// Score the runs of `truth` against `tracks` on `threads` workers, outputs in run order.
fn score_runs(
    truth: &Truth,
    tracks: &BTreeMap<u32, Vec<TrackLife>>,
    input: &ScoreInput,
    opts: &ScoreOptions,
    threads: usize,
) -> Vec<RunOutput> {
    let empty_tracks: Vec<TrackLife> = Vec::new();
    let empty_targets: Vec<TargetTruth> = Vec::new();
    let run_inputs: Vec<RunInput<'_>> = truth
        .runs
        .iter()
        .map(|&run| RunInput {
            run,
            n_times: track_metrics::n_scoring_times(truth.t_end.get(&run).copied().unwrap_or(0.0), opts.interval_s),
            interval_s: opts.interval_s,
            gate_m: opts.gate_m,
            ospa_c_m: opts.ospa_c_m,
            ospa_p: opts.ospa_p,
            targets: truth.per_run.get(&run).unwrap_or(&empty_targets),
            target_names: &truth.target_names,
            tracks: tracks.get(&run).unwrap_or(&empty_tracks),
            scorable: &*input.scorable,
        })
        .collect();
    crate::parallel::parallel(&run_inputs, threads, &track_metrics::score_run)
}

fn add(acc: &mut TargetTally, t: &TargetTally) {
    acc.scorable += t.scorable;
    acc.assigned += t.assigned;
    acc.breaks += t.breaks;
    acc.switches += t.switches;
}

/// Every truth and tracks file read at once (the path that names errors).
pub(crate) fn track_results_whole(
    input: &ScoreInput,
    opts: &ScoreOptions,
    threads: usize,
) -> Result<TrackResults, MetricsError> {
    let truth = load_truth(&input.truth)?;
    check_scoring_times(&truth, opts)?;
    let run_set: BTreeSet<u32> = truth.runs.iter().copied().collect();
    let tracks = load_tracks(&input.tracks, &run_set)?;
    let outputs = score_runs(&truth, &tracks, input, opts, threads);
    let mut out = TrackResults {
        runs: truth.runs.clone(),
        target_names: truth.target_names.clone(),
        track_metrics: Vec::new(),
        assignments: Vec::new(),
        tally: vec![TargetTally::default(); truth.target_names.len()],
        n_scorable: BTreeMap::new(),
    };
    for (&run, o) in truth.runs.iter().zip(outputs) {
        out.n_scorable.insert(run, o.rows.iter().map(|r| r.n_scorable).collect());
        out.track_metrics.extend(o.rows);
        out.assignments.extend(o.assignments);
        for (acc, t) in out.tally.iter_mut().zip(&o.tally) {
            add(acc, t);
        }
    }
    Ok(out)
}

/// Part by part ([`crate::parts`]): `threads` parts at a time, each scored on one thread.
pub(crate) fn track_results_by_parts(
    split: &parts::Split,
    input: &ScoreInput,
    opts: &ScoreOptions,
    threads: usize,
) -> Result<TrackResults, MetricsError> {
    let all_runs = &split.truth_runs;
    let check = |t: &Truth| check_scoring_times(t, opts);
    let score = |t: &Truth, k: &BTreeMap<u32, Vec<TrackLife>>| score_runs(t, k, input, opts, 1);
    let results =
        crate::parallel::parallel(&split.parts, threads, &|p: &Part| parts::score_part(p, all_runs, &check, &score));
    let mut by_run: BTreeMap<u32, (RunOutput, BTreeMap<String, TargetTally>)> = BTreeMap::new();
    for r in results {
        for (run, o, tally) in r?.runs {
            by_run.insert(run, (o, tally));
        }
    }
    let names: BTreeSet<String> = by_run.values().flat_map(|(_, t)| t.keys().cloned()).collect();
    let target_names: Vec<String> = names.into_iter().collect();
    let index: BTreeMap<&str, usize> = target_names.iter().enumerate().map(|(i, n)| (n.as_str(), i)).collect();
    let mut out = TrackResults {
        runs: by_run.keys().copied().collect(),
        target_names: target_names.clone(),
        track_metrics: Vec::new(),
        assignments: Vec::new(),
        tally: vec![TargetTally::default(); target_names.len()],
        n_scorable: BTreeMap::new(),
    };
    for (run, (o, tally)) in by_run {
        out.n_scorable.insert(run, o.rows.iter().map(|r| r.n_scorable).collect());
        out.track_metrics.extend(o.rows);
        out.assignments.extend(o.assignments);
        for (name, t) in &tally {
            if let Some(&i) = index.get(name.as_str()) {
                add(&mut out.tally[i], t);
            }
        }
    }
    Ok(out)
}
