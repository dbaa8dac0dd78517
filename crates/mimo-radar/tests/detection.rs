//! Monte Carlo tests of noise, false alarms, detection probability, range centroid, monopulse and
//! measurement consistency (docs/model.md §9 items 6–8, and the radar-side checks the brief lists).
//! Fixed seeds; every tolerance is a stated confidence band.

mod common;

use common::{SEED, Ship, fidelity, rcs_for_snr, test_dwell, within};
use mimo_core::params::{RadarParams, Swerling};
use mimo_core::rng::{Stream, domain};
use mimo_radar::detect::{range_centroid, range_sigma_m, range_sigma_predicted_m};
use mimo_radar::dwell::{Dwell, Target, evaluate, simulate};
use mimo_radar::measure::measurements_from_primitives;
use mimo_radar::monopulse::{MERGE_T_THRESHOLD, monopulse};
use num_complex::Complex64;

fn cn(s: &mut Stream) -> Complex64 {
    let (a, b) = s.cn01();
    Complex64::new(a, b)
}

/// Noise-only window, brute force: mean |Σ|² = 1 in every channel and the per-cell crossing rate
/// is P_FA within its binomial band; the shortcut's false-alarm count is within its band too.
#[test]
fn noise_only_cells_have_unit_power_and_the_false_alarm_rate() {
    let p = RadarParams { pfa: 1e-3, ..RadarParams::default() };
    let fid = fidelity();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let window = (30e3, 30e3 + 2000.0 * p.range_cell_m() - 1.0);
    let (mut n, mut s_sum, mut s_az, mut s_el, mut crossings) = (0u64, 0.0, 0.0, 0.0, 0u64);
    let mut shortcut_fa = 0u64;
    let mut shortcut_m = 0u64;
    let dwells = 500u64;
    for trial in 0..dwells {
        let txs = [ship.tx(&p, 0, 0.0, 0.0, 1)];
        let rxs = [ship.rx(&p, trial, 0, 0.0, 0.0, window)];
        let keys = [trial];
        let mut d = Dwell { simulate_all_cells: true, ..test_dwell(&keys, &txs, &rxs, &fid) };
        for ch in simulate(&d, &[]) {
            for c in &ch.cells {
                n += 1;
                s_sum += c.sum.norm_sqr();
                s_az += c.az.norm_sqr();
                s_el += c.el.norm_sqr();
                crossings += u64::from(c.sum.norm_sqr() > p.threshold());
            }
        }
        d.simulate_all_cells = false;
        for ch in simulate(&d, &[]) {
            shortcut_fa += ch.false_alarms;
            shortcut_m += ch.shortcut_cells;
        }
    }
    let nf = n as f64;
    assert_eq!(n, dwells * 2000);
    // |Σ|² ~ Exp(1): sd of the mean is 1/√n; 4.5σ band.
    for (name, s) in [("sum", s_sum), ("az", s_az), ("el", s_el)] {
        assert!(within(s / nf, 1.0, 1.0 / nf.sqrt(), 4.5), "{name}: mean power {}", s / nf);
    }
    let pfa = p.pfa;
    let sd = (pfa * (1.0 - pfa) / nf).sqrt();
    assert!(within(crossings as f64 / nf, pfa, sd, 4.5), "brute-force FA rate {}", crossings as f64 / nf);
    eprintln!(
        "noise: mean |Σ|² {:.4} {:.4} {:.4}; FA rate brute {:.3e} shortcut {:.3e} (P_FA {pfa:.1e}, sd {sd:.1e})",
        s_sum / nf,
        s_az / nf,
        s_el / nf,
        crossings as f64 / nf,
        shortcut_fa as f64 / nf
    );
    assert_eq!(shortcut_m, n);
    assert!(within(shortcut_fa as f64 / nf, pfa, sd, 4.5), "shortcut FA rate {}", shortcut_fa as f64 / nf);
}

/// Two-sample Kolmogorov–Smirnov statistic.
fn ks(mut a: Vec<f64>, mut b: Vec<f64>) -> f64 {
    a.sort_by(f64::total_cmp);
    b.sort_by(f64::total_cmp);
    let (mut i, mut j, mut d) = (0, 0, 0.0f64);
    while i < a.len() && j < b.len() {
        if a[i] <= b[j] {
            i += 1;
        } else {
            j += 1;
        }
        d = d.max((i as f64 / a.len() as f64 - j as f64 / b.len() as f64).abs());
    }
    d
}

/// §4.4 shortcut vs brute force: the per-dwell false-alarm count follows Binomial(M, P_FA) in both
/// (chi-square goodness of fit, 0.1 % critical value) and the crossing |Σ|² have the same
/// distribution (two-sample KS, 0.1 % critical value). Neighbour cells of false alarms are below γ.
#[test]
fn false_alarm_shortcut_matches_brute_force() {
    let p = RadarParams { pfa: 2e-3, ..RadarParams::default() };
    let fid = fidelity();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let m_cells = 1000.0;
    let window = (30e3, 30e3 + m_cells * p.range_cell_m() - 1.0);
    let dwells = 3000u64;
    let mut counts = [[0u64; 6]; 2];
    let mut powers: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    for trial in 0..dwells {
        for (mode, all) in [(0usize, true), (1, false)] {
            let txs = [ship.tx(&p, 0, 0.0, 0.0, 1)];
            let rxs = [ship.rx(&p, trial, 0, 0.0, 0.0, window)];
            let keys = [trial, mode as u64];
            let d = Dwell { simulate_all_cells: all, ..test_dwell(&keys, &txs, &rxs, &fid) };
            let out = evaluate(&d, &[]);
            let ch = &out.channels[0];
            let crossing: Vec<f64> = ch.cells.iter().map(|c| c.sum.norm_sqr()).filter(|&x| x > p.threshold()).collect();
            if !all {
                assert_eq!(crossing.len() as u64, ch.false_alarms);
                // Every false alarm comes with its two (in-window) neighbours, below threshold.
                assert!(ch.cells.len() as u64 <= 3 * ch.false_alarms);
            }
            counts[mode][crossing.len().min(5)] += 1;
            powers[mode].extend(crossing);
            // Each false alarm gives one primitive, with no target hint.
            assert!(out.primitives.iter().all(|r| r.target_hint.is_none()));
        }
    }
    // Binomial(1000, 2e-3) pmf, last bin ≥ 5.
    let (m, q) = (m_cells, p.pfa);
    let mut pmf = [0.0; 6];
    let mut term = (1.0 - q).powf(m);
    for (k, slot) in pmf.iter_mut().enumerate().take(5) {
        *slot = term;
        term *= (m - k as f64) / (k as f64 + 1.0) * q / (1.0 - q);
    }
    pmf[5] = 1.0 - pmf[..5].iter().sum::<f64>();
    for (mode, c) in counts.iter().enumerate() {
        let chi2: f64 = (0..6)
            .map(|k| {
                let e = pmf[k] * dwells as f64;
                (c[k] as f64 - e).powi(2) / e
            })
            .sum();
        eprintln!("FA count chi2 mode {mode} (0 brute, 1 shortcut): {chi2:.2} (crit 20.5)");
        // 5 degrees of freedom: χ²₅(0.999) = 20.5.
        assert!(chi2 < 20.5, "mode {mode}: counts {c:?} chi2 {chi2}");
    }
    let (na, nb) = (powers[0].len() as f64, powers[1].len() as f64);
    assert!(na > 4000.0 && nb > 4000.0);
    let d = ks(powers[0].clone(), powers[1].clone());
    // KS critical value at α = 0.001: 1.95·√((n+m)/(nm)).
    let crit = 1.95 * ((na + nb) / (na * nb)).sqrt();
    eprintln!("KS |Σ|² brute vs shortcut: {d:.4} (crit {crit:.4}, n {na}/{nb})");
    assert!(d < crit, "KS {d} >= {crit}");
    // Both are γ + Exp(1): mean excess 1.
    for (mode, v) in powers.iter().enumerate() {
        let ex = v.iter().map(|x| x - p.threshold()).sum::<f64>() / v.len() as f64;
        assert!(within(ex, 1.0, 1.0 / (v.len() as f64).sqrt(), 4.5), "mode {mode}: excess {ex}");
    }
}

/// P_D of a SW1 target on the beam and on a cell centre (no straddle) follows P_FA^{1/(1+SNR)}.
#[test]
fn detection_probability_follows_the_swerling_1_curve() {
    let p = RadarParams::default();
    let fid = fidelity();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let k = 3000i64;
    let r = k as f64 * dr;
    let (bu, bv) = (0.1, -0.05);
    let w = (1.0f64 - bu * bu - bv * bv).sqrt();
    let trials = 4000u64;
    for snr_db in [8.0, 13.0, 18.0] {
        let snr = 10f64.powf(snr_db / 10.0);
        let rcs = rcs_for_snr(&p, snr, r, w);
        let pos = ship.point(0, r, bu, bv);
        let mut hits = 0u64;
        for trial in 0..trials {
            let keys = [trial, snr_db as u64];
            let tg = [Target { id: "T", index: 0, pos_ecef: pos, rcs_m2: rcs, pol: None }];
            let out = ship.monostatic_dwell(&p, &fid, &keys, (bu, bv), (r - 1000.0, r + 1000.0), &tg);
            if trial == 0 {
                let ret = &out.channels[0].returns[0];
                assert!((ret.peak_snr / snr - 1.0).abs() < 1e-9);
                assert!((ret.rho_m - r).abs() < 1e-3, "{}", ret.rho_m - r);
            }
            hits += u64::from(out.primitives.iter().any(|x| (x.range_cell - k).abs() <= 1));
        }
        let pd = p.pfa.powf(1.0 / (1.0 + snr));
        let est = hits as f64 / trials as f64;
        let sd = (pd * (1.0 - pd) / trials as f64).sqrt();
        eprintln!("P_D at {snr_db} dB: {est:.4} vs SW1 {pd:.4} (sd {sd:.4})");
        assert!(within(est, pd, sd, 4.0), "{snr_db} dB: P_D {est} vs {pd}");
    }
}

/// Two-point range centroid RMS against §4.6's table (0.234, 0.177, 0.094, 0.045, 0.0225 ΔR at
/// 13…30 dB), within 10 %. The table's setting: a steady target of peak SNR `SNR` at a uniform
/// fractional offset between two samples, detected (peak `|Σ|² > γ`), peak plus larger neighbour.
#[test]
fn range_centroid_rms_matches_the_table() {
    let gamma = RadarParams::default().threshold();
    let mut s = Stream::new(SEED, &[domain::TEST, 1]);
    for (snr_db, rms_table) in [(13.0, 0.234), (16.0, 0.177), (20.0, 0.094), (25.0, 0.045), (30.0, 0.0225)] {
        let amp = 10f64.powf(snr_db / 20.0);
        let (mut se, mut n) = (0.0, 0u64);
        while n < 40_000 {
            let delta = s.uniform();
            let ph = s.phase();
            // Cells −1, 0, 1, 2 with the target at 0 + delta.
            let a: Vec<f64> = (0..4)
                .map(|k| {
                    let pk = (1.0 - ((k as f64 - 1.0) - delta).abs()).max(0.0);
                    (Complex64::from_polar(amp * pk, ph) + cn(&mut s)).norm()
                })
                .collect();
            let kp = if a[1] >= a[2] { 1 } else { 2 };
            if a[kp] * a[kp] <= gamma {
                continue;
            }
            let (dir, a1) = if a[kp - 1] > a[kp + 1] { (-1.0, a[kp - 1]) } else { (1.0, a[kp + 1]) };
            let est = range_centroid(kp as f64 - 1.0, dir, a[kp], a1, 1.0);
            se += (est - delta).powi(2);
            n += 1;
        }
        let rms = (se / n as f64).sqrt();
        eprintln!("range centroid RMS at {snr_db} dB: {rms:.4} ΔR vs table {rms_table}");
        assert!((rms / rms_table - 1.0).abs() < 0.10, "{snr_db} dB: rms {rms} vs {rms_table}");
    }
}

/// Monopulse, deterministic target (SW0) at 20 dB, η = 0.4: the estimate is unbiased and its
/// normalized error (η̂−η)²·2S/(1+η̂²) has mean 1 (§2.6). Im-part statistic T ~ χ²₂: mean 2 and
/// P(T > 9.21) = 1 %.
#[test]
fn monopulse_deterministic_target() {
    let mut s = Stream::new(SEED, &[domain::TEST, 2]);
    let (eta_a, eta_e) = (0.4, -0.2);
    let amp = 10f64.powf(20.0 / 20.0);
    let n = 40_000;
    let (mut m_a, mut nv_a, mut nv_e, mut t_sum, mut t_exc, mut var_sum) = (0.0, 0.0, 0.0, 0.0, 0u64, 0.0);
    for _ in 0..n {
        let a = Complex64::from_polar(amp, s.phase());
        let smp = (a + cn(&mut s), a * eta_a + cn(&mut s), a * eta_e + cn(&mut s));
        let m = monopulse(&[smp], 1.0);
        m_a += m.eta_a;
        var_sum += m.var_a;
        nv_a += (m.eta_a - eta_a).powi(2) / m.var_a;
        nv_e += (m.eta_e - eta_e).powi(2) / m.var_e;
        t_sum += m.t_stat;
        t_exc += u64::from(m.t_stat > MERGE_T_THRESHOLD);
    }
    let nf = n as f64;
    let sd_mean = (var_sum / nf / nf).sqrt();
    assert!(within(m_a / nf, eta_a, sd_mean, 4.5), "mean η̂ {} vs {eta_a}", m_a / nf);
    // Normalized squared errors ~ χ²₁: sd of the mean √(2/n); allow 4.5σ plus the 1 % model error.
    let band = 4.5 * (2.0 / nf).sqrt() + 0.02;
    eprintln!(
        "SW0 monopulse: mean η̂ {:.4} (η {eta_a}), normalized var {:.4}/{:.4}, mean T {:.3}, P(T>9.21) {:.4}",
        m_a / nf,
        nv_a / nf,
        nv_e / nf,
        t_sum / nf,
        t_exc as f64 / nf
    );
    assert!((nv_a / nf - 1.0).abs() < band, "normalized var az {}", nv_a / nf);
    assert!((nv_e / nf - 1.0).abs() < band, "normalized var el {}", nv_e / nf);
    // T ~ χ²₂: mean 2 (sd of mean 2/√n), exceedance 1 % (binomial).
    assert!(within(t_sum / nf, 2.0, 2.0 / nf.sqrt(), 4.5) || (t_sum / nf - 2.0).abs() < 0.04, "mean T {}", t_sum / nf);
    let exc = t_exc as f64 / nf;
    assert!(within(exc, 0.01, (0.01 * 0.99 / nf).sqrt(), 4.5), "P(T > 9.21) = {exc}");
}

/// Monopulse, Rayleigh (SW1) target of mean SNR 15 dB, detected cells only: the uncorrected ratio
/// has conditional mean η·c (the bias of §2.5), the corrected one is unbiased, and the normalized
/// error with the conditional variance (1 + η²c)/(2Sc²) has mean 1 (§2.6); T ~ χ²₂.
#[test]
fn monopulse_rayleigh_target_conditional() {
    let mut s = Stream::new(SEED, &[domain::TEST, 3]);
    let gamma = RadarParams::default().threshold();
    let r = 10f64.powf(1.5);
    let c = r / (1.0 + r);
    let eta = 0.5;
    let (mut raw, mut cor, mut nv, mut t_sum, mut t_exc, mut var_sum, mut n) = (0.0, 0.0, 0.0, 0.0, 0u64, 0.0, 0u64);
    while n < 40_000 {
        let a = cn(&mut s) * r.sqrt();
        let sum = a + cn(&mut s);
        if sum.norm_sqr() <= gamma {
            continue;
        }
        let smp = (sum, a * eta + cn(&mut s), a * (-0.3) + cn(&mut s));
        let m1 = monopulse(&[smp], 1.0);
        let mc = monopulse(&[smp], c);
        raw += m1.eta_a;
        cor += mc.eta_a;
        var_sum += mc.var_a;
        nv += (mc.eta_a - eta).powi(2) / mc.var_a;
        t_sum += mc.t_stat;
        t_exc += u64::from(mc.t_stat > MERGE_T_THRESHOLD);
        n += 1;
    }
    let nf = n as f64;
    let sd = (var_sum / nf / nf).sqrt();
    eprintln!(
        "SW1 monopulse: raw mean {:.4} (ηc {:.4}), corrected {:.4} (η {eta}), normalized var {:.4}, mean T {:.3}, P(T>9.21) {:.4}",
        raw / nf,
        eta * c,
        cor / nf,
        nv / nf,
        t_sum / nf,
        t_exc as f64 / nf
    );
    assert!(within(raw / nf, eta * c, sd, 4.5), "raw mean {} vs ηc {}", raw / nf, eta * c);
    assert!(within(cor / nf, eta, sd, 4.5), "corrected mean {} vs η {eta}", cor / nf);
    assert!((nv / nf - 1.0).abs() < 4.5 * (2.0 / nf).sqrt() + 0.03, "normalized var {}", nv / nf);
    assert!((t_sum / nf - 2.0).abs() < 0.1, "mean T {}", t_sum / nf);
    let exc = t_exc as f64 / nf;
    assert!((exc - 0.01).abs() < 0.003, "P(T > 9.21) = {exc}");
}

/// Full pipeline, single target, monostatic: measurements' normalized error in (ρ, u, v) against
/// truth. NEES ~ χ²₃: its mean over N measurements must lie in the 95 % band 3 ± 1.96·√(6/N).
/// The target is SW1 of mean SNR 15 dB (where the 1 m range floor, meant for unmodelled bias,
/// rarely binds), at a random fractional range offset and a random direction within ±0.3
/// beamwidths of the beam; the dwell carries a predicted SNR, so the ML bias factor is exercised.
#[test]
fn single_target_measurements_are_consistent() {
    let p = RadarParams::default();
    let fid = fidelity();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let th = p.beamwidth_u();
    let mut s = Stream::new(SEED, &[domain::TEST, 4]);
    let (bu, bv) = (-0.2, 0.1);
    let w = (1.0f64 - bu * bu - bv * bv).sqrt();
    let mut nees = Vec::new();
    let mut comp = [0.0; 3];
    let mut trial = 0u64;
    while nees.len() < 3000 {
        trial += 1;
        let r = (4000.0 + s.uniform()) * dr;
        let (u, v) = (bu + 0.3 * th * (2.0 * s.uniform() - 1.0), bv + 0.3 * th * (2.0 * s.uniform() - 1.0));
        let pos = ship.point(1, r, u, v);
        let rcs = rcs_for_snr(&p, 30.0, r, w);
        let txs = [ship.tx(&p, 1, bu, bv, 1)];
        let mut rxs = [ship.rx(&p, trial, 1, bu, bv, (r - 1000.0, r + 1000.0))];
        rxs[0].predicted_snr = Some(25.0);
        let keys = [trial];
        let d = test_dwell(&keys, &txs, &rxs, &fid);
        let tg = [Target { id: "T", index: 0, pos_ecef: pos, rcs_m2: rcs, pol: None }];
        let out = evaluate(&d, &tg);
        let meas = measurements_from_primitives(&out.primitives, 0);
        let Some(ret) = out.channels[0].returns.first() else { continue };
        for m in meas.iter().filter(|m| m.target_hint.is_some()) {
            let e = [
                (m.range_m - ret.rho_m).powi(2) / m.var_range_m2,
                (m.u - ret.u).powi(2) / m.var_u,
                (m.v - ret.v).powi(2) / m.var_v,
            ];
            for k in 0..3 {
                comp[k] += e[k];
            }
            nees.push(e.iter().sum::<f64>());
        }
    }
    let n = nees.len() as f64;
    let mean = nees.iter().sum::<f64>() / n;
    let half = 1.96 * (6.0 / n).sqrt();
    let c = comp.map(|x| x / n);
    eprintln!("mean NEES {mean} (band 3 ± {half}), components (ρ, u, v) {c:?}, n {n}");
    assert!((mean - 3.0).abs() < half, "mean NEES {mean} outside 3 ± {half}; components {c:?}");
}

/// Two SW1 targets of equal mean SNR in one range cell, 0.4 beamwidths apart: the merged flag
/// fires far more often than for a single target (≈ 1 %).
#[test]
fn unresolved_pair_raises_the_merged_flag() {
    let p = RadarParams::default();
    let fid = fidelity();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let th = p.beamwidth_u();
    let r = 3500.3 * dr;
    let rcs = rcs_for_snr(&p, 10f64.powf(2.2), r, 1.0);
    let trials = 1500u64;
    let mut rate = [0.0; 2];
    for (case, pair) in [(0usize, false), (1, true)] {
        let (mut merged, mut det) = (0u64, 0u64);
        for trial in 0..trials {
            let mut tg =
                vec![Target { id: "A", index: 0, pos_ecef: ship.point(0, r, -0.2 * th, 0.0), rcs_m2: rcs, pol: None }];
            if pair {
                tg.push(Target {
                    id: "B",
                    index: 1,
                    pos_ecef: ship.point(0, r + 3.0, 0.2 * th, 0.0),
                    rcs_m2: rcs,
                    pol: None,
                });
            } else {
                tg[0].pos_ecef = ship.point(0, r, 0.0, 0.0);
            }
            let keys = [trial, case as u64];
            let out = ship.monostatic_dwell(&p, &fid, &keys, (0.0, 0.0), (r - 1000.0, r + 1000.0), &tg);
            for m in measurements_from_primitives(&out.primitives, 0).iter().filter(|m| m.target_hint.is_some()) {
                det += 1;
                merged += u64::from(m.merged);
            }
        }
        rate[case] = merged as f64 / det as f64;
    }
    eprintln!("merged rate: single {:.4}, unresolved pair {:.4}", rate[0], rate[1]);
    // Single target: about 1 % (χ²₂ tail); pair: many times that.
    assert!(rate[0] < 0.03, "single-target merged rate {}", rate[0]);
    assert!(rate[1] > 0.15 && rate[1] > 5.0 * rate[0], "pair merged rate {} vs single {}", rate[1], rate[0]);
}

/// Swerling 3 through the pipeline: the peak-cell mean power of a target at the cell centre is
/// 1 + SNR (signal plus noise), for SW0, SW1 and SW3 alike.
#[test]
fn peak_cell_power_is_signal_plus_noise() {
    let p = RadarParams::default();
    let ship = Ship::new(0, 36.0, -70.0, &p);
    let dr = p.range_cell_m();
    let k = 2000i64;
    let r = k as f64 * dr;
    let snr = 10.0;
    let rcs = rcs_for_snr(&p, snr, r, 1.0);
    for sw in [Swerling::Sw0, Swerling::Sw1, Swerling::Sw3] {
        let fid = mimo_core::params::Fidelity { swerling: sw, ..fidelity() };
        let trials = 20_000u64;
        let mut sum = 0.0;
        for trial in 0..trials {
            let txs = [ship.tx(&p, 0, 0.0, 0.0, 1)];
            let rxs = [ship.rx(&p, trial, 0, 0.0, 0.0, (r - 300.0, r + 300.0))];
            let keys = [trial];
            let d = test_dwell(&keys, &txs, &rxs, &fid);
            let tg = [Target { id: "T", index: 0, pos_ecef: ship.point(0, r, 0.0, 0.0), rcs_m2: rcs, pol: None }];
            let ch = simulate(&d, &tg).remove(0);
            let c = ch.cells.iter().find(|c| c.k == k).expect("peak cell simulated");
            sum += c.sum.norm_sqr();
        }
        let mean = sum / trials as f64;
        // Variance of |Σ|²: SW1 (1+SNR)²; SW3 ≈ 1 + 2SNR + 1.5 SNR²; SW0 1 + 2 SNR.
        let var = match sw {
            Swerling::Sw0 => 1.0 + 2.0 * snr,
            Swerling::Sw1 => (1.0 + snr).powi(2),
            Swerling::Sw3 => 1.0 + 2.0 * snr + 1.5 * snr * snr,
        };
        assert!(within(mean, 1.0 + snr, (var / trials as f64).sqrt(), 4.5), "{sw:?}: {mean}");
    }
}

/// The reported range sigma follows §4.6 and its floor.
#[test]
fn range_sigma_floor_and_shape() {
    let dr = 29.98;
    // Bin centre (20 dB, x̂ = 0.25): f² = 0.522.
    assert!((range_sigma_m(100.0, 0.25, dr) - 0.522f64.sqrt() * dr / 200f64.sqrt()).abs() < 1e-9);
    assert!((range_sigma_predicted_m(100.0, dr) - 1.329 * dr / 200f64.sqrt()).abs() < 1e-9);
    assert_eq!(range_sigma_m(1e9, 0.1, dr), 1.0);
    assert!(range_sigma_m(20.0, 0.3, dr) > range_sigma_m(40.0, 0.3, dr));
    assert!(range_sigma_m(f64::NAN, f64::NAN, dr).is_finite());
}

/// Polarization (docs/model.md §3.5) end to end: a VV radar detects a target whose σ_vv gives
/// 13 dB with the SW1 probability of 13 dB (its σ_hh, four times smaller, does not count), and an
/// H-transmit, V-receive radar detects the same target with the SW1 probability of σ_hv's SNR.
#[test]
fn polarization_sets_the_detected_power() {
    let base = RadarParams::default();
    let fid = mimo_core::params::Fidelity { polarization: true, ..fidelity() };
    let ship = Ship::new(0, 36.0, -70.0, &base);
    let dr = base.range_cell_m();
    let k = 3000i64;
    let r = k as f64 * dr;
    let (bu, bv) = (0.1, -0.05);
    let w = (1.0f64 - bu * bu - bv * bv).sqrt();
    let pos = ship.point(0, r, bu, bv);
    let trials = 4000u64;
    let rcs_13 = rcs_for_snr(&base, 10f64.powf(1.3), r, w);
    let rcs_16 = rcs_for_snr(&base, 10f64.powf(1.6), r, w);
    let pol = mimo_core::polarimetry::Polarimetry {
        hh_m2: 0.25 * rcs_13,
        vv_m2: rcs_13,
        hv_m2: rcs_16,
        hh_vv_correlation: 0.5,
        rotation_deg: 0.0,
    };
    for (case, (tx_deg, rx_deg, snr_db)) in [(90.0, 90.0, 13.0), (0.0, 90.0, 16.0)].into_iter().enumerate() {
        let p = RadarParams { tx_polarization_deg: tx_deg, rx_polarization_deg: rx_deg, ..base.clone() };
        let snr = 10f64.powf(snr_db / 10.0);
        let mut hits = 0u64;
        for trial in 0..trials {
            let keys = [trial, 77 + case as u64];
            // The target's nominal σ̄ is irrelevant with polarization on.
            let tg = [Target { id: "T", index: 0, pos_ecef: pos, rcs_m2: 1.0, pol: Some(pol) }];
            let out = ship.monostatic_dwell(&p, &fid, &keys, (bu, bv), (r - 1000.0, r + 1000.0), &tg);
            if trial == 0 {
                let ret = &out.channels[0].returns[0];
                assert!((ret.peak_snr / snr - 1.0).abs() < 1e-9, "case {case}: mean SNR {}", ret.peak_snr);
            }
            hits += u64::from(out.primitives.iter().any(|x| (x.range_cell - k).abs() <= 1));
        }
        let pd = p.pfa.powf(1.0 / (1.0 + snr));
        let est = hits as f64 / trials as f64;
        let sd = (pd * (1.0 - pd) / trials as f64).sqrt();
        eprintln!("polarization case {case}: P_D {est:.4} vs SW1 {pd:.4} at {snr_db} dB (sd {sd:.4})");
        assert!(within(est, pd, sd, 4.0), "case {case}: P_D {est} vs {pd}");
    }
}
