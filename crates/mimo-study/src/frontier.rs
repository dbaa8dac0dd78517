//! A family's efficient frontier (docs/studies.md, "The challenge"): of its points (mean energy
//! per scorable object, total or the test article's part as the plan's `frontier_energy` says
//! ([`FrontierEnergy`]), mean completeness), those no other point beats, i.e. reaching at
//! least their completeness for at most their energy. Ordered by energy, the frontier's
//! completeness rises strictly: the least energy that reaches each completeness, monotone by
//! construction, whatever the knobs the family sweeps (one, or a grid of several).
//!
//! The 98 % crossing is read on the frontier: the first frontier point that *holds* (no failed
//! run, mean completeness at least the requirement) and the frontier point before it bracket
//! the crossing, interpolated linearly in completeness between the two.

use crate::challenge::PointMeans;
pub use crate::frontier_energy::FrontierEnergy;

/// Where a family's frontier meets the requirement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Crossing {
    /// Between frontier points `lo` and `hi` (indices of the family's points), a fraction `t`
    /// of the way from `lo` to `hi`.
    At {
        /// The frontier point below the crossing.
        lo: usize,
        /// The first frontier point that holds.
        hi: usize,
        /// Interpolation weight of `hi`.
        t: f64,
    },
    /// One point (or no point with a completed run): no curve.
    OnePoint,
    /// Holds at the frontier's cheapest point: the crossing lies below the swept range.
    BelowRange,
    /// Holds at no point: the crossing lies above the swept range.
    Nowhere,
}

/// The indices of the points on the efficient frontier built on `energy`, by increasing energy
/// (and so strictly increasing completeness). A point without a mean energy or completeness (no
/// completed run) has no place on it.
pub fn frontier(means: &[PointMeans], energy: FrontierEnergy) -> Vec<usize> {
    let mut placed: Vec<(usize, f64, f64)> = means
        .iter()
        .enumerate()
        .filter_map(|(i, m)| Some((i, m.figures[energy.run_figure()]?, m.completeness?)))
        .filter(|(_, e, c)| e.is_finite() && c.is_finite())
        .collect();
    // Cheapest first; at equal energy the most complete first, so that it shadows the others.
    placed.sort_by(|a, b| a.1.total_cmp(&b.1).then(b.2.total_cmp(&a.2)).then(a.0.cmp(&b.0)));
    let mut out = Vec::new();
    let mut best = f64::NEG_INFINITY;
    for (i, _, c) in placed {
        if c > best {
            out.push(i);
            best = c;
        }
    }
    out
}

/// The crossing of the requirement `required` on the frontier `front` of `means`.
pub fn crossing_on(means: &[PointMeans], front: &[usize], required: f64) -> Crossing {
    if means.len() < 2 || front.is_empty() {
        return Crossing::OnePoint;
    }
    let Some(j) = front.iter().position(|&i| means[i].holds) else { return Crossing::Nowhere };
    if j == 0 {
        return Crossing::BelowRange;
    }
    let (lo, hi) = (front[j - 1], front[j]);
    let (a, b) = (means[lo].completeness.unwrap_or(0.0), means[hi].completeness.unwrap_or(0.0));
    // A lower point already at the requirement (it failed a run, so it does not hold) gives way
    // to the upper one.
    let t = if b > a && a < required { ((required - a) / (b - a)).clamp(0.0, 1.0) } else { 1.0 };
    Crossing::At { lo, hi, t }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m(energy_j: f64, completeness: f64) -> PointMeans {
        PointMeans {
            completeness: Some(completeness),
            holds: completeness >= 0.98,
            figures: [Some(energy_j), None, None, None, None],
        }
    }

    #[test]
    fn the_frontier_keeps_the_least_energy_for_each_completeness() {
        // (J, completeness): 300 J/0.95 is beaten by 200 J/0.96; 500 J/0.99 ties 400 J/0.99;
        // 100 J/0.90 and 600 J/0.995 stay.
        let means = [m(300.0, 0.95), m(100.0, 0.90), m(200.0, 0.96), m(500.0, 0.99), m(400.0, 0.99), m(600.0, 0.995)];
        assert_eq!(frontier(&means, FrontierEnergy::Total), vec![1, 2, 4, 5]);
        // 98 % lies between 200 J (0.96) and 400 J (0.99), two thirds of the way.
        match crossing_on(&means, &frontier(&means, FrontierEnergy::Total), 0.98) {
            Crossing::At { lo, hi, t } => {
                assert_eq!((lo, hi), (2, 4));
                assert!((t - 2.0 / 3.0).abs() < 1e-12, "{t}");
            }
            c => panic!("{c:?}"),
        }
    }

    /// A power budget's family: the total falls as the budget grows (test-article dwells take
    /// the time of search dwells that radiate more) while the test article's part rises. On the
    /// total the largest budget is cheapest and holds at once; on the test article's part the
    /// frontier is every point and the crossing lies between the 1-W and 1.5-W budgets.
    #[test]
    fn a_budget_family_crosses_on_the_test_articles_energy() {
        // (budget W, total J, TA J, completeness)
        let pts = [
            (0.25, 141_675.0, 110.0, 0.9606),
            (1.0, 141_113.0, 480.0, 0.9790),
            (1.5, 140_768.0, 703.0, 0.9847),
            (4.0, 139_160.0, 1727.0, 0.9942),
        ];
        let means: Vec<PointMeans> = pts
            .iter()
            .map(|&(_, total, ta, c)| PointMeans { figures: [Some(total), None, Some(ta), None, None], ..m(0.0, c) })
            .collect();
        assert_eq!(frontier(&means, FrontierEnergy::Total), vec![3]);
        assert_eq!(crossing_on(&means, &frontier(&means, FrontierEnergy::Total), 0.98), Crossing::BelowRange);
        let front = frontier(&means, FrontierEnergy::TestArticle);
        assert_eq!(front, vec![0, 1, 2, 3]);
        match crossing_on(&means, &front, 0.98) {
            Crossing::At { lo, hi, t } => {
                assert_eq!((lo, hi), (1, 2));
                assert!((t - (0.98 - 0.9790) / (0.9847 - 0.9790)).abs() < 1e-12, "{t}");
            }
            c => panic!("{c:?}"),
        }
    }

    #[test]
    fn no_completed_run_no_place() {
        let mut means = vec![m(100.0, 0.5), m(200.0, 0.99)];
        means[1].figures[0] = None;
        assert_eq!(frontier(&means, FrontierEnergy::Total), vec![0]);
        assert_eq!(crossing_on(&means, &frontier(&means, FrontierEnergy::Total), 0.98), Crossing::Nowhere);
        assert_eq!(crossing_on(&means[..1], &[0], 0.98), Crossing::OnePoint);
        let cheap_holds = [m(100.0, 0.99), m(200.0, 1.0)];
        assert_eq!(
            crossing_on(&cheap_holds, &frontier(&cheap_holds, FrontierEnergy::Total), 0.98),
            Crossing::BelowRange
        );
    }
}
