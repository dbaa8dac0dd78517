//! Quick closed-loop study without files: `cargo run --release -p mimo-sim --example study -- 7 default 2`
//! runs scenario 7 with a tracker for N runs and prints a rough completeness per target (scorable
//! truths at 1-s steps, gated one-to-one assignment at 1 km). `mimo score` is the reference metric.

use mimo_core::DVec3;
use mimo_core::records::TrackStatus;
use mimo_sim::{EngineConfig, SearchConfig, World, builtin_ta, run_one};
use std::collections::BTreeMap;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let n: u32 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(7);
    let tracker = args.get(2).cloned().unwrap_or_else(|| "default".into());
    let runs: u32 = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let duration: f64 = args.get(4).and_then(|s| s.parse().ok()).unwrap_or(1000.0);
    let mut scenario = mimo_scenario::load_standard(n).expect("scenario");
    scenario.duration_s = duration;
    let world = World::new(scenario).expect("world");
    let cfg = EngineConfig {
        seed: 20_261_122,
        duration_s: duration,
        record_voltages: false,
        search: SearchConfig::default(),
    };
    for run in 0..runs {
        let mut ta = builtin_ta(&tracker, &world).expect("tracker");
        let t0 = std::time::Instant::now();
        let (tables, stats) = run_one(&world, &cfg, run, ta.as_mut());
        let wall = t0.elapsed().as_secs_f64();
        // Track lives.
        let mut first_conf: BTreeMap<u64, f64> = BTreeMap::new();
        let mut deleted: BTreeMap<u64, f64> = BTreeMap::new();
        let mut rows: BTreeMap<u64, Vec<(f64, DVec3, DVec3)>> = BTreeMap::new();
        for r in &tables.tracks {
            match r.status {
                TrackStatus::Confirmed => {
                    first_conf.entry(r.track_id).or_insert(r.t_s);
                }
                TrackStatus::Deleted => {
                    deleted.insert(r.track_id, r.t_s);
                }
                TrackStatus::Tentative => {}
            }
            rows.entry(r.track_id).or_default().push((
                r.t_s,
                DVec3::new(r.x_m, r.y_m, r.z_m),
                DVec3::new(r.vx_mps, r.vy_mps, r.vz_mps),
            ));
        }
        let mut per: BTreeMap<String, (u32, u32, Vec<u32>)> = BTreeMap::new();
        let (mut ok, mut tot) = (0u32, 0u32);
        let mut excess = 0usize;
        let mut t = 1.0;
        while t < duration {
            let live: Vec<DVec3> = first_conf
                .iter()
                .filter(|(id, tc)| **tc <= t && deleted.get(id).is_none_or(|d| *d > t))
                .filter_map(|(id, _)| {
                    let v = &rows[id];
                    let k = v.partition_point(|x| x.0 <= t);
                    (k > 0).then(|| v[k - 1].1 + v[k - 1].2 * (t - v[k - 1].0))
                })
                .collect();
            let truths: Vec<_> = world
                .targets_at(t)
                .into_iter()
                .filter(|x| world.scenario.ships.iter().any(|s| s.sees(t, x.pos_ecef, x.alt_m)))
                .collect();
            let cost: Vec<f64> = truths
                .iter()
                .flat_map(|x| {
                    live.iter().map(move |p| {
                        let d = (*p - x.pos_ecef).length();
                        if d < 1000.0 { d } else { f64::INFINITY }
                    })
                })
                .collect();
            let miss = vec![1e7; truths.len()];
            let sol = mimo_core::assign::assign_with_miss(&cost, truths.len(), live.len(), &miss);
            excess += live.len() - sol.iter().filter(|s| s.is_some()).count();
            for (x, s) in truths.iter().zip(&sol) {
                let e = per.entry(x.id.to_string()).or_default();
                e.1 += 1;
                tot += 1;
                if s.is_some() {
                    e.0 += 1;
                    ok += 1;
                } else {
                    e.2.push(t as u32);
                }
            }
            t += 1.0;
        }
        println!(
            "scenario {n} {tracker} run {run}: completeness {:.4}, unassigned live tracks per second {:.2} ({} dwells, {} TA, {} meas, {} confirmed tracks) in {wall:.1} s",
            f64::from(ok) / f64::from(tot.max(1)),
            excess as f64 / duration,
            stats.dwells,
            stats.ta_dwells,
            stats.measurements,
            first_conf.len()
        );
        let ta_e: f64 = tables
            .dwells
            .iter()
            .filter(|d| d.requested_by == mimo_core::records::Requester::Ta)
            .map(|d| d.energy_j)
            .sum();
        println!("  TA energy {ta_e:.0} J");
        for (id, (a, b, misses)) in &per {
            let mut iv: Vec<(u32, u32)> = Vec::new();
            for &m in misses {
                match iv.last_mut() {
                    Some(l) if m == l.1 + 1 => l.1 = m,
                    _ => iv.push((m, m)),
                }
            }
            println!("  {id:4} {:.4}  missed {:?}", f64::from(*a) / f64::from((*b).max(1)), &iv[..iv.len().min(10)]);
        }
    }
}
