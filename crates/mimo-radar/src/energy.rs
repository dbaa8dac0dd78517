//! Energy and pulse sizing for trackers (docs/model.md §3.1, §4.3, §7.2, §7.3).
//!
//! `N_p = ⌈SNR_req · L_bs · L_str / SNR₁⌉` clipped to `[1, N_max]`, with `SNR_req = ln P_FA / ln P_D − 1`
//! (SW1, one coherent sample), the expected beam-pointing loss `L_bs` of the Gaussian pattern for a
//! pointing error of `V₀` beamwidths, and the average straddle loss `L_str` (2.66 dB).

use crate::equation::snr1;
use crate::geometry::{Bistatic, beam_point, bistatic, visible};
use crate::range::straddle_loss_mean_db;
use mimo_core::face::FaceFrame;
use mimo_core::params::RadarParams;
use mimo_core::{DVec3, db_to_lin};

/// A predicted Tx→Rx look at a target with both beams steered onto it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairPrediction {
    /// Faces chosen (indices into the slices given).
    pub tx_face: u8,
    /// Receiving face chosen.
    pub rx_face: u8,
    /// Beam boresight cosines (scan loss).
    pub w_tx: f64,
    /// Receive beam boresight cosine (scan loss).
    pub w_rx: f64,
    /// Bistatic geometry of the target for the chosen faces.
    pub geometry: Bistatic,
    /// Predicted single-pulse mean SNR (linear), beams on the target, no straddle.
    pub snr1: f64,
}

impl PairPrediction {
    /// Mean SNR of `n_pulses` coherently integrated pulses (linear).
    pub fn snr(&self, n_pulses: u32) -> f64 {
        f64::from(n_pulses) * self.snr1
    }
}

/// One end of a Tx→Rx pair: a radar's parameters and its faces at the look's instant.
#[derive(Debug, Clone, Copy)]
pub struct PairEnd<'a> {
    /// The radar's parameters.
    pub params: &'a RadarParams,
    /// Its faces (the prediction names one by its index in this slice).
    pub faces: &'a [FaceFrame],
}

/// Predict the mean SNR of a Tx→Rx pair for a target at `p` with mean RCS `rcs_m2`: each radar
/// uses its best face, and the look must be inside both scan limits, above both 4/3-earth horizons
/// and at a bistatic angle ≤ 150°; otherwise `None`. Monostatic: the same radar twice.
pub fn predict_pair(tx: PairEnd<'_>, rx: PairEnd<'_>, p: DVec3, rcs_m2: f64) -> Option<PairPrediction> {
    predict_pair_seen(tx, rx, p, rcs_m2, |site| visible(site, p))
}

/// [`predict_pair`] with the 4/3-earth horizon test given by the caller: `seen_from(site)` says
/// whether `p` is above the horizon of an antenna at `site` ([`visible`]'s answer, which a caller
/// that knows the heights, say, can give without converting the points to geodetic again).
pub fn predict_pair_seen(
    tx: PairEnd<'_>,
    rx: PairEnd<'_>,
    p: DVec3,
    rcs_m2: f64,
    seen_from: impl Fn(DVec3) -> bool,
) -> Option<PairPrediction> {
    let bt = beam_point(tx.faces, tx.params, p)?;
    let br = beam_point(rx.faces, rx.params, p)?;
    let t = tx.faces[bt.face as usize].origin_ecef;
    let r = rx.faces[br.face as usize].origin_ecef;
    let geometry = bistatic(t, r, p);
    if !geometry.usable() || !seen_from(t) || (r != t && !seen_from(r)) {
        return None;
    }
    let s = snr1(tx.params, rx.params, bt.w, br.w, rcs_m2, geometry.r_t_m, geometry.r_r_m);
    Some(PairPrediction { tx_face: bt.face, rx_face: br.face, w_tx: bt.w, w_rx: br.w, geometry, snr1: s })
}

/// Single-look SNR (linear) needed for detection probability `pd` at false-alarm probability
/// `pfa`, SW1 with one coherent sample: `ln P_FA / ln P_D − 1` (21.1 dB for 0.9 at 1e-6).
pub fn required_snr_sw1(pd: f64, pfa: f64) -> f64 {
    let pd = pd.clamp(1e-12, 1.0 - 1e-12);
    (pfa.ln() / pd.ln() - 1.0).max(0.0)
}

/// SW1 detection probability of one coherent sample at mean SNR `snr`: `P_FA^{1/(1+SNR)}`.
pub fn pd_sw1(snr: f64, pfa: f64) -> f64 {
    pfa.powf(1.0 / (1.0 + snr.max(0.0)))
}

/// Expected beam-pointing loss (linear, ≥ 1) of the Gaussian pattern (model A) when the
/// transmit and receive beams are off the target by Gaussian errors of `v0_tx`, `v0_rx`
/// beamwidths (std per axis): `1/E[g_Σtx² g_Σrx²]`. Monostatic (`same_error`: the two errors are
/// the same) it is `∏_axes (1 + 16 ln2 V₀²)^{1/2}`, 1.6 dB at `V₀ = 0.2`; bistatic errors are taken
/// as independent: `∏_axes [(1 + 8 ln2 V_t²)(1 + 8 ln2 V_r²)]^{1/2}`.
pub fn pointing_loss(v0_tx: f64, v0_rx: f64, same_error: bool) -> f64 {
    let k = 8.0 * std::f64::consts::LN_2;
    // Per axis the loss is the square root of these; the two axes multiply back to them.
    if same_error {
        // g_tx² g_rx² = exp(−8 ln2 x²) for x in beamwidths; E over N(0, V₀²) per axis.
        1.0 + 2.0 * k * v0_tx * v0_tx
    } else {
        (1.0 + k * v0_tx * v0_tx) * (1.0 + k * v0_rx * v0_rx)
    }
}

/// Mean straddle loss (linear): 2.66 dB.
pub fn straddle_loss() -> f64 {
    db_to_lin(straddle_loss_mean_db())
}

/// Pulses needed to reach `snr_required` given the single-pulse SNR `snr1` and the product of the
/// expected losses (linear ≥ 1), clipped to `[1, max_pulses]` (§7.2). A non-positive or non-finite
/// `snr1` asks for `max_pulses`.
pub fn pulses_for(snr_required: f64, snr1: f64, losses: f64, max_pulses: u32) -> u32 {
    let max = max_pulses.max(1);
    if !(snr1 > 0.0 && snr1.is_finite() && snr_required.is_finite()) {
        return max;
    }
    let n = (snr_required * losses.max(1.0) / snr1).ceil();
    if n.is_nan() || n > f64::from(max) {
        max
    } else if n < 1.0 {
        1
    } else {
        n as u32
    }
}

/// Dwell duration on the timeline: `N_p / PRF` plus the fixed overhead (s) (§7.3).
pub fn dwell_duration_s(params: &RadarParams, n_pulses: u32) -> f64 {
    f64::from(n_pulses) / params.prf_hz + params.dwell_overhead_s
}

/// Emitted energy `P_t τ N_p` (J).
pub fn dwell_energy_j(params: &RadarParams, n_pulses: u32) -> f64 {
    params.peak_power_w * params.pulse_width_s * f64::from(n_pulses)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mimo_core::geo::Geodetic;
    use mimo_core::lin_to_db;

    #[test]
    fn required_snr_and_losses() {
        assert!((lin_to_db(required_snr_sw1(0.9, 1e-6)) - 21.1).abs() < 0.05);
        assert!((lin_to_db(required_snr_sw1(0.5, 1e-6)) - 12.8).abs() < 0.05);
        assert!((lin_to_db(required_snr_sw1(0.8, 1e-6)) - 17.8).abs() < 0.05);
        assert!((pd_sw1(required_snr_sw1(0.9, 1e-6), 1e-6) - 0.9).abs() < 1e-12);
        assert!((lin_to_db(pointing_loss(0.2, 0.2, true)) - 1.594).abs() < 0.01);
        assert!((lin_to_db(straddle_loss()) - 2.66).abs() < 0.01);
        // Monte Carlo of the monostatic pointing loss.
        let mut s = mimo_core::rng::Stream::new(3, &[mimo_core::rng::domain::TEST]);
        let n = 200_000;
        let ln2 = std::f64::consts::LN_2;
        let m: f64 = (0..n)
            .map(|_| {
                let (x, y) = (0.2 * s.normal(), 0.2 * s.normal());
                (-8.0 * ln2 * (x * x + y * y)).exp()
            })
            .sum::<f64>()
            / n as f64;
        assert!((1.0 / m / pointing_loss(0.2, 0.2, true) - 1.0).abs() < 0.01);
    }

    #[test]
    fn pulses_and_timeline() {
        let p = RadarParams::default();
        let req = required_snr_sw1(0.9, 1e-6);
        // 2 m² fighter at 150 km broadside: 21.1 dB single pulse, losses 2.66 + 1.6 dB → 3 pulses.
        let s1 = crate::equation::snr1_monostatic(&p, 2.0, 150e3);
        let n = pulses_for(req, s1, straddle_loss() * pointing_loss(0.2, 0.2, true), p.max_pulses);
        assert_eq!(n, 3);
        assert_eq!(pulses_for(req, 1e-9, 1.0, 16), 16);
        assert_eq!(pulses_for(req, 1e9, 1.0, 16), 1);
        assert_eq!(pulses_for(req, f64::NAN, 1.0, 16), 16);
        assert!((dwell_energy_j(&p, 4) - 4.0).abs() < 1e-12);
        assert!((dwell_duration_s(&p, 3) - (0.01 + 1e-3)).abs() < 1e-12);
    }

    #[test]
    fn pair_prediction_matches_the_radar_equation() {
        let p = RadarParams::default();
        let site = Geodetic::from_deg(36.0, -70.0, 20.0);
        let faces: Vec<FaceFrame> = p
            .face_azimuths_deg
            .iter()
            .map(|a| FaceFrame::new(site, a.to_radians(), p.face_tilt_deg.to_radians()))
            .collect();
        let tgt = faces[1].from_ruv(100e3, 0.0, 0.0);
        let radar = PairEnd { params: &p, faces: &faces };
        let pr = predict_pair(radar, radar, tgt, 1.0).expect("visible");
        assert_eq!(pr.tx_face, 1);
        assert!((lin_to_db(pr.snr1) - 25.1).abs() < 0.05);
        assert!((pr.snr(4) / pr.snr1 - 4.0).abs() < 1e-12);
        // Below the horizon: none.
        let far = faces[1].from_ruv(300e3, 0.0, -0.3);
        assert!(predict_pair(radar, radar, far, 1.0).is_none());
    }
}
