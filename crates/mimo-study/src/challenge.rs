//! The challenge figures of a family (docs/studies.md, "The challenge"): where its
//! mean-completeness curve crosses the required completeness, and the TA energy, dwell time and
//! power per scorable object there, with bootstrap intervals over the Monte Carlo runs; and the
//! paired ratio of two families' energies.
//!
//! The points of a family are ordered by knob value. A point *holds* when none of its runs
//! failed and its mean completeness (a failed run counting as 0) reaches the requirement. The
//! crossing is the **first upward one**: the first point that holds whose predecessor does not,
//! interpolated linearly between the two in completeness — the least knob (and so, for a power
//! budget, the least energy) at which the family reaches 98 %. A curve that crosses several times
//! (noise, or a timeline that saturates) is counted in `crossings`. A family that holds already
//! at its lowest knob value has its crossing below the swept range, one that holds nowhere above
//! it, and one point (an unswept method) draws no curve: the figures are then null with a reason.

use crate::bootstrap::{Replicate, percentile_95};

/// The completeness the challenge requires.
pub use crate::charts::COMPLETENESS_REQUIRED;

/// One point of a family: per Monte Carlo run `k` (index `k`), its figures.
#[derive(Debug, Clone, PartialEq)]
pub struct PointRuns {
    /// The knob value (`None` for an unswept family).
    pub knob: Option<f64>,
    /// Whether run `k` failed.
    pub failed: Vec<bool>,
    /// Completeness of run `k` (`None`: failed or undefined).
    pub completeness: Vec<Option<f64>>,
    /// TA energy per scorable object (J).
    pub energy_j: Vec<Option<f64>>,
    /// TA dwell time per scorable object (s).
    pub dwell_s: Vec<Option<f64>>,
}

/// Means of a point over a resample of runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointMeans {
    /// Mean completeness, a failed run counting as 0 (`None`: no defined value).
    pub completeness: Option<f64>,
    /// Whether the point holds: no failed run and mean completeness ≥ the requirement.
    pub holds: bool,
    /// Mean TA energy per object over the completed runs.
    pub energy_j: Option<f64>,
    /// Mean TA dwell time per object over the completed runs.
    pub dwell_s: Option<f64>,
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
        PointMeans {
            completeness,
            holds: !failed && completeness.is_some_and(|c| c >= COMPLETENESS_REQUIRED),
            energy_j: mean(idx.iter().filter_map(|&k| self.energy_j[k])),
            dwell_s: mean(idx.iter().filter_map(|&k| self.dwell_s[k])),
        }
    }
}

/// Where a family's curve meets the requirement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Crossing {
    /// Between points `i − 1` and `i` (knob order), a fraction `t` of the way.
    At {
        /// The upper point of the bracket.
        i: usize,
        /// Interpolation weight of point `i`.
        t: f64,
    },
    /// One point: no curve.
    OnePoint,
    /// Holds at the lowest knob value: the crossing lies below the swept range.
    BelowRange,
    /// Holds at no point: the crossing lies above the swept range.
    Nowhere,
}

/// The first upward crossing of `means` (points in knob order).
pub fn crossing(means: &[PointMeans]) -> Crossing {
    if means.len() < 2 {
        return Crossing::OnePoint;
    }
    if means[0].holds {
        return Crossing::BelowRange;
    }
    let Some(i) = (1..means.len()).find(|&i| means[i].holds) else { return Crossing::Nowhere };
    let (a, b) = (means[i - 1].completeness.unwrap_or(0.0), means[i].completeness.unwrap_or(0.0));
    let t = if b > a { ((COMPLETENESS_REQUIRED - a) / (b - a)).clamp(0.0, 1.0) } else { 1.0 };
    Crossing::At { i, t }
}

/// Times the curve changes between holding and not, along the knob.
pub fn crossings(means: &[PointMeans]) -> u32 {
    means.windows(2).filter(|w| w[0].holds != w[1].holds).count() as u32
}

/// The figures at a crossing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AtRequired {
    /// The knob value.
    pub knob: Option<f64>,
    /// TA energy per scorable object (J).
    pub energy_j: f64,
    /// TA dwell time per scorable object (s).
    pub dwell_s: f64,
    /// Energy per object ÷ duration (W).
    pub power_w: f64,
}

/// A family on one scenario at one stress point.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyRuns {
    /// Its points, ordered by knob value.
    pub points: Vec<PointRuns>,
    /// Simulated seconds per run.
    pub duration_s: f64,
}

/// The figures of a family over runs `idx`: `Ok` at a crossing inside the sweep, or why not.
pub fn at_required(f: &FamilyRuns, idx: &[usize]) -> Result<AtRequired, Crossing> {
    let means: Vec<PointMeans> = f.points.iter().map(|p| p.means(idx)).collect();
    let c = crossing(&means);
    let Crossing::At { i, t } = c else { return Err(c) };
    let lerp = |a: f64, b: f64| a + t * (b - a);
    let (lo, hi) = (&means[i - 1], &means[i]);
    // A bracketing point without a completed run has no energy: the figure is undefined.
    let (Some(e0), Some(e1), Some(d0), Some(d1)) = (lo.energy_j, hi.energy_j, lo.dwell_s, hi.dwell_s) else {
        return Err(Crossing::OnePoint);
    };
    let energy_j = lerp(e0, e1);
    let knob = match (f.points[i - 1].knob, f.points[i].knob) {
        (Some(a), Some(b)) => Some(lerp(a, b)),
        _ => None,
    };
    Ok(AtRequired { knob, energy_j, dwell_s: lerp(d0, d1), power_w: energy_j / f.duration_s })
}

/// A bootstrap replicate of one figure of [`AtRequired`].
pub fn replicate(r: &Result<AtRequired, Crossing>, g: fn(&AtRequired) -> f64) -> Replicate {
    match r {
        Ok(a) => Replicate::Value(g(a)),
        Err(Crossing::BelowRange) => Replicate::Below,
        Err(Crossing::Nowhere) => Replicate::Above,
        Err(Crossing::OnePoint | Crossing::At { .. }) => Replicate::Undefined,
    }
}

/// A point estimate with its 95 % interval.
pub type WithCi = (f64, Option<f64>, Option<f64>);

/// A family's challenge figures.
#[derive(Debug, Clone, PartialEq)]
pub struct Challenge {
    /// Some point holds (over every run).
    pub holds: bool,
    /// Crossings of the curve.
    pub crossings: u32,
    /// The figures, or why they are null.
    pub at: Result<(Option<f64>, WithCi, WithCi, WithCi), Crossing>,
    /// Resamples whose crossing lies inside the sweep.
    pub resamples_crossing: u32,
}

/// Why a family's figures are null, as the table says it.
pub fn reason(c: &Crossing) -> &'static str {
    match c {
        Crossing::OnePoint => "one point: not swept, or a bracketing point has no completed run",
        Crossing::BelowRange => "holds already at the lowest knob value: the crossing lies below the sweep",
        Crossing::Nowhere => "holds at no point: the crossing lies above the sweep",
        Crossing::At { .. } => "",
    }
}

/// The challenge figures of `f`, with intervals from `resamples` (each a list of run indices).
pub fn challenge(f: &FamilyRuns, resamples: &[Vec<usize>]) -> Challenge {
    let runs = f.points.first().map_or(0, |p| p.failed.len());
    let all: Vec<usize> = (0..runs).collect();
    let means: Vec<PointMeans> = f.points.iter().map(|p| p.means(&all)).collect();
    let point = at_required(f, &all);
    let boot: Vec<Result<AtRequired, Crossing>> = resamples.iter().map(|idx| at_required(f, idx)).collect();
    let ci = |g: fn(&AtRequired) -> f64| percentile_95(&boot.iter().map(|r| replicate(r, g)).collect::<Vec<_>>());
    let at = point.map(|a| {
        let with = |g: fn(&AtRequired) -> f64| {
            let (lo, hi) = ci(g);
            (g(&a), lo, hi)
        };
        (a.knob, with(|a| a.energy_j), with(|a| a.dwell_s), with(|a| a.power_w))
    });
    Challenge {
        holds: means.iter().any(|m| m.holds),
        crossings: crossings(&means),
        at,
        resamples_crossing: boot.iter().filter(|r| r.is_ok()).count() as u32,
    }
}

/// The paired ratio `a ÷ b` of two families' energies at the requirement, with its interval
/// from the same resamples applied to both, and the resamples in which it is defined.
pub fn energy_ratio(a: &FamilyRuns, b: &FamilyRuns, resamples: &[Vec<usize>]) -> (Result<WithCi, String>, u32) {
    let ratio =
        |idx: &[usize]| -> Replicate {
            let (ra, rb) = (at_required(a, idx), at_required(b, idx));
            let (x, y) = (replicate(&ra, |r| r.energy_j), replicate(&rb, |r| r.energy_j));
            match (x, y) {
                (Replicate::Value(x), Replicate::Value(y)) if y > 0.0 => Replicate::Value(x / y),
                (Replicate::Below, Replicate::Value(_) | Replicate::Above)
                | (Replicate::Value(_), Replicate::Above) => Replicate::Below,
                (Replicate::Above, Replicate::Value(_) | Replicate::Below)
                | (Replicate::Value(_), Replicate::Below) => Replicate::Above,
                _ => Replicate::Undefined,
            }
        };
    let runs = a.points.first().map_or(0, |p| p.failed.len());
    let all: Vec<usize> = (0..runs).collect();
    let reps: Vec<Replicate> = resamples.iter().map(|idx| ratio(idx)).collect();
    let defined = reps.iter().filter(|r| matches!(r, Replicate::Value(_))).count() as u32;
    let point = match (at_required(a, &all), at_required(b, &all)) {
        (Ok(x), Ok(y)) if y.energy_j > 0.0 => {
            let (lo, hi) = percentile_95(&reps);
            Ok((x.energy_j / y.energy_j, lo, hi))
        }
        (Ok(_), Ok(_)) => Err("the conventional family's energy at 98 % is zero".to_string()),
        (Err(e), _) => Err(format!("MIMO family: {}", reason(&e))),
        (_, Err(e)) => Err(format!("conventional family: {}", reason(&e))),
    };
    (point, defined)
}
