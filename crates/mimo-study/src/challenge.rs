//! The challenge figures of a family (docs/studies.md, "The challenge"): where its efficient
//! frontier ([`crate::frontier`], on the energy its study's plan names:
//! [`crate::frontier_energy`]) crosses the required completeness, and the total energy, dwell
//! time and power per scorable object there (search and test article), the test article's part
//! of each and the time to first track of the worst target, with bootstrap intervals over the
//! Monte Carlo runs; and the paired ratio of two families' energies.
//!
//! A point *holds* when none of its runs failed and its mean completeness (a failed run counting
//! as 0) reaches the requirement. The crossing lies between the first frontier point that holds
//! and the frontier point before it, interpolated linearly in completeness. Each bootstrap
//! resample of the runs rebuilds the frontier from its own means and re-reads the crossing on
//! it; a figure's interval runs from the 2.5 % point of the resamples' lower bracketing values to
//! the 97.5 % point of their upper ones, so that it holds the grid's part (where between its two
//! points a monotone frontier crosses) as well as the spread of the runs. The paired ratio's
//! interval is the bootstrap's alone: two families on the same grid share its error.
//! A family that holds already at its cheapest frontier point has its crossing below the swept
//! range, one that holds nowhere above it, and one point (an unswept method) draws no curve: the
//! figures are then null with a reason.

use crate::bootstrap::{Replicate, percentile_95};
pub use crate::frontier::Crossing;
use crate::frontier::{crossing_on, frontier};
pub use crate::frontier_energy::FrontierEnergy;

/// The completeness the challenge requires.
pub use crate::charts::COMPLETENESS_REQUIRED;

/// Index in [`PointRuns::figures`] and [`PointMeans::figures`]: total energy per object (J).
pub const RUN_ENERGY: usize = 0;
/// Total dwell time per object (s).
pub const RUN_DWELL: usize = 1;
/// TA energy per object (J).
pub const RUN_TA_ENERGY: usize = 2;
/// TA dwell time per object (s).
pub const RUN_TA_DWELL: usize = 3;
/// Time to first track of the run's worst target (s).
pub const RUN_FIRST_TRACK_MAX: usize = 4;
/// Per-run figures of a point.
pub const RUN_FIGURES: usize = 5;

/// One point of a family: per Monte Carlo run `k` (index `k`), its figures.
#[derive(Debug, Clone, PartialEq)]
pub struct PointRuns {
    /// The method's name.
    pub method: String,
    /// The knob value of a one-knob family (`None` for an unswept family or a grid).
    pub knob: Option<f64>,
    /// Whether run `k` failed.
    pub failed: Vec<bool>,
    /// Completeness of run `k` (`None`: failed or undefined).
    pub completeness: Vec<Option<f64>>,
    /// Per figure (`RUN_ENERGY`, …), its value in run `k`.
    pub figures: [Vec<Option<f64>>; RUN_FIGURES],
}

/// Means of a point over a resample of runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointMeans {
    /// Mean completeness, a failed run counting as 0 (`None`: no defined value).
    pub completeness: Option<f64>,
    /// Whether the point holds: no failed run and mean completeness ≥ the requirement.
    pub holds: bool,
    /// Per figure, its mean over the completed runs where defined.
    pub figures: [Option<f64>; RUN_FIGURES],
}

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (s, n) = v.fold((0.0, 0usize), |(s, n), x| (s + x, n + 1));
    (n > 0).then(|| s / n as f64)
}

impl PointRuns {
    /// The point's means over the runs `idx` (a resample, or every run).
    pub fn means(&self, idx: &[usize]) -> PointMeans {
        let failed = idx.iter().any(|&k| self.failed[k]);
        let completeness =
            mean(idx.iter().filter_map(|&k| if self.failed[k] { Some(0.0) } else { self.completeness[k] }));
        let of = |f: &Vec<Option<f64>>| mean(idx.iter().filter_map(|&k| f.get(k).copied().flatten()));
        PointMeans {
            completeness,
            holds: !failed && completeness.is_some_and(|c| c >= COMPLETENESS_REQUIRED),
            figures: [0, 1, 2, 3, 4].map(|i| of(&self.figures[i])),
        }
    }
}

/// Times the curve changes between holding and not, along the points' order (knob order).
pub fn crossings(means: &[PointMeans]) -> u32 {
    means.windows(2).filter(|w| w[0].holds != w[1].holds).count() as u32
}

/// Index in [`AtRequired::figures`]: total energy per object (J).
pub const AT_ENERGY: usize = 0;
/// Total dwell time per object (s).
pub const AT_DWELL: usize = 1;
/// Total energy per object ÷ duration (W).
pub const AT_POWER: usize = 2;
/// TA energy per object (J).
pub const AT_TA_ENERGY: usize = 3;
/// TA dwell time per object (s).
pub const AT_TA_DWELL: usize = 4;
/// TA energy per object ÷ duration (W).
pub const AT_TA_POWER: usize = 5;
/// Time to first track of the worst target (s).
pub const AT_FIRST_TRACK_MAX: usize = 6;
/// Figures at a crossing.
pub const AT_FIGURES: usize = 7;

/// The figures at a crossing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtRequired {
    /// The knob value (one-knob families).
    pub knob: Option<f64>,
    /// The bracketing frontier points (indices of the family's points).
    pub bracket: (usize, usize),
    /// Per figure (`AT_ENERGY`, …), its value at the crossing (`None` when a bracketing point
    /// has no value: a study made before the figure existed).
    pub figures: [Option<f64>; AT_FIGURES],
    /// Per figure, the least and the greatest of its values at the two bracketing points: where
    /// the figure can lie for any monotone frontier between them (the grid's part).
    pub ends: [Option<(f64, f64)>; AT_FIGURES],
}

/// A family on one scenario at one stress point.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyRuns {
    /// Its points, in knob order.
    pub points: Vec<PointRuns>,
    /// Simulated seconds per run.
    pub duration_s: f64,
    /// The energy its frontier is built on.
    pub energy: FrontierEnergy,
}

/// The figures of a family over runs `idx`: `Ok` at a crossing inside the sweep, or why not.
pub fn at_required(f: &FamilyRuns, idx: &[usize]) -> Result<AtRequired, Crossing> {
    let means: Vec<PointMeans> = f.points.iter().map(|p| p.means(idx)).collect();
    let c = crossing_on(&means, &frontier(&means, f.energy), COMPLETENESS_REQUIRED);
    let Crossing::At { lo, hi, t } = c else { return Err(c) };
    let lerp = |a: Option<f64>, b: Option<f64>| Some(a? + t * (b? - a?));
    let fig = |i: usize| lerp(means[lo].figures[i], means[hi].figures[i]);
    let (energy, ta_energy) = (fig(RUN_ENERGY), fig(RUN_TA_ENERGY));
    let power = |e: Option<f64>| e.map(|e| e / f.duration_s);
    let end = |i: usize| {
        let (a, b) = (means[lo].figures[i]?, means[hi].figures[i]?);
        Some((a.min(b), a.max(b)))
    };
    let per_s = |e: Option<(f64, f64)>| e.map(|(a, b)| (a / f.duration_s, b / f.duration_s));
    let (energy_ends, ta_ends) = (end(RUN_ENERGY), end(RUN_TA_ENERGY));
    Ok(AtRequired {
        knob: lerp(f.points[lo].knob, f.points[hi].knob),
        bracket: (lo, hi),
        ends: [
            energy_ends,
            end(RUN_DWELL),
            per_s(energy_ends),
            ta_ends,
            end(RUN_TA_DWELL),
            per_s(ta_ends),
            end(RUN_FIRST_TRACK_MAX),
        ],
        figures: [
            energy,
            fig(RUN_DWELL),
            power(energy),
            ta_energy,
            fig(RUN_TA_DWELL),
            power(ta_energy),
            fig(RUN_FIRST_TRACK_MAX),
        ],
    })
}

/// A bootstrap replicate of figure `i` of [`AtRequired`].
pub fn replicate(r: &Result<AtRequired, Crossing>, i: usize) -> Replicate {
    match r {
        Ok(a) => a.figures[i].map_or(Replicate::Undefined, Replicate::Value),
        Err(Crossing::BelowRange) => Replicate::Below,
        Err(Crossing::Nowhere) => Replicate::Above,
        Err(Crossing::OnePoint | Crossing::At { .. }) => Replicate::Undefined,
    }
}

/// A bootstrap replicate of the low (`low`) or high end of figure `i`'s bracket.
fn replicate_end(r: &Result<AtRequired, Crossing>, i: usize, low: bool) -> Replicate {
    match r {
        Ok(a) => a.ends[i].map_or(Replicate::Undefined, |(l, h)| Replicate::Value(if low { l } else { h })),
        Err(_) => replicate(r, i),
    }
}

/// A point estimate with its 95 % interval.
pub type WithCi = (f64, Option<f64>, Option<f64>);

/// The figures at the crossing over every run, with their intervals.
#[derive(Debug, Clone, PartialEq)]
pub struct AtFigures {
    /// The knob value (one-knob families).
    pub knob: Option<f64>,
    /// The bracketing frontier points.
    pub bracket: (usize, usize),
    /// Per figure (`AT_ENERGY`, …), its value and interval (`None`: undefined).
    pub figures: [Option<WithCi>; AT_FIGURES],
}

/// A family's challenge figures.
#[derive(Debug, Clone, PartialEq)]
pub struct Challenge {
    /// Some point holds (over every run).
    pub holds: bool,
    /// Crossings of the curve along the knob.
    pub crossings: u32,
    /// The points on the frontier over every run (indices, by increasing energy).
    pub frontier: Vec<usize>,
    /// The figures, or why they are null.
    pub at: Result<AtFigures, Crossing>,
    /// Resamples whose crossing lies inside the sweep.
    pub resamples_crossing: u32,
}

/// Why a family's figures are null, as the table says it.
pub fn reason(c: &Crossing) -> &'static str {
    match c {
        Crossing::OnePoint => "one point: not swept, or no point with a completed run",
        Crossing::BelowRange => "holds already at the cheapest point: the crossing lies below the sweep",
        Crossing::Nowhere => "holds at no point: the crossing lies above the sweep",
        Crossing::At { .. } => "",
    }
}

/// The means of every point of `f` over every run.
pub fn all_means(f: &FamilyRuns) -> Vec<PointMeans> {
    let all: Vec<usize> = (0..runs_of(f)).collect();
    f.points.iter().map(|p| p.means(&all)).collect()
}

fn runs_of(f: &FamilyRuns) -> usize {
    f.points.first().map_or(0, |p| p.failed.len())
}

/// The challenge figures of `f`, with intervals from `resamples` (each a list of run indices).
pub fn challenge(f: &FamilyRuns, resamples: &[Vec<usize>]) -> Challenge {
    let all: Vec<usize> = (0..runs_of(f)).collect();
    let means = all_means(f);
    let point = at_required(f, &all);
    let boot: Vec<Result<AtRequired, Crossing>> = resamples.iter().map(|idx| at_required(f, idx)).collect();
    let at = point.map(|a| {
        // The interval holds the runs' spread and the grid's part: its low end is the 2.5 %
        // point of the resamples' lower bracket values, its high end the 97.5 % point of their
        // upper ones (docs/studies.md, "The challenge").
        let with = |i: usize| {
            let v = a.figures[i]?;
            let (lo, _) = percentile_95(&boot.iter().map(|r| replicate_end(r, i, true)).collect::<Vec<_>>());
            let (_, hi) = percentile_95(&boot.iter().map(|r| replicate_end(r, i, false)).collect::<Vec<_>>());
            Some((v, lo, hi))
        };
        AtFigures { knob: a.knob, bracket: a.bracket, figures: [0, 1, 2, 3, 4, 5, 6].map(with) }
    });
    Challenge {
        holds: means.iter().any(|m| m.holds),
        crossings: crossings(&means),
        frontier: frontier(&means, f.energy),
        at,
        resamples_crossing: boot.iter().filter(|r| r.is_ok()).count() as u32,
    }
}

/// The paired ratio `a ÷ b` of two families' figure `i` at the requirement (`AT_ENERGY` or
/// `AT_TA_ENERGY`), with its interval from the same resamples applied to both (each rebuilding
/// both frontiers), and the resamples in which it is defined.
pub fn energy_ratio(
    a: &FamilyRuns,
    b: &FamilyRuns,
    resamples: &[Vec<usize>],
    i: usize,
) -> (Result<WithCi, String>, u32) {
    let ratio =
        |idx: &[usize]| -> Replicate {
            let (x, y) = (replicate(&at_required(a, idx), i), replicate(&at_required(b, idx), i));
            match (x, y) {
                (Replicate::Value(x), Replicate::Value(y)) if y > 0.0 => Replicate::Value(x / y),
                (Replicate::Below, Replicate::Value(_) | Replicate::Above)
                | (Replicate::Value(_), Replicate::Above) => Replicate::Below,
                (Replicate::Above, Replicate::Value(_) | Replicate::Below)
                | (Replicate::Value(_), Replicate::Below) => Replicate::Above,
                _ => Replicate::Undefined,
            }
        };
    let all: Vec<usize> = (0..runs_of(a)).collect();
    let reps: Vec<Replicate> = resamples.iter().map(|idx| ratio(idx)).collect();
    let defined = reps.iter().filter(|r| matches!(r, Replicate::Value(_))).count() as u32;
    let point = match (at_required(a, &all), at_required(b, &all)) {
        (Ok(x), Ok(y)) => match (x.figures[i], y.figures[i]) {
            (Some(x), Some(y)) if y > 0.0 => {
                let (lo, hi) = percentile_95(&reps);
                Ok((x / y, lo, hi))
            }
            (Some(_), Some(_)) => Err("the conventional family's energy at 98 % is zero".to_string()),
            _ => Err("a family's energy at 98 % is undefined (the study predates the figure)".to_string()),
        },
        (Err(e), _) => Err(format!("MIMO family: {}", reason(&e))),
        (_, Err(e)) => Err(format!("conventional family: {}", reason(&e))),
    };
    (point, defined)
}
