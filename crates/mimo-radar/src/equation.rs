//! The radar range equation (docs/model.md §3.1, defaults §3.3).
//!
//! Matched-filter single-pulse SNR at the peak, bistatic:
//! `SNR₁ = P_t G_t G_r λ² σ τ / ((4π)³ R_t² R_r² k T_s L)` with `T_s = T0·F`. It reproduces the
//! MathWorks `radareqsnr` documentation examples (5.5868, 14.3778 and bistatic 9.0547 dB) and
//! the §3.3 reference of 25.1 dB (σ = 1 m², 100 km, broadside, default radar).

use crate::geometry::scan_gain;
use mimo_core::params::RadarParams;
use mimo_core::{BOLTZMANN_J_PER_K, T0_K, db_to_lin};

/// All terms of the radar equation, linear SI units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadarEquation {
    /// Peak transmit power `P_t` (W).
    pub peak_power_w: f64,
    /// Pulse width `τ` (s); with pulse compression it brings the gain `τB`.
    pub pulse_width_s: f64,
    /// Transmit gain `G_t` (linear).
    pub gain_tx: f64,
    /// Receive gain `G_r` (linear).
    pub gain_rx: f64,
    /// Wavelength `λ` (m).
    pub wavelength_m: f64,
    /// Radar cross-section `σ` (m²).
    pub rcs_m2: f64,
    /// System noise temperature `T_s = T0·F` (K).
    pub system_temp_k: f64,
    /// Total loss `L` (linear, ≥ 1).
    pub loss: f64,
}

impl RadarEquation {
    /// Single-pulse SNR (linear) at transmitter range `r_t_m` and receiver range `r_r_m`
    /// (monostatic: both equal `R`).
    pub fn snr(&self, r_t_m: f64, r_r_m: f64) -> f64 {
        let four_pi3 = (4.0 * std::f64::consts::PI).powi(3);
        self.peak_power_w
            * self.gain_tx
            * self.gain_rx
            * self.wavelength_m
            * self.wavelength_m
            * self.rcs_m2
            * self.pulse_width_s
            / (four_pi3 * r_t_m * r_t_m * r_r_m * r_r_m * BOLTZMANN_J_PER_K * self.system_temp_k * self.loss)
    }

    /// For a transmitter and a receiver of the model (docs/model.md §3.1): `P_t`, `τ` and `λ` are
    /// the transmitter's, the noise figure the receiver's, the loss the mean (in dB) of the two
    /// radars' total losses (equal to either for identical radars), and the gains are the peak
    /// gains with scan loss for the beams' boresight cosines `w_tx`, `w_rx`.
    pub fn for_pair(tx: &RadarParams, rx: &RadarParams, w_tx: f64, w_rx: f64, rcs_m2: f64) -> RadarEquation {
        RadarEquation {
            peak_power_w: tx.peak_power_w,
            pulse_width_s: tx.pulse_width_s,
            gain_tx: scan_gain(tx, w_tx),
            gain_rx: scan_gain(rx, w_rx),
            wavelength_m: tx.wavelength_m(),
            rcs_m2,
            system_temp_k: T0_K * db_to_lin(rx.noise_figure_db),
            loss: db_to_lin(0.5 * (tx.loss_db + rx.loss_db)),
        }
    }
}

/// Single-pulse mean SNR (linear) for a Tx–Rx pair with beams at boresight cosines `w_tx`, `w_rx`
/// and the target at ranges `r_t_m`, `r_r_m` (beam-centre: off-beam pattern factors are applied
/// to the voltages, docs/model.md §2.4).
pub fn snr1(tx: &RadarParams, rx: &RadarParams, w_tx: f64, w_rx: f64, rcs_m2: f64, r_t_m: f64, r_r_m: f64) -> f64 {
    RadarEquation::for_pair(tx, rx, w_tx, w_rx, rcs_m2).snr(r_t_m, r_r_m)
}

/// Monostatic broadside single-pulse SNR of one radar (linear).
pub fn snr1_monostatic(params: &RadarParams, rcs_m2: f64, range_m: f64) -> f64 {
    snr1(params, params, 1.0, 1.0, rcs_m2, range_m, range_m)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::{SPEED_OF_LIGHT_MPS, lin_to_db};

    /// MathWorks `radareqsnr` defaults: gain 20 dB, RCS 1 m², Ts 290 K, loss 0 dB.
    fn matlab(lambda: f64, pt: f64, tau: f64) -> RadarEquation {
        RadarEquation {
            peak_power_w: pt,
            pulse_width_s: tau,
            gain_tx: db_to_lin(20.0),
            gain_rx: db_to_lin(20.0),
            wavelength_m: lambda,
            rcs_m2: 1.0,
            system_temp_k: 290.0,
            loss: 1.0,
        }
    }

    #[test]
    fn reproduces_radareqsnr_examples() {
        // Example 1: 1 GHz, 50 km, 1 MW, 0.2 µs, 20 dB gains → 5.5868 dB.
        let e1 = matlab(SPEED_OF_LIGHT_MPS / 1e9, 1e6, 0.2e-6);
        let s1 = lin_to_db(e1.snr(50e3, 50e3));
        assert!((s1 - 5.5868).abs() < 5e-4, "{s1}");
        // Example 2: 10 GHz, 100 km, RCS 0.5, gain 40 dB, Ts 300 K, loss 3 dB, 1 µs → 14.3778 dB.
        let e2 = RadarEquation {
            rcs_m2: 0.5,
            gain_tx: db_to_lin(40.0),
            gain_rx: db_to_lin(40.0),
            system_temp_k: 300.0,
            loss: db_to_lin(3.0),
            ..matlab(SPEED_OF_LIGHT_MPS / 10e9, 1e6, 1e-6)
        };
        let s2 = lin_to_db(e2.snr(100e3, 100e3));
        assert!((s2 - 14.3778).abs() < 5e-4, "{s2}");
        // Example 3, bistatic: 50 km / 75 km, gains 40 / 20 dB, 10 GHz, 1 MW, 1 µs → 9.0547 dB.
        let e3 = RadarEquation { gain_tx: db_to_lin(40.0), ..matlab(SPEED_OF_LIGHT_MPS / 10e9, 1e6, 1e-6) };
        let s3 = lin_to_db(e3.snr(50e3, 75e3));
        assert!((s3 - 9.0547).abs() < 5e-4, "{s3}");
    }

    #[test]
    fn reference_snr_of_the_default_radar() {
        let p = RadarParams::default();
        let s = lin_to_db(snr1_monostatic(&p, 1.0, 100e3));
        assert!((s - 25.1).abs() < 0.05, "{s}");
        // §3.3 table: fighter 2 m² at 150 km 21.1 dB; airliner 30 m² at 300 km 20.8 dB.
        assert!((lin_to_db(snr1_monostatic(&p, 2.0, 150e3)) - 21.1).abs() < 0.05);
        assert!((lin_to_db(snr1_monostatic(&p, 30.0, 300e3)) - 20.8).abs() < 0.05);
        // Bistatic 2 m², 150 km / 180 km: 19.5 dB.
        let b = lin_to_db(snr1(&p, &p, 1.0, 1.0, 2.0, 150e3, 180e3));
        assert!((b - 19.5).abs() < 0.05, "{b}");
        // Peak gain 42.0 dB.
        assert!((lin_to_db(p.peak_gain()) - 42.0).abs() < 0.05);
    }
}
