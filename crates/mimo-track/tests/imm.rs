//! IMM behaviour in a 5 g turn (docs/model.md §6.3): the CV-high mode probability rises during the
//! turn, and the IMM's RMS position error during the turn is smaller than that of an EKF with
//! the CV-low model alone. Also: the default tracker's EKF (σ_a = 15 m/s²) holds an n = 3 turn
//! at 1 s revisit, as its configuration documents.

mod common;

use common::*;
use mimo_core::G0_MPS2;
use mimo_core::records::{DwellKind, TrackStatus};
use mimo_track::deletion::DeletionConfig;
use mimo_track::motion::{HorizontalTurn, MotionModel, Ncv, ProcessNoise};
use mimo_track::{DwellContext, MultiTargetTracker, TrackerConfig, TrackerKind};

const T_TURN: (f64, f64) = (20.0, 30.0);
const T_END: f64 = 45.0;
const N_RUNS: u64 = 20;

/// Truth every `dt`: straight west at 250 m/s, a level left turn with lateral acceleration
/// `accel` over T_TURN, straight again.
fn truth(accel: f64, dt: f64) -> Vec<[f64; 6]> {
    let speed = 250.0;
    let omega = accel / speed;
    let turn = HorizontalTurn { omega_radps: omega, noise: ProcessNoise::Dwna { sigma_a_mps2: 0.0 } };
    let cv = Ncv::dwna(0.0);
    let mut x = [30_000.0, 25_000.0, 5_000.0, -speed, 0.0, 0.0];
    let mut out = vec![x];
    let n = (T_END / dt).round() as usize;
    for k in 1..=n {
        let t0 = (k - 1) as f64 * dt;
        x = if t0 >= T_TURN.0 && t0 < T_TURN.1 { turn.propagate(&x, dt) } else { cv.propagate(&x, dt) };
        out.push(x);
    }
    out
}

struct Outcome {
    /// Per step, summed squared position error over runs.
    sq_err: Vec<f64>,
    /// Per step, summed CV-high probability over runs.
    mu_high: Vec<f64>,
}

fn run(cfg: &TrackerConfig, truth: &[[f64; 6]], dt: f64) -> Outcome {
    let sim = Sim::new();
    let n = truth.len();
    let mut out = Outcome { sq_err: vec![0.0; n], mu_high: vec![0.0; n] };
    for r in 0..N_RUNS {
        let mut rng = rng(&[555, r]);
        let mut tr = MultiTargetTracker::new(cfg.clone(), sim.centre);
        let m = sim.measure(&mut rng, &truth[0], R1, R1, 5.0, 5e-4, 0.0, 1);
        let id = tr.process_dwell(&DwellContext::search(0, 0, 0.0), &[m], &sim.geom)[0].track_id;
        for (k, x) in truth.iter().enumerate().skip(1) {
            let t = k as f64 * dt;
            let m = sim.measure(&mut rng, x, R1, R1, 5.0, 5e-4, t, 1 + k as u64);
            let rows =
                tr.process_dwell(&DwellContext::aimed(0, k as u64, t, DwellKind::Track, vec![id]), &[m], &sim.geom);
            rows.iter().for_each(assert_row_finite);
            assert!(rows.iter().all(|r| r.status != TrackStatus::Deleted));
            let track = tr.track(id).expect("track alive");
            assert!(track.state.is_finite(), "non-finite state at t = {t}");
            let est = tr.predict(id, t).expect("prediction");
            let e = (est.pos - sim.ecef(x)).length();
            assert!(e.is_finite());
            out.sq_err[k] += e * e;
            out.mu_high[k] += track.state.mu.get(1).copied().unwrap_or(0.0);
        }
    }
    out
}

/// Keep tracks alive through the turn so that errors can be compared.
fn keep() -> DeletionConfig {
    DeletionConfig {
        n_miss: 10_000,
        max_position_trace_m2: 1e15,
        confirmed_max_coast_s: 1e9,
        ..DeletionConfig::default()
    }
}

/// Mean over steps with time in `[a, b]` of the run-averaged per-step values.
fn mean_over(v: &[f64], dt: f64, a: f64, b: f64) -> f64 {
    let r = ((a / dt).round() as usize)..=((b / dt).round() as usize);
    let len = r.clone().count() as f64;
    r.map(|k| v[k] / N_RUNS as f64).sum::<f64>() / len
}

#[test]
fn imm_detects_a_5g_turn_and_beats_the_cv_low_ekf() {
    const DT: f64 = 0.5;
    let truth = truth(5.0 * G0_MPS2, DT);
    let keep = keep();
    let imm_cfg = TrackerConfig { deletion: keep, ..TrackerConfig::for_kind(TrackerKind::Imm) };
    let ekf_cfg = TrackerConfig {
        deletion: keep,
        ekf_noise: ProcessNoise::Dwna { sigma_a_mps2: imm_cfg.imm.sigma_low_mps2 },
        ..TrackerConfig::for_kind(TrackerKind::Default)
    };
    let imm = run(&imm_cfg, &truth, DT);
    let ekf = run(&ekf_cfg, &truth, DT);
    let mean_over = |v: &[f64], a: f64, b: f64| mean_over(v, DT, a, b);
    let rms_over = |v: &[f64], a: f64, b: f64| mean_over(v, a, b).sqrt();
    let mu_pre = mean_over(&imm.mu_high, 12.0, T_TURN.0);
    let mu_turn = mean_over(&imm.mu_high, T_TURN.0 + 2.0, T_TURN.1);
    let mu_after = mean_over(&imm.mu_high, T_END - 5.0, T_END);
    let imm_rms = rms_over(&imm.sq_err, T_TURN.0, T_TURN.1 + 1.0);
    let ekf_rms = rms_over(&ekf.sq_err, T_TURN.0, T_TURN.1 + 1.0);
    let imm_rms_straight = rms_over(&imm.sq_err, 10.0, T_TURN.0);
    let ekf_rms_straight = rms_over(&ekf.sq_err, 10.0, T_TURN.0);
    println!(
        "CV-high probability: {mu_pre:.3} before the turn, {mu_turn:.3} during it, {mu_after:.3} at the end; \
         RMS position error in the turn: IMM {imm_rms:.1} m vs CV-low EKF {ekf_rms:.1} m; \
         straight: IMM {imm_rms_straight:.1} m vs EKF {ekf_rms_straight:.1} m"
    );
    assert!(mu_pre < 0.3, "CV-high probability before the turn: {mu_pre}");
    assert!(mu_turn > 0.6 && mu_turn > mu_pre + 0.4, "CV-high probability during the turn: {mu_turn}");
    assert!(mu_after < mu_turn, "CV-high probability falls after the turn: {mu_after}");
    assert!(imm_rms < ekf_rms, "IMM {imm_rms} m vs EKF {ekf_rms} m");
}

#[test]
fn default_ekf_holds_a_3g_turn_at_one_second_revisit() {
    const DT: f64 = 1.0;
    // n = 3: lateral acceleration √(n² − 1) g = 27.7 m/s².
    let truth = truth(8f64.sqrt() * G0_MPS2, DT);
    let cfg = TrackerConfig { deletion: keep(), ..TrackerConfig::default() };
    let out = run(&cfg, &truth, DT);
    let rms_turn = mean_over(&out.sq_err, DT, T_TURN.0, T_TURN.1 + 1.0).sqrt();
    let rms_straight = mean_over(&out.sq_err, DT, 10.0, T_TURN.0).sqrt();
    println!("default EKF, n = 3 turn: RMS {rms_turn:.1} m in the turn, {rms_straight:.1} m straight");
    assert!(rms_turn < 60.0, "default EKF loses an n = 3 turn: RMS {rms_turn} m");
}
