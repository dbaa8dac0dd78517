//! False-track management (docs/model.md §6.4): hand-made search streams where false alarms
//! start tracks at the rate the evidence rule predicts and never confirm, a real target still
//! confirms within the expected number of search revisits, and a flood of false alarms keeps at
//! most the tentative-track budget alive, the strongest kept.

mod common;

use common::*;
use mimo_core::records::{DwellKind, MeasurementRow, TrackStatus};
use mimo_core::rng::Stream;
use mimo_track::initiation_evidence::FalseTrackConfig;
use mimo_track::{DwellContext, MultiTargetTracker, SensorGeometry, TrackerConfig};

/// Square-law threshold of a false-alarm probability (docs/model.md §4.3).
fn gamma(pfa: f64) -> f64 {
    -pfa.ln()
}

fn tracker(false_tracks: FalseTrackConfig, sim: &Sim) -> MultiTargetTracker {
    let confirmation = mimo_track::initiation::MOfN { m: 2, n: 2 };
    MultiTargetTracker::new(TrackerConfig { false_tracks, confirmation, ..TrackerConfig::default() }, sim.centre)
}

/// A detection on R1's face 0 at `range` and direction (u, v), with observed power `power`.
fn detection(sim: &Sim, range: f64, u: f64, v: f64, power: f64, t_s: f64, meas_id: u64) -> MeasurementRow {
    let face = sim.geom.face(R1, 0, t_s).expect("face");
    let mut rng = rng(&[meas_id, 7]);
    let truth = sim.frame.to_local(face.from_ruv(range, u, v));
    let mut m = sim.measure(&mut rng, &[truth.x, truth.y, truth.z, 0.0, 0.0, 0.0], R1, R1, 5.0, 5e-4, t_s, meas_id);
    m.snr_db = 10.0 * power.log10();
    m.target_hint = None;
    m
}

/// A false alarm anywhere in face 0's search window: power `γ + Exp(1)` (docs/model.md §4.4).
fn false_alarm(sim: &Sim, s: &mut Stream, pfa: f64, t_s: f64, meas_id: u64) -> MeasurementRow {
    let (range, u, v) = (20_000.0 + 300_000.0 * s.uniform(), 1.4 * s.uniform() - 0.7, 0.1 * s.uniform());
    detection(sim, range, u, v, gamma(pfa) + s.exp1(), t_s, meas_id)
}

#[test]
fn false_alarms_start_tracks_at_the_predicted_rate_and_never_confirm() {
    // Radar P_FA 1e-4 (γ = 9.21) against the evidence rule 1e-6 (13.82): a false alarm starts a
    // track with probability e^{−(13.82 − 9.21)} = 0.01. Each tentative track gets its confirmation
    // look 0.3 s later, which finds nothing (a false alarm does not come back).
    let sim = Sim::new();
    let rule = FalseTrackConfig { power_pfa: 1e-6, max_tentative: 0 };
    let mut tr = tracker(rule, &sim);
    let mut s = rng(&[4242]);
    let n = 20_000u64;
    for k in 0..n {
        let t = k as f64;
        let fa = false_alarm(&sim, &mut s, 1e-4, t, 2 * k + 1);
        tr.process_dwell(&DwellContext::search(0, 2 * k + 1, t), &[fa], &sim.geom);
        let due: Vec<u64> = tr.track_dues().filter(|d| d.status == TrackStatus::Tentative).map(|d| d.id).collect();
        if !due.is_empty() {
            let ctx = DwellContext::aimed(0, 2 * k + 2, t + 0.3, DwellKind::Confirm, due);
            tr.process_dwell(&ctx, &[], &sim.geom);
        }
    }
    let p = (-(gamma(1e-6) - gamma(1e-4))).exp();
    let (mean, sd) = (n as f64 * p, (n as f64 * p * (1.0 - p)).sqrt());
    let started = tr.stats().initiated as f64;
    assert!((started - mean).abs() <= 4.0 * sd, "{started} tracks started, expected {mean:.0} ± {:.0}", 4.0 * sd);
    assert_eq!(tr.stats().confirmed, 0, "false alarms alone confirmed a track");
    assert_eq!(tr.track_dues().count(), 0, "every false track was dropped");
}

/// Search revisits (1 s apart) until a Swerling-1 target of mean SNR `snr` is confirmed: each
/// revisit detects it with `P_D = e^{−γ/(1+snr)}` at power `γ + Exp(1 + snr)`, and a track's
/// confirmation look 0.3 s later detects it.
fn revisits_to_confirm(rule: FalseTrackConfig, pfa: f64, snr: f64, trial: u64) -> u32 {
    let sim = Sim::new();
    let mut tr = tracker(rule, &sim);
    let mut s = rng(&[trial, 99]);
    let (range, u, v) = (150_000.0, 0.2, 0.03);
    for k in 1..=200u32 {
        let t = f64::from(k);
        let id = u64::from(k) * 4;
        let detected = s.uniform() < (-gamma(pfa) / (1.0 + snr)).exp();
        let meas: Vec<MeasurementRow> = if detected {
            vec![detection(&sim, range, u, v, gamma(pfa) + (1.0 + snr) * s.exp1(), t, id + 1)]
        } else {
            Vec::new()
        };
        tr.process_dwell(&DwellContext::search(0, id + 1, t), &meas, &sim.geom);
        let due: Vec<u64> = tr.track_dues().filter(|d| d.status == TrackStatus::Tentative).map(|d| d.id).collect();
        if !due.is_empty() {
            let hit = detection(&sim, range, u, v, gamma(pfa) + (1.0 + snr) * s.exp1(), t + 0.3, id + 2);
            let ctx = DwellContext::aimed(0, id + 2, t + 0.3, DwellKind::Confirm, due);
            tr.process_dwell(&ctx, &[hit], &sim.geom);
        }
        if tr.stats().confirmed > 0 {
            return k;
        }
    }
    panic!("trial {trial}: the target never confirmed");
}

#[test]
fn a_real_target_confirms_within_the_expected_number_of_revisits() {
    // SNR 20 (13 dB) at the radar's P_FA 1e-4 with the default test article's rule 1e-8: a revisit
    // yields a track-starting detection with probability q = P(power ≥ γ_ev) = e^{−γ_ev/(1+SNR)}
    // = 0.416, so the revisits to confirmation are geometric with mean 1/q = 2.40 (sd 1.83).
    let rule = FalseTrackConfig { power_pfa: 1e-8, max_tentative: 400 };
    let (pfa, snr) = (1e-4, 20.0);
    let q = (-gamma(1e-8) / (1.0 + snr)).exp();
    let n = 400u64;
    let total: u64 = (0..n).map(|k| u64::from(revisits_to_confirm(rule, pfa, snr, k))).sum();
    let mean = total as f64 / n as f64;
    let (expect, sd) = (1.0 / q, (1.0 - q).sqrt() / q);
    let band = 4.0 * sd / (n as f64).sqrt();
    assert!((mean - expect).abs() <= band, "mean {mean:.3} revisits, expected {expect:.3} ± {band:.3}");
}

#[test]
fn a_flood_of_false_alarms_keeps_the_tentative_budget_and_the_strongest() {
    // Evidence off, budget 50: 400 search dwells of 10 false alarms each at P_FA 1e-3 and no
    // confirmation looks (a saturated timeline). Without the budget every one would live until the
    // tentative coasting limit; with it at most 50 live, and they are the strongest.
    let sim = Sim::new();
    let rule = FalseTrackConfig { power_pfa: 1.0, max_tentative: 50 };
    let mut tr = tracker(rule, &sim);
    let mut s = rng(&[77]);
    let mut most = 0;
    let mut weakest_kept = f64::INFINITY;
    let mut powers = std::collections::BTreeMap::new();
    for k in 0..400u64 {
        let t = 0.01 * k as f64;
        let fas: Vec<MeasurementRow> = (0..10).map(|j| false_alarm(&sim, &mut s, 1e-3, t, 16 * k + j)).collect();
        for m in &fas {
            powers.insert(m.meas_id, 10f64.powf(m.snr_db / 10.0));
        }
        tr.process_dwell(&DwellContext::search(0, k, t), &fas, &sim.geom);
        let live: Vec<_> = tr.track_dues().filter(|d| d.status == TrackStatus::Tentative).collect();
        most = most.max(live.len());
        if k == 399 {
            weakest_kept = live
                .iter()
                .filter_map(|d| tr.track(d.id).and_then(|x| x.last_meas_id).and_then(|m| powers.get(&m)))
                .fold(f64::INFINITY, |a, &b| a.min(b));
        }
    }
    assert_eq!(most, 50, "the budget bounds the tentative tracks");
    // 4000 false alarms were offered; the 50 kept are among the strongest: their weakest lies
    // above the 90th percentile of γ + Exp(1) (γ + ln 10).
    assert!(weakest_kept >= gamma(1e-3) + 10f64.ln(), "weakest kept {weakest_kept:.2}");
}
