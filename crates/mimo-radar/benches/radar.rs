//! Radar model throughput, single thread: `cargo bench -p mimo-radar`.
//!
//! A realistic mix of search dwells (whole instrumented range, 2–450 km, ~15 000 cells) and track
//! dwells (±1 km windows) over a scene of 4 fighters in formation and 3 airliners, then the cost of
//! a dwell against the number of targets in the beam and against the range-window length. The
//! cost should follow targets, not cells. Plain `std::time`, no harness.

#[path = "../tests/common/mod.rs"]
mod common;

use common::Ship;
use mimo_core::DVec3;
use mimo_core::geo::Geodetic;
use mimo_core::params::{Fidelity, RadarParams};
use mimo_core::rng::Stream;
use mimo_radar::dwell::{Dwell, RangeWindow, Receiver, Target, Transmitter, evaluate};
use mimo_radar::geometry::beam_point;
use mimo_radar::measure::measurements_from_primitives;
use std::hint::black_box;
use std::time::{Duration, Instant};

/// One dwell's description, owned, so the bench can prebuild a list.
#[derive(Clone)]
struct Spec {
    tx: Vec<(usize, usize, f64, f64, u32)>,         // ship, face, u, v, pulses
    rx: Vec<(usize, usize, f64, f64, RangeWindow)>, // ship, face, u, v, window
}

struct Bench {
    p: RadarParams,
    fid: Fidelity,
    ships: Vec<Ship>,
}

impl Bench {
    /// Evaluate one dwell and form its measurements; returns the number of measurements.
    fn run(&self, spec: &Spec, targets: &[Target], key: u64) -> usize {
        let txs: Vec<Transmitter> = spec
            .tx
            .iter()
            .map(|&(s, f, u, v, n)| Transmitter {
                radar: self.ships[s].id,
                params: &self.p,
                frame: self.ships[s].faces[f],
                beam_u: u,
                beam_v: v,
                n_pulses: n,
                waveform: 0,
            })
            .collect();
        let rxs: Vec<Receiver> = spec
            .rx
            .iter()
            .enumerate()
            .map(|(k, &(s, f, u, v, window))| Receiver {
                radar: self.ships[s].id,
                dwell_id: key * 8 + k as u64,
                params: &self.p,
                face: f as u8,
                frame: self.ships[s].faces[f],
                beam_u: u,
                beam_v: v,
                window,
                predicted_snr: None,
            })
            .collect();
        let keys = [key];
        let d = Dwell {
            run: 0,
            t_s: key as f64 * 0.01,
            seed: 1,
            keys: &keys,
            transmitters: &txs,
            receivers: &rxs,
            fidelity: &self.fid,
            record_voltages: false,
            simulate_all_cells: false,
        };
        let out = evaluate(&d, targets);
        measurements_from_primitives(&out.primitives, key * 64).len()
    }

    fn track_spec(&self, aim: DVec3, half_window: f64, pulses: u32) -> Spec {
        let s = &self.ships[0];
        let b = beam_point(&s.faces, &self.p, aim).expect("aim is steerable");
        let window = RangeWindow::AroundAim { aim_ecef: aim, half_width_m: half_window };
        Spec { tx: vec![(0, b.face as usize, b.u, b.v, pulses)], rx: vec![(0, b.face as usize, b.u, b.v, window)] }
    }
}

/// Time `f` over `specs` repeatedly for at least `min` wall time; returns (dwells/s, meas/s).
fn time(min: Duration, n_specs: usize, mut f: impl FnMut(usize, u64) -> usize) -> (f64, f64, f64) {
    let start = Instant::now();
    let (mut dwells, mut meas, mut key) = (0u64, 0u64, 0u64);
    while start.elapsed() < min {
        for i in 0..n_specs {
            meas += black_box(f(i, key)) as u64;
            key += 1;
            dwells += 1;
        }
    }
    let s = start.elapsed().as_secs_f64();
    (dwells as f64 / s, meas as f64 / s, s * 1e6 / dwells as f64)
}

fn main() {
    let p = RadarParams::default();
    // The voltage level: the figures in reports/benchmarks-history.md are the voltage model's.
    let fid = Fidelity { level: mimo_core::params::FidelityLevel::Voltage, ..Fidelity::default() };
    let ships = vec![Ship::new(0, 36.0, -70.0, &p), Ship::new(1, 36.25, -70.3, &p), Ship::new(2, 35.8, -69.7, &p)];
    let b = Bench { p, fid, ships };
    // Targets: a fighter formation 120 km NE at 6 km (2 m²) and three airliners (30 m²).
    let lead = Geodetic::from_deg(36.8, -69.1, 6000.0).to_ecef();
    let mut targets: Vec<Target> = (0..4)
        .map(|k| Target {
            id: ["F-1", "F-2", "F-3", "F-4"][k],
            index: k as u32,
            pos_ecef: lead + DVec3::new(300.0 * k as f64, -200.0 * k as f64, 50.0 * (k % 2) as f64),
            rcs_m2: 2.0,
            pol: None,
        })
        .collect();
    for (k, (lat, lon, alt)) in
        [(38.2, -68.0, 10_000.0), (34.0, -72.5, 10_700.0), (36.5, -73.2, 11_300.0)].into_iter().enumerate()
    {
        targets.push(Target {
            id: ["A", "B", "C"][k],
            index: 4 + k as u32,
            pos_ecef: Geodetic::from_deg(lat, lon, alt).to_ecef(),
            rcs_m2: 30.0,
            pol: None,
        });
    }

    // The mix: 70 % search dwells on a raster of every face, 30 % track dwells at the targets.
    let mut s = Stream::new(7, &[1]);
    let th = b.p.beamwidth_u();
    let search = RangeWindow::Fixed { rho_min_m: b.p.min_range_m, rho_max_m: b.p.instrumented_range_m };
    let mut specs: Vec<Spec> = Vec::new();
    for k in 0..700 {
        let face = k % 4;
        let (u, v) = loop {
            let (u, v) = (s.uniform() * 1.6 - 0.8, s.uniform() * 1.6 - 0.8);
            if (1.0 - u * u - v * v) >= 0.25 {
                break (u, v);
            }
        };
        specs.push(Spec { tx: vec![(0, face, u, v, 1)], rx: vec![(0, face, u, v, search)] });
    }
    // Search beams that happen to hold the formation (a search raster finds it now and then).
    for _ in 0..20 {
        let mut spec = b.track_spec(lead, 0.0, 1);
        spec.rx[0].4 = search;
        specs.push(spec);
    }
    for k in 0..300 {
        let t = &targets[k % targets.len()];
        // Predicted position off by a fraction of a beamwidth.
        let aim = t.pos_ecef + DVec3::new(s.normal(), s.normal(), s.normal()) * 150.0;
        let mut spec = b.track_spec(aim, 1000.0, 4);
        spec.tx[0].2 += 0.1 * th * s.normal();
        specs.push(spec);
    }
    let n_search = 720;
    let min = Duration::from_millis(1500);

    println!("mimo-radar bench (single thread, opt-level 3)");
    println!();
    println!("{:<52} {:>12} {:>14} {:>10}", "workload", "dwells/s", "meas/s", "µs/dwell");
    let row = |name: &str, (d, m, us): (f64, f64, f64)| {
        println!("{name:<52} {d:>12.0} {m:>14.0} {us:>10.2}");
    };
    let all = |i: usize, key: u64| b.run(&specs[i], &targets, key);
    row("realistic mix (72% search 450 km, 28% track ±1 km)", time(min, specs.len(), all));
    row("  search dwells only (window 2–450 km)", time(min, n_search, |i, k| b.run(&specs[i], &targets, k)));
    row(
        "  track dwells only (window ±1 km, 4 pulses)",
        time(min, specs.len() - n_search, |i, k| b.run(&specs[n_search + i], &targets, k)),
    );

    println!();
    println!("cost vs targets in the beam (track dwell at the formation, window ±1 km):");
    let tspec = b.track_spec(lead + DVec3::new(450.0, -300.0, 25.0), 1000.0, 4);
    for n in [0usize, 1, 2, 4, 7] {
        // 7 = the formation plus 3 extra close targets.
        let mut tg: Vec<Target> = targets[..n.min(4)].to_vec();
        for k in 4..n {
            tg.push(Target {
                id: "X",
                index: 10 + k as u32,
                pos_ecef: lead + DVec3::new(-150.0 * k as f64, 100.0, 20.0),
                rcs_m2: 2.0,
                pol: None,
            });
        }
        row(&format!("  {n} targets"), time(Duration::from_millis(600), 1, |_, k| b.run(&tspec, &tg, k)));
    }
    println!();
    println!("cost vs range-window length (one target in the beam):");
    for half in [500.0, 5e3, 50e3, 220e3] {
        let spec = b.track_spec(lead, half, 4);
        row(
            &format!("  window {:.0} km ({:.0} cells)", 2.0 * half / 1e3, 2.0 * half / b.p.range_cell_m()),
            time(Duration::from_millis(600), 1, |_, k| b.run(&spec, &targets[..1], k)),
        );
    }
    println!();
    println!("MIMO dwell, 2 transmitters × 3 receivers (6 channels), 7 targets, windows ±1 km:");
    let mut mimo = Spec { tx: Vec::new(), rx: Vec::new() };
    for (si, sh) in b.ships.iter().enumerate() {
        let bp = beam_point(&sh.faces, &b.p, lead).expect("steerable");
        if si < 2 {
            mimo.tx.push((si, bp.face as usize, bp.u, bp.v, 4));
        }
        let window = RangeWindow::AroundAim { aim_ecef: lead, half_width_m: 1000.0 };
        mimo.rx.push((si, bp.face as usize, bp.u, bp.v, window));
    }
    row("  2 tx × 3 rx", time(Duration::from_millis(600), 1, |_, k| b.run(&mimo, &targets, k)));
}
