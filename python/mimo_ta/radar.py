"""Radar parameters, the radar equation and dwell sizing (docs/model.md §1.5, §1.6, §3, §4.3,
§7.2), mirroring ``crates/mimo-radar/src/equation.rs`` and ``energy.rs`` so a test article can
size its dwells as the default one does.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from .geo import FaceFrame, ecef_to_geodetic_rad, visible_effective_earth

SPEED_OF_LIGHT_MPS = 299_792_458.0
BOLTZMANN_J_PER_K = 1.380_649e-23
T0_K = 290.0
MAX_BISTATIC_ANGLE_DEG = 150.0
"""Pairs with a larger bistatic angle are not used (docs/model.md §5.1)."""


def db_to_lin(db: float) -> float:
    return 10.0 ** (db / 10.0)


def lin_to_db(x: float) -> float:
    return 10.0 * math.log10(x)


@dataclass
class RadarParams:
    """A radar's parameters as the ``start`` event sends them (SI units; defaults of §3.3)."""

    frequency_hz: float = 3.3e9
    aperture_x_m: float = 3.6
    aperture_y_m: float = 3.6
    aperture_efficiency: float = 0.8
    beamwidth_factor: float = 1.0
    scan_loss_exponent: float = 1.5
    max_scan_deg: float = 60.0
    monopulse_slope: float = 1.6
    face_azimuths_deg: list = field(default_factory=lambda: [45.0, 135.0, 225.0, 315.0])
    face_tilt_deg: float = 15.0
    peak_power_w: float = 100e3
    pulse_width_s: float = 10e-6
    bandwidth_hz: float = 5e6
    prf_hz: float = 300.0
    max_pulses: int = 16
    noise_figure_db: float = 4.0
    loss_db: float = 5.0
    pfa: float = 1e-6
    instrumented_range_m: float = 450e3
    min_range_m: float = 2e3
    dwell_overhead_s: float = 1e-3

    @staticmethod
    def from_dict(d: dict) -> "RadarParams":
        """From the ``params`` object of a ship (unknown keys are ignored, missing ones default)."""
        names = {f.name for f in dataclasses.fields(RadarParams)}
        return RadarParams(**{k: v for k, v in d.items() if k in names})

    @property
    def wavelength_m(self) -> float:
        return SPEED_OF_LIGHT_MPS / self.frequency_hz

    @property
    def beamwidth_u(self) -> float:
        """Sine-space half-power beamwidth along u (§2.1)."""
        return self.beamwidth_factor * self.wavelength_m / self.aperture_x_m

    @property
    def beamwidth_v(self) -> float:
        return self.beamwidth_factor * self.wavelength_m / self.aperture_y_m

    @property
    def peak_gain(self) -> float:
        """G0 = 4 pi eta Dx Dy / lambda^2 (linear)."""
        lam = self.wavelength_m
        return 4.0 * math.pi * self.aperture_efficiency * self.aperture_x_m * self.aperture_y_m / (lam * lam)

    @property
    def min_scan_w(self) -> float:
        """Smallest boresight cosine a beam may be steered to (§1.5)."""
        return math.cos(math.radians(self.max_scan_deg))

    @property
    def range_cell_m(self) -> float:
        return SPEED_OF_LIGHT_MPS / (2.0 * self.bandwidth_hz)

    def scan_gain(self, w: float) -> float:
        """Steered one-way gain G0 w^alpha (§1.6); 0 behind the face."""
        return self.peak_gain * (w ** self.scan_loss_exponent if w > 0.0 else 0.0)

    def dwell_duration_s(self, n_pulses: int) -> float:
        """Time a dwell occupies the radar (§7.3)."""
        return n_pulses / self.prf_hz + self.dwell_overhead_s

    def dwell_energy_j(self, n_pulses: int) -> float:
        return self.peak_power_w * self.pulse_width_s * n_pulses


def snr1(tx: RadarParams, rx: RadarParams, w_tx: float, w_rx: float, rcs_m2: float, r_t_m: float,
         r_r_m: float) -> float:
    """Single-pulse mean SNR (linear) of a Tx-Rx pair, beams on the target (§3.1)."""
    lam = tx.wavelength_m
    loss = db_to_lin(0.5 * (tx.loss_db + rx.loss_db))
    t_sys = T0_K * db_to_lin(rx.noise_figure_db)
    num = tx.peak_power_w * tx.scan_gain(w_tx) * rx.scan_gain(w_rx) * lam * lam * rcs_m2 * tx.pulse_width_s
    return num / ((4.0 * math.pi) ** 3 * r_t_m ** 2 * r_r_m ** 2 * BOLTZMANN_J_PER_K * t_sys * loss)


def required_snr_sw1(pd: float, pfa: float) -> float:
    """Mean SNR (linear) for detection probability ``pd`` at ``pfa``, SW1, one coherent sample
    (§4.3): ln P_FA / ln P_D - 1 (21.1 dB for 0.9 at 1e-6)."""
    pd = min(max(pd, 1e-12), 1.0 - 1e-12)
    return max(math.log(pfa) / math.log(pd) - 1.0, 0.0)


def pd_sw1(snr: float, pfa: float) -> float:
    """SW1 detection probability at mean SNR ``snr``: P_FA^(1/(1+SNR))."""
    return pfa ** (1.0 / (1.0 + max(snr, 0.0)))


def pointing_loss(v0: float = 0.2) -> float:
    """Expected monostatic pointing loss of model A for errors of ``v0`` beamwidths per axis
    (§7.2): 1 + 16 ln2 v0^2 (1.6 dB at 0.2)."""
    return 1.0 + 16.0 * math.log(2.0) * v0 * v0


def straddle_loss() -> float:
    """Mean straddle loss (linear), 2.66 dB (§4.1)."""
    ln_half = math.log(0.5)
    db = -(20.0 / math.log(10.0)) * 2.0 * ((0.0 - 1.0) - (0.5 * ln_half - 0.5))
    return db_to_lin(db)


def pulses_for(snr_required: float, snr1_lin: float, losses: float, max_pulses: int) -> int:
    """Pulses to reach ``snr_required`` given the single-pulse SNR and the losses, clipped to
    ``[1, max_pulses]`` (§7.2)."""
    top = max(int(max_pulses), 1)
    if not (snr1_lin > 0.0 and math.isfinite(snr1_lin) and math.isfinite(snr_required)):
        return top
    n = math.ceil(snr_required * max(losses, 1.0) / snr1_lin)
    return min(max(n, 1), top)


def beam_point(faces: list[FaceFrame], params: RadarParams, aim_ecef):
    """The face that sees ``aim_ecef`` at the smallest scan angle, if within the scan limit
    (§1.5): ``(face_index, u, v, w, range_m)`` or ``None``."""
    best = None
    for i, f in enumerate(faces):
        s = f.to_sine(aim_ecef)
        if math.isfinite(s.w) and (best is None or s.w > best[3]):
            best = (i, s.u, s.v, s.w, s.range_m)
    if best is None or best[3] < params.min_scan_w - 1e-12:
        return None
    return best


def visible(site_ecef, p_ecef) -> bool:
    """4/3-earth visibility, heights from the ECEF positions (§1.7)."""
    return visible_effective_earth(site_ecef, ecef_to_geodetic_rad(site_ecef)[2], p_ecef,
                                   ecef_to_geodetic_rad(p_ecef)[2])


def predict_pair(tx: RadarParams, tx_faces, rx: RadarParams, rx_faces, p_ecef, rcs_m2: float):
    """Predicted single-pulse SNR of a Tx->Rx look at ``p_ecef`` with both beams on it:
    ``(snr1, tx_face, rx_face)``, or ``None`` outside a scan limit, below a horizon or beyond a
    150 deg bistatic angle (as ``mimo_radar::energy::predict_pair``). Monostatic: the same
    radar twice."""
    bt = beam_point(tx_faces, tx, p_ecef)
    br = beam_point(rx_faces, rx, p_ecef)
    if bt is None or br is None:
        return None
    t = tx_faces[bt[0]].origin_ecef
    r = rx_faces[br[0]].origin_ecef
    p = np.asarray(p_ecef, dtype=float)
    a, b = t - p, r - p
    la, lb = float(np.linalg.norm(a)), float(np.linalg.norm(b))
    beta = math.acos(max(-1.0, min(1.0, float(a @ b) / (la * lb)))) if la > 0 and lb > 0 else 0.0
    if beta > math.radians(MAX_BISTATIC_ANGLE_DEG) or not visible(t, p):
        return None
    if not np.array_equal(r, t) and not visible(r, p):
        return None
    return snr1(tx, rx, bt[3], br[3], rcs_m2, la, lb), bt[0], br[0]
