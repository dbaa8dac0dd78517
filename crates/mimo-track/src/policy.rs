//! Pure policy functions the scheduler calls (docs/model.md §7): adaptive revisit interval, which
//! tracks are due, and dwell energy. No event logic lives here; `mimo-sim` owns the timeline.

use crate::frame::dmat3_rows;
use crate::frame::{Gaussian, LocalFace};
use crate::linalg::sym2_eigenvalues;
use crate::measurement::BistaticRuv;
use mimo_core::records::TrackStatus;
use serde::{Deserialize, Serialize};

/// Revisit policy parameters.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RevisitPolicy {
    /// Track sharpness V₀: the predicted u–v standard deviation allowed at the revisit, as a
    /// fraction of the beamwidth. Default 0.2 (docs/model.md §7.1).
    pub sharpness_v0: f64,
    /// Shortest revisit interval (s). Default 0.25.
    pub t_min_s: f64,
    /// Longest revisit interval (s). Default 4.
    pub t_max_s: f64,
    /// Sine-space beamwidth θ (default 0.0252, docs/model.md §3.3).
    pub beamwidth: f64,
    /// Delay before a confirmation dwell on a tentative track (s). Default 0.3.
    pub confirm_delay_s: f64,
    /// Delay before a re-dwell after a missed look (s). Default 0.05.
    pub redwell_delay_s: f64,
}

impl Default for RevisitPolicy {
    fn default() -> Self {
        RevisitPolicy {
            sharpness_v0: 0.2,
            t_min_s: 0.25,
            t_max_s: 4.0,
            beamwidth: 0.0252,
            confirm_delay_s: 0.3,
            redwell_delay_s: 0.05,
        }
    }
}

/// `P_uv = J_uv P_pp J_uvᵀ`: the position covariance mapped into a face's sine space.
pub fn uv_covariance(g: &Gaussian, face: &LocalFace) -> [[f64; 2]; 2] {
    let m = BistaticRuv::monostatic(face.origin, dmat3_rows(&face.face_from_local));
    let j = m.jacobian_pos(g.pos());
    let p = g.pos_cov();
    let mut out = [[0.0; 2]; 2];
    for a in 0..2 {
        for b in 0..2 {
            let mut s = 0.0;
            for i in 0..3 {
                for k in 0..3 {
                    s += j[a + 1][i] * p[i][k] * j[b + 1][k];
                }
            }
            out[a][b] = s;
        }
    }
    out
}

/// `√λ_max(P_uv)`: the largest u–v standard deviation of an estimate seen from a face.
pub fn uv_std_max(g: &Gaussian, face: &LocalFace) -> f64 {
    sym2_eigenvalues(&uv_covariance(g, face)).0.max(0.0).sqrt()
}

/// Covariance-based revisit interval (docs/model.md §7.1): the largest `T` in
/// `[t_min_s, t_max_s]` with `√λ_max(P_uv(T)) ≤ V₀ θ`, where `predict(T)` is the (IMM-combined)
/// prediction `T` seconds after the last update. Returns `t_min_s` when even that is too late
/// and `t_max_s` when the track stays sharp throughout. Bisection to 1 ms, assuming the
/// predicted spread grows with `T`.
pub fn revisit_interval(predict: &dyn Fn(f64) -> Gaussian, face: &LocalFace, policy: &RevisitPolicy) -> f64 {
    let limit = policy.sharpness_v0 * policy.beamwidth;
    let ok = |t: f64| {
        let s = uv_std_max(&predict(t), face);
        s.is_finite() && s <= limit
    };
    let (mut lo, mut hi) = (policy.t_min_s, policy.t_max_s.max(policy.t_min_s));
    if ok(hi) {
        return hi;
    }
    if !ok(lo) {
        return lo;
    }
    while hi - lo > 1e-3 {
        let mid = 0.5 * (lo + hi);
        if ok(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// What the scheduler needs to know about a track to decide when to look at it.
#[derive(Debug, Clone, PartialEq)]
pub struct DueInfo {
    /// Track id.
    pub track_id: u64,
    /// Tentative or confirmed.
    pub status: TrackStatus,
    /// When the track should next be looked at (s).
    pub next_due_s: f64,
}

/// Tracks due at `t_now` (next look at or before `t_now + lookahead_s`), in scheduling order:
/// confirmed tracks before tentative ones (track dwells before confirmation dwells,
/// docs/model.md §7.3), then by due time, then by id. Deleted tracks are never due.
pub fn due_tracks(tracks: &[DueInfo], t_now: f64, lookahead_s: f64) -> Vec<u64> {
    let mut due: Vec<&DueInfo> =
        tracks.iter().filter(|t| t.status != TrackStatus::Deleted && t.next_due_s <= t_now + lookahead_s).collect();
    let rank = |s: TrackStatus| if s == TrackStatus::Confirmed { 0 } else { 1 };
    due.sort_by(|a, b| {
        rank(a.status)
            .cmp(&rank(b.status))
            .then(a.next_due_s.total_cmp(&b.next_due_s))
            .then(a.track_id.cmp(&b.track_id))
    });
    due.into_iter().map(|t| t.track_id).collect()
}

/// Required single-look SNR (linear) for a Swerling 1 target with one coherent sample:
/// `ln P_FA / ln P_D − 1` (docs/model.md §7.2; 21.1 dB for P_D = 0.9, P_FA = 1e-6).
pub fn required_snr_sw1(pfa: f64, pd: f64) -> f64 {
    pfa.ln() / pd.ln() - 1.0
}

/// Expected two-way beam-pointing gain (≤ 1) of the Gaussian pattern (model A) for a monostatic
/// look with u–v spread `V₀·θ` on each axis: `Π_axes (1 + 16 ln2 V₀²)^(−1/2)` (1.6 dB loss at 0.2).
pub fn beam_pointing_gain_monostatic(v0: f64) -> f64 {
    1.0 / (1.0 + 16.0 * std::f64::consts::LN_2 * v0 * v0)
}

/// Average straddle loss of the range sampling (linear, 2.7 dB, docs/model.md §4.1).
pub const STRADDLE_LOSS_LIN: f64 = 1.862_087_136_662_868;

/// Pulses for a dwell: `⌈SNR_req · L / SNR₁⌉` clipped to `[1, n_max]`, where `snr1_lin` is the
/// predicted single-pulse SNR and `loss_lin ≥ 1` the product of beam-pointing and straddle losses.
pub fn pulses_required(snr_req_lin: f64, loss_lin: f64, snr1_lin: f64, n_max: u32) -> u32 {
    let n_max = n_max.max(1);
    if snr1_lin.is_nan() || snr1_lin <= 0.0 || snr1_lin.is_infinite() {
        return n_max;
    }
    let n = (snr_req_lin * loss_lin / snr1_lin).ceil();
    if !n.is_finite() {
        return n_max;
    }
    (n.max(1.0) as u64).min(n_max as u64) as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::identity;
    use crate::motion::{MotionModel, Ncv};
    use mimo_core::DMat3;

    fn face() -> LocalFace {
        LocalFace { origin: mimo_core::DVec3::ZERO, face_from_local: DMat3::IDENTITY }
    }

    #[test]
    fn revisit_is_the_largest_sharp_interval() {
        let f = face();
        let mut p = identity::<6>();
        for i in 0..3 {
            p[i][i] = 100.0;
            p[i + 3][i + 3] = 200.0 * 200.0;
        }
        let g = Gaussian { x: [0.0, 0.0, 100_000.0, 200.0, 0.0, 0.0], p };
        let model = Ncv::dwna(5.0);
        let pred = |t: f64| crate::motion::ekf_predict(&model, &g, t);
        let pol = RevisitPolicy::default();
        let t = revisit_interval(&pred, &f, &pol);
        assert!(t > pol.t_min_s && t < pol.t_max_s, "{t}");
        let lim = pol.sharpness_v0 * pol.beamwidth;
        assert!(uv_std_max(&pred(t), &f) <= lim);
        assert!(uv_std_max(&pred(t + 0.002), &f) > lim);
        // A sloppier track is revisited sooner; a far sharper one at the maximum.
        let g2 = Gaussian { p: crate::linalg::scale(&p, 4.0), ..g };
        let t2 = revisit_interval(&|t| crate::motion::ekf_predict(&model, &g2, t), &f, &pol);
        assert!(t2 < t);
        let g3 = Gaussian { p: crate::linalg::scale(&p, 1e-4), ..g };
        let quiet = Ncv::dwna(0.01);
        assert_eq!(revisit_interval(&|t| crate::motion::ekf_predict(&quiet, &g3, t), &f, &pol), pol.t_max_s);
        let g4 = Gaussian { p: crate::linalg::scale(&p, 1e4), ..g };
        assert_eq!(revisit_interval(&|t| crate::motion::ekf_predict(&model, &g4, t), &f, &pol), pol.t_min_s);
        let _ = model.name();
    }

    #[test]
    fn due_order_and_energy_helpers() {
        let infos = vec![
            DueInfo { track_id: 3, status: TrackStatus::Tentative, next_due_s: 1.0 },
            DueInfo { track_id: 1, status: TrackStatus::Confirmed, next_due_s: 2.0 },
            DueInfo { track_id: 2, status: TrackStatus::Confirmed, next_due_s: 1.5 },
            DueInfo { track_id: 4, status: TrackStatus::Confirmed, next_due_s: 9.0 },
        ];
        assert_eq!(due_tracks(&infos, 2.0, 0.0), vec![2, 1, 3]);
        let snr = required_snr_sw1(1e-6, 0.9);
        assert!((10.0 * snr.log10() - 21.1).abs() < 0.05);
        let g = beam_pointing_gain_monostatic(0.2);
        assert!((-10.0 * g.log10() - 1.6).abs() < 0.05);
        assert!((10.0 * STRADDLE_LOSS_LIN.log10() - 2.7).abs() < 1e-9);
        assert_eq!(pulses_required(100.0, 2.0, 50.0, 16), 4);
        assert_eq!(pulses_required(100.0, 2.0, 1.0, 16), 16);
        assert_eq!(pulses_required(100.0, 2.0, 1e6, 16), 1);
        assert_eq!(pulses_required(100.0, 2.0, f64::NAN, 16), 16);
    }
}
