//! Shared helpers for the integration tests: a two-ship geometry, truth propagation and a
//! measurement simulator that works in ECEF through `mimo-core`'s face frames (independently of
//! the tracker's own measurement model).

#![allow(dead_code)]

use mimo_core::DVec3;
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::params::RadarParams;
use mimo_core::records::{MeasurementRow, TrackRow, unpack_cov};
use mimo_core::rng::{Stream, domain};
use mimo_track::geometry::{SensorGeometry, best_face};
use mimo_track::linalg::{chol_mahalanobis, cholesky};
use mimo_track::{StaticGeometry, TrackFrame};

pub const R1: RadarId = RadarId(0);
pub const R2: RadarId = RadarId(1);

pub struct Sim {
    pub centre: Geodetic,
    pub frame: TrackFrame,
    pub geom: StaticGeometry,
}

impl Sim {
    /// R1 at the centre, R2 about 30 km to the north-east; both stationary.
    pub fn new() -> Sim {
        let centre = Geodetic::from_deg(36.0, -70.0, 0.0);
        let params = RadarParams::default();
        let mut geom = StaticGeometry::new();
        geom.add_ship(R1, Geodetic::from_deg(36.0, -70.0, 20.0), 0.0, &params);
        geom.add_ship(R2, Geodetic::from_deg(36.2, -69.78, 20.0), 30f64.to_radians(), &params);
        Sim { centre, frame: TrackFrame::new(centre), geom }
    }

    /// ECEF position of a tracking-frame state.
    pub fn ecef(&self, x: &[f64; 6]) -> DVec3 {
        self.frame.to_ecef(DVec3::new(x[0], x[1], x[2]))
    }

    /// A noisy measurement of `truth` (tracking frame) on channel tx → rx, on rx's best face,
    /// with the given standard deviations of ρ (m) and u, v.
    #[allow(clippy::too_many_arguments)]
    pub fn measure(
        &self,
        rng: &mut Stream,
        truth: &[f64; 6],
        tx: RadarId,
        rx: RadarId,
        sigma_rho: f64,
        sigma_uv: f64,
        t_s: f64,
        meas_id: u64,
    ) -> MeasurementRow {
        let p = self.ecef(truth);
        let (face, _) = best_face(&self.geom, rx, p, t_s, 4).expect("face");
        let f = self.geom.face(rx, face, t_s).expect("face");
        let s = f.to_sine(p);
        let rt = if tx == rx { s.range_m } else { (p - self.geom.site_ecef(tx, t_s).expect("site")).length() };
        let rho = 0.5 * (rt + s.range_m);
        MeasurementRow {
            run: 0,
            meas_id,
            dwell_id: meas_id,
            t_s,
            rx,
            tx,
            rx_face: face,
            range_m: rho + sigma_rho * rng.normal(),
            u: s.u + sigma_uv * rng.normal(),
            v: s.v + sigma_uv * rng.normal(),
            snr_db: 25.0,
            var_range_m2: sigma_rho * sigma_rho,
            var_u: sigma_uv * sigma_uv,
            var_v: sigma_uv * sigma_uv,
            n_primitives: 2,
            merged: false,
            target_hint: Some("T".into()),
        }
    }

    /// NEES of a track row against a tracking-frame truth: (full 6-D, position-only 3-D).
    pub fn nees(&self, row: &TrackRow, truth: &[f64; 6]) -> (f64, f64) {
        let p = self.ecef(truth);
        let v = self.frame.vec_to_ecef(DVec3::new(truth[3], truth[4], truth[5]));
        let e = [p.x - row.x_m, p.y - row.y_m, p.z - row.z_m, v.x - row.vx_mps, v.y - row.vy_mps, v.z - row.vz_mps];
        let cov = unpack_cov(&row.cov);
        let l = cholesky(&cov).expect("track covariance is positive definite");
        let pc: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| cov[i][j]));
        let lp = cholesky(&pc).expect("position covariance is positive definite");
        (chol_mahalanobis(&l, &e), chol_mahalanobis(&lp, &[e[0], e[1], e[2]]))
    }

    /// Position error (m) of a row against a tracking-frame truth.
    pub fn pos_error(&self, row: &TrackRow, truth: &[f64; 6]) -> f64 {
        (self.ecef(truth) - DVec3::new(row.x_m, row.y_m, row.z_m)).length()
    }
}

/// A test random stream.
pub fn rng(keys: &[u64]) -> Stream {
    let mut k = vec![domain::TEST];
    k.extend_from_slice(keys);
    Stream::new(20_260_101, &k)
}

/// One step of the DWNA nearly-constant-velocity truth: `x ← F x + Γ w`, `w ~ N(0, σ² I₃)`.
pub fn dwna_step(rng: &mut Stream, x: &[f64; 6], dt: f64, sigma_a: f64) -> [f64; 6] {
    let mut y = *x;
    for i in 0..3 {
        let w = sigma_a * rng.normal();
        y[i] = x[i] + dt * x[i + 3] + 0.5 * dt * dt * w;
        y[i + 3] = x[i + 3] + dt * w;
    }
    y
}

/// Assert every number of a row is finite.
pub fn assert_row_finite(row: &TrackRow) {
    let vals = [row.t_s, row.x_m, row.y_m, row.z_m, row.vx_mps, row.vy_mps, row.vz_mps];
    assert!(vals.iter().chain(row.cov.iter()).all(|v| v.is_finite()), "non-finite row {row:?}");
}

/// Two confirmed tracks spawned at the local states `truth` (position sigma 10 m, velocity
/// sigma 3 m/s), at t = 0 on radar 0; their ids.
pub fn spawn_confirmed_pair(tracker: &mut mimo_track::MultiTargetTracker, truth: &[[f64; 6]; 2]) -> [u64; 2] {
    let mut ids = [0u64; 2];
    for (k, x) in truth.iter().enumerate() {
        let mut p = [[0.0; 6]; 6];
        for (i, row) in p.iter_mut().enumerate() {
            row[i] = if i < 3 { 100.0 } else { 9.0 };
        }
        let e = tracker.frame().state_to_ecef(&mimo_track::Gaussian { x: *x, p });
        ids[k] = tracker.spawn_track(0, 0.0, &e, mimo_core::records::TrackStatus::Confirmed).expect("spawned").0;
    }
    ids
}
