//! Compute in machine-independent units: a test article's CPU time divided by the CPU time of
//! one *reference Kalman-filter cycle* (KFU) measured on the same machine when the study starts,
//! so that `costs.parquet`'s `ta_cpu_kfu` compares across machines (docs/studies.md).
//!
//! The reference cycle is the default tracker's EKF from `mimo-track` ([`SingleModelFilter`]
//! with a [`KalmanPredictor`] of the nearly-constant-velocity model and the Joseph-form
//! [`EkfUpdater`], one linearization): a 6-state prediction over 1 s followed by an update with
//! one 3-D monostatic radar measurement `(R_B, u, v)` of a target 60 km out. The same prior,
//! measurement and noise are used in every cycle, so every cycle does the same arithmetic.
//! [`measure_kf_cycle_s`] times [`CYCLES_PER_REPEAT`] cycles on the calling thread's CPU clock,
//! [`REPEATS`] times, and returns the median time per cycle: the median ignores a repeat that a
//! busy machine interrupted.

use glam::DVec3;
use mimo_track::filter::{FilterState, SingleModelFilter, TrackFilter};
use mimo_track::frame::Gaussian;
use mimo_track::measurement::{BistaticRuv, Observation};
use mimo_track::motion::{KalmanPredictor, Ncv};
use mimo_track::update::EkfUpdater;
use std::hint::black_box;

/// Cycles timed together (a few milliseconds: far above the clock's resolution).
pub const CYCLES_PER_REPEAT: u32 = 4000;
/// Timed repeats; the median is kept.
pub const REPEATS: usize = 9;

/// The reference filter, prior and measurement.
pub struct ReferenceCycle {
    filter: SingleModelFilter,
    model: BistaticRuv,
    prior: FilterState,
    z: [f64; 3],
    r: [[f64; 3]; 3],
}

impl Default for ReferenceCycle {
    fn default() -> Self {
        Self::new()
    }
}

impl ReferenceCycle {
    /// The reference set-up: a face at the origin looking along +z, a target at (10, 5, 60) km
    /// moving at 250 m/s, a prior of 100 m and 20 m/s standard deviations, range-sum and
    /// sine-space noise of 30 m and 1e-3.
    pub fn new() -> Self {
        let filter = SingleModelFilter {
            name: "ekf-ncv".into(),
            predictor: Box::new(KalmanPredictor::new(Ncv::dwna(5.0))),
            updater: Box::new(EkfUpdater::default()),
        };
        let model = BistaticRuv::monostatic(DVec3::ZERO, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let x = [10_000.0, 5_000.0, 60_000.0, -150.0, 0.0, -200.0];
        let mut p = [[0.0; 6]; 6];
        for (i, row) in p.iter_mut().enumerate() {
            row[i] = if i < 3 { 100.0f64.powi(2) } else { 20.0f64.powi(2) };
        }
        let truth = DVec3::new(x[0] + x[3] + 40.0, x[1] + x[4] - 25.0, x[2] + x[5] + 60.0);
        let h = model.h_pos(truth);
        ReferenceCycle {
            filter,
            model,
            prior: FilterState::single(Gaussian { x, p }),
            z: [h[0] + 12.0, h[1] + 4e-4, h[2] - 3e-4],
            r: [[30.0f64.powi(2), 0.0, 0.0], [0.0, 1e-6, 0.0], [0.0, 0.0, 1e-6]],
        }
    }

    /// One predict (1 s) + update cycle; the posterior state, or `None` if the update is refused.
    pub fn cycle(&self) -> Option<FilterState> {
        let pred = self.filter.predict(black_box(&self.prior), black_box(1.0));
        let up = self
            .filter
            .update(&pred, Observation { model: &self.model, z: black_box(&self.z), r: black_box(&self.r) }, 1)
            .ok()?;
        Some(up.state)
    }
}

/// CPU seconds of one reference cycle on this machine: the median over [`REPEATS`] of the
/// thread CPU time of [`CYCLES_PER_REPEAT`] cycles, divided by the cycles.
pub fn measure_kf_cycle_s() -> f64 {
    let reference = ReferenceCycle::new();
    let mut per_cycle: Vec<f64> = (0..REPEATS)
        .map(|_| {
            let t0 = crate::cpu::thread_cpu();
            for _ in 0..CYCLES_PER_REPEAT {
                black_box(reference.cycle());
            }
            (crate::cpu::thread_cpu() - t0).as_secs_f64() / f64::from(CYCLES_PER_REPEAT)
        })
        .collect();
    per_cycle.sort_by(f64::total_cmp);
    per_cycle[REPEATS / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_reference_cycle_is_a_real_ekf_update() {
        // The update pulls the predicted state towards the measurement and shrinks the position
        // covariance; the measured time is a positive, finite number.
        let r = ReferenceCycle::new();
        let prior = r.prior.combined();
        let pred = r.filter.predict(&r.prior, 1.0).combined;
        let post = r.cycle().expect("the update is accepted").combined();
        let truth =
            DVec3::new(prior.x[0] + prior.x[3] + 40.0, prior.x[1] + prior.x[4] - 25.0, prior.x[2] + prior.x[5] + 60.0);
        let d = |g: &Gaussian| (DVec3::new(g.x[0], g.x[1], g.x[2]) - truth).length();
        assert!(d(&post) < d(&pred), "posterior {} m from the truth, prediction {} m", d(&post), d(&pred));
        let tr = |g: &Gaussian| g.p[0][0] + g.p[1][1] + g.p[2][2];
        assert!(tr(&post) < 0.5 * tr(&pred), "{} vs {}", tr(&post), tr(&pred));
        assert_eq!(r.cycle(), r.cycle(), "every cycle does the same arithmetic");
        let k = measure_kf_cycle_s();
        assert!(k.is_finite() && k > 0.0, "{k}");
    }
}
