//! Failure points (docs/studies.md, "Where each method fails"): where a method's mean track
//! completeness on one stress axis falls through the requirement, interpolated between the grid
//! values, with a 95 % bootstrap interval over the Monte Carlo runs.
//!
//! The points of a sweep are ordered from the least to the most stressing value (the unstressed
//! value first in a plan that starts at the baseline). A point *holds* as in the challenge
//! ([`PointRuns::means`]): no run failed and the mean completeness, a failed run counting as 0,
//! reaches the requirement. The failure point lies between the last point that holds before the
//! first that does not and that one, interpolated linearly in mean completeness — on log10 of
//! the value for an axis drawn on a log scale (`pfa`). A sweep that holds at every point *holds
//! over the whole range*; one that does not hold at its first point *fails at the baseline*.
//!
//! The interval is the 95 % percentile interval of the failure point over bootstrap resamples
//! of the runs. When run `k` of every point shares its random draws (a study's common random
//! numbers), one resample of run indices is applied to every point, keeping the pairing;
//! otherwise each point is resampled on its own. A resample that holds everywhere ranks above
//! every value and one that fails at the baseline below, so an end of the interval can run off
//! either end of the grid.

use crate::bootstrap::{Replicate, percentile_95_ends};
use crate::challenge::{COMPLETENESS_REQUIRED, PointMeans, PointRuns};

/// One method's sweep of one axis on one scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepRuns {
    /// Axis values, from the least to the most stressing.
    pub values: Vec<f64>,
    /// Interpolate on log10 of the value (the axis is drawn on a log scale).
    pub log: bool,
    /// The runs of each point, in the order of `values`.
    pub points: Vec<PointRuns>,
}

/// Where a sweep falls through the requirement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Failure {
    /// At position `u` along the sweep (`0` the first point, `n − 1` the last; between points
    /// `i` and `i + 1` for `i ≤ u ≤ i + 1`).
    At(f64),
    /// Holds at every point: the failure point lies beyond the most stressing value.
    Holds,
    /// Does not hold at the least stressing value: the failure point lies before the sweep.
    FailsAtBaseline,
}

impl Failure {
    /// The status word of the tables.
    pub fn status(&self) -> &'static str {
        match self {
            Failure::At(_) => "crosses",
            Failure::Holds => "holds",
            Failure::FailsAtBaseline => "fails_at_baseline",
        }
    }

    fn replicate(&self) -> Replicate {
        match self {
            Failure::At(u) => Replicate::Value(*u),
            Failure::Holds => Replicate::Above,
            Failure::FailsAtBaseline => Replicate::Below,
        }
    }
}

/// The first fall through the requirement of `means` (points from the least stressing).
pub fn failure(means: &[PointMeans]) -> Failure {
    let Some(i) = means.iter().position(|m| !m.holds) else { return Failure::Holds };
    if i == 0 {
        return Failure::FailsAtBaseline;
    }
    let (a, b) = (means[i - 1].completeness.unwrap_or(0.0), means[i].completeness.unwrap_or(0.0));
    // Point i − 1 holds (a ≥ the requirement); point i may still reach it and fail on a run.
    let t = if a > b { ((a - COMPLETENESS_REQUIRED) / (a - b)).clamp(0.0, 1.0) } else { 1.0 };
    Failure::At((i - 1) as f64 + t)
}

/// Times the sweep changes between holding and not, from the least to the most stressing.
pub fn crossings(means: &[PointMeans]) -> u32 {
    means.windows(2).filter(|w| w[0].holds != w[1].holds).count() as u32
}

impl SweepRuns {
    fn coord(&self, v: f64) -> f64 {
        if self.log { v.log10() } else { v }
    }

    /// The axis value at position `u` along the sweep: linear between grid values, in log10 of
    /// the value on a log axis.
    pub fn value_at(&self, u: f64) -> f64 {
        let n = self.values.len();
        if n < 2 {
            return self.values.first().copied().unwrap_or(f64::NAN);
        }
        let i = (u.floor().max(0.0) as usize).min(n - 2);
        let t = u - i as f64;
        let x = self.coord(self.values[i]) + t * (self.coord(self.values[i + 1]) - self.coord(self.values[i]));
        if self.log { 10f64.powf(x) } else { x }
    }

    /// The means of every point `i` over its runs `idx(i)`.
    pub fn means(&self, idx: &dyn Fn(usize) -> Vec<usize>) -> Vec<PointMeans> {
        self.points.iter().enumerate().map(|(i, p)| p.means(&idx(i))).collect()
    }
}

/// Bootstrap resamples of run indices for the points of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub enum Resamples {
    /// One list of resamples applied to every point (runs paired across points).
    Paired(Vec<Vec<usize>>),
    /// Resamples of each point of its own: `[point][resample]`.
    Independent(Vec<Vec<Vec<usize>>>),
}

impl Resamples {
    fn count(&self) -> usize {
        match self {
            Resamples::Paired(r) => r.len(),
            Resamples::Independent(r) => r.first().map_or(0, Vec::len),
        }
    }

    fn get(&self, point: usize, b: usize) -> Vec<usize> {
        match self {
            Resamples::Paired(r) => r[b].clone(),
            Resamples::Independent(r) => r[point][b].clone(),
        }
    }
}

/// An end of a failure point's interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum End {
    /// Runs off the grid before the least stressing value.
    BeforeGrid,
    /// An axis value.
    Value(f64),
    /// Runs off the grid beyond the most stressing value.
    BeyondGrid,
}

/// A sweep's failure point and its interval.
#[derive(Debug, Clone, PartialEq)]
pub struct FailurePoint {
    /// Where the sweep falls through the requirement over every run.
    pub failure: Failure,
    /// The axis value there (`Failure::At` only).
    pub value: Option<f64>,
    /// The 95 % interval's ends, the less stressing first (`None`: no resample).
    pub interval: Option<(End, End)>,
    /// Times the curve changes between holding and not.
    pub crossings: u32,
    /// Resamples whose failure point lies inside the grid.
    pub resamples_crossing: u32,
}

/// The failure point of `s`, with its interval over `boot`.
pub fn failure_point(s: &SweepRuns, boot: &Resamples) -> FailurePoint {
    let all = |i: usize| (0..s.points[i].failed.len()).collect::<Vec<_>>();
    let means = s.means(&all);
    let point = failure(&means);
    let reps: Vec<Replicate> = (0..boot.count()).map(|b| failure(&s.means(&|i| boot.get(i, b))).replicate()).collect();
    let end = |r: Replicate| match r {
        Replicate::Value(u) => End::Value(s.value_at(u)),
        Replicate::Below => End::BeforeGrid,
        Replicate::Above | Replicate::Undefined => End::BeyondGrid,
    };
    FailurePoint {
        failure: point,
        value: match point {
            Failure::At(u) => Some(s.value_at(u)),
            _ => None,
        },
        interval: percentile_95_ends(&reps).map(|(lo, hi)| (end(lo), end(hi))),
        crossings: crossings(&means),
        resamples_crossing: reps.iter().filter(|r| matches!(r, Replicate::Value(_))).count() as u32,
    }
}

/// An interval in axis units, as the tables give it: the numerically lower and upper ends
/// (`None` where the end runs off the grid) and a word saying which ends are open.
pub fn numeric_interval(
    interval: Option<(End, End)>,
    larger_is_harder: bool,
) -> (Option<f64>, Option<f64>, &'static str) {
    let Some((a, b)) = interval else { return (None, None, "none") };
    // Stress order to numeric order: before the grid is below it when a larger value stresses more.
    let side = |e: End| match (e, larger_is_harder) {
        (End::Value(v), _) => (Some(v), 0),
        (End::BeforeGrid, true) | (End::BeyondGrid, false) => (None, -1),
        (End::BeforeGrid, false) | (End::BeyondGrid, true) => (None, 1),
    };
    let (mut lo, mut hi) = (side(a), side(b));
    if !larger_is_harder {
        std::mem::swap(&mut lo, &mut hi);
    }
    let word = match (lo.1, hi.1) {
        (0, 0) => "closed",
        (-1, 0) => "open_below",
        (0, 1) => "open_above",
        (-1, 1) => "open_both",
        (-1, -1) => "below_grid",
        _ => "above_grid",
    };
    (lo.0, hi.0, word)
}

#[cfg(test)]
#[path = "failure_point_tests.rs"]
mod tests;
