//! Track initiation and confirmation (docs/model.md §6.4).
//!
//! [`Initiator`] turns a search detection that no track claimed into a tentative track:
//! [`OnePointInitiator`] at once (position from the bistatic ruv→cart map with covariance
//! `J R Jᵀ`, velocity zero with a large standard deviation), [`TwoPointInitiator`] once a second
//! consistent detection arrives (two-point differencing, TCL `twoPointDiffInit`).
//! [`Confirmer`] decides from a tentative track's looks (hit/miss) whether it is confirmed,
//! still pending, or dropped; [`MOfN`] is the classic M-of-N rule.

use crate::frame::Gaussian;
use crate::linalg::{Mat3, add, scale, trace};
use crate::measurement::PreparedMeasurement;
use mimo_core::DVec3;
use serde::{Deserialize, Serialize};

/// A new tentative track.
#[derive(Debug, Clone, PartialEq)]
pub struct Initiation {
    /// The initial estimate.
    pub state: Gaussian,
    /// Measurements used (the last one is the current detection).
    pub meas_ids: Vec<u64>,
    /// The confirmation looks this initiation already stands for (one hit per detection used).
    pub looks: Vec<bool>,
}

/// The initiation family. Initiators may keep state (unused detections).
pub trait Initiator: Send + Sync {
    /// Offer an unclaimed search detection at time `meas.t_s`; returns a new track or `None`.
    fn initiate(&mut self, meas: &PreparedMeasurement) -> Option<Initiation>;
}

/// Build `[[Rp, 0], [0, σ_v² I]]` around a position.
fn one_point(p: DVec3, rp: &Mat3, velocity_std_mps: f64) -> Gaussian {
    let mut cov = [[0.0; 6]; 6];
    for i in 0..3 {
        for j in 0..3 {
            cov[i][j] = rp[i][j];
        }
        cov[i + 3][i + 3] = velocity_std_mps * velocity_std_mps;
    }
    Gaussian { x: [p.x, p.y, p.z, 0.0, 0.0, 0.0], p: cov }
}

/// One-point initiation: every unclaimed detection starts a tentative track.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OnePointInitiator {
    /// Prior velocity standard deviation per axis (m/s). Default 300 (enough for fighters).
    pub velocity_std_mps: f64,
}

impl Default for OnePointInitiator {
    fn default() -> Self {
        OnePointInitiator { velocity_std_mps: 300.0 }
    }
}

impl Initiator for OnePointInitiator {
    fn initiate(&mut self, meas: &PreparedMeasurement) -> Option<Initiation> {
        let (p, rp) = meas.to_cartesian()?;
        let state = one_point(p, &rp, self.velocity_std_mps);
        state.is_finite().then(|| Initiation { state, meas_ids: vec![meas.meas_id], looks: vec![true] })
    }
}

/// Parameters of two-point differencing.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TwoPointConfig {
    /// Largest plausible target speed (m/s). Default 700.
    pub max_speed_mps: f64,
    /// Oldest detection kept for pairing (s). Default 12.
    pub max_age_s: f64,
    /// Position-uncertainty allowance in standard deviations. Default 4.
    pub n_sigma: f64,
    /// Acceleration standard deviation for the process-noise term (m/s²). Default 10.
    pub sigma_a_mps2: f64,
}

impl Default for TwoPointConfig {
    fn default() -> Self {
        TwoPointConfig { max_speed_mps: 700.0, max_age_s: 12.0, n_sigma: 4.0, sigma_a_mps2: 10.0 }
    }
}

#[derive(Debug, Clone, PartialEq)]
struct Pending {
    t_s: f64,
    p: DVec3,
    r: Mat3,
    meas_id: u64,
}

/// Two-point differencing: a detection waits until a second one within reach arrives, then
/// `x = [p₂; (p₂ − p₁)/T]`, `P = [[R₂, R₂/T], [R₂/T, (R₁ + R₂)/T²]]` plus a DWNA velocity term.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TwoPointInitiator {
    /// Gating and velocity limits.
    pub config: TwoPointConfig,
    pending: Vec<Pending>,
}

impl TwoPointInitiator {
    /// A two-point initiator with this configuration.
    pub fn new(config: TwoPointConfig) -> TwoPointInitiator {
        TwoPointInitiator { config, pending: Vec::new() }
    }

    /// Detections waiting for a partner.
    pub fn n_pending(&self) -> usize {
        self.pending.len()
    }
}

impl Initiator for TwoPointInitiator {
    fn initiate(&mut self, meas: &PreparedMeasurement) -> Option<Initiation> {
        let (p2, r2) = meas.to_cartesian()?;
        let t2 = meas.t_s;
        let c = self.config;
        self.pending.retain(|d| t2 - d.t_s <= c.max_age_s);
        let mut best: Option<(usize, f64)> = None;
        for (k, d) in self.pending.iter().enumerate() {
            let dt = t2 - d.t_s;
            if dt <= 1e-3 {
                continue;
            }
            let dist = (p2 - d.p).length();
            let allowance = c.max_speed_mps * dt + c.n_sigma * trace(&add(&d.r, &r2)).sqrt();
            if dist <= allowance && best.is_none_or(|(_, bd)| dist < bd) {
                best = Some((k, dist));
            }
        }
        let Some((k, _)) = best else {
            self.pending.push(Pending { t_s: t2, p: p2, r: r2, meas_id: meas.meas_id });
            return None;
        };
        let d = self.pending.remove(k);
        let t = t2 - d.t_s;
        let v = (p2 - d.p) / t;
        let rvv = scale(&add(&d.r, &r2), 1.0 / (t * t));
        let rpv = scale(&r2, 1.0 / t);
        let qa = c.sigma_a_mps2 * c.sigma_a_mps2 * t * t;
        let mut cov = [[0.0; 6]; 6];
        for i in 0..3 {
            for j in 0..3 {
                cov[i][j] = r2[i][j];
                cov[i][j + 3] = rpv[i][j];
                cov[i + 3][j] = rpv[j][i];
                cov[i + 3][j + 3] = rvv[i][j];
            }
            cov[i + 3][i + 3] += qa;
        }
        let state = Gaussian { x: [p2.x, p2.y, p2.z, v.x, v.y, v.z], p: cov };
        state.is_finite().then(|| Initiation {
            state,
            meas_ids: vec![d.meas_id, meas.meas_id],
            looks: vec![true, true],
        })
    }
}

/// Outcome of the confirmation logic for a tentative track.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Confirmation {
    /// Enough hits: confirm.
    Confirm,
    /// Not decided yet.
    Pending,
    /// Too many misses: drop.
    Reject,
}

/// The confirmation family: decide from the looks at a tentative track (`true` = detected),
/// starting with the initiating detection(s).
pub trait Confirmer: Send + Sync {
    /// Decide from the looks so far.
    fn decide(&self, looks: &[bool]) -> Confirmation;
}

/// Confirm when `m` of the first `n` looks are hits; reject as soon as that is impossible.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MOfN {
    /// Hits needed.
    pub m: u32,
    /// Looks in the window.
    pub n: u32,
}

impl Default for MOfN {
    fn default() -> Self {
        MOfN { m: 2, n: 3 }
    }
}

impl Confirmer for MOfN {
    fn decide(&self, looks: &[bool]) -> Confirmation {
        let n = self.n.max(self.m).max(1) as usize;
        let window = &looks[..looks.len().min(n)];
        let hits = window.iter().filter(|h| **h).count();
        let misses = window.len() - hits;
        if hits >= self.m as usize {
            Confirmation::Confirm
        } else if misses > n - self.m as usize || window.len() >= n {
            Confirmation::Reject
        } else {
            Confirmation::Pending
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use Confirmation::*;

    #[test]
    fn two_of_three() {
        let c = MOfN { m: 2, n: 3 };
        assert_eq!(c.decide(&[true]), Pending);
        assert_eq!(c.decide(&[true, true]), Confirm);
        assert_eq!(c.decide(&[true, false]), Pending);
        assert_eq!(c.decide(&[true, false, true]), Confirm);
        assert_eq!(c.decide(&[true, false, false]), Reject);
    }

    #[test]
    fn three_of_four() {
        let c = MOfN { m: 3, n: 4 };
        assert_eq!(c.decide(&[true, true]), Pending);
        assert_eq!(c.decide(&[true, false]), Pending);
        assert_eq!(c.decide(&[true, false, true]), Pending);
        assert_eq!(c.decide(&[true, false, true, true]), Confirm);
        assert_eq!(c.decide(&[true, true, false, true]), Confirm);
        assert_eq!(c.decide(&[true, false, false]), Reject);
        assert_eq!(c.decide(&[true, true, true]), Confirm);
    }
}
