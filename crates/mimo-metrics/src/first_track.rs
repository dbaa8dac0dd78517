//! How soon targets are first tracked (docs/design.md §6, "Time to first track"): per run and
//! target scorable at some scoring time, the first scoring time it is scorable, the first at
//! which the assignment gives it a confirmed track, and the time between; and their summary
//! (mean and worst over the targets that got a track, and how many never did). Read from the
//! assignments, so at the resolution of the scoring interval.

use crate::{AssignmentRow, FirstTrackRow, FirstTrackSummary};
use std::collections::{BTreeMap, HashMap};

/// A target's first times in a run: (order of first appearance, scorable from, first track).
type FirstTimes = (usize, f64, Option<f64>);

/// The rows of `score/first_track.parquet`: by run, then by first scorable time, then in the
/// order the targets first appear in the assignments (truth-table order at a scoring time).
pub(crate) fn first_track_rows(assignments: &[AssignmentRow]) -> Vec<FirstTrackRow> {
    // Per run: target → (order of first appearance, scorable from, first track).
    let mut by_run: BTreeMap<u32, HashMap<&str, FirstTimes>> = BTreeMap::new();
    for a in assignments {
        let run = by_run.entry(a.run).or_default();
        let next = run.len();
        let e = run.entry(a.target.as_str()).or_insert((next, a.t_s, None));
        // Rows come in time order within a run, but take the least times whatever the order.
        e.1 = e.1.min(a.t_s);
        if a.track_id.is_some() {
            e.2 = Some(e.2.map_or(a.t_s, |t: f64| t.min(a.t_s)));
        }
    }
    let mut out = Vec::new();
    for (run, targets) in by_run {
        let mut rows: Vec<(&str, FirstTimes)> = targets.into_iter().collect();
        rows.sort_by(|a, b| a.1.1.total_cmp(&b.1.1).then(a.1.0.cmp(&b.1.0)));
        out.extend(rows.into_iter().map(|(target, (_, from, first))| FirstTrackRow {
            run,
            target_id: target.to_string(),
            scorable_from_s: from,
            first_track_s: first,
            time_to_first_track_s: first.map(|t| (t - from).max(0.0)),
        }));
    }
    out
}

/// The summary of some rows (one run's, or every run's).
pub(crate) fn first_track_summary<'a>(rows: impl Iterator<Item = &'a FirstTrackRow>) -> FirstTrackSummary {
    let mut s = FirstTrackSummary::default();
    let (mut sum, mut n) = (0.0, 0u32);
    for r in rows {
        s.targets += 1;
        match r.time_to_first_track_s {
            Some(t) => {
                sum += t;
                n += 1;
                s.max_s = Some(s.max_s.map_or(t, |m: f64| m.max(t)));
            }
            None => s.never_tracked += 1,
        }
    }
    s.mean_s = (n > 0).then(|| sum / f64::from(n));
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn a(run: u32, t_s: f64, target: &str, track: Option<u64>) -> AssignmentRow {
        AssignmentRow {
            run,
            t_s,
            target: target.into(),
            track_id: track,
            position_error_m: None,
            velocity_error_mps: None,
        }
    }

    #[test]
    fn times_to_first_track_of_a_hand_made_run() {
        // Run 0: A scorable from 1 s, tracked from 3 s (2 s); B scorable from 2 s, tracked at 2 s
        // (0 s), lost at 3 s; C scorable from 3 s, never tracked. Run 1: A scorable from 5 s,
        // tracked at 9 s (4 s).
        let rows = [
            a(0, 1.0, "A", None),
            a(0, 2.0, "A", None),
            a(0, 2.0, "B", Some(7)),
            a(0, 3.0, "A", Some(4)),
            a(0, 3.0, "B", None),
            a(0, 3.0, "C", None),
            a(1, 5.0, "A", None),
            a(1, 9.0, "A", Some(1)),
        ];
        let ft = first_track_rows(&rows);
        type Row<'a> = (u32, &'a str, f64, Option<f64>, Option<f64>);
        let got: Vec<Row> = ft
            .iter()
            .map(|r| (r.run, r.target_id.as_str(), r.scorable_from_s, r.first_track_s, r.time_to_first_track_s))
            .collect();
        assert_eq!(
            got,
            [
                (0, "A", 1.0, Some(3.0), Some(2.0)),
                (0, "B", 2.0, Some(2.0), Some(0.0)),
                (0, "C", 3.0, None, None),
                (1, "A", 5.0, Some(9.0), Some(4.0))
            ]
        );
        let run0 = first_track_summary(ft.iter().filter(|r| r.run == 0));
        assert_eq!(run0, FirstTrackSummary { targets: 3, mean_s: Some(1.0), max_s: Some(2.0), never_tracked: 1 });
        let all = first_track_summary(ft.iter());
        assert_eq!(all, FirstTrackSummary { targets: 4, mean_s: Some(2.0), max_s: Some(4.0), never_tracked: 1 });
        assert_eq!(first_track_summary(std::iter::empty()), FirstTrackSummary::default());
    }
}
