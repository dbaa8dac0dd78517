//! Structure of dwells: MIMO channels, orthogonality and leakage, determinism, voltages on demand,
//! cost that follows targets, bistatic detections, offline re-forming of measurements.

mod common;

use common::{SEED, Ship, fidelity, rcs_for_snr, test_dwell};
use mimo_core::DVec3;
use mimo_core::geo::Geodetic;
use mimo_core::params::{Fidelity, RadarParams};
use mimo_core::rng::{Stream, domain};
use mimo_radar::dwell::{Dwell, RangeWindow, Receiver, Target, Transmitter, evaluate, simulate};
use mimo_radar::geometry::{beam_point, bistatic, measure};
use mimo_radar::measure::measurements_from_primitives;

struct Mimo {
    p: RadarParams,
    ships: Vec<Ship>,
    aim: DVec3,
}

impl Mimo {
    fn new() -> Mimo {
        let p = RadarParams::default();
        let ships = vec![Ship::new(0, 36.0, -70.0, &p), Ship::new(1, 36.25, -70.3, &p), Ship::new(2, 35.8, -69.7, &p)];
        let aim = Geodetic::from_deg(37.0, -69.2, 6000.0).to_ecef();
        Mimo { p, ships, aim }
    }

    fn tx(&self, s: usize, aim: DVec3, n_pulses: u32) -> Transmitter<'_> {
        let b = beam_point(&self.ships[s].faces, &self.p, aim).expect("steerable");
        self.ships[s].tx(&self.p, b.face as usize, b.u, b.v, n_pulses)
    }

    /// A receiver on the aim point; each channel's window is `ρ_ji(aim) ± window_m` (§5.2).
    fn rx(&self, s: usize, dwell_id: u64, window_m: f64) -> Receiver<'_> {
        let b = beam_point(&self.ships[s].faces, &self.p, self.aim).expect("steerable");
        let mut r = self.ships[s].rx(&self.p, dwell_id, b.face as usize, b.u, b.v, (0.0, 0.0));
        r.window = RangeWindow::AroundAim { aim_ecef: self.aim, half_width_m: window_m };
        r
    }
}

fn dwell<'a>(
    keys: &'a [u64],
    txs: &'a [Transmitter<'a>],
    rxs: &'a [Receiver<'a>],
    fid: &'a Fidelity,
    all: bool,
) -> Dwell<'a> {
    Dwell { run: 3, t_s: 12.5, simulate_all_cells: all, ..test_dwell(keys, txs, rxs, fid) }
}

/// 2 transmitters × 3 receivers give 6 channels, one per (tx, rx) pair, with uncorrelated noise.
#[test]
fn mimo_dwell_has_one_channel_per_pair_with_independent_noise() {
    let m = Mimo::new();
    let fid = fidelity();
    let txs = [m.tx(0, m.aim, 2), m.tx(1, m.aim, 2)];
    let rxs = [m.rx(0, 10, 30e3), m.rx(1, 11, 30e3), m.rx(2, 12, 30e3)];
    let keys = [1u64, 7];
    let d = dwell(&keys, &txs, &rxs, &fid, true);
    let chans = simulate(&d, &[]);
    assert_eq!(chans.len(), 6);
    let pairs: Vec<(usize, usize)> = chans.iter().map(|c| (c.tx, c.rx)).collect();
    assert_eq!(pairs, vec![(0, 0), (0, 1), (0, 2), (1, 0), (1, 1), (1, 2)]);
    // Complex correlation of Σ noise between channels sharing a receiver, and between receivers.
    let corr = |a: usize, b: usize| {
        let (ca, cb) = (&chans[a].cells, &chans[b].cells);
        let n = ca.len().min(cb.len());
        let mut acc = num_complex::Complex64::new(0.0, 0.0);
        for k in 0..n {
            acc += ca[k].sum * cb[k].sum.conj();
        }
        (acc.norm() / n as f64, n as f64)
    };
    for (a, b) in [(0, 3), (1, 4), (0, 1), (2, 5), (0, 5)] {
        let (r, n) = corr(a, b);
        // |mean of n products of independent CN(0,1)| has sd 1/√n; 4.5σ.
        assert!(r < 4.5 / n.sqrt(), "channels {a},{b}: correlation {r}");
        assert!(n > 1500.0);
    }
}

/// Ideal orthogonality: a target illuminated by transmitter 0 only shows in channels (0 → i); with
/// 17 dB isolation its leakage appears in the channels of transmitter 1 too.
#[test]
fn orthogonal_waveforms_do_not_cross_talk_and_leakage_is_optional() {
    let m = Mimo::new();
    let tgt_pos = m.aim;
    // Transmitter 1 looks 8 beamwidths away, so it does not illuminate the target.
    let b1 = beam_point(&m.ships[1].faces, &m.p, m.aim).expect("steerable");
    let tx1 = m.ships[1].tx(&m.p, b1.face as usize, b1.u + 8.0 * m.p.beamwidth_u(), b1.v, 1);
    let txs = [m.tx(0, m.aim, 4), tx1];
    // Windows wide enough that transmitter 0's echo (at ρ_0i) also falls in the windows of
    // transmitter 1's channels (centred on ρ_1i), where its leakage would show.
    let rxs = [m.rx(0, 10, 30e3), m.rx(1, 11, 30e3), m.rx(2, 12, 30e3)];
    let r0 = bistatic(m.ships[0].faces[0].origin_ecef, m.ships[0].faces[0].origin_ecef, tgt_pos).r_t_m;
    let rcs = rcs_for_snr(&m.p, 1000.0, r0, 0.8);
    let tg = [Target { id: "F-1", index: 0, pos_ecef: tgt_pos, rcs_m2: rcs, pol: None }];
    let keys = [2u64];
    let ideal = fidelity();
    let out = evaluate(&dwell(&keys, &txs, &rxs, &ideal, false), &tg);
    for ch in &out.channels {
        let sourced = ch.cells.iter().filter(|c| c.source.is_some()).count();
        if ch.tx == 0 {
            assert_eq!(ch.returns.len(), 1, "channel {:?}", (ch.tx, ch.rx));
            assert!(sourced >= 1);
        } else {
            assert!(ch.returns.is_empty() && sourced == 0, "cross-talk in {:?}", (ch.tx, ch.rx));
        }
    }
    // Every receiver detects the target in its channel from transmitter 0.
    for (i, rx) in rxs.iter().enumerate() {
        assert!(
            out.primitives.iter().any(|p| p.rx == rx.radar && p.tx == txs[0].radar && p.target_hint.is_some()),
            "rx {i} missed the target"
        );
    }
    let leaky = Fidelity { waveform_isolation_db: Some(17.0), ..fidelity() };
    let out = evaluate(&dwell(&keys, &txs, &rxs, &leaky, false), &tg);
    let half_cells = (m.p.pulse_width_s * mimo_core::SPEED_OF_LIGHT_MPS / 2.0 / m.p.range_cell_m()) as usize;
    for ch in out.channels.iter().filter(|c| c.tx == 1) {
        let sourced = ch.cells.iter().filter(|c| c.source.is_some()).count();
        // Leakage covers ±τc/2 around the return (a strong return leaks well above 1e-3 of the noise).
        assert!(sourced >= 2 * half_cells, "rx {}: {sourced} leaked cells", ch.rx);
        assert!(ch.returns.is_empty());
    }
}

/// Same inputs, same outputs (bit for bit); different dwell keys, different noise. Voltages are
/// only materialized when asked.
#[test]
fn deterministic_and_voltages_on_demand() {
    let m = Mimo::new();
    let fid = fidelity();
    let txs = [m.tx(0, m.aim, 2), m.tx(1, m.aim, 2)];
    let rxs = [m.rx(0, 10, 5e3), m.rx(2, 12, 5e3)];
    let r0 = (m.aim - m.ships[0].faces[0].origin_ecef).length();
    let tg = [
        Target { id: "A", index: 4, pos_ecef: m.aim, rcs_m2: rcs_for_snr(&m.p, 100.0, r0, 0.8), pol: None },
        Target { id: "B", index: 5, pos_ecef: m.aim + DVec3::new(0.0, 50.0, 0.0), rcs_m2: 5.0, pol: None },
    ];
    let keys = [9u64, 1];
    let mut d = dwell(&keys, &txs, &rxs, &fid, false);
    let a = evaluate(&d, &tg);
    let b = evaluate(&d, &tg);
    assert_eq!(a, b);
    assert!(a.voltages.is_empty());
    d.record_voltages = true;
    let c = evaluate(&d, &tg);
    assert_eq!(c.primitives, a.primitives);
    let n_cells: usize = c.channels.iter().map(|ch| ch.cells.len()).sum();
    assert_eq!(c.voltages.len(), n_cells);
    assert!(c.voltages.iter().all(|v| v.run == 3 && (v.dwell_id == 10 || v.dwell_id == 12)));
    let keys2 = [9u64, 2];
    let d2 = dwell(&keys2, &txs, &rxs, &fid, false);
    assert_ne!(evaluate(&d2, &tg).channels[0].cells, a.channels[0].cells);
    // A target's fluctuation draw on a pair does not depend on the other targets.
    let only_a = simulate(&d, &tg[..1]);
    let both = simulate(&d, &tg);
    for (x, y) in only_a.iter().zip(&both) {
        let ra = x.returns.iter().find(|r| r.target == 0);
        let rb = y.returns.iter().find(|r| r.target == 0);
        assert_eq!(ra.map(|r| r.sum), rb.map(|r| r.sum));
    }
}

/// Cost follows targets, not cells: a search dwell over the whole instrumented range simulates
/// only the cells near the returns plus false-alarm triples; far-off-beam targets, targets below
/// the horizon or behind the face are never evaluated.
#[test]
fn cost_follows_targets() {
    let p = RadarParams::default();
    let fid = fidelity();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let (bu, bv) = (0.05, 0.02);
    let txs = [ship.tx(&p, 2, bu, bv, 1)];
    let rxs = [ship.rx(&p, 1, 2, bu, bv, (p.min_range_m, p.instrumented_range_m))];
    let th = p.beamwidth_u();
    let tg = [
        Target { id: "in", index: 0, pos_ecef: ship.point(2, 120e3, bu + 0.2 * th, bv), rcs_m2: 2.0, pol: None },
        Target { id: "near", index: 1, pos_ecef: ship.point(2, 200e3, bu, bv - 0.5 * th), rcs_m2: 30.0, pol: None },
        Target { id: "off", index: 2, pos_ecef: ship.point(2, 100e3, bu + 3.0 * th, bv), rcs_m2: 30.0, pol: None },
        Target { id: "behind", index: 3, pos_ecef: ship.point(0, 100e3, 0.0, 0.0), rcs_m2: 30.0, pol: None },
    ];
    let mut cells_total = 0usize;
    let mut fa_total = 0u64;
    let trials = 200u64;
    for trial in 0..trials {
        let keys = [trial];
        let d = dwell(&keys, &txs, &rxs, &fid, false);
        let ch = simulate(&d, &tg).remove(0);
        let ids: Vec<usize> = ch.returns.iter().map(|r| r.target).collect();
        assert_eq!(ids, vec![0, 1], "only the targets in the beam are evaluated");
        let w = fid.explicit_cells_each_side as usize;
        assert!(ch.cells.len() <= 2 * (2 * w + 2) + 3 * ch.false_alarms as usize);
        cells_total += ch.cells.len();
        fa_total += ch.false_alarms;
    }
    // About 15 000 cells in the window, ~0.015 false alarms per dwell: ~16 cells simulated per dwell.
    assert!(cells_total < 20 * trials as usize, "{cells_total}");
    assert!(fa_total < 20, "{fa_total}");

    // A 100 m-altitude target 80 km away is below the 4/3-earth horizon (60 km for a 20 m mast):
    // never evaluated even with the beam right on it.
    let d_deg = 80.0 / 111.2 * std::f64::consts::FRAC_1_SQRT_2;
    let low = Geodetic::from_deg(36.0 - d_deg, -70.0 - d_deg / 36f64.to_radians().cos(), 100.0).to_ecef();
    let s = ship.faces[2].to_sine(low);
    let txs = [ship.tx(&p, 2, s.u, s.v, 1)];
    let rxs = [ship.rx(&p, 1, 2, s.u, s.v, (p.min_range_m, p.instrumented_range_m))];
    let keys = [1u64];
    let tg = [Target { id: "low", index: 4, pos_ecef: low, rcs_m2: 1000.0, pol: None }];
    assert!(simulate(&dwell(&keys, &txs, &rxs, &fid, false), &tg)[0].returns.is_empty());
    let visible_one = [Target { pos_ecef: ship.faces[2].from_ruv(50e3, s.u, s.v + 0.3 * th), ..tg[0] }];
    assert_eq!(simulate(&dwell(&keys, &txs, &rxs, &fid, false), &visible_one)[0].returns.len(), 1);
}

/// A bistatic channel measures ρ = R_B/2 and the direction in the receiver face; converting the
/// measurement back lands near the target.
#[test]
fn bistatic_detection_measures_rho_and_receiver_direction() {
    let m = Mimo::new();
    let fid = fidelity();
    let txs = [m.tx(0, m.aim, 8)];
    let rxs = [m.rx(1, 21, 3e3)];
    let rcs = 30.0;
    let tg = [Target { id: "A", index: 0, pos_ecef: m.aim, rcs_m2: rcs, pol: None }];
    let mut s = Stream::new(SEED, &[domain::TEST, 8]);
    let mut n = 0;
    for trial in 0..200u64 {
        let keys = [trial, s.next_u64()];
        let out = evaluate(&dwell(&keys, &txs, &rxs, &fid, false), &tg);
        let ret = out.channels[0].returns.first().expect("evaluated");
        assert!((ret.rho_m - 0.5 * ret.geometry.r_b_m).abs() < 1e-9);
        let z = measure(m.aim, txs[0].frame.origin_ecef, &rxs[0].frame);
        assert!((ret.rho_m - 0.5 * z[0]).abs() < 1e-6 && (ret.u - z[1]).abs() < 1e-12);
        for meas in measurements_from_primitives(&out.primitives, 0).iter().filter(|x| x.target_hint.is_some()) {
            n += 1;
            assert!((meas.range_m - ret.rho_m).abs() < 6.0 * meas.var_range_m2.sqrt() + 30.0);
            assert!((meas.u - ret.u).abs() < 6.0 * meas.var_u.sqrt());
            let p = mimo_radar::geometry::bistatic_ruv_to_ecef(
                2.0 * meas.range_m,
                meas.u,
                meas.v,
                txs[0].frame.origin_ecef,
                &rxs[0].frame,
            )
            .expect("converts");
            assert!((p - m.aim).length() < 3000.0, "{}", (p - m.aim).length());
        }
    }
    assert!(n > 150, "{n} detections");
}

/// Offline re-forming: measurements from recorded primitives, in any order, equal those formed
/// online from the same primitives.
#[test]
fn measurements_reform_identically_from_recorded_primitives() {
    let m = Mimo::new();
    let fid = fidelity();
    let txs = [m.tx(0, m.aim, 4), m.tx(1, m.aim, 4)];
    let tg: Vec<Target> = (0..4)
        .map(|k| Target {
            id: ["F-1", "F-2", "F-3", "F-4"][k],
            index: k as u32,
            pos_ecef: m.aim + DVec3::new(40.0 * k as f64, -70.0 * k as f64, 10.0),
            rcs_m2: 2.0,
            pol: None,
        })
        .collect();
    let mut prims = Vec::new();
    let mut online = Vec::new();
    for trial in 0..20u64 {
        let rxs = [m.rx(0, 100 * trial, 3e3), m.rx(1, 100 * trial + 1, 3e3), m.rx(2, 100 * trial + 2, 3e3)];
        let keys = [trial];
        let out = evaluate(&dwell(&keys, &txs, &rxs, &fid, false), &tg);
        let start = online.len() as u64;
        online.extend(measurements_from_primitives(&out.primitives, start));
        prims.extend(out.primitives);
    }
    assert!(!online.is_empty());
    let mut shuffled = prims.clone();
    shuffled.reverse();
    shuffled.rotate_left(prims.len() / 3);
    // Dwell ids grow with the trial, so one call on all recorded primitives, in any order,
    // reproduces the online rows exactly, meas_ids included.
    let offline = measurements_from_primitives(&shuffled, 0);
    assert_eq!(offline, online);
}

/// Malformed or extreme inputs never panic: NaN positions, zero or NaN RCS, NaN or inverted
/// windows, zero pulses, no transmitters, huge windows with a high false-alarm probability.
#[test]
fn bad_inputs_do_not_panic() {
    let p = RadarParams::default();
    let fid = fidelity();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let good = ship.point(0, 100e3, 0.0, 0.0);
    let tg = [
        Target { id: "nan", index: 0, pos_ecef: DVec3::new(f64::NAN, 0.0, 0.0), rcs_m2: 2.0, pol: None },
        Target { id: "zero", index: 1, pos_ecef: good, rcs_m2: 0.0, pol: None },
        Target { id: "nanrcs", index: 2, pos_ecef: good, rcs_m2: f64::NAN, pol: None },
        Target { id: "at-site", index: 3, pos_ecef: ship.faces[0].origin_ecef, rcs_m2: 2.0, pol: None },
    ];
    let keys = [1u64];
    for (lo, hi) in [(f64::NAN, 1e5), (2e5, 1e5), (0.0, f64::INFINITY), (-1e6, 1e5)] {
        let txs = [ship.tx(&p, 0, 0.0, 0.0, 0)];
        let rxs = [ship.rx(&p, 1, 0, 0.0, 0.0, (lo, hi))];
        let out = evaluate(&dwell(&keys, &txs, &rxs, &fid, false), &tg);
        assert!(out.channels[0].returns.is_empty());
    }
    let none: [Transmitter; 0] = [];
    let rxs = [ship.rx(&p, 1, 0, 0.0, 0.0, (0.0, 1e5))];
    assert!(evaluate(&dwell(&keys, &none, &rxs, &fid, false), &tg).channels.is_empty());
    // 3.3 million cells at P_FA = 0.01: ~33 000 false alarms, distinct, each with its neighbours.
    let hp = RadarParams { pfa: 0.01, ..RadarParams::default() };
    let txs = [ship.tx(&hp, 0, 0.0, 0.0, 1)];
    let rxs = [ship.rx(&hp, 1, 0, 0.0, 0.0, (0.0, 1e8))];
    let ch = simulate(&dwell(&keys, &txs, &rxs, &fid, false), &[]).remove(0);
    assert!(ch.false_alarms > 30_000);
    assert!(ch.cells.windows(2).all(|w| w[0].k < w[1].k), "cells sorted and unique");
    let crossing = ch.cells.iter().filter(|c| c.sum.norm_sqr() > hp.threshold()).count() as u64;
    assert_eq!(crossing, ch.false_alarms);
}

/// Pattern model B (uniform aperture, arctan monopulse curve) through the pipeline: the angle
/// estimate of a steady 25 dB target 0.4 beamwidths off the beam is unbiased.
#[test]
fn uniform_aperture_model_estimates_angles() {
    let p = RadarParams::default();
    let fid = Fidelity {
        pattern: mimo_core::params::PatternModel::UniformAperture,
        swerling: mimo_core::params::Swerling::Sw0,
        ..fidelity()
    };
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let ant = mimo_radar::pattern::Antenna::new(&p, fid.pattern);
    let r = 3000.0 * p.range_cell_m();
    let du = 0.4 * ant.theta_u();
    let g = ant.sum_gain(du, 0.0);
    let rcs = rcs_for_snr(&p, 10f64.powf(2.5), r, 1.0) / g.powi(4);
    let tg = [Target { id: "T", index: 0, pos_ecef: ship.point(0, r, du, 0.0), rcs_m2: rcs, pol: None }];
    let (mut err, mut var, mut n) = (0.0, 0.0, 0.0);
    for trial in 0..2000u64 {
        let txs = [ship.tx(&p, 0, 0.0, 0.0, 1)];
        let rxs = [ship.rx(&p, trial, 0, 0.0, 0.0, (r - 1000.0, r + 1000.0))];
        let keys = [trial];
        let out = evaluate(&dwell(&keys, &txs, &rxs, &fid, false), &tg);
        let truth_u = out.channels[0].returns[0].u;
        for m in out.primitives.iter().filter(|m| m.target_hint.is_some()) {
            err += m.u - truth_u;
            var += m.var_u;
            n += 1.0;
        }
    }
    assert!(n > 1900.0);
    assert!((err / n).abs() < 4.5 * (var / n / n).sqrt(), "bias {} (sd {})", err / n, (var / n / n).sqrt());
}
