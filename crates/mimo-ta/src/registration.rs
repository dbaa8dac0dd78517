//! Online registration of the radars for the default test article (docs/model.md §6.9): the
//! biases of every radar (range, u, v, heading; docs/model.md §5.5) estimated from MIMO looks
//! that see one target on several channels at once, with the target's position eliminated, and
//! every measurement corrected with the estimate before it reaches the tracker.

use crate::dense::Dense;
use crate::geometry::ShipGeometry;
use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::ids::RadarId;
use mimo_core::records::{MeasurementRow, RegistrationRow};
use mimo_core::registration::{RadarBias, typical};
use mimo_radar::registration::{physical_beam, up_in_face};
use mimo_sim::messages::DwellReport;
use mimo_track::SensorGeometry;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Biases per radar: range, u, v, heading.
const K: usize = 4;

/// The registration option of the default test article (`registration.*`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RegistrationConfig {
    /// Estimate the radars' biases and correct measurements with them. Default false.
    pub enabled: bool,
    /// Prior σ of every radar's range bias (m). Default the typical 10 m.
    pub sigma_range_m: f64,
    /// Prior σ of the u and v biases. Default the typical 1e-3.
    pub sigma_uv: f64,
    /// Prior σ of the heading bias (deg). Default the typical 0.1°.
    pub sigma_heading_deg: f64,
}

impl Default for RegistrationConfig {
    fn default() -> Self {
        RegistrationConfig {
            enabled: false,
            sigma_range_m: typical::RANGE_M,
            sigma_uv: typical::UV,
            sigma_heading_deg: typical::HEADING_DEG,
        }
    }
}

impl RegistrationConfig {
    /// Off with the default prior: not written into a recorded configuration.
    pub fn is_default(&self) -> bool {
        *self == RegistrationConfig::default()
    }

    /// Check the values; the error names the key and what was expected.
    pub fn validate(&self) -> Result<(), (String, String)> {
        for (k, x) in [
            ("registration.sigma_range_m", self.sigma_range_m),
            ("registration.sigma_uv", self.sigma_uv),
            ("registration.sigma_heading_deg", self.sigma_heading_deg),
        ] {
            if !(x.is_finite() && x > 0.0) {
                return Err((k.to_string(), format!("a positive finite standard deviation, got {x}")));
            }
        }
        Ok(())
    }
}

/// One channel of a look with its one measurement: `z = (R_B, u, v)` and its variances.
struct Channel {
    tx: RadarId,
    rx: RadarId,
    tx_site: DVec3,
    face: FaceFrame,
    up: DVec3,
    z: [f64; 3],
    var: [f64; 3],
}

impl Channel {
    fn h(&self, p: DVec3) -> [f64; 3] {
        let s = self.face.to_sine(p);
        [(p - self.tx_site).length() + s.range_m, s.u, s.v]
    }

    /// `∂h/∂p`, rows (R_B, u, v) (docs/model.md §5.4).
    fn jacobian(&self, p: DVec3) -> [DVec3; 3] {
        let (dt, dr) = (p - self.tx_site, p - self.face.origin_ecef);
        let l = self.face.face_from_ecef * dr;
        let r3 = l.length().powi(3);
        let mt = self.face.face_from_ecef.transpose();
        let du = mt * (DVec3::new(l.y * l.y + l.z * l.z, -l.x * l.y, -l.x * l.z) / r3);
        let dv = mt * (DVec3::new(-l.x * l.y, l.x * l.x + l.z * l.z, -l.y * l.z) / r3);
        [dt / dt.length() + dr / dr.length(), du, dv]
    }

    /// Rows of `∂z/∂β` (3 × 4n) in the estimator's scaled biases (each bias over its prior σ).
    fn bias_rows(&self, n: usize, sigma: &[f64; K]) -> Dense {
        let mut b = Dense::zeros(3, K * n);
        b.add_at(0, K * self.tx.index(), sigma[0]);
        b.add_at(0, K * self.rx.index(), sigma[0]);
        b.add_at(1, K * self.rx.index() + 1, sigma[1]);
        b.add_at(2, K * self.rx.index() + 2, sigma[2]);
        // A heading bias turns the direction d by −b_ψ about the vertical: ∂d/∂b_ψ = −k × d.
        let w = (1.0 - self.z[1].powi(2) - self.z[2].powi(2)).max(0.0).sqrt();
        let turn = -self.up.cross(DVec3::new(self.z[1], self.z[2], w)) * sigma[3].to_radians();
        b.set(1, K * self.rx.index() + 3, turn.x);
        b.set(2, K * self.rx.index() + 3, turn.y);
        b
    }
}

/// The χ² quantile of probability 0.999 with `dof` degrees of freedom (Wilson–Hilferty).
fn chi2_999(dof: usize) -> f64 {
    let k = dof as f64;
    let c = 2.0 / (9.0 * k);
    k * (1.0 - c + 3.090_232 * c.sqrt()).powi(3)
}

/// The estimate of every radar's biases: an information filter over the scaled biases
/// `β/σ_prior`, starting from the prior `N(0, I)`.
#[derive(Debug, Clone)]
pub struct Registration {
    n: usize,
    sigma: [f64; K],
    info: Dense,
    est: Vec<f64>,
    cov: Dense,
    used: u64,
}

impl Registration {
    /// The prior of `n` radars.
    pub fn new(n: usize, cfg: &RegistrationConfig) -> Registration {
        let sigma = [cfg.sigma_range_m, cfg.sigma_uv, cfg.sigma_uv, cfg.sigma_heading_deg];
        let one = vec![1.0; K * n];
        Registration { n, sigma, info: Dense::diag(&one), est: vec![0.0; K * n], cov: Dense::diag(&one), used: 0 }
    }

    /// Every radar's estimated biases.
    pub fn estimate(&self) -> Vec<RadarBias> {
        (0..self.n)
            .map(|r| {
                let e = |k: usize| self.est[K * r + k] * self.sigma[k];
                RadarBias { range_m: e(0), u: e(1), v: e(2), heading_deg: e(3) }
            })
            .collect()
    }

    /// Every radar's estimate variances (range m², u, v, heading deg²).
    pub fn variances(&self) -> Vec<[f64; K]> {
        (0..self.n)
            .map(|r| std::array::from_fn(|k| self.cov.at(K * r + k, K * r + k) * self.sigma[k].powi(2)))
            .collect()
    }

    /// The `registration` table's rows of the estimate at `t_s` (docs/model.md §6.9): per radar,
    /// its biases and the 4 × 4 block of their covariance, in the table's units.
    pub fn rows(&self, t_s: f64, radars: &[RadarId]) -> Vec<RegistrationRow> {
        self.estimate()
            .into_iter()
            .zip(radars)
            .enumerate()
            .map(|(r, (b, &radar))| {
                let c = |i: usize, j: usize| self.cov.at(K * r + i, K * r + j) * self.sigma[i] * self.sigma[j];
                RegistrationRow {
                    run: 0,
                    t_s,
                    radar,
                    range_m: b.range_m,
                    u: b.u,
                    v: b.v,
                    heading_deg: b.heading_deg,
                    var_range_m2: c(0, 0),
                    var_u: c(1, 1),
                    var_v: c(2, 2),
                    var_heading_deg2: c(3, 3),
                    cov_range_u_m: c(0, 1),
                    cov_range_v_m: c(0, 2),
                    cov_range_heading_m_deg: c(0, 3),
                    cov_u_v: c(1, 2),
                    cov_u_heading_deg: c(1, 3),
                    cov_v_heading_deg: c(2, 3),
                    looks: self.used,
                }
            })
            .collect()
    }

    /// Looks used so far.
    pub fn looks_used(&self) -> u64 {
        self.used
    }

    /// The normalized estimation error squared of the estimate against `truth` (one per radar).
    pub fn nees(&self, truth: &[RadarBias]) -> f64 {
        let e: Vec<f64> = truth
            .iter()
            .enumerate()
            .flat_map(|(r, b)| {
                let t = [b.range_m, b.u, b.v, b.heading_deg];
                (0..K).map(move |k| (r, k, t[k]))
            })
            .map(|(r, k, t)| self.est[K * r + k] - t / self.sigma[k])
            .collect();
        e.iter().zip(self.info.mul_vec(&e)).map(|(a, b)| a * b).sum()
    }

    /// The look's channels with exactly one unmerged measurement, if every channel that detected
    /// anything did so (one target: no association to get wrong) and at least two did.
    fn channels(&self, report: &DwellReport, geom: &ShipGeometry) -> Option<Vec<Channel>> {
        let mut by_channel: BTreeMap<(RadarId, RadarId), Vec<&MeasurementRow>> = BTreeMap::new();
        for m in &report.measurements {
            by_channel.entry((m.tx, m.rx)).or_default().push(m);
        }
        if by_channel.len() < 2 || by_channel.values().any(|v| v.len() != 1 || v[0].merged) {
            return None;
        }
        let mut out = Vec::with_capacity(by_channel.len());
        for ((tx, rx), v) in by_channel {
            let m = v[0];
            let face = *geom.faces_at(rx, m.t_s).get(usize::from(m.rx_face))?;
            let tx_site = geom.site_ecef(tx, m.t_s)?;
            let (z, var) = ([2.0 * m.range_m, m.u, m.v], [4.0 * m.var_range_m2, m.var_u, m.var_v]);
            out.push(Channel { tx, rx, tx_site, face, up: up_in_face(&face), z, var });
        }
        Some(out)
    }

    /// Learn from one look (docs/model.md §6.9): with the measurements corrected by the current
    /// estimate, the target's position is solved by Gauss–Newton from the aim point, and the
    /// residual, projected off the position, updates the biases.
    pub fn learn(&mut self, report: &DwellReport, geom: &ShipGeometry) {
        let Some(chans) = self.channels(report, geom) else { return };
        let m = 3 * chans.len();
        let b = stack(chans.iter().map(|c| c.bias_rows(self.n, &self.sigma)), m, K * self.n);
        let shift = b.mul_vec(&self.est);
        let z: Vec<f64> = chans.iter().flat_map(|c| c.z).zip(&shift).map(|(z, s)| z - s).collect();
        let rinv: Vec<f64> = chans.iter().flat_map(|c| c.var).map(|v| 1.0 / v).collect();
        let Some(p) = solve_position(&chans, &z, &rinv, report.aim_ecef) else { return };
        let res: Vec<f64> = chans.iter().flat_map(|c| c.h(p)).zip(&z).map(|(h, z)| z - h).collect();
        let h = stack_jacobian(&chans, p);
        // W = R⁻¹ − R⁻¹H(HᵀR⁻¹H)⁻¹HᵀR⁻¹: the residual's information once the position is free.
        let rinv_d = Dense::diag(&rinv);
        let rh = rinv_d.mul(&h);
        let Some(hrh_inv) = h.t().mul(&rh).spd_inverse() else { return };
        let w = rinv_d.minus(&rh.mul(&hrh_inv).mul(&rh.t()));
        // Gate against a wrong association or a false alarm: the residual under R + BΣBᵀ.
        let s = Dense::diag(&chans.iter().flat_map(|c| c.var).collect::<Vec<_>>()).plus(&b.mul(&self.cov).mul(&b.t()));
        let Some(sl) = s.cholesky() else { return };
        let q: f64 = res.iter().zip(sl.chol_solve(&res)).map(|(a, b)| a * b).sum();
        // A NaN residual fails the gate too.
        if q.is_nan() || q > chi2_999(m - 3) {
            return;
        }
        let bt = b.t();
        let info = self.info.plus(&bt.mul(&w).mul(&b));
        let Some(cov) = info.spd_inverse() else { return };
        let step = cov.mul_vec(&bt.mul(&w).mul_vec(&res));
        self.est.iter_mut().zip(step).for_each(|(e, d)| *e += d);
        (self.info, self.cov) = (info, cov);
        self.used += 1;
    }

    /// A look's measurements corrected with the current estimate (docs/model.md §6.9): ranges
    /// less half the two radars' range biases, directions through the receiver's inverse bias
    /// map, and the variances grown by the estimate's own uncertainty.
    pub fn correct(&self, report: &DwellReport, geom: &ShipGeometry) -> Vec<MeasurementRow> {
        let est = self.estimate();
        let zero = RadarBias::default();
        let of = |r: RadarId| est.get(r.index()).unwrap_or(&zero);
        let mut out = report.measurements.clone();
        for m in &mut out {
            let Some(face) = geom.faces_at(m.rx, m.t_s).get(usize::from(m.rx_face)).copied() else { continue };
            let up = up_in_face(&face);
            let c = Channel { tx: m.tx, rx: m.rx, tx_site: DVec3::ZERO, face, up, z: [0.0, m.u, m.v], var: [0.0; 3] };
            let b = c.bias_rows(self.n, &self.sigma);
            let grow = b.mul(&self.cov).mul(&b.t());
            m.range_m -= 0.5 * (of(m.tx).range_m + of(m.rx).range_m);
            (m.u, m.v) = physical_beam(m.u, m.v, up, of(m.rx));
            m.var_range_m2 += 0.25 * grow.at(0, 0);
            m.var_u += grow.at(1, 1);
            m.var_v += grow.at(2, 2);
        }
        out
    }
}

/// Rows stacked into one `rows × cols` matrix.
fn stack(parts: impl Iterator<Item = Dense>, rows: usize, cols: usize) -> Dense {
    let mut out = Dense::zeros(rows, cols);
    for (i, p) in parts.enumerate() {
        out.a[3 * i * cols..3 * (i + 1) * cols].copy_from_slice(&p.a);
    }
    out
}

/// `∂h/∂p` of every channel at `p`, stacked (3C × 3).
fn stack_jacobian(chans: &[Channel], p: DVec3) -> Dense {
    Dense {
        rows: 3 * chans.len(),
        cols: 3,
        a: chans.iter().flat_map(|c| c.jacobian(p)).flat_map(|v| v.to_array()).collect(),
    }
}

/// The position whose measurements best fit `z` (weights `rinv`), by Gauss–Newton from `start`.
fn solve_position(chans: &[Channel], z: &[f64], rinv: &[f64], start: DVec3) -> Option<DVec3> {
    let mut p = start;
    for _ in 0..8 {
        let h = stack_jacobian(chans, p);
        let res: Vec<f64> = chans.iter().flat_map(|c| c.h(p)).zip(z).map(|(h, z)| z - h).collect();
        let rh = Dense::diag(rinv).mul(&h);
        let step = h.t().mul(&rh).cholesky()?.chol_solve(&rh.t().mul_vec(&res));
        p += DVec3::new(step[0], step[1], step[2]);
        if step.iter().map(|x| x * x).sum::<f64>() < 1e-6 {
            return p.is_finite().then_some(p);
        }
    }
    None
}
