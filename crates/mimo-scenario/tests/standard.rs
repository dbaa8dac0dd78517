//! Properties of the standard scenarios and their trajectories (docs/model.md §8, §9 item 10).

use glam::DVec3;
use mimo_core::G0_MPS2;
use mimo_core::geo::{EnuFrame, ecef_to_geodetic};
use mimo_scenario::{Scenario, Trajectories, list_standard, load_standard};
use std::sync::OnceLock;

const FIGHTERS: [&str; 4] = ["F-1", "F-2", "F-3", "F-4"];

fn s7() -> &'static (Scenario, Trajectories) {
    static S: OnceLock<(Scenario, Trajectories)> = OnceLock::new();
    S.get_or_init(|| {
        let s = load_standard(7).expect("scenario 7 loads");
        let t = s.build_trajectories().expect("scenario 7 flies");
        (s, t)
    })
}

fn idx(t: &Trajectories, id: &str) -> usize {
    t.index_of(id).expect("target present")
}

#[test]
fn every_standard_scenario_has_the_table_1_targets_and_four_ships() {
    let want: [&[&str]; 7] = [
        &["F-1", "A", "B", "C"],
        &["F-2", "A", "B", "C"],
        &["F-3", "A", "B", "C"],
        &["F-4", "A", "B", "C"],
        &["F-1", "F-2", "A", "B", "C"],
        &["F-3", "F-4", "A", "B", "C"],
        &["F-1", "F-2", "F-3", "F-4", "A", "B", "C"],
    ];
    let all = list_standard().expect("all standard scenarios load");
    assert_eq!(all.len(), 7);
    for (n, s) in &all {
        let n = *n as usize;
        assert_eq!(s.target_ids(), want[n - 1], "scenario {n}");
        assert_eq!(s.name, format!("scenario-{n}"));
        assert_eq!(s.duration_s, 1000.0);
        let ids: Vec<String> = s.ships.iter().map(|x| x.id.to_string()).collect();
        assert_eq!(ids, ["R1", "R2", "R3", "R4"]);
        for t in &s.targets {
            let (rcs, kind) = if t.id.starts_with("F-") { (2.0, "fighter") } else { (30.0, "airliner") };
            assert_eq!((t.rcs_m2, t.kind.as_str()), (rcs, kind), "{}", t.id);
        }
        s.validate().expect("valid");
    }
    // Ship layout: a diamond 20–50 km apart around 36°N 70°W, arrays 20 m up, some ships
    // steaming, some with fewer faces.
    let s = &all[6].1;
    let c = s.centre();
    assert!((c.lat_deg() - 36.0).abs() < 0.01 && (c.lon_deg() + 70.0).abs() < 0.01);
    for (i, a) in s.ships.iter().enumerate() {
        assert_eq!(a.array_height_m, 20.0);
        for b in &s.ships[i + 1..] {
            let d = (a.start_position().to_ecef() - b.start_position().to_ecef()).length();
            assert!((20e3..=50e3).contains(&d), "{} to {}: {d} m", a.id, b.id);
        }
    }
    let faces: Vec<usize> = s.ships.iter().map(|x| x.faces_at(0.0).len()).collect();
    assert_eq!(faces, [4, 2, 4, 3]);
    let steaming: Vec<bool> = s.ships.iter().map(|x| x.speed_mps > 0.0).collect();
    assert_eq!(steaming, [true, false, true, false]);
    let moved = (s.ships[0].position_at(1000.0).to_ecef() - s.ships[0].start_position().to_ecef()).length();
    assert!((moved - 9000.0).abs() < 1.0, "R1 moved {moved} m");
}

#[test]
fn fighters_start_inbound_200_to_250_km_out_and_airliners_300_to_400() {
    let (s, t) = s7();
    let centre = EnuFrame::at(s.centre());
    for (i, id) in t.ids().iter().enumerate() {
        let st = t.state_at(i, 0.0);
        let p = centre.to_enu(st.pos_ecef);
        let v = centre.vec_to_enu(st.vel_ecef);
        let range = p.truncate().length();
        let closing = -p.truncate().normalize().dot(v.truncate()) / v.truncate().length();
        if id.starts_with("F-") {
            assert!((200e3..=250e3).contains(&range), "{id}: {range}");
            assert!(closing > 0.95, "{id} inbound: {closing}");
        } else {
            assert!((300e3..=400e3).contains(&range), "{id}: {range}");
        }
    }
}

/// Second differences of node positions give the acceleration; every sample is checked.
#[test]
fn speeds_and_accelerations_stay_inside_each_envelope() {
    let (s, t) = s7();
    let h = t.step_s();
    let n = (s.duration_s / h).round() as usize;
    for (i, target) in s.targets.iter().enumerate() {
        let env = target.envelope;
        let limit = env.max_accel_g * G0_MPS2;
        let (mut max_a, mut max_lat, mut vmin, mut vmax) = (0.0f64, 0.0f64, f64::MAX, 0.0f64);
        let mut worst_v_err = 0.0f64;
        for k in 1..n {
            let tk = k as f64 * h;
            let (pm, p0, pp) = (t.position_at(i, tk - h), t.position_at(i, tk), t.position_at(i, tk + h));
            let v = t.state_at(i, tk).vel_ecef;
            let a = (pp - 2.0 * p0 + pm) / (h * h);
            let lat = a - v.normalize() * a.dot(v.normalize());
            max_a = max_a.max(a.length());
            max_lat = max_lat.max(lat.length());
            vmin = vmin.min(v.length());
            vmax = vmax.max(v.length());
            worst_v_err = worst_v_err.max(((pp - pm) / (2.0 * h) - v).length());
        }
        assert!(max_a <= limit, "{}: |a| {} g > {}", target.id, max_a / G0_MPS2, env.max_accel_g);
        assert!(max_lat <= limit, "{}: a_lat {} g", target.id, max_lat / G0_MPS2);
        assert!(vmin >= env.min_speed_mps && vmax <= env.max_speed_mps, "{}: {vmin}..{vmax}", target.id);
        eprintln!(
            "{}: speed {vmin:.1}..{vmax:.1} m/s, max |a| {:.2} g, max lateral {:.2} g",
            target.id,
            max_a / G0_MPS2,
            max_lat / G0_MPS2
        );
        // The stored velocity is the derivative of the stored position. The central difference
        // is exact to O(h²) except where the acceleration steps, by ΔA·h/4: the only step is the
        // start and end of the sin² vertical pass of a crossover (docs/model.md §8.2), ΔA =
        // 2π²·150 m / (20 s)² = 7.4 m/s², which gives 0.093 m/s.
        assert!(worst_v_err < 0.1, "{}: velocity vs positions {worst_v_err} m/s", target.id);
        if target.id.starts_with("F-") {
            // The turns really happen (n = 2–3), so the bound above is not vacuous.
            assert!(max_a > 2.5 * G0_MPS2, "{}: max {} g", target.id, max_a / G0_MPS2);
            // In the rigid formation turn the outer aircraft fly faster, the inner slower.
            assert!(vmax - vmin > 20.0, "{}: {vmin}..{vmax}", target.id);
        } else {
            assert!(max_a < 0.01 * G0_MPS2, "{} flies straight: {} g", target.id, max_a / G0_MPS2);
            assert!((vmin - 230.0).abs() < 0.01 && (vmax - 230.0).abs() < 0.01);
        }
    }
}

#[test]
fn fighters_never_come_closer_than_150_m() {
    let (s, t) = s7();
    let ids: Vec<usize> = FIGHTERS.iter().map(|f| idx(t, f)).collect();
    let mut min = (f64::MAX, 0.0, 0, 0);
    let n = (s.duration_s * 100.0) as usize; // every 10 ms
    for j in 0..=n {
        let tt = j as f64 * 0.01;
        let p: Vec<DVec3> = ids.iter().map(|&i| t.position_at(i, tt)).collect();
        for a in 0..4 {
            for b in a + 1..4 {
                let d = (p[a] - p[b]).length();
                if d < min.0 {
                    min = (d, tt, a, b);
                }
            }
        }
    }
    // Exactly 150 m at mid-crossover by design (F-1 over F-3, F-2 over F-4): allow rounding.
    assert!(
        min.0 >= 150.0 - 1e-6,
        "min separation {} m at t = {} ({}, {})",
        min.0,
        min.1,
        FIGHTERS[min.2],
        FIGHTERS[min.3]
    );
    assert!(min.0 < 150.1 && (min.1 - 110.0).abs() < 0.02, "{min:?}");
}

/// Lateral positions (m, positive right) of `ids` relative to their mean, in the local
/// horizontal frame of their mean velocity.
fn lateral(t: &Trajectories, ids: &[&str], at: f64) -> Vec<f64> {
    let st: Vec<_> = ids.iter().map(|id| t.state_at(idx(t, id), at)).collect();
    let mean_p = st.iter().map(|s| s.pos_ecef).sum::<DVec3>() / st.len() as f64;
    let mean_v = st.iter().map(|s| s.vel_ecef).sum::<DVec3>() / st.len() as f64;
    let frame = EnuFrame::at(ecef_to_geodetic(mean_p));
    let v = frame.vec_to_enu(mean_v);
    let psi = v.x.atan2(v.y);
    let right = frame.vec_to_ecef(DVec3::new(psi.cos(), -psi.sin(), 0.0));
    st.iter().map(|s| (s.pos_ecef - mean_p).dot(right)).collect()
}

#[test]
fn crossovers_swap_sides() {
    let (_, t) = s7();
    let order = |at: f64| {
        let c = lateral(t, &FIGHTERS, at);
        let mut o: Vec<usize> = (0..4).collect();
        o.sort_by(|&a, &b| c[a].total_cmp(&c[b]));
        o.iter().map(|&q| FIGHTERS[q]).collect::<Vec<_>>()
    };
    assert_eq!(order(99.0), ["F-1", "F-2", "F-3", "F-4"]);
    assert_eq!(order(121.0), ["F-3", "F-4", "F-1", "F-2"]);
    let mid = lateral(t, &FIGHTERS, 110.0);
    assert!((mid[0] - mid[2]).abs() < 1.0 && (mid[1] - mid[3]).abs() < 1.0, "{mid:?}");
    // Line abreast 300 m apart before and after.
    let before = lateral(t, &FIGHTERS, 99.0);
    for q in 0..3 {
        assert!((before[q + 1] - before[q] - 300.0).abs() < 1.0, "{before:?}");
    }
    // The second crossover: pair A swaps sides within the pair at 450–470 s.
    let a_before = lateral(t, &["F-1", "F-2"], 449.0);
    let a_after = lateral(t, &["F-1", "F-2"], 471.0);
    assert!(a_before[0] < a_before[1] && a_after[0] > a_after[1], "{a_before:?} {a_after:?}");
}

#[test]
fn at_mid_crossover_the_crossing_aircraft_are_unresolved() {
    let (s, t) = s7();
    let tm = 110.0;
    for ship in &s.ships {
        let site = ship.position_at(tm).to_ecef();
        for (a, b) in [("F-1", "F-3"), ("F-2", "F-4")] {
            let pa = t.state_at(idx(t, a), tm);
            let pb = t.state_at(idx(t, b), tm);
            assert!(ship.sees(tm, pa.pos_ecef, pa.geodetic.alt_m), "{} sees {a}", ship.id);
            let (ra, rb) = ((pa.pos_ecef - site).length(), (pb.pos_ecef - site).length());
            assert!((ra - rb).abs() <= ship.radar.range_cell_m(), "{}: {a}/{b} Δr {}", ship.id, ra - rb);
            let angle = (pa.pos_ecef - site).normalize().dot((pb.pos_ecef - site).normalize()).min(1.0).acos();
            assert!(angle <= ship.radar.beamwidth_u(), "{}: {a}/{b} angle {angle}", ship.id);
            // And in the sine space of the face that would track them.
            let (f, _) = ship.best_face(tm, pa.pos_ecef).expect("in a face");
            let face = ship.faces_at(tm)[f];
            let (ua, ub) = (face.to_sine(pa.pos_ecef), face.to_sine(pb.pos_ecef));
            assert!((ua.u - ub.u).abs() <= ship.radar.beamwidth_u());
            assert!((ua.v - ub.v).abs() <= ship.radar.beamwidth_v());
        }
    }
}

#[test]
fn level_airliners_hold_their_altitude_within_a_metre() {
    let (s, t) = s7();
    for a in &s.aircraft {
        let i = idx(t, &a.id);
        let n = (s.duration_s / 0.125) as usize;
        let worst =
            (0..=n).map(|j| (t.state_at(i, j as f64 * 0.125).geodetic.alt_m - a.start.alt_m).abs()).fold(0.0, f64::max);
        assert!(worst < 1.0, "{}: altitude off by {worst} m", a.id);
    }
    let alts: Vec<f64> = s.aircraft.iter().map(|a| a.start.alt_m).collect();
    assert_eq!(alts, [10_000.0, 10_700.0, 11_300.0]);
}

/// At 1 s resolution: which radars see each target.
fn visibility(s: &Scenario, t: &Trajectories) -> Vec<Vec<Vec<bool>>> {
    (0..t.len())
        .map(|i| {
            (0..=s.duration_s as usize)
                .map(|j| {
                    let st = t.state_at(i, j as f64);
                    s.ships.iter().map(|sh| sh.sees(j as f64, st.pos_ecef, st.geodetic.alt_m)).collect()
                })
                .collect()
        })
        .collect()
}

#[test]
fn targets_leave_and_enter_radars_while_mostly_seen_by_another() {
    let (s, t) = s7();
    let vis = visibility(s, t);
    let mut leaves = 0;
    let mut enters = 0;
    for (i, id) in t.ids().iter().enumerate() {
        let seen_by_some = vis[i].iter().filter(|v| v.iter().any(|&x| x)).count() as f64 / vis[i].len() as f64;
        assert!(seen_by_some >= 0.95, "{id} seen by some radar only {seen_by_some}");
        let mut both_on_one_radar = false;
        let mut any = false;
        for r in 0..s.ships.len() {
            let (mut l, mut e) = (0, 0);
            for w in vis[i].windows(2) {
                match (w[0][r], w[1][r]) {
                    (true, false) => l += 1,
                    (false, true) => e += 1,
                    _ => {}
                }
            }
            leaves += l;
            enters += e;
            any |= l + e > 0;
            both_on_one_radar |= l > 0 && e > 0;
        }
        assert!(any, "{id} never leaves or enters any radar's coverage");
        if id.starts_with("F-") {
            assert!(both_on_one_radar, "{id} should both leave and re-enter some radar's coverage");
        }
    }
    assert!(leaves >= 7 && enters >= 7, "{leaves} leaves, {enters} enters");
}

#[test]
fn scenarios_1_to_6_fly_the_same_paths_as_7() {
    let (_, t7) = s7();
    let rows7 = t7.truth_rows(0, 1.0);
    for n in 1..=6 {
        let s = load_standard(n).expect("loads");
        let t = s.build_trajectories().expect("flies");
        let rows = t.truth_rows(0, 1.0);
        for id in t.ids() {
            let a: Vec<_> = rows.iter().filter(|r| &r.target == id).collect();
            let b: Vec<_> = rows7.iter().filter(|r| &r.target == id).collect();
            assert_eq!(a, b, "scenario {n}, target {id}");
        }
    }
}

#[test]
fn truth_rows_are_ordered_complete_and_deterministic() {
    let (s, t) = s7();
    let rows = t.truth_rows(3, 10.0);
    assert_eq!(rows.len(), 10_001 * 7);
    for (j, chunk) in rows.chunks(7).enumerate() {
        let tt = j as f64 / 10.0;
        for (r, id) in chunk.iter().zip(t.ids()) {
            assert_eq!((r.run, r.t_s, &r.target), (3, tt, id));
            let g = ecef_to_geodetic(DVec3::new(r.x_m, r.y_m, r.z_m));
            assert!((g.lat_deg() - r.lat_deg).abs() < 1e-12 && (g.alt_m - r.alt_m).abs() < 1e-6);
            assert!([r.vx_mps, r.vy_mps, r.vz_mps].iter().all(|v| v.is_finite()));
        }
    }
    assert_eq!(rows.last().map(|r| r.t_s), Some(1000.0));
    let again = s.build_trajectories().expect("flies").truth_rows(3, 10.0);
    assert_eq!(rows, again);
    assert!(t.truth_rows(0, 0.0).is_empty() && t.truth_rows(0, f64::NAN).is_empty());
}

#[test]
fn interpolation_is_smooth_between_samples_and_extrapolates_outside() {
    let (_, t) = s7();
    let i = idx(t, "F-4");
    // Mid-sample velocity agrees with a fine central difference of positions, including in the
    // formation turn (60–80 s) and the break (170 s).
    for &tt in &[10.013, 62.5, 64.987, 70.02, 110.03, 170.01, 171.337, 650.4] {
        let v = t.state_at(i, tt).vel_ecef;
        let fd = (t.position_at(i, tt + 1e-3) - t.position_at(i, tt - 1e-3)) / 2e-3;
        assert!((v - fd).length() < 0.02, "t {tt}: {}", (v - fd).length());
    }
    // Beyond the ends: constant velocity.
    let end = t.state_at(i, 1002.0);
    let later = t.state_at(i, 1010.0);
    assert!((later.pos_ecef - (end.pos_ecef + end.vel_ecef * 8.0)).length() < 0.5);
    let before = t.state_at(i, -1.0);
    assert!(before.pos_ecef.is_finite());
}

#[test]
fn break_up_keeps_positions_and_velocities_continuous() {
    let (_, t) = s7();
    let h = t.step_s();
    for f in FIGHTERS {
        let i = idx(t, f);
        for &ts in &[170.0, 169.95, 170.05] {
            let (a, b) = (t.state_at(i, ts - h), t.state_at(i, ts));
            let predicted = a.pos_ecef + (a.vel_ecef + b.vel_ecef) * (h / 2.0);
            assert!((predicted - b.pos_ecef).length() < 0.05, "{f} at {ts}: {}", (predicted - b.pos_ecef).length());
            assert!((a.vel_ecef - b.vel_ecef).length() < 0.5, "{f} at {ts}");
        }
    }
}

#[test]
fn resolved_scenario_round_trips_through_json() {
    let (s, t) = s7();
    let json = serde_json::to_string_pretty(s).expect("serializes");
    assert!(json.contains("\"id\": \"R1\"") && json.contains("\"reference\""));
    let back: Scenario = serde_json::from_str(&json).expect("deserializes");
    assert_eq!(&back, s);
    back.validate().expect("valid");
    let rows = back.build_trajectories().expect("flies").truth_rows(0, 2.0);
    assert_eq!(rows, t.truth_rows(0, 2.0));
    // A subset scenario round trips too (pruned formation with explicit split references).
    let s1 = load_standard(1).expect("loads");
    let back1: Scenario = serde_json::from_str(&serde_json::to_string(&s1).expect("ser")).expect("de");
    assert_eq!(back1, s1);
}
