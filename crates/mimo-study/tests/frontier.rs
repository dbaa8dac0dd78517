//! The efficient frontier of a family (docs/studies.md, "The challenge"): a grid family read on
//! its frontier on a hand-made case, and, on a synthetic study whose truth is known, bootstrap
//! intervals from a coarse grid that cover the dense grid's answer.

use mimo_core::rng::Stream;
use mimo_study::bootstrap::{RESAMPLES, resamples};
use mimo_study::challenge::{AT_ENERGY, FamilyRuns, PointRuns, challenge};

/// A point whose every run has completeness `c` and total energy `e` (other figures from it).
fn flat(method: &str, runs: usize, c: f64, e: f64) -> PointRuns {
    PointRuns {
        method: method.to_string(),
        knob: None,
        failed: vec![false; runs],
        completeness: vec![Some(c); runs],
        figures: [
            vec![Some(e); runs],
            vec![Some(e / 1000.0); runs],
            vec![Some(e / 10.0); runs],
            vec![None; runs],
            vec![None; runs],
        ],
    }
}

#[test]
fn a_grid_family_crosses_on_its_frontier() {
    // A 2 × 3 grid (budget × search period): (completeness, J). The frontier by energy is
    // 100 J 0.90, 150 J 0.95, 260 J 0.99, 400 J 0.995; 200 J 0.93 and 300 J 0.97 are beaten.
    // 98 % lies between 150 J (0.95) and 260 J (0.99), three quarters of the way: 232.5 J.
    let pts = [
        ("g@b:1,p:1", 0.90, 100.0),
        ("g@b:1,p:2", 0.95, 150.0),
        ("g@b:1,p:4", 0.93, 200.0),
        ("g@b:2,p:1", 0.97, 300.0),
        ("g@b:2,p:2", 0.99, 260.0),
        ("g@b:2,p:4", 0.995, 400.0),
    ];
    let f = FamilyRuns {
        points: pts.iter().map(|(m, c, e)| flat(m, 3, *c, *e)).collect(),
        duration_s: 100.0,
        energy: Default::default(),
    };
    let c = challenge(&f, &resamples(4, 3, RESAMPLES));
    assert_eq!(c.frontier, vec![0, 1, 4, 5]);
    let a = c.at.expect("a crossing");
    assert_eq!(a.bracket, (1, 4));
    assert_eq!(a.knob, None, "a grid has no single knob value");
    let e = a.figures[AT_ENERGY].expect("energy");
    assert!((e.0 - 232.5).abs() < 1e-9, "{e:?}");
    // Every run alike: the interval is the bracket, 150–260 J.
    assert_eq!((e.1, e.2), (Some(150.0), Some(260.0)));
}

/// The synthetic truth: completeness `1 − 0.1 exp(−b / 1.5)` and energy `100 b` J per object
/// at knob `b`; 98 % is reached at `b = 1.5 ln 5`, 241.42 J.
fn truth_completeness(b: f64) -> f64 {
    1.0 - 0.1 * (-b / 1.5).exp()
}

const TRUE_ENERGY_J: f64 = 150.0 * 1.609_437_912_434_100_3;

/// A synthetic study of `runs` runs at `knobs`: run `k` shares a completeness offset (σ 0.8
/// point) and an energy factor (σ 5 %) over the points, as the runs of a study share their random
/// draws; each point adds its own noise (σ 0.4 point, 2 %).
fn synthetic(knobs: &[f64], runs: usize, seed: u64) -> FamilyRuns {
    let shared: Vec<(f64, f64)> = (0..runs)
        .map(|k| {
            let mut s = Stream::new(seed, &[1, k as u64]);
            (0.008 * s.normal(), 0.05 * s.normal())
        })
        .collect();
    let points = knobs
        .iter()
        .enumerate()
        .map(|(j, &b)| {
            let mut s = Stream::new(seed, &[2, j as u64]);
            let (mut c, mut e) = (Vec::new(), Vec::new());
            for &(u, v) in &shared {
                c.push(Some((truth_completeness(b) + u + 0.004 * s.normal()).clamp(0.0, 1.0)));
                e.push(Some(100.0 * b * (1.0 + v) * (1.0 + 0.02 * s.normal())));
            }
            PointRuns {
                method: format!("s@{b}"),
                knob: Some(b),
                failed: vec![false; runs],
                completeness: c,
                figures: [e, vec![None; runs], vec![None; runs], vec![None; runs], vec![None; runs]],
            }
        })
        .collect();
    FamilyRuns { points, duration_s: 1000.0, energy: Default::default() }
}

#[test]
fn a_coarse_grid_interval_covers_the_dense_grid_answer() {
    // The dense grid's answer: 0.25 to 6 by 0.125, 400 runs, read on its frontier.
    let dense_knobs: Vec<f64> = (2..=48).map(|i| f64::from(i) * 0.125).collect();
    let dense = challenge(&synthetic(&dense_knobs, 400, 99), &resamples(99, 400, 200));
    let dense_j = dense.at.expect("dense crossing").figures[AT_ENERGY].expect("energy").0;
    assert!((dense_j - TRUE_ENERGY_J).abs() < 0.03 * TRUE_ENERGY_J, "dense {dense_j} J, truth {TRUE_ENERGY_J} J");
    // A coarse grid (0.5, 1.5, 3, 4.5: the crossing between 150 and 300 J, where linear
    // interpolation reads about 7 % high) with 20 runs, on 40 independent synthetic studies:
    // the 95 % interval covers the dense answer in nearly all of them. (An interval of the
    // interpolated crossing's resamples alone covered it in 19 of 40.)
    let coarse = [0.5, 1.5, 3.0, 4.5];
    let mut covered = 0;
    let studies = 40;
    for seed in 0..studies {
        let c = challenge(&synthetic(&coarse, 20, 1000 + seed), &resamples(seed, 20, RESAMPLES));
        let (_, lo, hi) = c.at.expect("coarse crossing").figures[AT_ENERGY].expect("energy");
        if lo.is_none_or(|lo| lo <= dense_j) && hi.is_none_or(|hi| dense_j <= hi) {
            covered += 1;
        }
    }
    assert!(covered >= 34, "the coarse interval covered the dense answer in {covered} of {studies} studies");
}
