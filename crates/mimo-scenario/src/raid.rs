//! A raid: N aircraft added to a scenario, drawn from a seed (docs/model.md §8.4).
//!
//! Each raid aircraft is a fighter or an airliner on a straight, level path (or one with a single
//! gentle turn) that passes its closest point to the centroid of the ships within
//! [`CPA_MAX_M`] of it, between a quarter and three quarters of the way through the run, so
//! every path crosses the ships' coverage while the scenario runs. Aircraft `k` is drawn from its
//! own stream `(seed, RAID, k)`: the raid of N aircraft is the first N of the raid of N + 1, and
//! the same seed and N give the same raid on every machine and thread count.
//!
//! The aircraft join the scenario as ordinary single aircraft and targets (`RAID-0001`, …), so
//! the truth table, the radar model and the scoring see them like any other target, and the run
//! manifest records them with the rest of the scenario.

use crate::model::{Aircraft, Envelope, LatLonAlt, Manoeuvre, Scenario, Target};
use mimo_core::geo::{EnuFrame, Geodetic, ecef_to_geodetic};
use mimo_core::rng::{Stream, domain};

/// Most raid aircraft a scenario may be given.
pub const MAX_RAID_TARGETS: u32 = 4096;
/// Largest horizontal distance of a raid path's closest approach from the ships' centroid (m):
/// well inside the radars' 450-km instrumented range and the radar horizon of a 3-km target
/// (about 240 km for a 20-m array).
pub const CPA_MAX_M: f64 = 150e3;
/// Prefix of raid target ids (`RAID-0001`, …).
pub const ID_PREFIX: &str = "RAID-";

/// One class of raid aircraft: how its mean RCS, speed, altitude and turns are drawn.
struct Class {
    kind: &'static str,
    /// Mean RCS range (m²), drawn log-uniformly.
    rcs_m2: (f64, f64),
    /// Horizontal speed range (m/s), uniform.
    speed_mps: (f64, f64),
    /// Altitude range (m), uniform.
    alt_m: (f64, f64),
    /// Load factor of a turn, uniform.
    load_factor: (f64, f64),
    envelope: Envelope,
}

/// Fighters: 1–5 m², 200–300 m/s at 3–9 km, turns at 1.5–3 g load factor.
const FIGHTER: Class = Class {
    kind: "fighter",
    rcs_m2: (1.0, 5.0),
    speed_mps: (200.0, 300.0),
    alt_m: (3000.0, 9000.0),
    load_factor: (1.5, 3.0),
    envelope: Envelope { min_speed_mps: 150.0, max_speed_mps: 400.0, max_accel_g: 5.0 },
};

/// Airliners: 10–100 m², 210–250 m/s at 9–12 km, rate-one turns banked 18–25° (load factor
/// 1.05–1.10, lateral acceleration under 0.5 g).
const AIRLINER: Class = Class {
    kind: "airliner",
    rcs_m2: (10.0, 100.0),
    speed_mps: (210.0, 250.0),
    alt_m: (9000.0, 12000.0),
    load_factor: (1.05, 1.10),
    envelope: Envelope { min_speed_mps: 200.0, max_speed_mps: 260.0, max_accel_g: 0.5 },
};

fn uniform(s: &mut Stream, (lo, hi): (f64, f64)) -> f64 {
    lo + (hi - lo) * s.uniform()
}

/// The id of raid aircraft `k` (0-based).
pub fn raid_id(k: u32) -> String {
    format!("{ID_PREFIX}{:04}", k + 1)
}

/// The geodetic centroid of the ships at t = 0 (their mean ECEF position, on the surface).
fn ships_centroid(s: &Scenario) -> Geodetic {
    let n = s.ships.len().max(1) as f64;
    let sum = s.ships.iter().map(|sh| sh.start_position().to_ecef()).fold(glam::DVec3::ZERO, |a, p| a + p);
    let mut g = ecef_to_geodetic(sum / n);
    g.alt_m = 0.0;
    g
}

/// Draw raid aircraft `k` of `seed` for a scenario of `duration_s` around `centre`.
fn draw(seed: u64, k: u32, centre: &EnuFrame, duration_s: f64) -> (Aircraft, Target) {
    let mut s = Stream::new(seed, &[domain::RAID, u64::from(k)]);
    let class = if s.uniform() < 0.5 { &FIGHTER } else { &AIRLINER };
    let rcs_m2 = class.rcs_m2.0 * (class.rcs_m2.1 / class.rcs_m2.0).powf(s.uniform());
    let speed_mps = uniform(&mut s, class.speed_mps);
    let alt_m = uniform(&mut s, class.alt_m);
    // Closest approach: a point uniform over the disc of radius CPA_MAX_M, a course uniform in
    // direction, reached at a time in the middle half of the run.
    let (r_m, bearing) = (CPA_MAX_M * s.uniform().sqrt(), std::f64::consts::TAU * s.uniform());
    let course = std::f64::consts::TAU * s.uniform();
    let t_cpa_s = duration_s * uniform(&mut s, (0.25, 0.75));
    let dir = glam::DVec3::new(course.sin(), course.cos(), 0.0);
    let cpa = glam::DVec3::new(r_m * bearing.sin(), r_m * bearing.cos(), 0.0);
    let start_enu = cpa - dir * speed_mps * t_cpa_s;
    let start = ecef_to_geodetic(centre.to_ecef(start_enu));
    // The start heading: the bearing of the closest-approach point seen from the start.
    let there = EnuFrame::at(start).to_enu(centre.to_ecef(cpa));
    let heading_deg = there.x.atan2(there.y).to_degrees().rem_euclid(360.0);
    let mut manoeuvres = Vec::new();
    if s.uniform() < 0.5 {
        let sign = if s.uniform() < 0.5 { -1.0 } else { 1.0 };
        manoeuvres.push(Manoeuvre::Turn {
            at_s: duration_s * uniform(&mut s, (0.1, 0.8)),
            turn_deg: sign * uniform(&mut s, (10.0, 60.0)),
            load_factor: uniform(&mut s, class.load_factor),
            ramp_s: 2.0,
        });
    }
    let id = raid_id(k);
    let start = LatLonAlt { lat_deg: start.lat_deg(), lon_deg: start.lon_deg(), alt_m };
    let aircraft = Aircraft {
        id: id.clone(),
        kind: class.kind.into(),
        start,
        heading_deg,
        speed_mps,
        manoeuvres,
        rcs_m2: Some(rcs_m2),
    };
    let target = Target { id, kind: class.kind.into(), rcs_m2, envelope: class.envelope, polarimetry: None };
    (aircraft, target)
}

/// Add `n` raid aircraft drawn from `seed` to a resolved scenario (after its own targets).
pub fn add_raid(s: &mut Scenario, n: u32, seed: u64) {
    let centre = EnuFrame::at(ships_centroid(s));
    for k in 0..n {
        let (a, t) = draw(seed, k, &centre, s.duration_s);
        s.aircraft.push(a);
        s.targets.push(t);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn raided(n: u32, seed: u64) -> Scenario {
        let mut s = crate::load_standard(7).expect("scenario 7");
        add_raid(&mut s, n, seed);
        s
    }

    #[test]
    fn the_same_seed_gives_the_same_raid_and_another_seed_another() {
        let (a, b, c) = (raided(16, 5), raided(16, 5), raided(16, 6));
        assert_eq!(a, b);
        assert_eq!(a.targets.len(), 7 + 16);
        let starts = |s: &Scenario| s.aircraft.iter().map(|x| (x.start.lat_deg, x.start.lon_deg)).collect::<Vec<_>>();
        let (sa, sc) = (starts(&a), starts(&c));
        // Every raid aircraft differs between the seeds (the airliners A-C are the scenario's).
        let differ = sa.iter().zip(&sc).filter(|(x, y)| x != y).count();
        assert_eq!(differ, 16, "{sa:?} {sc:?}");
        // Serialized and read back (a manifest), the raid is the same scenario.
        let text = serde_json::to_string(&a).expect("json");
        let back: Scenario = serde_json::from_str(&text).expect("read back");
        assert_eq!(back, a);
    }

    #[test]
    fn a_raid_nests_and_flies_inside_its_envelopes() {
        let (small, big) = (raided(8, 11), raided(40, 11));
        assert_eq!(small.targets[..], big.targets[..small.targets.len()]);
        assert_eq!(small.aircraft[..], big.aircraft[..small.aircraft.len()]);
        // Both kinds and turning and straight paths occur.
        let kinds = |k: &str| big.targets.iter().filter(|t| t.id.starts_with(ID_PREFIX) && t.kind == k).count();
        assert!(kinds("fighter") >= 8 && kinds("airliner") >= 8, "{} {}", kinds("fighter"), kinds("airliner"));
        let turning = big.aircraft.iter().filter(|a| !a.manoeuvres.is_empty()).count();
        assert!((8..=32).contains(&turning), "{turning} of 40 turn");
        // build_trajectories validates the scenario and checks every sample against its envelope.
        let tr = big.build_trajectories().expect("the raid flies");
        assert_eq!(tr.len(), 47);
        assert_eq!(tr.index_of("RAID-0040"), Some(46));
    }

    #[test]
    fn every_raid_path_crosses_a_radar_coverage() {
        let s = raided(64, 20261126);
        let tr = s.build_trajectories().expect("trajectories");
        for k in 0..64 {
            let i = tr.index_of(&raid_id(k)).expect("raid target");
            let seen_s = (0..=100)
                .map(|n| f64::from(n) * s.duration_s / 100.0)
                .filter(|&t| {
                    let st = tr.state_at(i, t);
                    s.ships.iter().any(|sh| sh.sees(t, st.pos_ecef, st.geodetic.alt_m))
                })
                .count();
            // Seen by some radar for at least a fifth of the run.
            assert!(seen_s >= 20, "{} seen at {seen_s} of 101 times", raid_id(k));
        }
    }
}
