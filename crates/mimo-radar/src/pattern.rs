//! Monopulse antenna patterns (docs/model.md §2.1–§2.3) and the mapping between the monopulse
//! ratio and the sine-space offset from the beam (§2.5).
//!
//! Patterns are shift-invariant in sine space: they depend only on `(Δu, Δv) = (u − u_b, v − v_b)`
//! in the face's own u–v, so beam broadening off boresight comes for free (§1.5). Gains are
//! normalized **voltage** patterns (1 at the beam peak for the sum channel); the peak gain and scan
//! loss live in the radar equation.

use mimo_core::params::{PatternModel, RadarParams};

/// Normalized voltage gains of the three monopulse channels toward one direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gains {
    /// Sum channel `g_Σ`.
    pub sum: f64,
    /// Azimuth (u) difference channel `g_Δa`, after the −90° hybrid (real ratio to the sum).
    pub az: f64,
    /// Elevation (v) difference channel `g_Δe`.
    pub el: f64,
}

/// One receive/transmit antenna's pattern model with its constants precomputed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Antenna {
    model: PatternModel,
    /// Half-power beamwidths in sine space (model A: κλ/D; model B: 0.886λ/D).
    theta_u: f64,
    theta_v: f64,
    /// Normalized monopulse slope (model A: the parameter; model B: 0.886π/2).
    k_m: f64,
    /// Model B: `πD/λ` per axis.
    scale_u: f64,
    scale_v: f64,
}

const FOUR_LN2: f64 = 4.0 * std::f64::consts::LN_2;
/// Half-power width of a uniform aperture, in units of λ/D.
const UNIFORM_HPBW: f64 = 0.886;

fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-4 { 1.0 - x * x / 6.0 } else { x.sin() / x }
}

/// `(1 − cos x)/x`, the half-aperture difference pattern.
fn cosc(x: f64) -> f64 {
    if x.abs() < 1e-4 { x / 2.0 - x * x * x / 24.0 } else { (1.0 - x.cos()) / x }
}

impl Antenna {
    /// The antenna of a radar under a pattern model.
    pub fn new(params: &RadarParams, model: PatternModel) -> Antenna {
        let lambda = params.wavelength_m();
        let scale_u = std::f64::consts::PI * params.aperture_x_m / lambda;
        let scale_v = std::f64::consts::PI * params.aperture_y_m / lambda;
        match model {
            PatternModel::Gaussian => Antenna {
                model,
                theta_u: params.beamwidth_u(),
                theta_v: params.beamwidth_v(),
                k_m: params.monopulse_slope,
                scale_u,
                scale_v,
            },
            PatternModel::UniformAperture => Antenna {
                model,
                theta_u: UNIFORM_HPBW * lambda / params.aperture_x_m,
                theta_v: UNIFORM_HPBW * lambda / params.aperture_y_m,
                k_m: UNIFORM_HPBW * std::f64::consts::FRAC_PI_2,
                scale_u,
                scale_v,
            },
        }
    }

    /// The pattern model.
    pub fn model(&self) -> PatternModel {
        self.model
    }
    /// Half-power beamwidth along u (sine space).
    pub fn theta_u(&self) -> f64 {
        self.theta_u
    }
    /// Half-power beamwidth along v (sine space).
    pub fn theta_v(&self) -> f64 {
        self.theta_v
    }
    /// Normalized monopulse slope `k_m` (ratio per beamwidth at the beam centre).
    pub fn slope(&self) -> f64 {
        self.k_m
    }

    /// Sum-channel voltage gain only (cheap pre-check).
    pub fn sum_gain(&self, du: f64, dv: f64) -> f64 {
        match self.model {
            PatternModel::Gaussian => {
                let a = du / self.theta_u;
                let b = dv / self.theta_v;
                (-0.5 * FOUR_LN2 * (a * a + b * b)).exp()
            }
            PatternModel::UniformAperture => sinc(self.scale_u * du) * sinc(self.scale_v * dv),
        }
    }

    /// Voltage gains of Σ, Δa, Δe at offset `(du, dv)` from the beam (docs/model.md §2.2, §2.3).
    pub fn gains(&self, du: f64, dv: f64) -> Gains {
        match self.model {
            PatternModel::Gaussian => {
                let a = du / self.theta_u;
                let b = dv / self.theta_v;
                let s = (-0.5 * FOUR_LN2 * (a * a + b * b)).exp();
                Gains { sum: s, az: self.k_m * a * s, el: self.k_m * b * s }
            }
            PatternModel::UniformAperture => {
                let x = self.scale_u * du;
                let y = self.scale_v * dv;
                let (sx, sy) = (sinc(x), sinc(y));
                Gains { sum: sx * sy, az: cosc(x) * sy, el: sx * cosc(y) }
            }
        }
    }

    /// The noise-free monopulse ratios `(η_a, η_e)` at offset `(du, dv)` (receive side).
    pub fn ratio(&self, du: f64, dv: f64) -> (f64, f64) {
        match self.model {
            PatternModel::Gaussian => (self.k_m * du / self.theta_u, self.k_m * dv / self.theta_v),
            PatternModel::UniformAperture => ((0.5 * self.scale_u * du).tan(), (0.5 * self.scale_v * dv).tan()),
        }
    }

    /// Invert the monopulse curve: offsets `(Δu, Δv)` from ratios `(η_a, η_e)` (docs/model.md §2.5).
    pub fn offset_from_ratio(&self, eta_a: f64, eta_e: f64) -> (f64, f64) {
        match self.model {
            PatternModel::Gaussian => (self.theta_u / self.k_m * eta_a, self.theta_v / self.k_m * eta_e),
            PatternModel::UniformAperture => (2.0 / self.scale_u * eta_a.atan(), 2.0 / self.scale_v * eta_e.atan()),
        }
    }

    /// Slopes `dΔu/dη_a`, `dΔv/dη_e` of the inverse monopulse curve at the given ratios, used to map
    /// ratio variances to sine-space variances (§2.6).
    pub fn offset_slope(&self, eta_a: f64, eta_e: f64) -> (f64, f64) {
        match self.model {
            PatternModel::Gaussian => (self.theta_u / self.k_m, self.theta_v / self.k_m),
            PatternModel::UniformAperture => {
                (2.0 / self.scale_u / (1.0 + eta_a * eta_a), 2.0 / self.scale_v / (1.0 + eta_e * eta_e))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_give_the_antennas_half_power_beamwidths() {
        // The score's beam footprints (docs/design.md §6) take the beamwidths from the params.
        let p = RadarParams { aperture_x_m: 3.6, aperture_y_m: 2.4, beamwidth_factor: 1.2, ..RadarParams::default() };
        for model in [PatternModel::Gaussian, PatternModel::UniformAperture] {
            let a = Antenna::new(&p, model);
            assert_eq!(p.half_power_beamwidths(model), (a.theta_u(), a.theta_v()), "{model:?}");
        }
    }

    #[test]
    fn gaussian_pattern_constants() {
        let p = RadarParams::default();
        let a = Antenna::new(&p, PatternModel::Gaussian);
        assert!((a.theta_u() - 0.0252).abs() < 1e-4);
        // −3 dB one-way power at Δu = θ/2.
        let g = a.sum_gain(a.theta_u() / 2.0, 0.0);
        assert!((g * g - 0.5).abs() < 1e-12);
        // Difference peak at 0.60θ with 0.364·k_m of the sum peak.
        let mut best = (0.0, 0.0);
        for i in 0..20000 {
            let du = i as f64 * 1e-4 * a.theta_u();
            let d = a.gains(du, 0.0).az;
            if d > best.1 {
                best = (du / a.theta_u(), d);
            }
        }
        assert!((best.0 - 0.60).abs() < 0.005, "{best:?}");
        assert!((best.1 / a.slope() - 0.364).abs() < 0.002, "{best:?}");
        // Ratio is exactly linear and inverts.
        let g = a.gains(0.3 * a.theta_u(), -0.2 * a.theta_v());
        let (ea, ee) = (g.az / g.sum, g.el / g.sum);
        let (du, dv) = a.offset_from_ratio(ea, ee);
        assert!((du - 0.3 * a.theta_u()).abs() < 1e-15 && (dv + 0.2 * a.theta_v()).abs() < 1e-15);
        assert_eq!(a.ratio(0.3 * a.theta_u(), 0.0).0, ea);
    }

    #[test]
    fn uniform_aperture_pattern() {
        let p = RadarParams::default();
        let a = Antenna::new(&p, PatternModel::UniformAperture);
        // Half power at θ/2 = 0.443 λ/D (to the accuracy of the 0.886 constant).
        let g = a.sum_gain(a.theta_u() / 2.0, 0.0);
        assert!((g * g - 0.5).abs() < 2e-3, "{}", g * g);
        // First sidelobe −13.3 dB near x = 1.43π.
        let x = 1.4303 * std::f64::consts::PI;
        let du = x / (std::f64::consts::PI * p.aperture_x_m / p.wavelength_m());
        let sl = 20.0 * a.sum_gain(du, 0.0).abs().log10();
        assert!((sl + 13.26).abs() < 0.05, "{sl}");
        // Ratio tan(x/2) inverts through arctan; slope k_m = 1.39.
        for &f in &[-0.7, -0.2, 0.0, 0.1, 0.5, 0.9] {
            let du = f * a.theta_u();
            let g = a.gains(du, 0.0);
            let (back, _) = a.offset_from_ratio(g.az / g.sum, 0.0);
            assert!((back - du).abs() < 1e-12, "{f}");
        }
        assert!((a.slope() - 1.39).abs() < 0.005);
        let (ea, _) = a.ratio(1e-6 * a.theta_u(), 0.0);
        assert!((ea / 1e-6 - a.slope()).abs() < 1e-3);
    }
}
