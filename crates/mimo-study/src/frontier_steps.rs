//! A family's efficient frontier step by step (docs/studies.md, "The frontier point by point"):
//! the marginal cost of each step — the energy added per point of completeness gained from the
//! frontier point before it — and, from the third point on, how often the step gains
//! completeness faster per joule than the step before across the bootstrap's resamples of the
//! runs. A step that does is a place where the frontier is not convex (its marginal cost falls,
//! marked ↓); its share of the resamples tells a knee the runs resolve (at least 97.5 %) from one
//! their spread makes by chance.
//!
//! The resampled steps are those between the same points, the frontier of every run (a resample
//! re-reads their means, not which points are on it), and compare slopes — completeness per
//! joule, (C₂ − C₁) ÷ (E₂ − E₁) against (C₁ − C₀) ÷ (E₁ − E₀) — rather than their inverses, so
//! that a resample in which a step gains nothing or loses is still ordered. A resample in which a
//! step's energy does not rise is left out (the share is over the others).

use crate::challenge::FamilyRuns;

/// The marginal cost of each step along a frontier's points `(energy, completeness fraction)`:
/// the energy added per point (per cent) of completeness gained from the point before; none for
/// the first point, or a step that gains nothing.
pub fn marginal_costs(points: &[(f64, f64)]) -> Vec<Option<f64>> {
    let mut out = vec![None; points.len()];
    for (k, w) in points.windows(2).enumerate() {
        let ((e0, c0), (e1, c1)) = (w[0], w[1]);
        out[k + 1] = (c1 > c0).then(|| (e1 - e0) / (100.0 * (c1 - c0)));
    }
    out
}

/// For each point `k` of `frontier` (indices into `f.points`, by increasing energy on the
/// family's frontier energy), the share of `resamples` (lists of run indices) in which the step
/// into it rises faster than the step before: completeness per joule from `k − 1` to `k` above
/// that from `k − 2` to `k − 1`. `None` for the first two points, and where no resample has both
/// steps' energies rising or a mean undefined.
pub fn steeper_share(f: &FamilyRuns, frontier: &[usize], resamples: &[Vec<usize>]) -> Vec<Option<f64>> {
    let energy = f.energy.run_figure();
    let mut steeper = vec![0usize; frontier.len()];
    let mut counted = vec![0usize; frontier.len()];
    for idx in resamples {
        let points: Vec<Option<(f64, f64)>> = frontier
            .iter()
            .map(|&j| {
                let m = f.points[j].means(idx);
                Some((m.figures[energy]?, m.completeness?))
            })
            .collect();
        for k in 2..frontier.len() {
            let (Some((e0, c0)), Some((e1, c1)), Some((e2, c2))) = (points[k - 2], points[k - 1], points[k]) else {
                continue;
            };
            if e1 <= e0 || e2 <= e1 {
                continue;
            }
            counted[k] += 1;
            if (c2 - c1) / (e2 - e1) > (c1 - c0) / (e1 - e0) {
                steeper[k] += 1;
            }
        }
    }
    steeper.iter().zip(&counted).map(|(&s, &n)| (n > 0).then(|| s as f64 / n as f64)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bootstrap::resamples;
    use crate::challenge::{PointRuns, RUN_ENERGY, RUN_FIGURES};
    use crate::frontier_energy::FrontierEnergy;

    #[test]
    fn a_steps_cost_is_its_energy_per_point_gained() {
        // 100 → 200 J for 90 → 95 %: 20 J a point; 200 → 250 J for 95 → 99 %: 12.5 J a point.
        let got = marginal_costs(&[(100.0, 0.90), (200.0, 0.95), (250.0, 0.99)]);
        assert_eq!(got.len(), 3);
        assert_eq!(got[0], None);
        assert!((got[1].expect("step") - 20.0).abs() < 1e-9 && (got[2].expect("step") - 12.5).abs() < 1e-9, "{got:?}");
        assert_eq!(marginal_costs(&[(1.0, 0.5), (2.0, 0.5)]), vec![None, None]);
    }

    /// A point whose runs have energy `e` J and completeness `c + spread · z_k`, with `z` the same
    /// centred pattern for every point of a family shifted by `shift` runs (so the points' noise
    /// is not one draw).
    fn point(e: f64, c: f64, spread: f64, shift: usize, runs: usize) -> PointRuns {
        let z = |k: usize| ((((k + shift) * 7) % runs) as f64 / (runs - 1) as f64) - 0.5;
        let mut figures: [Vec<Option<f64>>; RUN_FIGURES] = Default::default();
        figures[RUN_ENERGY] = vec![Some(e); runs];
        PointRuns {
            method: format!("m@{e}"),
            knob: Some(e),
            failed: vec![false; runs],
            completeness: (0..runs).map(|k| Some(c + spread * z(k))).collect(),
            figures,
        }
    }

    fn family(points: Vec<PointRuns>) -> FamilyRuns {
        FamilyRuns { points, duration_s: 1000.0, energy: FrontierEnergy::Total }
    }

    /// A knee larger than the runs' spread is steeper in (nearly) every resample; one inside the
    /// spread in some share well away from both ends; a concave frontier's steps almost never.
    #[test]
    fn the_share_tells_a_real_knee_from_the_runs_spread() {
        let runs = 20;
        let boot = resamples(5, runs, 2000);
        // 0.90 → 0.91 for 100 J, then 0.91 → 0.97 for 100 J: six times steeper, spread 0.002.
        let knee = family(vec![
            point(100.0, 0.90, 0.002, 0, runs),
            point(200.0, 0.91, 0.002, 3, runs),
            point(300.0, 0.97, 0.002, 5, runs),
        ]);
        let s = steeper_share(&knee, &[0, 1, 2], &boot);
        assert_eq!(&s[..2], &[None, None]);
        assert!(s[2].expect("share") >= 0.975, "{s:?}");
        // 0.90 → 0.95 → 0.99: the second step is the flatter (concave): the share is small.
        let concave = family(vec![
            point(100.0, 0.90, 0.002, 0, runs),
            point(200.0, 0.95, 0.002, 3, runs),
            point(300.0, 0.99, 0.002, 5, runs),
        ]);
        assert!(steeper_share(&concave, &[0, 1, 2], &boot)[2].expect("share") <= 0.025);
        // Steps of 0.002 and 0.003 with a spread ten times as large: chance.
        let noise = family(vec![
            point(100.0, 0.970, 0.03, 0, runs),
            point(200.0, 0.972, 0.03, 3, runs),
            point(300.0, 0.975, 0.03, 5, runs),
        ]);
        let share = steeper_share(&noise, &[0, 1, 2], &boot)[2].expect("share");
        assert!((0.1..0.9).contains(&share), "{share}");
    }
}
