//! Shared scene for the Monte Carlo tests: one ship (or two) with the default radar.
#![allow(dead_code)]

use mimo_core::DVec3;
use mimo_core::face::FaceFrame;
use mimo_core::geo::Geodetic;
use mimo_core::ids::RadarId;
use mimo_core::params::{Fidelity, RadarParams};
use mimo_radar::dwell::{Dwell, DwellOutput, RangeWindow, Receiver, Target, Transmitter, evaluate};
use mimo_radar::equation::snr1;

pub const SEED: u64 = 20_261_122;

pub struct Ship {
    pub id: RadarId,
    pub site: Geodetic,
    pub faces: Vec<FaceFrame>,
}

impl Ship {
    pub fn new(id: u8, lat: f64, lon: f64, p: &RadarParams) -> Ship {
        let site = Geodetic::from_deg(lat, lon, 20.0);
        let faces = p
            .face_azimuths_deg
            .iter()
            .map(|a| FaceFrame::new(site, a.to_radians(), p.face_tilt_deg.to_radians()))
            .collect();
        Ship { id: RadarId(id), site, faces }
    }

    pub fn tx<'a>(&self, p: &'a RadarParams, face: usize, bu: f64, bv: f64, n_pulses: u32) -> Transmitter<'a> {
        Transmitter {
            radar: self.id,
            params: p,
            frame: self.faces[face],
            beam_u: bu,
            beam_v: bv,
            n_pulses,
            waveform: 0,
        }
    }

    #[allow(clippy::too_many_arguments)]
    pub fn rx<'a>(
        &self,
        p: &'a RadarParams,
        dwell_id: u64,
        face: usize,
        bu: f64,
        bv: f64,
        rho: (f64, f64),
    ) -> Receiver<'a> {
        Receiver {
            radar: self.id,
            dwell_id,
            params: p,
            face: face as u8,
            frame: self.faces[face],
            beam_u: bu,
            beam_v: bv,
            window: RangeWindow::Fixed { rho_min_m: rho.0, rho_max_m: rho.1 },
            predicted_snr: None,
        }
    }

    /// Evaluate one single-pulse monostatic dwell of face 0 steered at `beam` = (u, v), with
    /// stream keys `keys` (the first is also the receiver's dwell id) and the range window `rho` (m).
    pub fn monostatic_dwell(
        &self,
        p: &RadarParams,
        fid: &Fidelity,
        keys: &[u64],
        beam: (f64, f64),
        rho: (f64, f64),
        targets: &[Target],
    ) -> DwellOutput {
        let txs = [self.tx(p, 0, beam.0, beam.1, 1)];
        let rxs = [self.rx(p, keys.first().copied().unwrap_or(0), 0, beam.0, beam.1, rho)];
        let d = test_dwell(keys, &txs, &rxs, fid);
        evaluate(&d, targets)
    }

    /// A point at range `r` and direction `(u, v)` of a face.
    pub fn point(&self, face: usize, r: f64, u: f64, v: f64) -> DVec3 {
        self.faces[face].from_ruv(r, u, v)
    }
}

/// A dwell of run 0 at t = 0 with the tests' seed, recording no voltages and simulating the cells
/// near the returns only.
pub fn test_dwell<'a>(
    keys: &'a [u64],
    txs: &'a [Transmitter<'a>],
    rxs: &'a [Receiver<'a>],
    fid: &'a Fidelity,
) -> Dwell<'a> {
    Dwell {
        run: 0,
        t_s: 0.0,
        seed: SEED,
        keys,
        transmitters: txs,
        receivers: rxs,
        fidelity: fid,
        record_voltages: false,
        simulate_all_cells: false,
    }
}

/// RCS giving mean single-pulse SNR `snr` (linear) monostatic at range `r` with the beam at
/// boresight cosine `w` (on the beam peak).
pub fn rcs_for_snr(p: &RadarParams, snr: f64, r: f64, w: f64) -> f64 {
    snr / snr1(p, p, w, w, 1.0, r, r)
}

/// The default switches at the voltage level: these tests check the voltage model itself (the
/// other rungs are compared with it in tests/fidelity.rs).
pub fn fidelity() -> Fidelity {
    Fidelity { level: mimo_core::params::FidelityLevel::Voltage, ..Fidelity::default() }
}

/// Two-sided band `mean ± z·sd`.
pub fn within(x: f64, mean: f64, sd: f64, z: f64) -> bool {
    (x - mean).abs() <= z * sd
}
