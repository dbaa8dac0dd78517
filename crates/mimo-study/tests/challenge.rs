//! The challenge figures on hand-made families: the interpolated crossing of a known curve, the
//! reasons for null figures, bootstrap intervals that contain the estimate and respect bounds,
//! and the paired ratio of a family with itself.

use mimo_study::bootstrap::{RESAMPLES, resamples};
use mimo_study::challenge::{Crossing, FamilyRuns, PointRuns, challenge, crossings, energy_ratio};

/// A point whose runs have the given completeness and energy (dwell time = energy / 1000).
fn point(knob: f64, completeness: &[f64], energy_j: &[f64]) -> PointRuns {
    PointRuns {
        knob: Some(knob),
        failed: vec![false; completeness.len()],
        completeness: completeness.iter().map(|c| Some(*c)).collect(),
        energy_j: energy_j.iter().map(|e| Some(*e)).collect(),
        dwell_s: energy_j.iter().map(|e| Some(e / 1000.0)).collect(),
    }
}

fn family(points: Vec<PointRuns>) -> FamilyRuns {
    FamilyRuns { points, duration_s: 500.0 }
}

#[test]
fn a_known_curve_crosses_where_interpolation_says() {
    // Completeness 0.90, 0.96, 1.00 at knobs 1, 2, 4 with energies 100, 200, 400 J: 98 % is half
    // way from knob 2 to knob 4, so knob 3, 300 J, 0.3 s, 300 J / 500 s = 0.6 W. Every run alike:
    // the intervals have zero width.
    let f = family(vec![
        point(1.0, &[0.90; 4], &[100.0; 4]),
        point(2.0, &[0.96; 4], &[200.0; 4]),
        point(4.0, &[1.00; 4], &[400.0; 4]),
    ]);
    let boot = resamples(1, 4, RESAMPLES);
    let c = challenge(&f, &boot);
    assert!(c.holds);
    assert_eq!(c.crossings, 1);
    let (knob, e, d, p) = c.at.expect("a crossing");
    assert!((knob.expect("knob") - 3.0).abs() < 1e-9);
    assert!((e.0 - 300.0).abs() < 1e-9 && e.1 == Some(e.0) && e.2 == Some(e.0), "{e:?}");
    assert!((d.0 - 0.3).abs() < 1e-12);
    assert!((p.0 - 0.6).abs() < 1e-12);
    assert_eq!(c.resamples_crossing as usize, RESAMPLES);
}

#[test]
fn intervals_contain_the_estimate_and_respect_bounds() {
    // Runs that differ: the point estimate lies inside its interval, and the interval inside the
    // range of the energies the bracketing points can give (all positive).
    let f = family(vec![
        point(1.0, &[0.93, 0.95, 0.94, 0.96, 0.92], &[90.0, 110.0, 100.0, 120.0, 80.0]),
        point(2.0, &[0.97, 0.975, 0.965, 0.97, 0.975], &[190.0, 210.0, 200.0, 220.0, 180.0]),
        point(4.0, &[0.995, 1.0, 0.99, 0.985, 1.0], &[390.0, 410.0, 400.0, 420.0, 380.0]),
    ]);
    let c = challenge(&f, &resamples(20261122, 5, RESAMPLES));
    let (_, e, d, p) = c.at.expect("a crossing");
    for (x, lo, hi) in [e, d, p] {
        let (lo, hi) = (lo.expect("lo"), hi.expect("hi"));
        assert!(lo <= x && x <= hi, "{lo} <= {x} <= {hi}");
        assert!(lo > 0.0, "{lo}");
    }
    let (lo, hi) = (e.1.expect("lo"), e.2.expect("hi"));
    assert!(lo >= 180.0 && hi <= 420.0 && hi > lo, "{lo}–{hi}");
    // The same seed gives the same interval; another seed another.
    assert_eq!(challenge(&f, &resamples(20261122, 5, RESAMPLES)), c);
}

#[test]
fn null_figures_say_why() {
    let everywhere = family(vec![point(1.0, &[0.99; 3], &[1.0; 3]), point(2.0, &[1.0; 3], &[2.0; 3])]);
    let nowhere = family(vec![point(1.0, &[0.5; 3], &[1.0; 3]), point(2.0, &[0.97; 3], &[2.0; 3])]);
    let one = family(vec![point(1.0, &[1.0; 3], &[1.0; 3])]);
    let boot = resamples(3, 3, RESAMPLES);
    let c = challenge(&everywhere, &boot);
    assert_eq!((c.holds, c.at.err()), (true, Some(Crossing::BelowRange)));
    let c = challenge(&nowhere, &boot);
    assert_eq!((c.holds, c.at.err()), (false, Some(Crossing::Nowhere)));
    let c = challenge(&one, &boot);
    assert_eq!((c.holds, c.at.err()), (true, Some(Crossing::OnePoint)));
    // A failed run keeps a point from holding even when the others are perfect.
    let mut failing = point(2.0, &[1.0; 3], &[2.0; 3]);
    failing.failed[1] = true;
    failing.completeness[1] = None;
    let f = family(vec![point(1.0, &[0.5; 3], &[1.0; 3]), failing]);
    assert_eq!(challenge(&f, &boot).at.err(), Some(Crossing::Nowhere));
}

#[test]
fn a_non_monotone_curve_takes_its_first_upward_crossing() {
    // Holds at knob 2, not at 3, again at 4: the crossing is between knobs 1 and 2, and the
    // curve crosses three times.
    let f = family(vec![
        point(1.0, &[0.96; 2], &[10.0; 2]),
        point(2.0, &[0.99; 2], &[20.0; 2]),
        point(3.0, &[0.97; 2], &[30.0; 2]),
        point(4.0, &[0.99; 2], &[40.0; 2]),
    ]);
    let c = challenge(&f, &resamples(5, 2, RESAMPLES));
    assert_eq!(c.crossings, 3);
    let (knob, e, _, _) = c.at.expect("a crossing");
    assert!((knob.expect("knob") - (1.0 + 2.0 / 3.0)).abs() < 1e-9);
    assert!((e.0 - (10.0 + 10.0 * 2.0 / 3.0)).abs() < 1e-9);
    let means: Vec<_> = f.points.iter().map(|p| p.means(&[0, 1])).collect();
    assert_eq!(crossings(&means), 3);
}

#[test]
fn a_family_against_itself_has_ratio_one_exactly() {
    let f = family(vec![
        point(1.0, &[0.93, 0.95, 0.94, 0.90], &[90.0, 110.0, 100.0, 120.0]),
        point(2.0, &[0.99, 1.0, 0.995, 0.985], &[190.0, 210.0, 200.0, 220.0]),
    ]);
    let boot = resamples(9, 4, RESAMPLES);
    let (r, defined) = energy_ratio(&f, &f.clone(), &boot);
    assert_eq!(r, Ok((1.0, Some(1.0), Some(1.0))));
    assert_eq!(defined as usize, RESAMPLES);
    // A family spending twice the energy for the same completeness: ratio 1/2, and the pairing
    // keeps the interval at zero width.
    let mut g = f.clone();
    for p in &mut g.points {
        for e in p.energy_j.iter_mut() {
            *e = e.map(|x| 2.0 * x);
        }
    }
    let (r, _) = energy_ratio(&f, &g, &boot);
    assert_eq!(r, Ok((0.5, Some(0.5), Some(0.5))));
    let nowhere = family(vec![point(1.0, &[0.5; 4], &[1.0; 4]), point(2.0, &[0.6; 4], &[2.0; 4])]);
    let (r, defined) = energy_ratio(&f, &nowhere, &boot);
    assert!(r.expect_err("no crossing").contains("conventional family"));
    assert_eq!(defined, 0);
}
