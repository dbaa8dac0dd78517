//! Truth–track assignment and the track metrics at each scoring time (one Monte Carlo run).
//!
//! Linear in the number of scoring times: truth states are found with a forward cursor per
//! target, and each track's live states are laid out over its own scoring times once
//! (Σ over tracks of rows + live scoring times), so nothing is rescanned per time.

use crate::ospa::ospa_gospa;
use crate::{AssignmentRow, TrackMetricsRow};
use glam::DVec3;
use mimo_core::assign_components::assign_with_miss_by_components;

/// Time tolerance (s) when comparing a scoring time with sample times.
const T_EPS: f64 = 1e-9;

/// One truth sample.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TruthSample {
    pub t: f64,
    pub p: DVec3,
    pub v: DVec3,
    pub alt: f64,
}

/// One target's truth in one run, samples sorted by time.
#[derive(Debug, Clone)]
pub(crate) struct TargetTruth {
    /// Index into the scenario-wide target name list.
    pub target: usize,
    pub samples: Vec<TruthSample>,
}

/// One track state row.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TrackState {
    pub t: f64,
    pub p: DVec3,
    pub v: DVec3,
}

/// One track of one run: its rows before its `deleted` row (sorted), when it was first
/// confirmed, and when it was deleted (∞ if never).
#[derive(Debug, Clone)]
pub(crate) struct TrackLife {
    pub id: u64,
    pub t_confirm: f64,
    pub t_delete: f64,
    pub states: Vec<TrackState>,
}

/// Everything the per-run loop needs.
pub(crate) struct RunInput<'a> {
    pub run: u32,
    pub n_times: usize,
    pub interval_s: f64,
    pub gate_m: f64,
    pub ospa_c_m: f64,
    pub ospa_p: f64,
    pub targets: &'a [TargetTruth],
    pub target_names: &'a [String],
    pub tracks: &'a [TrackLife],
    pub scorable: &'a (dyn Fn(f64, DVec3, f64) -> bool + Sync),
}

/// Per-target tallies of one run (indexed by scenario-wide target index).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct TargetTally {
    pub scorable: u64,
    pub assigned: u64,
    pub breaks: u64,
    pub switches: u64,
}

/// The result of one run.
pub(crate) struct RunOutput {
    pub rows: Vec<TrackMetricsRow>,
    pub assignments: Vec<AssignmentRow>,
    pub tally: Vec<TargetTally>,
}

/// Scoring time `k` (1-based): `k · interval_s`.
pub(crate) fn scoring_time(k: usize, interval_s: f64) -> f64 {
    k as f64 * interval_s
}

/// Number of scoring times `1..=K` such that `K · interval_s <= t_end` (with a tolerance).
pub(crate) fn n_scoring_times(t_end: f64, interval_s: f64) -> usize {
    if t_end.is_nan() || t_end < interval_s - T_EPS {
        return 0;
    }
    let mut k = (t_end / interval_s).floor() as usize;
    while scoring_time(k + 1, interval_s) <= t_end + T_EPS {
        k += 1;
    }
    while k > 0 && scoring_time(k, interval_s) > t_end + T_EPS {
        k -= 1;
    }
    k
}

/// Truth state at `t` by cubic Hermite interpolation of position (with the sampled velocities)
/// and linear interpolation of velocity and altitude. `None` outside the sampled span.
pub(crate) fn truth_at(samples: &[TruthSample], cursor: &mut usize, t: f64) -> Option<(DVec3, DVec3, f64)> {
    let first = samples.first()?;
    let last = samples.last()?;
    if t < first.t - T_EPS || t > last.t + T_EPS {
        return None;
    }
    while *cursor + 1 < samples.len() && samples[*cursor + 1].t <= t {
        *cursor += 1;
    }
    let a = samples[*cursor];
    if *cursor + 1 >= samples.len() || (t - a.t).abs() <= T_EPS {
        return Some((a.p, a.v, a.alt));
    }
    let b = samples[*cursor + 1];
    let h = b.t - a.t;
    if h <= 0.0 {
        return Some((a.p, a.v, a.alt));
    }
    let s = ((t - a.t) / h).clamp(0.0, 1.0);
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    let p = a.p * h00 + a.v * (h10 * h) + b.p * h01 + b.v * (h11 * h);
    let v = a.v + (b.v - a.v) * s;
    let alt = a.alt + (b.alt - a.alt) * s;
    Some((p, v, alt))
}

#[derive(Debug, Clone, Copy)]
struct LiveTrack {
    id: u64,
    p: DVec3,
    v: DVec3,
}

/// Lay every track's extrapolated state out over the scoring times at which it is live.
fn live_tracks(tracks: &[TrackLife], n_times: usize, interval_s: f64) -> Vec<Vec<LiveTrack>> {
    let mut live: Vec<Vec<LiveTrack>> = vec![Vec::new(); n_times + 1];
    for tr in tracks {
        if tr.states.is_empty() || !tr.t_confirm.is_finite() {
            continue;
        }
        // First scoring time at or after confirmation.
        let mut k = ((tr.t_confirm / interval_s).ceil().max(1.0)) as usize;
        while k > 1 && scoring_time(k - 1, interval_s) >= tr.t_confirm {
            k -= 1;
        }
        while scoring_time(k, interval_s) < tr.t_confirm {
            k += 1;
        }
        let mut r = 0;
        while k <= n_times {
            let t = scoring_time(k, interval_s);
            if t >= tr.t_delete {
                break;
            }
            while r + 1 < tr.states.len() && tr.states[r + 1].t <= t {
                r += 1;
            }
            let s = tr.states[r];
            live[k].push(LiveTrack { id: tr.id, p: s.p + s.v * (t - s.t), v: s.v });
            k += 1;
        }
    }
    live
}

fn ratio(num: u32, den: u32) -> Option<f64> {
    (den > 0).then(|| f64::from(num) / f64::from(den))
}

/// The truths present at one scoring time and their distances to the live tracks.
#[derive(Default)]
struct Scene {
    /// (local target, position, velocity, scorable) of each truth present.
    present: Vec<(usize, DVec3, DVec3, bool)>,
    /// Distance of present truth i to live track j at `i * m + j`.
    dist: Vec<f64>,
    /// The present truths that are scorable (indices into `present`).
    scorable: Vec<usize>,
    /// Live tracks.
    m: usize,
}

impl Scene {
    /// The truths present at `t` (`cursors` advance through each target's samples) and their
    /// distances to `tracks`.
    fn fill(&mut self, input: &RunInput<'_>, cursors: &mut [usize], t: f64, tracks: &[LiveTrack]) {
        self.present.clear();
        for (li, tt) in input.targets.iter().enumerate() {
            if let Some((p, v, alt)) = truth_at(&tt.samples, &mut cursors[li], t) {
                let ok = (input.scorable)(t, p, alt);
                self.present.push((li, p, v, ok));
            }
        }
        self.m = tracks.len();
        self.dist.clear();
        self.dist.reserve(self.present.len() * self.m);
        for &(_, p, _, _) in &self.present {
            self.dist.extend(tracks.iter().map(|tr| p.distance(tr.p)));
        }
        self.scorable.clear();
        self.scorable.extend((0..self.present.len()).filter(|&i| self.present[i].3));
    }

    /// Gated optimal assignment of the scorable truths to the tracks: maximum cardinality first,
    /// then minimum total distance. The track of each scorable truth, in `scorable` order.
    fn assign(&self, gate: f64, cost: &mut Vec<f64>) -> Vec<Option<usize>> {
        let (n, m) = (self.scorable.len(), self.m);
        cost.clear();
        for &i in &self.scorable {
            cost.extend(self.dist[i * m..(i + 1) * m].iter().map(|&d| if d <= gate { d } else { f64::INFINITY }));
        }
        let miss = gate * ((n.min(m) + 1) as f64);
        // Pairs form only inside the gate: each component of the gated graph is solved alone.
        assign_with_miss_by_components(cost, n, m, &vec![miss; n])
    }

    /// Redundant tracks (unassigned, inside the gate of some scorable truth) and spurious tracks
    /// (inside the gate of no truth at all, scorable or not).
    fn redundant_and_spurious(&self, track_assigned: &[bool], gate: f64) -> (u32, u32) {
        let m = self.m;
        let (mut n_redundant, mut n_spurious) = (0u32, 0u32);
        for (j, &assigned) in track_assigned.iter().enumerate() {
            let near_scorable = self.scorable.iter().any(|&i| self.dist[i * m + j] <= gate);
            if !assigned && near_scorable {
                n_redundant += 1;
            }
            if !(0..self.present.len()).any(|i| self.dist[i * m + j] <= gate) {
                n_spurious += 1;
            }
        }
        (n_redundant, n_spurious)
    }
}

/// What one scoring time's assignment gave: counts, squared-error sums, the redundant and
/// spurious tracks, and the run's cumulative breaks and switches so far.
#[derive(Default)]
struct Assigned {
    n_assigned: u32,
    breaks: u32,
    switches: u32,
    pos_sq: f64,
    vel_sq: f64,
    n_redundant: u32,
    n_spurious: u32,
    cum_breaks: u32,
    cum_switches: u32,
}

/// The state a run's scoring carries from one scoring time to the next, and its output.
struct RunScorer<'a, 'i> {
    input: &'a RunInput<'i>,
    /// Per local target: assigned at the previous scoring time, and the last track assigned.
    prev_assigned: Vec<bool>,
    last_track: Vec<Option<u64>>,
    tally: Vec<TargetTally>,
    assignments: Vec<AssignmentRow>,
    cum_breaks: u32,
    cum_switches: u32,
}

impl RunScorer<'_, '_> {
    /// Record the assignment `sol` at time `t`: per-target breaks, switches and tallies, the
    /// assignment rows, and which tracks were taken (`track_assigned`).
    fn record(
        &mut self,
        scene: &Scene,
        sol: &[Option<usize>],
        tracks: &[LiveTrack],
        t: f64,
        track_assigned: &mut [bool],
    ) -> Assigned {
        let input = self.input;
        let mut a = Assigned::default();
        let mut is_scorable_now = vec![false; input.targets.len()];
        for (row, &i) in scene.scorable.iter().enumerate() {
            let (li, _, v, _) = scene.present[i];
            is_scorable_now[li] = true;
            let target = input.targets[li].target;
            self.tally[target].scorable += 1;
            let (track_id, pe, ve) = match sol[row] {
                Some(j) => {
                    track_assigned[j] = true;
                    a.n_assigned += 1;
                    self.tally[target].assigned += 1;
                    let tr = tracks[j];
                    let pe = scene.dist[i * scene.m + j];
                    let ve = v.distance(tr.v);
                    a.pos_sq += pe * pe;
                    a.vel_sq += ve * ve;
                    if self.last_track[li].is_some_and(|id| id != tr.id) {
                        a.switches += 1;
                        self.tally[target].switches += 1;
                    }
                    self.last_track[li] = Some(tr.id);
                    self.prev_assigned[li] = true;
                    (Some(tr.id), Some(pe), Some(ve))
                }
                None => {
                    if self.prev_assigned[li] {
                        a.breaks += 1;
                        self.tally[target].breaks += 1;
                    }
                    self.prev_assigned[li] = false;
                    (None, None, None)
                }
            };
            self.assignments.push(AssignmentRow {
                run: input.run,
                t_s: t,
                target: input.target_names[target].clone(),
                track_id,
                position_error_m: pe,
                velocity_error_mps: ve,
            });
        }
        // A truth that is absent or not scorable now was not assigned at this time.
        for (li, s) in is_scorable_now.iter().enumerate() {
            if !s {
                self.prev_assigned[li] = false;
            }
        }
        self.cum_breaks += a.breaks;
        self.cum_switches += a.switches;
        (a.cum_breaks, a.cum_switches) = (self.cum_breaks, self.cum_switches);
        a
    }
}

/// The row of scoring time `k` (time `t`).
fn metrics_row(
    input: &RunInput<'_>,
    (k, t): (usize, f64),
    scene: &Scene,
    a: &Assigned,
    og: Option<crate::ospa::OspaGospa>,
) -> TrackMetricsRow {
    let (n, m) = (scene.scorable.len() as u32, scene.m as u32);
    let (n_assigned, n_redundant, n_spurious) = (a.n_assigned, a.n_redundant, a.n_spurious);
    TrackMetricsRow {
        run: input.run,
        k: k as u32,
        t_s: t,
        n_truths: scene.present.len() as u32,
        n_scorable: n,
        n_tracks: m,
        n_assigned,
        n_redundant,
        n_spurious,
        completeness: ratio(n_assigned, n),
        redundant_ratio: ratio(n_redundant, n),
        spurious_ratio: ratio(n_spurious, m),
        breaks: a.breaks,
        switches: a.switches,
        cum_breaks: a.cum_breaks,
        cum_switches: a.cum_switches,
        position_sq_sum_m2: a.pos_sq,
        velocity_sq_sum_m2ps2: a.vel_sq,
        position_rmse_m: (n_assigned > 0).then(|| (a.pos_sq / f64::from(n_assigned)).sqrt()),
        velocity_rmse_mps: (n_assigned > 0).then(|| (a.vel_sq / f64::from(n_assigned)).sqrt()),
        ospa_m: og.map(|o| o.ospa_m),
        gospa_m: og.map(|o| o.gospa_m),
        gospa_localisation_m: og.map(|o| o.gospa_localisation_m),
        gospa_missed: og.map(|o| o.gospa_missed),
        gospa_false: og.map(|o| o.gospa_false),
    }
}

/// Score one run: at each scoring time, the truths present ([`Scene::fill`]), their gated
/// optimal assignment to the live tracks ([`Scene::assign`]), breaks, switches and assignment
/// rows ([`RunScorer::record`]), redundant and spurious tracks, OSPA/GOSPA, and the row.
pub(crate) fn score_run(input: &RunInput<'_>) -> RunOutput {
    let live = live_tracks(input.tracks, input.n_times, input.interval_s);
    let n_local = input.targets.len();
    let mut s = RunScorer {
        input,
        prev_assigned: vec![false; n_local],
        last_track: vec![None; n_local],
        tally: vec![TargetTally::default(); input.target_names.len()],
        assignments: Vec::new(),
        cum_breaks: 0,
        cum_switches: 0,
    };
    let mut cursors = vec![0usize; n_local];
    let mut rows = Vec::with_capacity(input.n_times);
    // Scratch buffers reused across scoring times.
    let (mut scene, mut cost) = (Scene::default(), Vec::new());
    let (mut truth_pos, mut track_pos): (Vec<DVec3>, Vec<DVec3>) = (Vec::new(), Vec::new());
    for (k, tracks) in live.iter().enumerate().skip(1) {
        let t = scoring_time(k, input.interval_s);
        scene.fill(input, &mut cursors, t, tracks);
        let sol = scene.assign(input.gate_m, &mut cost);
        let mut track_assigned = vec![false; scene.m];
        let mut a = s.record(&scene, &sol, tracks, t, &mut track_assigned);
        (a.n_redundant, a.n_spurious) = scene.redundant_and_spurious(&track_assigned, input.gate_m);
        truth_pos.clear();
        truth_pos.extend(scene.scorable.iter().map(|&i| scene.present[i].1));
        track_pos.clear();
        track_pos.extend(tracks.iter().map(|tr| tr.p));
        let any = !scene.scorable.is_empty() || scene.m > 0;
        let og = any.then(|| ospa_gospa(&truth_pos, &track_pos, input.ospa_c_m, input.ospa_p));
        rows.push(metrics_row(input, (k, t), &scene, &a, og));
    }
    RunOutput { rows, assignments: s.assignments, tally: s.tally }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scoring_time_count() {
        assert_eq!(n_scoring_times(1000.0, 1.0), 1000);
        assert_eq!(n_scoring_times(999.9, 1.0), 999);
        assert_eq!(n_scoring_times(0.5, 1.0), 0);
        assert_eq!(n_scoring_times(0.3, 0.1), 3);
        assert_eq!(n_scoring_times(f64::NAN, 1.0), 0);
    }

    #[test]
    fn hermite_is_exact_for_constant_acceleration_endpoints() {
        let a = TruthSample { t: 0.0, p: DVec3::ZERO, v: DVec3::X * 100.0, alt: 0.0 };
        let b = TruthSample { t: 1.0, p: DVec3::X * 100.0, v: DVec3::X * 100.0, alt: 10.0 };
        let mut c = 0;
        let (p, v, alt) = truth_at(&[a, b], &mut c, 0.25).expect("inside");
        assert!((p.x - 25.0).abs() < 1e-12 && (v.x - 100.0).abs() < 1e-12 && (alt - 2.5).abs() < 1e-12);
        assert!(truth_at(&[a, b], &mut c, 1.5).is_none());
    }
}
