//! The challenge figures on hand-made families: the interpolated crossing of a known curve, the
//! reasons for null figures, bootstrap intervals that contain the estimate and respect bounds,
//! the paired ratio of a family with itself, a grid family read on its frontier, and intervals
//! from a coarse grid that cover a dense grid's answer on a synthetic study.

use mimo_study::bootstrap::{RESAMPLES, resamples};
use mimo_study::challenge::{
    AT_DWELL, AT_ENERGY, AT_FIRST_TRACK_MAX, AT_POWER, AT_TA_ENERGY, AT_TA_POWER, Crossing, FamilyRuns, PointRuns,
    RUN_ENERGY, challenge, crossings, energy_ratio,
};

/// A point whose runs have the given completeness and total energy (dwell time = energy / 1000,
/// the test article's part a tenth of each, the worst first track 10 s per 100 J).
fn point(knob: f64, completeness: &[f64], energy_j: &[f64]) -> PointRuns {
    let of = |f: fn(f64) -> f64| energy_j.iter().map(|e| Some(f(*e))).collect::<Vec<_>>();
    PointRuns {
        method: format!("f@{knob}"),
        knob: Some(knob),
        failed: vec![false; completeness.len()],
        completeness: completeness.iter().map(|c| Some(*c)).collect(),
        figures: [of(|e| e), of(|e| e / 1000.0), of(|e| e / 10.0), of(|e| e / 10_000.0), of(|e| e / 10.0)],
    }
}

fn family(points: Vec<PointRuns>) -> FamilyRuns {
    FamilyRuns { points, duration_s: 500.0, energy: Default::default() }
}

#[test]
fn a_known_curve_crosses_where_interpolation_says() {
    // Completeness 0.90, 0.96, 1.00 at knobs 1, 2, 4 with energies 100, 200, 400 J: 98 % is half
    // way from knob 2 to knob 4, so knob 3, 300 J, 0.3 s, 300 J / 500 s = 0.6 W.
    let f = family(vec![
        point(1.0, &[0.90; 4], &[100.0; 4]),
        point(2.0, &[0.96; 4], &[200.0; 4]),
        point(4.0, &[1.00; 4], &[400.0; 4]),
    ]);
    let boot = resamples(1, 4, RESAMPLES);
    let c = challenge(&f, &boot);
    assert!(c.holds);
    assert_eq!(c.crossings, 1);
    let a = c.at.expect("a crossing");
    let fig = |i: usize| a.figures[i].expect("defined");
    let (e, d, p) = (fig(AT_ENERGY), fig(AT_DWELL), fig(AT_POWER));
    assert!((a.knob.expect("knob") - 3.0).abs() < 1e-9);
    // Every run alike: the interval is the grid's part alone, the bracketing points' 200–400 J.
    assert!((e.0 - 300.0).abs() < 1e-9 && e.1 == Some(200.0) && e.2 == Some(400.0), "{e:?}");
    assert!((d.0 - 0.3).abs() < 1e-12);
    assert!((p.0 - 0.6).abs() < 1e-12);
    // The test article's part and the worst first track, interpolated the same way.
    assert!((fig(AT_TA_ENERGY).0 - 30.0).abs() < 1e-9 && (fig(AT_TA_POWER).0 - 0.06).abs() < 1e-12);
    assert!((fig(AT_FIRST_TRACK_MAX).0 - 30.0).abs() < 1e-9);
    assert_eq!(a.bracket, (1, 2));
    assert_eq!(c.frontier, vec![0, 1, 2]);
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
    let a = c.at.clone().expect("a crossing");
    let (e, d, p) =
        (a.figures[AT_ENERGY].expect("e"), a.figures[AT_DWELL].expect("d"), a.figures[AT_POWER].expect("p"));
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
    let a = c.at.expect("a crossing");
    assert!((a.knob.expect("knob") - (1.0 + 2.0 / 3.0)).abs() < 1e-9);
    assert!((a.figures[AT_ENERGY].expect("e").0 - (10.0 + 10.0 * 2.0 / 3.0)).abs() < 1e-9);
    // The frontier leaves out 30 J (beaten by 20 J) and 40 J (no more complete than 20 J).
    assert_eq!(c.frontier, vec![0, 1]);
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
    let (r, defined) = energy_ratio(&f, &f.clone(), &boot, AT_ENERGY);
    assert_eq!(r, Ok((1.0, Some(1.0), Some(1.0))));
    assert_eq!(defined as usize, RESAMPLES);
    // A family spending twice the energy for the same completeness: ratio 1/2, and the pairing
    // keeps the interval at zero width.
    let mut g = f.clone();
    for p in &mut g.points {
        for e in p.figures[RUN_ENERGY].iter_mut() {
            *e = e.map(|x| 2.0 * x);
        }
    }
    let (r, _) = energy_ratio(&f, &g, &boot, AT_ENERGY);
    assert_eq!(r, Ok((0.5, Some(0.5), Some(0.5))));
    // Its test article's part is unchanged: ratio 1.
    let (r, _) = energy_ratio(&f, &g, &boot, AT_TA_ENERGY);
    assert_eq!(r, Ok((1.0, Some(1.0), Some(1.0))));
    let nowhere = family(vec![point(1.0, &[0.5; 4], &[1.0; 4]), point(2.0, &[0.6; 4], &[2.0; 4])]);
    let (r, defined) = energy_ratio(&f, &nowhere, &boot, AT_ENERGY);
    assert!(r.expect_err("no crossing").contains("conventional family"));
    assert_eq!(defined, 0);
}

/// A power budget's family (the shape of scenario 7's): the total falls as the budget grows while
/// the test article's part rises. On the total the largest budget is cheapest and holds: no
/// crossing. On the test article's part the crossing lies half way between the 1-W and 2-W
/// points, and both energies at 98 % are read there, with the bracket's interval on each.
#[test]
fn a_budget_family_crosses_on_the_test_articles_energy() {
    // (knob, completeness, total J, TA J)
    let pts = [(0.5, 0.96, 1500.0, 100.0), (1.0, 0.97, 1400.0, 300.0), (2.0, 0.99, 1300.0, 700.0)];
    let points: Vec<PointRuns> = pts
        .iter()
        .map(|&(knob, c, total, ta)| {
            let mut p = point(knob, &[c; 3], &[total; 3]);
            p.figures[mimo_study::challenge::RUN_TA_ENERGY] = vec![Some(ta); 3];
            p
        })
        .collect();
    let boot = resamples(5, 3, RESAMPLES);
    let total = challenge(&family(points.clone()), &boot);
    assert_eq!(total.at, Err(Crossing::BelowRange));
    assert_eq!(total.frontier, vec![2]);
    let on_ta = FamilyRuns { energy: mimo_study::challenge::FrontierEnergy::TestArticle, ..family(points) };
    let c = challenge(&on_ta, &boot);
    assert_eq!(c.frontier, vec![0, 1, 2]);
    let a = c.at.expect("a crossing on the test article's energy");
    assert_eq!(a.bracket, (1, 2));
    assert!((a.knob.expect("knob") - 1.5).abs() < 1e-12);
    let ta = a.figures[AT_TA_ENERGY].expect("TA energy");
    assert!((ta.0 - 500.0).abs() < 1e-9 && ta.1 == Some(300.0) && ta.2 == Some(700.0), "{ta:?}");
    let e = a.figures[AT_ENERGY].expect("total energy");
    assert!((e.0 - 1350.0).abs() < 1e-9 && e.1 == Some(1300.0) && e.2 == Some(1400.0), "{e:?}");
}
