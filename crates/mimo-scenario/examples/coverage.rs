//! Print a scenario's coverage timeline: for each target every few seconds, its range and
//! bearing from the scenario centre, altitude, speed, and which radars could see it.
//!
//! `cargo run -p mimo-scenario --example coverage -- 7 [step_s]` (a standard number or a path).

use glam::DVec3;
use mimo_core::geo::EnuFrame;
use mimo_scenario::{Scenario, ScenarioError, load_path, load_standard};

fn main() {
    if let Err(e) = run() {
        eprintln!("error: {e}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), ScenarioError> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let which = args.first().map_or("7", String::as_str);
    let step: f64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(20.0);
    let sc: Scenario = match which.parse::<u32>() {
        Ok(n) => load_standard(n)?,
        Err(_) => load_path(which)?,
    };
    let traj = sc.build_trajectories()?;
    let centre = EnuFrame::at(sc.centre());
    if args.iter().any(|a| a == "--csv") {
        println!("t_s,target,east_km,north_km,alt_m,visible");
        for j in 0..=(sc.duration_s / step).floor() as usize {
            let t = j as f64 * step;
            for (i, id) in traj.ids().iter().enumerate() {
                let s = traj.state_at(i, t);
                let enu = centre.to_enu(s.pos_ecef);
                let vis: String = sc
                    .ships
                    .iter()
                    .map(|sh| if sh.sees(t, s.pos_ecef, s.geodetic.alt_m) { '1' } else { '0' })
                    .collect();
                println!("{t},{id},{:.3},{:.3},{:.1},{vis}", enu.x / 1000.0, enu.y / 1000.0, s.geodetic.alt_m);
            }
        }
        return Ok(());
    }
    println!("{} — {}", sc.name, sc.description);
    print!("{:>6}", "t_s");
    for id in traj.ids() {
        print!(" | {:^42}", id);
    }
    println!();
    let n = (sc.duration_s / step).floor() as usize;
    let mut last: Vec<Vec<bool>> = vec![vec![false; sc.ships.len()]; traj.len()];
    let mut events = Vec::new();
    let mut seen_any = vec![0usize; traj.len()];
    let fine = 1.0;
    let n_fine = (sc.duration_s / fine).floor() as usize;
    for j in 0..=n_fine {
        let t = j as f64 * fine;
        for i in 0..traj.len() {
            let s = traj.state_at(i, t);
            let vis: Vec<bool> = sc.ships.iter().map(|sh| sh.sees(t, s.pos_ecef, s.geodetic.alt_m)).collect();
            if vis.iter().any(|&v| v) {
                seen_any[i] += 1;
            }
            if j > 0 {
                for (r, (&now, &before)) in vis.iter().zip(&last[i]).enumerate() {
                    if now != before {
                        events.push(format!(
                            "t = {t:6.0} s  {:<4} {} R{}",
                            traj.ids()[i],
                            if now { "enters" } else { "leaves" },
                            r + 1
                        ));
                    }
                }
            }
            last[i] = vis;
        }
    }
    for j in 0..=n {
        let t = j as f64 * step;
        print!("{t:6.0}");
        for i in 0..traj.len() {
            let s = traj.state_at(i, t);
            let enu: DVec3 = centre.to_enu(s.pos_ecef);
            let range_km = (enu.x.hypot(enu.y)) / 1000.0;
            let brg = enu.x.atan2(enu.y).to_degrees().rem_euclid(360.0);
            let vis: String =
                sc.ships.iter().map(|sh| if sh.sees(t, s.pos_ecef, s.geodetic.alt_m) { '#' } else { '.' }).collect();
            print!(
                " | {:5.0},{:5.0} {range_km:4.0}km {brg:3.0}° {:5.0}m {:3.0} {vis}",
                enu.x / 1000.0,
                enu.y / 1000.0,
                s.geodetic.alt_m,
                s.vel_ecef.length()
            );
        }
        println!();
    }
    println!("\ncoverage events (1 s resolution):");
    for e in &events {
        println!("  {e}");
    }
    println!("\nfraction of time seen by at least one radar:");
    for (i, id) in traj.ids().iter().enumerate() {
        println!("  {id:<4} {:.3}", seen_any[i] as f64 / (n_fine + 1) as f64);
    }
    Ok(())
}
