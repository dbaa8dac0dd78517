//! Times scoring a synthetic study: 10 runs × 1000 s × 7 targets, 10 Hz truth, ~300 tracks per
//! run (each target re-tracked every ~100 s plus short-lived false tracks, 1 Hz updates) and
//! 4 radars × 100 dwells/s.
//!
//! ```text
//! cargo run --release -p mimo-metrics --example score_bench [-- RUNS DURATION_S DWELLS_PER_S]
//! ```

use glam::DVec3;
use mimo_core::ids::RadarId;
use mimo_core::records::{DwellKind, DwellRow, Requester, Role, TrackRow, TrackStatus, TruthRow};
use mimo_metrics::{ScoreInput, ScoreOptions, score, write_outputs};
use std::time::Instant;

/// Small deterministic generator (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn normal(&mut self) -> f64 {
        let (u, v) = (self.next().max(1e-300), self.next());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    }
}

const EARTH_R: f64 = 6_378_137.0;

fn target_state(i: usize, t: f64) -> (DVec3, DVec3) {
    // Straight lines 10 km up, spread around a point on the equator.
    let p0 = DVec3::new(EARTH_R + 10_000.0, -150_000.0 + 40_000.0 * i as f64, 20_000.0 * i as f64);
    let v = DVec3::new(0.0, 250.0 * (1.0 + 0.1 * i as f64), if i.is_multiple_of(2) { 30.0 } else { -30.0 });
    (p0 + v * t, v)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let runs: u32 = args.get(1).map(|s| s.parse()).transpose()?.unwrap_or(10);
    let duration: f64 = args.get(2).map(|s| s.parse()).transpose()?.unwrap_or(1000.0);
    let dwell_rate: f64 = args.get(3).map(|s| s.parse()).transpose()?.unwrap_or(100.0);
    let n_targets = 7;
    let dir = tempfile::tempdir()?;
    let t0 = Instant::now();
    let (mut n_truth, mut n_tracks, mut n_track_rows, mut n_dwells) = (0usize, 0usize, 0usize, 0usize);
    for run in 0..runs {
        let mut rng = Rng(u64::from(run) * 7919 + 1);
        let mut truth = Vec::new();
        let n_samples = (duration * 10.0).round() as usize;
        for i in 0..n_targets {
            for s in 0..=n_samples {
                let t = s as f64 / 10.0;
                let (p, v) = target_state(i, t);
                truth.push(TruthRow {
                    run,
                    t_s: t,
                    target: format!("T{i}"),
                    x_m: p.x,
                    y_m: p.y,
                    z_m: p.z,
                    vx_mps: v.x,
                    vy_mps: v.y,
                    vz_mps: v.z,
                    lat_deg: 0.0,
                    lon_deg: 0.0,
                    alt_m: 10_000.0,
                    rcs_m2: 2.0,
                });
            }
        }
        let mut tracks = Vec::new();
        let mut next_id = 1u64;
        let push = |tracks: &mut Vec<TrackRow>, id: u64, t: f64, st: TrackStatus, p: DVec3, v: DVec3| {
            tracks.push(TrackRow {
                run,
                t_s: t,
                track_id: id,
                status: st,
                x_m: p.x,
                y_m: p.y,
                z_m: p.z,
                vx_mps: v.x,
                vy_mps: v.y,
                vz_mps: v.z,
                cov: unit_cov(),
                n_updates: 1,
                last_meas_id: None,
            })
        };
        // Each target: a track every ~100 s with a 0–5 s gap between them, 1 Hz noisy updates.
        for i in 0..n_targets {
            let mut t = 2.0 + rng.next() * 3.0;
            while t < duration {
                let id = next_id;
                next_id += 1;
                let end = (t + 80.0 + rng.next() * 40.0).min(duration + 1.0);
                let mut first = true;
                let mut u = t;
                while u < end {
                    let (p, v) = target_state(i, u);
                    let noise = DVec3::new(rng.normal(), rng.normal(), rng.normal()) * 30.0;
                    let st = if first { TrackStatus::Tentative } else { TrackStatus::Confirmed };
                    push(&mut tracks, id, u, st, p + noise, v + noise * 0.1);
                    first = false;
                    u += 1.0;
                }
                let (p, v) = target_state(i, end);
                push(&mut tracks, id, end, TrackStatus::Deleted, p, v);
                t = end + rng.next() * 5.0;
            }
        }
        // False tracks: ~200 per run, 3–10 s long, far from the targets.
        for _ in 0..200 {
            let id = next_id;
            next_id += 1;
            let t = rng.next() * duration;
            let p = DVec3::new(EARTH_R + 5_000.0, rng.normal() * 300_000.0, 400_000.0 + rng.normal() * 50_000.0);
            let v = DVec3::new(0.0, 100.0, 0.0);
            let life = 3.0 + rng.next() * 7.0;
            let mut u = t;
            while u < t + life {
                push(&mut tracks, id, u, TrackStatus::Confirmed, p + v * (u - t), v);
                u += 1.0;
            }
            push(&mut tracks, id, t + life, TrackStatus::Deleted, p + v * life, v);
        }
        n_tracks += (next_id - 1) as usize;
        // Dwells: four radars, `dwell_rate` per second each; 20 % TA track dwells, every 50th a MIMO
        // group with two transmitters and two receivers.
        let mut dwells = Vec::new();
        let n_per_radar = (duration * dwell_rate) as usize;
        let mut id = 0u64;
        for k in 0..n_per_radar {
            let t = k as f64 / dwell_rate;
            let mimo = k % 50 == 0;
            for r in 0..4u8 {
                id += 1;
                let ta = mimo || rng.next() < 0.2;
                let role = if mimo && r >= 2 { Role::Rx } else { Role::Txrx };
                let kind = if mimo {
                    DwellKind::Mimo
                } else if ta {
                    DwellKind::Track
                } else {
                    DwellKind::Search
                };
                let np = 1 + (rng.next() * 8.0) as u32;
                dwells.push(DwellRow {
                    run,
                    dwell_id: id,
                    group_id: if mimo { id - u64::from(r) } else { id },
                    radar: RadarId(r),
                    role,
                    kind,
                    requested_by: if ta { Requester::Ta } else { Requester::Radar },
                    t_s: t + 1e-4 * f64::from(r),
                    duration_s: f64::from(np) / 300.0,
                    pulse_width_s: 10e-6,
                    n_pulses: np,
                    peak_power_w: 1e5,
                    energy_j: if role == Role::Rx { 0.0 } else { f64::from(np) },
                    waveform: 0,
                    face: 0,
                    beam_u: 0.0,
                    beam_v: 0.0,
                    aim_x_m: 0.0,
                    aim_y_m: 0.0,
                    aim_z_m: 0.0,
                });
            }
        }
        n_truth += truth.len();
        n_track_rows += tracks.len();
        n_dwells += dwells.len();
        let name = format!("run-{run:04}.parquet");
        mimo_store::write_table(&dir.path().join("truth").join(&name), &truth)?;
        mimo_store::write_table(&dir.path().join("tracks").join(&name), &tracks)?;
        mimo_store::write_table(&dir.path().join("dwells").join(&name), &dwells)?;
    }
    println!(
        "generated {runs} runs × {duration} s: {n_truth} truth rows, {n_tracks} tracks ({n_track_rows} rows), {n_dwells} dwell rows in {:.2} s",
        t0.elapsed().as_secs_f64()
    );

    // Scorable: within 400 km of one of two "ships" on the surface.
    let ships = [DVec3::new(EARTH_R, -100_000.0, 0.0), DVec3::new(EARTH_R, 100_000.0, 0.0)];
    let scorable = Box::new(move |_t: f64, p: DVec3, _alt: f64| ships.iter().any(|s| s.distance(p) < 400_000.0));
    let input = ScoreInput::from_run_dir(dir.path(), scorable)?;
    let opts = ScoreOptions { scenario: "bench".into(), ..ScoreOptions::default() };
    let t1 = Instant::now();
    let s = score(&input, &opts)?;
    let t_score = t1.elapsed().as_secs_f64();
    let t2 = Instant::now();
    write_outputs(&s, &dir.path().join("score"))?;
    let t_write = t2.elapsed().as_secs_f64();
    println!("score(): {t_score:.2} s; write_outputs(): {t_write:.2} s");
    if std::env::var_os("MIMO_BENCH_JSON").is_some() {
        println!("{}", s.summary_json()?);
    }
    println!(
        "completeness {:?}, breaks {:.1}/run, switches {:.1}/run, spurious {:?}, position RMSE {:?} m, total energy {:.0} J/run",
        s.summary.track.completeness,
        s.summary.track.breaks,
        s.summary.track.switches,
        s.summary.track.spurious_ratio,
        s.summary.track.position_rmse_m,
        s.summary.usage.totals.total_energy_j
    );
    Ok(())
}

/// A covariance of 1 m² and 1 m²/s² on the diagonal (the readers refuse a zero variance).
fn unit_cov() -> [f64; 21] {
    let mut c = [0.0; 21];
    for i in 0..6 {
        c[mimo_core::records::cov_index(i, i)] = 1.0;
    }
    c
}
