//! What the scheduler asks a tracker between dwells: snapshots, due tracks, predictions,
//! predicted measurements and revisit intervals (docs/model.md §7.1).

use crate::diagnostics::{PredictedMeasurement, TrackInfo};
use crate::frame::{Gaussian, StateEcef};
use crate::geometry::SensorGeometry;
use crate::linalg::sandwich;
use crate::measurement::{BistaticRuv, MeasurementModel};
use crate::policy::{DueInfo, due_tracks, revisit_interval};
use crate::tracker::{MultiTargetTracker, Track};
use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::records::TrackStatus;

/// What a scheduler needs of a live track ([`TrackInfo`] without the mode probabilities and the
/// NIS), from [`MultiTargetTracker::track_dues`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackDue {
    /// Track id.
    pub id: u64,
    /// Tentative or confirmed.
    pub status: TrackStatus,
    /// Time of the last update (s).
    pub t_last_update_s: f64,
    /// Updates so far.
    pub n_updates: u32,
    /// Missed looks in a row.
    pub consecutive_misses: u32,
    /// When the track should next be looked at (s).
    pub next_due_s: f64,
}

/// A track's scheduling state.
fn due_of(t: &Track) -> TrackDue {
    TrackDue {
        id: t.id,
        status: t.status,
        t_last_update_s: t.t_s,
        n_updates: t.n_updates,
        consecutive_misses: t.consecutive_misses,
        next_due_s: t.next_due_s,
    }
}

impl MultiTargetTracker {
    /// Snapshots of the live tracks, by id.
    pub fn tracks(&self) -> Vec<TrackInfo> {
        self.tracks
            .values()
            .map(|t| TrackInfo {
                due: due_of(t),
                last_face: t.last_face,
                mode_probabilities: t.state.mu.clone(),
                mean_nis: if t.nis_count > 0 { t.nis_sum / t.nis_count as f64 } else { f64::NAN },
            })
            .collect()
    }

    /// Tracks due for a look by `t_now + lookahead_s`, confirmed first, then by due time.
    pub fn due_tracks(&self, t_now: f64, lookahead_s: f64) -> Vec<u64> {
        let infos: Vec<DueInfo> = self
            .tracks
            .values()
            .map(|t| DueInfo { track_id: t.id, status: t.status, next_due_s: t.next_due_s })
            .collect();
        due_tracks(&infos, t_now, lookahead_s)
    }

    /// The (combined) prediction of a track at `t_s`, in the tracking frame.
    pub fn predict_local(&self, id: u64, t_s: f64) -> Option<Gaussian> {
        let t = self.tracks.get(&id)?;
        if !t_s.is_finite() {
            return None;
        }
        Some(self.c.filter.predict(&t.state, t_s - t.t_s).combined)
    }

    /// The (combined) prediction of a track at `t_s`, in ECEF.
    pub fn predict(&self, id: u64, t_s: f64) -> Option<StateEcef> {
        self.predict_local(id, t_s).map(|g| self.frame.state_to_ecef(&g))
    }

    /// The combined predicted position of a track at `t_s`, ECEF: [`Self::predict`]'s `pos` bit for
    /// bit, from the filter's mean prediction alone (no covariance, no rotation of one).
    pub fn predict_position(&self, id: u64, t_s: f64) -> Option<DVec3> {
        let t = self.tracks.get(&id)?;
        if !t_s.is_finite() {
            return None;
        }
        let x = self.c.filter.predict_mean(&t.state, t_s - t.t_s);
        Some(self.frame.to_ecef(DVec3::new(x[0], x[1], x[2])))
    }

    /// The live tracks' scheduling state, by id: [`Self::tracks`] without the mode probabilities
    /// and the NIS, and without allocating.
    pub fn track_dues(&self) -> impl Iterator<Item = TrackDue> + '_ {
        self.tracks.values().map(due_of)
    }

    /// One live track's scheduling state ([`Self::track_dues`]'s item for it).
    pub fn track_due(&self, id: u64) -> Option<TrackDue> {
        self.tracks.get(&id).map(due_of)
    }

    /// The predicted measurement of a prediction `g` at `t_s` (tracking frame, from
    /// [`Self::predict_local`]) on channel `tx → rx` (face `rx_face`): for a caller that already
    /// holds the prediction.
    pub fn predict_measurement_of(
        &self,
        g: &Gaussian,
        t_s: f64,
        tx: RadarId,
        rx: RadarId,
        rx_face: u8,
        geom: &dyn SensorGeometry,
    ) -> Option<PredictedMeasurement> {
        let m = BistaticRuv::from_geometry(&self.frame, geom, tx, rx, rx_face, t_s).ok()?;
        let z = m.h(&g.x);
        let h = m.jacobian(&g.x);
        let cov = sandwich(&h, &g.p);
        let out = PredictedMeasurement {
            rho_m: z[0] / 2.0,
            u: z[1],
            v: z[2],
            sigma_rho_m: cov[0][0].max(0.0).sqrt() / 2.0,
            cov,
        };
        (out.rho_m.is_finite() && out.u.is_finite() && out.v.is_finite()).then_some(out)
    }

    /// Covariance-based revisit interval of a track seen from `face` (docs/model.md §7.1), measured
    /// from its last update.
    pub fn revisit_interval(&self, id: u64, face: &FaceFrame) -> Option<f64> {
        let t = self.tracks.get(&id)?;
        let lf = self.frame.face_to_local(face);
        let filter = &*self.c.filter;
        Some(revisit_interval(&|dt| filter.predict(&t.state, dt).combined, &lf, &self.config.revisit))
    }
}
