//! The deletion pass on the expiry queue against the full scan, on a tracker driven through
//! updates, misses, coasting and covariance growth (docs/model.md §6.4). Every pass of these
//! unit-test builds also runs the scan and asserts that the queue named every track it checks.

use crate::dwell::DwellContext;
use crate::frame::StateEcef;
use crate::geometry::{SensorGeometry, StaticGeometry};
use crate::{MultiTargetTracker, TrackerConfig};
use mimo_core::DVec3;
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use mimo_core::records::{DwellKind, MeasurementRow, TrackStatus};

const R1: RadarId = RadarId(0);

/// A measurement of the ECEF point `p` on face 0 of R1 at `t_s`.
fn measure(geom: &StaticGeometry, p: DVec3, t_s: f64, meas_id: u64) -> MeasurementRow {
    let s = geom.face(R1, 0, t_s).expect("face").to_sine(p);
    MeasurementRow {
        run: 0,
        meas_id,
        dwell_id: meas_id,
        t_s,
        rx: R1,
        tx: R1,
        rx_face: 0,
        range_m: s.range_m,
        u: s.u,
        v: s.v,
        snr_db: 25.0,
        var_range_m2: 25.0,
        var_u: 1e-6,
        var_v: 1e-6,
        n_primitives: 2,
        merged: false,
        target_hint: None,
    }
}

/// Thirty stationary tracks of position variances from 10² to 1000² m², spread across face 0 of
/// R1; one dwell every 0.25 s for 100 s that updates every third track for a while, looks at (and
/// misses) every third other track now and then, and sometimes comes late (an earlier time than
/// the last). Tracks end by misses and by covariance growth, and the pass's check (the scan) never finds a
/// track the queue left out.
#[test]
fn the_queue_deletes_what_the_scan_deletes() {
    let centre = Geodetic::from_deg(36.0, -70.0, 0.0);
    let mut geom = StaticGeometry::new();
    geom.add_ship(R1, Geodetic::from_deg(36.0, -70.0, 20.0), 0.0, &RadarParams::default());
    let mut tr = MultiTargetTracker::new(TrackerConfig::default(), centre);
    let face = geom.face(R1, 0, 0.0).expect("face");
    let mut spawned = Vec::new();
    for k in 0..30u32 {
        let p = face.from_ruv(60_000.0 + 1500.0 * f64::from(k), -0.6 + 0.04 * f64::from(k), 0.0);
        let sd_m = 10.0 * 100f64.powf(f64::from(k % 10) / 9.0);
        let mut cov = [[0.0; 6]; 6];
        for i in 0..3 {
            cov[i][i] = sd_m * sd_m;
            cov[i + 3][i + 3] = 100.0;
        }
        let state = StateEcef { pos: p, vel: DVec3::ZERO, cov };
        let (id, _) = tr.spawn_track(0, 0.0, &state, TrackStatus::Confirmed).expect("spawn");
        spawned.push((id, p, k));
    }
    let mut deleted = 0;
    for step in 1..=400u64 {
        let late = step % 7 == 0;
        let t_s = 0.25 * step as f64 - if late { 0.2 } else { 0.0 };
        let meas: Vec<MeasurementRow> = spawned
            .iter()
            .filter(|(_, _, k)| k % 3 == 0 && f64::from(*k) * 2.0 > t_s)
            .map(|(id, p, _)| measure(&geom, *p, t_s, 1000 * step + id))
            .collect();
        let looked: Vec<u64> =
            spawned.iter().filter(|(_, _, k)| k % 3 == 1 && step % (u64::from(*k) + 2) == 0).map(|s| s.0).collect();
        let ctx = DwellContext::aimed(0, step, t_s, DwellKind::Track, looked);
        let rows = tr.process_dwell(&ctx, &meas, &geom);
        deleted += rows.iter().filter(|r| r.status == TrackStatus::Deleted).count();
        for r in &rows {
            assert!(tr.changed_tracks().contains(&r.track_id), "row of track {} not among the changed", r.track_id);
        }
    }
    let by_reason = &tr.stats().deleted;
    assert_eq!(deleted as u64, by_reason.values().sum::<u64>());
    for reason in [crate::deletion::DeleteReason::Misses, crate::deletion::DeleteReason::Covariance] {
        assert!(by_reason.get(&reason).copied().unwrap_or(0) > 0, "no deletion by {reason:?}: {by_reason:?}");
    }
    assert_eq!(deleted, 30, "{by_reason:?}");
}
