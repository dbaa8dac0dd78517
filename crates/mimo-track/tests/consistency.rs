//! Single-target Monte Carlo consistency (docs/model.md §6.6, §9 item 9): N = 50 runs of a
//! non-manoeuvring target (DWNA truth matching the filter's process noise), measurements
//! simulated from truth with Gaussian noise of the reported variances. ANEES (n = 6) must lie in
//! [5.08, 7.00], position-only ANEES in [2.36, 3.72], and the average NIS in its χ² band, for
//! monostatic and for bistatic updates.

mod common;

use common::*;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, TrackStatus};
use mimo_track::gating::chi2_mean_band;
use mimo_track::motion::ProcessNoise;
use mimo_track::{DwellContext, MultiTargetTracker, TrackerConfig, TrackerKind};

const N_RUNS: usize = 50;
const N_STEPS: usize = 60;
const BURN_IN: usize = 10;
const DT: f64 = 1.0;
const SIGMA_A: f64 = 2.0;

struct McResult {
    anees: Vec<f64>,
    anees_pos: Vec<f64>,
    mean_anees: f64,
    mean_anees_pos: f64,
    mean_nis: f64,
    n_nis: usize,
    nis_step: Vec<f64>,
}

fn run_mc(tx: RadarId, rx: RadarId, x0: [f64; 6], sigma_rho: f64, sigma_uv: f64, seed: u64) -> McResult {
    let sim = Sim::new();
    let cfg = TrackerConfig {
        kind: TrackerKind::Default,
        ekf_noise: ProcessNoise::Dwna { sigma_a_mps2: SIGMA_A },
        ..TrackerConfig::default()
    };
    let mut nees = vec![Vec::new(); N_STEPS + 1];
    let mut nees_pos = vec![Vec::new(); N_STEPS + 1];
    let mut nis_by_step = vec![Vec::new(); N_STEPS + 1];
    let mut all_nis = Vec::new();
    for run in 0..N_RUNS {
        let mut rng = rng(&[seed, run as u64]);
        let mut tracker = MultiTargetTracker::new(cfg.clone(), sim.centre);
        let mut x = x0;
        let m = sim.measure(&mut rng, &x, tx, rx, sigma_rho, sigma_uv, 0.0, 1);
        let rows = tracker.process_dwell(&DwellContext::search(run as u32, 1, 0.0), &[m], &sim.geom);
        assert_eq!(rows.len(), 1, "one tentative track from the first detection");
        assert_eq!(rows[0].status, TrackStatus::Tentative);
        let id = rows[0].track_id;
        for k in 1..=N_STEPS {
            let t = k as f64 * DT;
            x = dwna_step(&mut rng, &x, DT, SIGMA_A);
            let m = sim.measure(&mut rng, &x, tx, rx, sigma_rho, sigma_uv, t, 1 + k as u64);
            let ctx = DwellContext::aimed(run as u32, 1 + k as u64, t, DwellKind::Track, vec![id]);
            let rows = tracker.process_dwell(&ctx, &[m], &sim.geom);
            for r in &rows {
                assert_row_finite(r);
                assert_ne!(r.status, TrackStatus::Deleted, "run {run} step {k}: track lost");
            }
            if let Some(r) = rows.iter().find(|r| r.track_id == id) {
                let (a, b) = sim.nees(r, &x);
                nees[k].push(a);
                nees_pos[k].push(b);
            }
            if k >= 2 {
                assert_eq!(tracker.track(id).map(|t| t.status), Some(TrackStatus::Confirmed));
            }
        }
        for rec in tracker.nis_log() {
            let k = (rec.t_s / DT).round() as usize;
            nis_by_step[k].push(rec.nis);
            if k >= BURN_IN {
                all_nis.push(rec.nis);
            }
        }
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let anees: Vec<f64> = (BURN_IN..=N_STEPS).map(|k| mean(&nees[k])).collect();
    let anees_pos: Vec<f64> = (BURN_IN..=N_STEPS).map(|k| mean(&nees_pos[k])).collect();
    let nis_step: Vec<f64> = (BURN_IN..=N_STEPS).map(|k| mean(&nis_by_step[k])).collect();
    McResult {
        mean_anees: mean(&anees),
        mean_anees_pos: mean(&anees_pos),
        anees,
        anees_pos,
        mean_nis: mean(&all_nis),
        n_nis: all_nis.len(),
        nis_step,
    }
}

fn check(label: &str, r: &McResult) {
    let (lo6, hi6) = chi2_mean_band(6.0, N_RUNS as f64, 0.95);
    let (lo3, hi3) = chi2_mean_band(3.0, N_RUNS as f64, 0.95);
    let (nlo, nhi) = chi2_mean_band(3.0, r.n_nis as f64, 0.95);
    let inside =
        |v: &[f64], lo: f64, hi: f64| v.iter().filter(|x| **x >= lo && **x <= hi).count() as f64 / v.len() as f64;
    let f6 = inside(&r.anees, lo6, hi6);
    let f3 = inside(&r.anees_pos, lo3, hi3);
    let fn3 = inside(&r.nis_step, lo3, hi3);
    println!(
        "{label}: ANEES {:.3} in [{lo6:.2}, {hi6:.2}] ({:.0} % of steps inside), position ANEES {:.3} in [{lo3:.2}, {hi3:.2}] \
         ({:.0} %), mean NIS {:.3} over {} updates in [{nlo:.3}, {nhi:.3}] (per-step: {:.0} % inside [{lo3:.2}, {hi3:.2}])",
        r.mean_anees,
        100.0 * f6,
        r.mean_anees_pos,
        100.0 * f3,
        r.mean_nis,
        r.n_nis,
        100.0 * fn3
    );
    assert!(r.mean_anees >= lo6 && r.mean_anees <= hi6, "{label}: ANEES {}", r.mean_anees);
    assert!(r.mean_anees_pos >= lo3 && r.mean_anees_pos <= hi3, "{label}: position ANEES {}", r.mean_anees_pos);
    assert!(r.mean_nis >= nlo && r.mean_nis <= nhi, "{label}: mean NIS {}", r.mean_nis);
    // Each step's average is a 95 % test on its own, but successive steps are strongly
    // correlated (same runs), so only ask that most of them pass.
    assert!(f6 >= 0.75, "{label}: only {f6} of steps have ANEES inside the band");
    assert!(f3 >= 0.75, "{label}: only {f3} of steps have position ANEES inside the band");
    assert!(fn3 >= 0.75, "{label}: only {fn3} of steps have average NIS inside the band");
}

#[test]
fn monostatic_monte_carlo_is_consistent() {
    // 64 km out, 6 km up, 220 m/s; σ_ρ = 8 m, σ_u = σ_v = 1e-3 (≈ 64 m cross-range).
    let r = run_mc(R1, R1, [50_000.0, 40_000.0, 6_000.0, -200.0, -90.0, 0.0], 8.0, 1e-3, 1);
    check("monostatic", &r);
}

#[test]
fn bistatic_monte_carlo_is_consistent() {
    // R2 transmits, R1 receives; bistatic angle ≈ 30°.
    let r = run_mc(R2, R1, [60_000.0, -10_000.0, 6_000.0, -150.0, 150.0, 0.0], 8.0, 1e-3, 2);
    check("bistatic", &r);
}
