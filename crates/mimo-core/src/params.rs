//! Radar parameters and fidelity switches, shared by the scenario files (which set them) and
//! the radar model (which uses them). Defaults are docs/model.md §3.3's generic S-band ship radar.
//!
//! Every field is in SI units with the unit in its name; the scenario TOML uses the same names.

use serde::{Deserialize, Serialize};

/// Antenna pattern model (docs/model.md §2.2, §2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum PatternModel {
    /// Gaussian sum beam, linear-ratio difference beams (default).
    #[default]
    Gaussian,
    /// Uniform rectangular aperture: sinc sum beam, sidelobes, nonlinear monopulse curve.
    UniformAperture,
}

/// Swerling fluctuation case (docs/model.md §3.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Swerling {
    /// Swerling 0: constant RCS σ̄ (unit-magnitude voltage, uniform phase).
    Sw0,
    /// Swerling 1 (default): RCS exponential with mean σ̄, drawn anew per dwell and Tx–Rx pair.
    #[default]
    Sw1,
    /// Swerling 3: σ/σ̄ ~ Gamma(shape 2, scale ½) (χ², 4 d.o.f.), per dwell and Tx–Rx pair.
    Sw3,
}

/// Rung of the fidelity ladder (docs/model.md §4.8): how a channel's detections are produced.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum FidelityLevel {
    /// I/Q voltages per cell, threshold, clustering, centroiding and ML monopulse (§2–§4).
    Voltage,
    /// Measurements drawn from the statistics the voltage level produces; no cells simulated.
    Measurement,
    /// The default: the voltage level in channels with targets close to each other (or when
    /// voltages are recorded), the measurement level elsewhere (docs/decisions/0038-fidelity-ladder.md:
    /// the fastest rung that holds every band).
    #[default]
    Auto,
}

impl FidelityLevel {
    /// Every level, in ladder order.
    pub const ALL: [FidelityLevel; 3] = [FidelityLevel::Voltage, FidelityLevel::Measurement, FidelityLevel::Auto];

    /// The name used in scenario files, on the command line and in the manifest.
    pub fn name(self) -> &'static str {
        match self {
            FidelityLevel::Voltage => "voltage",
            FidelityLevel::Measurement => "measurement",
            FidelityLevel::Auto => "auto",
        }
    }

    /// Parse a name of [`FidelityLevel::name`].
    pub fn parse(s: &str) -> Option<FidelityLevel> {
        FidelityLevel::ALL.into_iter().find(|l| l.name() == s)
    }
}

/// Parameters of one ship radar (docs/model.md §3.3).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RadarParams {
    /// Carrier frequency (Hz).
    pub frequency_hz: f64,
    /// Aperture width along the face's x axis (m).
    pub aperture_x_m: f64,
    /// Aperture height along the face's y axis (m).
    pub aperture_y_m: f64,
    /// Aperture efficiency η_a.
    pub aperture_efficiency: f64,
    /// Beamwidth factor κ in θ = κλ/D (sine space).
    pub beamwidth_factor: f64,
    /// Scan-loss exponent α_s per way: G = G0·w^α_s.
    pub scan_loss_exponent: f64,
    /// Maximum scan angle off boresight (deg).
    pub max_scan_deg: f64,
    /// Normalized monopulse slope k_m (Gaussian model).
    pub monopulse_slope: f64,
    /// Face boresight azimuths relative to the bow (deg, clockwise).
    pub face_azimuths_deg: Vec<f64>,
    /// Face elevation tilt (deg).
    pub face_tilt_deg: f64,
    /// Peak transmit power (W).
    pub peak_power_w: f64,
    /// Pulse width τ (s).
    pub pulse_width_s: f64,
    /// Waveform bandwidth B (Hz); range cell ΔR = c/(2B).
    pub bandwidth_hz: f64,
    /// Pulse repetition frequency (Hz).
    pub prf_hz: f64,
    /// Maximum pulses per dwell.
    pub max_pulses: u32,
    /// Receiver noise figure (dB).
    pub noise_figure_db: f64,
    /// Total system loss L (dB).
    pub loss_db: f64,
    /// Per-cell false-alarm probability.
    pub pfa: f64,
    /// Instrumented range (m); search covers ρ up to this.
    pub instrumented_range_m: f64,
    /// Minimum range (m), eclipsed below.
    pub min_range_m: f64,
    /// Fixed per-dwell overhead added to the timeline (s).
    pub dwell_overhead_s: f64,
    /// Linear polarization of the transmitted wave, as the angle of its electric field from the
    /// face's horizontal (deg; 0 = H, 90 = V). Used only with `fidelity.polarization`
    /// (docs/model.md §3.5).
    pub tx_polarization_deg: f64,
    /// Linear polarization the receiver is matched to (deg from horizontal; 0 = H, 90 = V). Used
    /// only with `fidelity.polarization` (docs/model.md §3.5).
    pub rx_polarization_deg: f64,
}

impl Default for RadarParams {
    fn default() -> Self {
        RadarParams {
            frequency_hz: 3.3e9,
            aperture_x_m: 3.6,
            aperture_y_m: 3.6,
            aperture_efficiency: 0.8,
            beamwidth_factor: 1.0,
            scan_loss_exponent: 1.5,
            max_scan_deg: 60.0,
            monopulse_slope: 1.6,
            face_azimuths_deg: vec![45.0, 135.0, 225.0, 315.0],
            face_tilt_deg: 15.0,
            peak_power_w: 100e3,
            pulse_width_s: 10e-6,
            bandwidth_hz: 5e6,
            prf_hz: 300.0,
            max_pulses: 16,
            noise_figure_db: 4.0,
            loss_db: 5.0,
            pfa: 1e-6,
            instrumented_range_m: 450e3,
            min_range_m: 2e3,
            dwell_overhead_s: 1e-3,
            tx_polarization_deg: 0.0,
            rx_polarization_deg: 0.0,
        }
    }
}

/// Upper ends of the plausible ranges of docs/model.md §3.4 (lower ends: the checks above).
type Field = fn(&RadarParams) -> f64;
const PLAUSIBLE: &[(&str, Field, f64, &str)] = &[
    ("frequency_hz", |p| p.frequency_hz, 1e11, "Hz"),
    ("aperture_x_m", |p| p.aperture_x_m, 50.0, "m"),
    ("aperture_y_m", |p| p.aperture_y_m, 50.0, "m"),
    ("beamwidth_factor", |p| p.beamwidth_factor, 3.0, ""),
    ("monopulse_slope", |p| p.monopulse_slope, 10.0, ""),
    ("scan_loss_exponent", |p| p.scan_loss_exponent, 10.0, ""),
    ("peak_power_w", |p| p.peak_power_w, 1e8, "W"),
    ("pulse_width_s", |p| p.pulse_width_s, 1e-2, "s"),
    ("bandwidth_hz", |p| p.bandwidth_hz, 1e10, "Hz"),
    ("prf_hz", |p| p.prf_hz, 1e6, "Hz"),
    ("noise_figure_db", |p| p.noise_figure_db, 30.0, "dB"),
    ("loss_db", |p| p.loss_db, 60.0, "dB"),
    ("instrumented_range_m", |p| p.instrumented_range_m, 5e6, "m"),
    ("dwell_overhead_s", |p| p.dwell_overhead_s, 10.0, "s"),
];
/// Most pulses per dwell (docs/model.md §3.4).
pub const MAX_PULSES: u32 = 10_000;

impl RadarParams {
    /// Wavelength λ (m).
    pub fn wavelength_m(&self) -> f64 {
        crate::SPEED_OF_LIGHT_MPS / self.frequency_hz
    }
    /// Sine-space half-power beamwidth along u.
    pub fn beamwidth_u(&self) -> f64 {
        self.beamwidth_factor * self.wavelength_m() / self.aperture_x_m
    }
    /// Sine-space half-power beamwidth along v.
    pub fn beamwidth_v(&self) -> f64 {
        self.beamwidth_factor * self.wavelength_m() / self.aperture_y_m
    }
    /// Sine-space half-power beamwidths `(θ_u, θ_v)` under a pattern model (docs/model.md §2.1–§2.3):
    /// `κλ/D` for model A (Gaussian), `0.886 λ/D` for model B (uniform aperture, independent of κ).
    /// The power of one way is 3 dB down at `θ/2` from the beam centre in either model.
    pub fn half_power_beamwidths(&self, model: PatternModel) -> (f64, f64) {
        match model {
            PatternModel::Gaussian => (self.beamwidth_u(), self.beamwidth_v()),
            PatternModel::UniformAperture => {
                let lambda = self.wavelength_m();
                (0.886 * lambda / self.aperture_x_m, 0.886 * lambda / self.aperture_y_m)
            }
        }
    }
    /// Range cell ΔR = c/(2B) (m).
    pub fn range_cell_m(&self) -> f64 {
        crate::SPEED_OF_LIGHT_MPS / (2.0 * self.bandwidth_hz)
    }
    /// Peak gain G0 = 4π η_a Dx Dy / λ² (linear).
    pub fn peak_gain(&self) -> f64 {
        let l = self.wavelength_m();
        4.0 * std::f64::consts::PI * self.aperture_efficiency * self.aperture_x_m * self.aperture_y_m / (l * l)
    }
    /// Square-law detection threshold γ = −ln P_FA on |Σ|².
    pub fn threshold(&self) -> f64 {
        -self.pfa.ln()
    }
    /// Minimum w = cos θ_max a beam may be steered to.
    pub fn min_scan_w(&self) -> f64 {
        self.max_scan_deg.to_radians().cos()
    }

    /// Check physical sanity; returns the name of the first offending field and what was wanted.
    pub fn validate(&self) -> Result<(), (String, String)> {
        let pos = |name: &str, x: f64| -> Result<(), (String, String)> {
            if x.is_finite() && x > 0.0 {
                Ok(())
            } else {
                Err((name.to_string(), format!("a positive finite number, got {x}")))
            }
        };
        pos("frequency_hz", self.frequency_hz)?;
        if self.frequency_hz < 1e8 {
            return Err((
                "frequency_hz".into(),
                format!("at least 1e8 Hz (plausible range, docs/model.md §3.4), got {:e}", self.frequency_hz),
            ));
        }
        pos("aperture_x_m", self.aperture_x_m)?;
        pos("aperture_y_m", self.aperture_y_m)?;
        pos("aperture_efficiency", self.aperture_efficiency)?;
        if self.aperture_efficiency > 1.0 {
            return Err(("aperture_efficiency".into(), format!("at most 1, got {}", self.aperture_efficiency)));
        }
        pos("beamwidth_factor", self.beamwidth_factor)?;
        pos("monopulse_slope", self.monopulse_slope)?;
        pos("peak_power_w", self.peak_power_w)?;
        pos("pulse_width_s", self.pulse_width_s)?;
        pos("bandwidth_hz", self.bandwidth_hz)?;
        pos("prf_hz", self.prf_hz)?;
        pos("instrumented_range_m", self.instrumented_range_m)?;
        if !(self.scan_loss_exponent.is_finite() && self.scan_loss_exponent >= 0.0) {
            return Err(("scan_loss_exponent".into(), "a finite number >= 0".into()));
        }
        if !(self.max_scan_deg > 0.0 && self.max_scan_deg < 90.0) {
            return Err(("max_scan_deg".into(), format!("between 0 and 90 degrees, got {}", self.max_scan_deg)));
        }
        if !(self.pfa > 0.0 && self.pfa < 0.1) {
            return Err(("pfa".into(), format!("between 0 and 0.1, got {}", self.pfa)));
        }
        if self.max_pulses == 0 {
            return Err(("max_pulses".into(), "at least 1".into()));
        }
        if self.face_azimuths_deg.is_empty() || self.face_azimuths_deg.iter().any(|a| !a.is_finite()) {
            return Err(("face_azimuths_deg".into(), "a non-empty list of finite angles".into()));
        }
        if !(self.face_tilt_deg.is_finite() && self.face_tilt_deg.abs() < 90.0) {
            return Err(("face_tilt_deg".into(), "a tilt between -90 and 90 degrees".into()));
        }
        for (n, x) in [("noise_figure_db", self.noise_figure_db), ("loss_db", self.loss_db)] {
            if !(x.is_finite() && x >= 0.0) {
                return Err((n.into(), format!("a finite number of dB >= 0, got {x}")));
            }
        }
        self.validate_plausible()
    }

    /// The plausible ranges of docs/model.md §3.4 (wide around any real surface radar, narrow
    /// enough that energies, SNRs and cell counts stay finite and tractable), the minimum range,
    /// the dwell overhead and the polarizations.
    fn validate_plausible(&self) -> Result<(), (String, String)> {
        for &(name, x, hi, unit) in PLAUSIBLE {
            let x = x(self);
            if x > hi {
                return Err((
                    name.into(),
                    format!("at most {hi:e} {unit} (plausible range, docs/model.md §3.4), got {x:e}"),
                ));
            }
        }
        if self.max_pulses > MAX_PULSES {
            return Err((
                "max_pulses".into(),
                format!("at most {MAX_PULSES} (plausible range, docs/model.md §3.4), got {}", self.max_pulses),
            ));
        }
        if !(self.min_range_m.is_finite() && self.min_range_m >= 0.0 && self.min_range_m < self.instrumented_range_m) {
            return Err(("min_range_m".into(), "a range >= 0 and below instrumented_range_m".into()));
        }
        if !(self.dwell_overhead_s.is_finite() && self.dwell_overhead_s >= 0.0) {
            return Err(("dwell_overhead_s".into(), "a duration >= 0".into()));
        }
        for (n, x) in
            [("tx_polarization_deg", self.tx_polarization_deg), ("rx_polarization_deg", self.rx_polarization_deg)]
        {
            if !(x.is_finite() && x.abs() <= 360.0) {
                return Err((n.into(), format!("an angle between -360 and 360 degrees, got {x}")));
            }
        }
        Ok(())
    }
}

/// Modelling switches a scene may or may not need (docs/design.md §2 `fidelity`). Recorded in the
/// manifest of every run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Fidelity {
    /// Antenna pattern model of every radar (docs/model.md §2.2, §2.3); default Gaussian.
    pub pattern: PatternModel,
    /// Target RCS fluctuation model (docs/model.md §3.2); default Swerling 1.
    pub swerling: Swerling,
    /// Apply 4/3-earth refraction to measured elevation (docs/model.md §1.8). Default off.
    pub refraction: bool,
    /// Model orthogonal-waveform leakage with this isolation (dB); `None` is ideal.
    pub waveform_isolation_db: Option<f64>,
    /// Cells simulated explicitly on each side of a target return (docs/model.md §4.4).
    pub explicit_cells_each_side: u32,
    /// Truth sample rate (Hz) of the truth table.
    pub truth_rate_hz: f64,
    /// Polarimetric scattering (docs/model.md §3.5): each target's echo is `h_rᵀ S h_t` for a
    /// Gaussian 2×2 scattering matrix `S` and the radars' linear polarizations, in place of the
    /// Swerling draw. Default off (every radar and target then behaves as co-polarized SW1/SW0/SW3).
    pub polarization: bool,
    /// Rung of the fidelity ladder (docs/model.md §4.8); default auto.
    pub level: FidelityLevel,
    /// Fit two point targets to each cluster of crossings at the voltage rung (docs/model.md §4.9): an
    /// unresolved pair 1–2 range cells apart gives two measurements. Default off.
    pub two_target: bool,
}

impl Default for Fidelity {
    fn default() -> Self {
        Fidelity {
            pattern: PatternModel::Gaussian,
            swerling: Swerling::Sw1,
            refraction: false,
            waveform_isolation_db: None,
            explicit_cells_each_side: 3,
            truth_rate_hz: 10.0,
            polarization: false,
            level: FidelityLevel::Auto,
            two_target: false,
        }
    }
}
