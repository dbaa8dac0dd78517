//! Quiet dwells (`mimo_radar::quiet::is_quiet`): a dwell declared quiet is one the full model
//! evaluates to nothing, and a dwell the full model evaluates to no return and no false alarm is
//! declared quiet unless a target was dropped by the horizon alone (the one gate `is_quiet`
//! leaves to the full model).

mod common;

use common::{SEED, Ship, rcs_for_snr, test_dwell};
use mimo_core::params::{Fidelity, PatternModel, RadarParams};
use mimo_core::rng::{Stream, domain};
use mimo_radar::dwell::{Dwell, Target, evaluate};
use mimo_radar::geometry::visible;
use mimo_radar::quiet::{QuietRadar, TargetBall, beam_clear, is_quiet};

/// A target position a few beamwidths `th` around the beam `(bu, bv)` of `face`, 10 to 210 km
/// out, its range, and a ball of up to 3 km somewhere around it that holds it.
fn near_the_beam(
    s: &mut Stream,
    ship: &Ship,
    face: usize,
    (bu, bv): (f64, f64),
    (th_u, th_v): (f64, f64),
) -> (mimo_core::DVec3, f64, TargetBall) {
    let (du, dv) = ((s.uniform() - 0.5) * 10.0 * th_u, (s.uniform() - 0.5) * 10.0 * th_v);
    let r = 10e3 + s.uniform() * 200e3;
    let pos = ship.point(face, r, bu + du, bv + dv);
    let off = mimo_core::DVec3::new(s.uniform() - 0.5, s.uniform() - 0.5, s.uniform() - 0.5) * 3e3;
    (pos, r, TargetBall { center_ecef: pos + off, radius_m: off.length() * (1.0 + s.uniform()) })
}

/// The dwell of both tests: run 5 at t = 1 s, one transmitter and one receiver, cells only
/// near the returns.
fn dwell<'a>(
    keys: &'a [u64],
    txs: &'a [mimo_radar::dwell::Transmitter<'a>],
    rxs: &'a [mimo_radar::dwell::Receiver<'a>],
    fid: &'a Fidelity,
    record_voltages: bool,
) -> Dwell<'a> {
    Dwell { run: 5, t_s: 1.0, record_voltages, ..test_dwell(keys, txs, rxs, fid) }
}

#[test]
fn quiet_means_the_full_model_gives_nothing() {
    let mut quiet = 0;
    let mut loud = 0;
    let mut horizon_only = 0;
    for case in 0..1200u64 {
        let mut s = Stream::new(SEED, &[domain::TEST, case]);
        // Every third case a high false-alarm rate, so that the draw decides often.
        let mut p = RadarParams::default();
        if case % 3 == 0 {
            p.pfa = 1e-4;
        }
        let fid = Fidelity {
            pattern: if case % 2 == 0 { PatternModel::Gaussian } else { PatternModel::UniformAperture },
            ..Fidelity::default()
        };
        let ship = Ship::new(0, 36.0, -70.0, &p);
        let face = (case % 4) as usize;
        let (bu, bv) = (0.6 * s.uniform() - 0.3, 0.3 * s.uniform() - 0.05);
        let (th_u, th_v) = (p.beamwidth_u(), p.beamwidth_v());
        let ids: Vec<String> = (0..4).map(|i| format!("T{i}")).collect();
        // Targets around the beam: a few beamwidths off (sidelobes, pattern floor), some behind.
        let targets: Vec<Target> = (0..4)
            .map(|i| {
                let (du, dv) = ((s.uniform() - 0.5) * 12.0 * th_u, (s.uniform() - 0.5) * 12.0 * th_v);
                let r = 20e3 + s.uniform() * 380e3;
                let f = if s.uniform() < 0.1 { (face + 2) % 4 } else { face };
                let snr = 10f64.powf(s.uniform() * 3.0 - 1.0);
                Target {
                    id: &ids[i],
                    index: i as u32,
                    pos_ecef: ship.point(f, r, bu + du, bv + dv),
                    rcs_m2: rcs_for_snr(&p, snr, r, 1.0),
                    pol: None,
                }
            })
            .collect();
        let txs = [ship.tx(&p, face, bu, bv, 2)];
        let rxs = [ship.rx(&p, case, face, bu, bv, (p.min_range_m, p.instrumented_range_m))];
        let keys = [5, case];
        let d = dwell(&keys, &txs, &rxs, &fid, true);
        let out = evaluate(&d, &targets);
        let ch = &out.channels[0];
        let nothing = ch.returns.is_empty() && ch.false_alarms == 0;
        if is_quiet(&d, &targets) {
            quiet += 1;
            assert!(
                nothing,
                "case {case}: declared quiet, but {} returns, {} false alarms",
                ch.returns.len(),
                ch.false_alarms
            );
            assert!(out.primitives.is_empty() && out.voltages.is_empty(), "case {case}");
        } else if nothing {
            // Only a target below the horizon may make a dwell with nothing in it "unsure".
            let site = ship.site.to_ecef();
            assert!(targets.iter().any(|t| !visible(site, t.pos_ecef)), "case {case}: nothing, yet not quiet");
            horizon_only += 1;
        } else {
            loud += 1;
        }
    }
    // Both answers occur often, so the checks above bite.
    assert!(quiet > 200 && loud > 200, "quiet {quiet}, loud {loud}, horizon only {horizon_only}");
}

#[test]
fn a_clear_beam_gets_no_return_from_any_target_in_its_ball() {
    let (mut clear, mut unsure) = (0, 0);
    for case in 0..1200u64 {
        let mut s = Stream::new(SEED, &[domain::TEST, 7, case]);
        let p = RadarParams::default();
        let fid = Fidelity {
            pattern: if case % 5 == 0 { PatternModel::UniformAperture } else { PatternModel::Gaussian },
            ..Fidelity::default()
        };
        let ship = Ship::new(0, 36.0, -70.0, &p);
        let face = (case % 4) as usize;
        let (bu, bv) = (0.6 * s.uniform() - 0.3, 0.3 * s.uniform() - 0.05);
        let (th_u, th_v) = (p.beamwidth_u(), p.beamwidth_v());
        let ids: Vec<String> = (0..3).map(|i| format!("T{i}")).collect();
        // Strong targets a few beamwidths around the beam, each somewhere in a ball of up to 3 km.
        let mut balls = Vec::new();
        let targets: Vec<Target> = (0..3)
            .map(|i| {
                let (pos, r, ball) = near_the_beam(&mut s, &ship, face, (bu, bv), (th_u, th_v));
                balls.push(ball);
                Target { id: &ids[i], index: i as u32, pos_ecef: pos, rcs_m2: rcs_for_snr(&p, 1e3, r, 1.0), pol: None }
            })
            .collect();
        let txs = [ship.tx(&p, face, bu, bv, 2)];
        let rxs = [ship.rx(&p, case, face, bu, bv, (p.min_range_m, p.instrumented_range_m))];
        let keys = [5, case];
        let d = dwell(&keys, &txs, &rxs, &fid, false);
        if beam_clear(&d, balls.iter().copied()) {
            clear += 1;
            assert_eq!(fid.pattern, PatternModel::Gaussian, "case {case}");
            let out = evaluate(&d, &targets);
            assert!(out.channels[0].returns.is_empty(), "case {case}: clear, yet a target returned");
            assert_eq!(is_quiet(&d, &targets), is_quiet(&d, &[]), "case {case}");
        } else {
            unsure += 1;
        }
    }
    assert!(clear > 200 && unsure > 200, "clear {clear}, unsure {unsure}");
}

/// A [`QuietRadar`] made once and used for many dwells answers as the per-dwell functions do,
/// for its own radar (cached antenna, clearance and window cells) and for dwells it was not made
/// for (other parameters, another pattern model, another window: computed afresh).
#[test]
fn a_radar_made_once_answers_as_each_dwell_alone() {
    let p = RadarParams { pfa: 1e-4, ..RadarParams::default() };
    let other = RadarParams { pfa: 2e-4, ..RadarParams::default() };
    let made = QuietRadar::new(&p, PatternModel::Gaussian);
    let (mut quiet, mut clear, mut loud) = (0, 0, 0);
    for case in 0..900u64 {
        let mut s = Stream::new(SEED, &[domain::TEST, 11, case]);
        let params = if case % 7 == 0 { &other } else { &p };
        let fid = Fidelity {
            pattern: if case % 5 == 0 { PatternModel::UniformAperture } else { PatternModel::Gaussian },
            ..Fidelity::default()
        };
        let ship = Ship::new(0, 36.0, -70.0, params);
        let face = (case % 4) as usize;
        let (bu, bv) = (0.6 * s.uniform() - 0.3, 0.3 * s.uniform() - 0.05);
        let (th_u, th_v) = (params.beamwidth_u(), params.beamwidth_v());
        let window = if case % 3 == 0 {
            (params.min_range_m, 0.5 * params.instrumented_range_m)
        } else {
            (params.min_range_m, params.instrumented_range_m)
        };
        let ids: Vec<String> = (0..3).map(|i| format!("T{i}")).collect();
        let mut balls = Vec::new();
        let targets: Vec<Target> = (0..3)
            .map(|i| {
                let (pos, r, ball) = near_the_beam(&mut s, &ship, face, (bu, bv), (th_u, th_v));
                balls.push(ball);
                let snr = 10f64.powf(s.uniform() * 3.0 - 1.0);
                Target {
                    id: &ids[i],
                    index: i as u32,
                    pos_ecef: pos,
                    rcs_m2: rcs_for_snr(params, snr, r, 1.0),
                    pol: None,
                }
            })
            .collect();
        let txs = [ship.tx(params, face, bu, bv, 2)];
        let rxs = [ship.rx(params, case, face, bu, bv, window)];
        let keys = [5, case];
        let d = dwell(&keys, &txs, &rxs, &fid, false);
        let c = beam_clear(&d, balls.iter().copied());
        assert_eq!(made.beam_clear(&d, balls.iter().copied()), c, "case {case}");
        for tg in [&targets[..], &[]] {
            let q = is_quiet(&d, tg);
            assert_eq!(made.is_quiet(&d, tg), q, "case {case}");
            if q {
                quiet += 1;
            } else {
                loud += 1;
            }
        }
        clear += usize::from(c);
    }
    // Every branch is taken often enough for the comparisons to bite.
    assert!(quiet > 200 && loud > 100 && clear > 100, "quiet {quiet}, loud {loud}, clear {clear}");
}
