//! The fidelity ladder (docs/model.md §4.8): the measurement and auto rungs against the voltage
//! rung on the same scenes. Fixed seeds; every band is stated from the Monte Carlo sample size.
//! The rungs share the fluctuation draws (same stream keys) and differ in the noise, so their
//! difference has at most the variance of two independent estimates: the bands below use that.

mod common;

use common::{SEED, Ship, fidelity, rcs_for_snr, test_dwell};
use mimo_core::params::{Fidelity, FidelityLevel, RadarParams, Swerling};
use mimo_core::rng::{Stream, domain};
use mimo_radar::dwell::{DwellOutput, Receiver, Target, Transmitter, evaluate};
use mimo_radar::measure::measurements_from_primitives;

fn at(level: FidelityLevel, base: &Fidelity) -> Fidelity {
    Fidelity { level, ..base.clone() }
}

fn run(keys: &[u64], txs: &[Transmitter], rxs: &[Receiver], fid: &Fidelity, tg: &[Target]) -> DwellOutput {
    let d = test_dwell(keys, txs, rxs, fid);
    evaluate(&d, tg)
}

/// Band half-width for the difference of two proportions near `p` from `n` trials each, at `z`.
fn prop_band(p: f64, n: f64, z: f64) -> f64 {
    z * (2.0 * p.max(0.01) * (1.0 - p).max(0.01) / n).sqrt()
}

/// P_D against mean SNR, SW0 and SW1, target on the beam at a random offset between range samples
/// (straddle included): the measurement rung's P_D is the voltage rung's within 4σ of the
/// difference of two proportions (3000 trials each).
#[test]
fn detection_probability_curve_matches_the_voltage_level() {
    let p = RadarParams::default();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let (bu, bv) = (0.1, -0.05);
    let w = (1.0f64 - bu * bu - bv * bv).sqrt();
    let trials = 3000u64;
    for sw in [Swerling::Sw0, Swerling::Sw1] {
        let base = Fidelity { swerling: sw, ..fidelity() };
        for snr_db in [10.0, 13.0, 16.0, 19.0] {
            let snr = 10f64.powf(snr_db / 10.0);
            let mut pd = [0.0; 2];
            for (n, level) in [FidelityLevel::Voltage, FidelityLevel::Measurement].into_iter().enumerate() {
                let fid = at(level, &base);
                let mut offsets = Stream::new(SEED, &[domain::TEST, 41, sw as u64]);
                let mut hits = 0u64;
                for trial in 0..trials {
                    let k = 3000i64;
                    let r = (k as f64 + offsets.uniform()) * dr;
                    let rcs = rcs_for_snr(&p, snr, r, w);
                    let tg = [Target { id: "T", index: 0, pos_ecef: ship.point(0, r, bu, bv), rcs_m2: rcs, pol: None }];
                    let txs = [ship.tx(&p, 0, bu, bv, 1)];
                    let rxs = [ship.rx(&p, trial, 0, bu, bv, (r - 1000.0, r + 1000.0))];
                    let out = run(&[trial, snr_db as u64, sw as u64], &txs, &rxs, &fid, &tg);
                    hits += u64::from(out.primitives.iter().any(|x| x.target_hint.is_some()));
                }
                pd[n] = hits as f64 / trials as f64;
            }
            let band = prop_band(pd[0], trials as f64, 4.0);
            eprintln!("{sw:?} {snr_db} dB: P_D voltage {:.4}, measurement {:.4} (band ±{band:.4})", pd[0], pd[1]);
            assert!((pd[1] - pd[0]).abs() <= band, "{sw:?} {snr_db} dB: P_D {} vs {}", pd[1], pd[0]);
        }
    }
}

/// False alarms per dwell with a target in a 20 000-cell window (P_FA raised to 1e-4 so that the
/// rate is measurable): both rungs within 4σ of the Poisson difference of their counts, and each
/// within 4σ of `M·P_FA`.
#[test]
fn false_alarm_rate_matches_the_voltage_level() {
    let p = RadarParams { pfa: 1e-4, ..RadarParams::default() };
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let r = 5000.4 * dr;
    let half = 10_000.0 * dr;
    let rcs = rcs_for_snr(&p, 30.0, r, 1.0);
    let dwells = 1000u64;
    let mut counts = [0u64; 2];
    for (n, level) in [FidelityLevel::Voltage, FidelityLevel::Measurement].into_iter().enumerate() {
        let fid = at(level, &fidelity());
        for trial in 0..dwells {
            let tg = [Target { id: "T", index: 0, pos_ecef: ship.point(0, r, 0.0, 0.0), rcs_m2: rcs, pol: None }];
            let txs = [ship.tx(&p, 0, 0.0, 0.0, 1)];
            let rxs = [ship.rx(&p, trial, 0, 0.0, 0.0, (r - half, r + half))];
            let out = run(&[trial, 7], &txs, &rxs, &fid, &tg);
            counts[n] += out.primitives.iter().filter(|x| x.target_hint.is_none()).count() as u64;
        }
    }
    // A false alarm yields one primitive unless its monopulse estimate is off the beam (rejected),
    // so compare the two rungs, and each to the expected crossings as an upper bound.
    let expected = 20_000.0 * p.pfa * dwells as f64;
    let (a, b) = (counts[0] as f64, counts[1] as f64);
    let band = 4.0 * (a + b).sqrt();
    eprintln!("false-alarm primitives: voltage {a}, measurement {b} (band ±{band:.1}), crossings expected {expected}");
    assert!((a - b).abs() <= band, "false alarms {a} vs {b}");
    for x in [a, b] {
        assert!(x <= expected + 4.0 * expected.sqrt() && x >= 0.3 * expected, "{x} vs {expected}");
    }
}

/// Mean NEES of single-target measurements (SW1, 15 dB mean, random offsets within ±0.3
/// beamwidths, ML bias factor exercised): each rung's mean within the 95 % χ²₃ band
/// `3 ± 2.576·√(6/N)` (99 %: two rungs are tested), N = 3000. The measurement rung's expectation is
/// exactly 3 by construction (errors drawn with the reported variances, floors not binding here).
#[test]
fn measurement_nees_matches_the_voltage_level() {
    let p = RadarParams::default();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let th = p.beamwidth_u();
    let (bu, bv) = (-0.2, 0.1);
    let w = (1.0f64 - bu * bu - bv * bv).sqrt();
    for level in [FidelityLevel::Voltage, FidelityLevel::Measurement] {
        let fid = at(level, &fidelity());
        let mut s = Stream::new(SEED, &[domain::TEST, 42]);
        let mut nees = Vec::new();
        let mut trial = 0u64;
        while nees.len() < 3000 {
            trial += 1;
            let r = (4000.0 + s.uniform()) * dr;
            let (u, v) = (bu + 0.3 * th * (2.0 * s.uniform() - 1.0), bv + 0.3 * th * (2.0 * s.uniform() - 1.0));
            let rcs = rcs_for_snr(&p, 30.0, r, w);
            let tg = [Target { id: "T", index: 0, pos_ecef: ship.point(1, r, u, v), rcs_m2: rcs, pol: None }];
            let txs = [ship.tx(&p, 1, bu, bv, 1)];
            let mut rxs = [ship.rx(&p, trial, 1, bu, bv, (r - 1000.0, r + 1000.0))];
            rxs[0].predicted_snr = Some(25.0);
            let out = run(&[trial], &txs, &rxs, &fid, &tg);
            let Some(ret) = out.channels[0].returns.first() else { continue };
            for m in measurements_from_primitives(&out.primitives, 0).iter().filter(|m| m.target_hint.is_some()) {
                nees.push(
                    (m.range_m - ret.rho_m).powi(2) / m.var_range_m2
                        + (m.u - ret.u).powi(2) / m.var_u
                        + (m.v - ret.v).powi(2) / m.var_v,
                );
            }
        }
        let n = nees.len() as f64;
        let mean = nees.iter().sum::<f64>() / n;
        let half = 2.576 * (6.0 / n).sqrt();
        eprintln!("{level:?}: mean NEES {mean:.3} (band 3 ± {half:.3})");
        assert!((mean - 3.0).abs() < half, "{level:?}: mean NEES {mean} outside 3 ± {half}");
    }
}

/// Two SW1 targets of equal mean SNR (22 dB) in one range cell, 0.4 beamwidths apart: the fraction
/// of detections flagged merged at each rung. `auto` evaluates such a channel at the voltage level,
/// so its output is the voltage rung's, byte for byte; the measurement rung's fraction must be the
/// voltage rung's within 4σ of the difference of two proportions.
#[test]
fn merged_fraction_of_an_unresolved_pair() {
    let p = RadarParams::default();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let th = p.beamwidth_u();
    let r = 3500.3 * dr;
    let rcs = rcs_for_snr(&p, 10f64.powf(2.2), r, 1.0);
    let trials = 2000u64;
    let mut frac = Vec::new();
    for level in FidelityLevel::ALL {
        let fid = at(level, &fidelity());
        let (mut merged, mut det, mut bytes) = (0u64, 0u64, Vec::new());
        for trial in 0..trials {
            let tg = [
                Target { id: "A", index: 0, pos_ecef: ship.point(0, r, -0.2 * th, 0.0), rcs_m2: rcs, pol: None },
                Target { id: "B", index: 1, pos_ecef: ship.point(0, r + 3.0, 0.2 * th, 0.0), rcs_m2: rcs, pol: None },
            ];
            let txs = [ship.tx(&p, 0, 0.0, 0.0, 1)];
            let rxs = [ship.rx(&p, trial, 0, 0.0, 0.0, (r - 1000.0, r + 1000.0))];
            let out = run(&[trial, 9], &txs, &rxs, &fid, &tg);
            for m in measurements_from_primitives(&out.primitives, 0).iter().filter(|m| m.target_hint.is_some()) {
                det += 1;
                merged += u64::from(m.merged);
            }
            if trial < 50 {
                bytes.push(format!("{:?}", out.primitives));
            }
        }
        frac.push((merged as f64 / det as f64, det, bytes));
    }
    let (v, m, a) = (&frac[0], &frac[1], &frac[2]);
    let band = prop_band(v.0, trials as f64, 4.0);
    eprintln!(
        "merged fraction: voltage {:.4} ({} det), measurement {:.4} ({} det), auto {:.4} (band ±{band:.4})",
        v.0, v.1, m.0, m.1, a.0
    );
    assert_eq!(a.2, v.2, "auto evaluates an unresolved pair at the voltage level");
    assert_eq!(a.0, v.0);
    assert!((m.0 - v.0).abs() <= band, "measurement merged fraction {} vs voltage {}", m.0, v.0);
}

/// `auto` on a lone target uses the measurement level (same bytes), and on two targets a few cells
/// and beamwidths apart the voltage level (same bytes).
#[test]
fn auto_picks_the_rung_by_proximity() {
    let p = RadarParams::default();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let th = p.beamwidth_u();
    let r = 4200.6 * dr;
    let rcs = rcs_for_snr(&p, 100.0, r, 1.0);
    let lone = [Target { id: "A", index: 0, pos_ecef: ship.point(0, r, 0.1 * th, 0.0), rcs_m2: rcs, pol: None }];
    let pair = [
        lone[0],
        Target { id: "B", index: 1, pos_ecef: ship.point(0, r + 2.0 * dr, -0.3 * th, 0.0), rcs_m2: rcs, pol: None },
    ];
    let far = [
        lone[0],
        Target { id: "B", index: 1, pos_ecef: ship.point(0, r + 10.0 * dr, -0.3 * th, 0.0), rcs_m2: rcs, pol: None },
    ];
    let txs = [ship.tx(&p, 0, 0.0, 0.0, 1)];
    let rxs = [ship.rx(&p, 5, 0, 0.0, 0.0, (r - 1000.0, r + 1000.0))];
    let fid = |l| at(l, &fidelity());
    for (tg, same_as) in [
        (&lone[..], FidelityLevel::Measurement),
        (&pair[..], FidelityLevel::Voltage),
        (&far[..], FidelityLevel::Measurement),
    ] {
        let auto = run(&[1], &txs, &rxs, &fid(FidelityLevel::Auto), tg);
        let reference = run(&[1], &txs, &rxs, &fid(same_as), tg);
        let other = run(
            &[1],
            &txs,
            &rxs,
            &fid(if same_as == FidelityLevel::Voltage { FidelityLevel::Measurement } else { FidelityLevel::Voltage }),
            tg,
        );
        assert!(!auto.primitives.is_empty());
        assert_eq!(auto.primitives, reference.primitives, "{} targets: auto = {same_as:?}", tg.len());
        assert_ne!(auto.primitives, other.primitives);
    }
}
