"""Scheduling looks as the default test article does (docs/model.md §5.2, §6.7, §7.1, §7.2, §7.5).

* :func:`revisit_interval_s` — the covariance-based revisit of §7.1: the largest interval in
  ``[t_min_s, t_max_s]`` (0.25-2 s in the built-in test articles) at which the predicted position
  covariance, seen in the sine space of the face that last updated the track, keeps its largest
  standard deviation below ``v0`` beamwidths (0.2), found by bisection to 1 ms.
* :class:`LookPlanner` — one dwell for a track (§7.2, §7.5): the radar with the best predicted
  monostatic SNR transmits, pulses sized for the wanted P_D with the expected pointing and
  straddle losses for an assumed 2 m^2, doubled after each miss (``N 2^(m mod 3)``, at most
  ``max_pulses``); a confirmed track gets every other radar that can see it as a receiver (a
  ``mimo`` dwell); the range window is ``max(5 sigma_rho, 1 km)``.
* :func:`in_beam` — whether a point lies in a dwell part's beam (§6.7: a look counts when the
  prediction is within half a beamwidth of the beam centre, in front of the face).

Numpy only: any test article may use them.
"""

from __future__ import annotations

import math
from typing import Callable, Optional

import numpy as np

from .geo import Ship
from .messages import DwellRequest, TxOrder
from .radar import RadarParams, pointing_loss, predict_pair, pulses_for, required_snr_sw1, straddle_loss


def revisit_interval_s(pos_cov_at: Callable[[float], np.ndarray], j_uv: np.ndarray, beamwidth: float,
                       v0: float = 0.2, t_min_s: float = 0.25, t_max_s: float = 2.0, tol_s: float = 1e-3) -> float:
    """The largest ``T`` in ``[t_min_s, t_max_s]`` with ``sqrt(lambda_max(J P(T) J^T)) <= v0 *
    beamwidth``, where ``pos_cov_at(T)`` is the predicted 3x3 position covariance ``T`` seconds
    after the last update and ``j_uv`` the (2, 3) rows ``d(u, v)/dp`` of the face that made it
    (any frame, as long as both agree). ``t_min_s`` if even that is too late."""
    limit = (v0 * beamwidth) ** 2

    def sharp(t_s: float) -> bool:
        puv = j_uv @ pos_cov_at(t_s) @ j_uv.T
        tr = puv[0, 0] + puv[1, 1]
        det = puv[0, 0] * puv[1, 1] - puv[0, 1] * puv[1, 0]
        return tr / 2 + math.sqrt(max(tr * tr / 4 - det, 0.0)) <= limit

    if sharp(t_max_s):
        return t_max_s
    if not sharp(t_min_s):
        return t_min_s
    lo, hi = t_min_s, t_max_s
    while hi - lo > tol_s:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if sharp(mid) else (lo, mid)
    return lo


def in_beam(part, p_ecef, beamwidth: float, fraction: float = 0.5) -> bool:
    """Whether ``p_ecef`` is in front of the part's face and within ``fraction`` beamwidths of
    its beam centre ``(beam_u, beam_v)`` (docs/model.md §6.7)."""
    l = part.face_from_ecef @ (np.asarray(p_ecef, dtype=float) - part.site_ecef)
    r = float(np.linalg.norm(l))
    if not (r > 0.0 and l[2] > 0.0):
        return False
    du, dv = l[0] / r - part.beam_u, l[1] / r - part.beam_v
    return du * du + dv * dv <= (fraction * beamwidth) ** 2


class LookPlanner:
    """Plans one dwell at a predicted position, as the default test article (§7.2, §7.5).

    ``ships`` and ``params`` map each radar to its :class:`mimo_ta.geo.Ship` and
    :class:`mimo_ta.radar.RadarParams` (from the ``start`` event)."""

    def __init__(self, ships: dict, params: dict, *, pd_target: float = 0.9, confirm_pd: float = 0.9,
                 assumed_rcs_m2: float = 2.0, min_window_half_m: float = 1000.0, mimo: bool = True,
                 pointing_v0: float = 0.2) -> None:
        self.ships: dict[str, Ship] = ships
        self.params: dict[str, RadarParams] = params
        self.pd_target = pd_target
        self.confirm_pd = confirm_pd
        self.assumed_rcs_m2 = assumed_rcs_m2
        self.min_window_half_m = min_window_half_m
        self.mimo = mimo
        self.losses = pointing_loss(pointing_v0) * straddle_loss()

    @staticmethod
    def from_start(start, **kwargs) -> "LookPlanner":
        ships = {s.radar: Ship.from_info(s, start.duration_s) for s in start.ships}
        return LookPlanner(ships, {s.radar: s.radar_params for s in start.ships}, **kwargs)

    def best_transmitter(self, aim_ecef, now_s: float) -> Optional[tuple[str, float]]:
        """The radar with the best predicted single-pulse SNR of its monostatic look (ties by
        radar id), with that SNR; ``None`` if no radar can see the point."""
        best = None
        for radar in sorted(self.ships):
            par = self.params[radar]
            faces = self.ships[radar].faces_sampled(now_s)
            pr = predict_pair(par, faces, par, faces, aim_ecef, self.assumed_rcs_m2)
            if pr is not None and (best is None or pr[0] > best[1]):
                best = (radar, pr[0])
        return best

    def receivers(self, tx: str, aim_ecef, now_s: float) -> list:
        """The transmitter, then every other radar whose pair prediction succeeds (§7.5)."""
        par = self.params[tx]
        tx_faces = self.ships[tx].faces_sampled(now_s)
        out = [tx]
        for other in sorted(self.ships):
            if other != tx and predict_pair(par, tx_faces, self.params[other], self.ships[other].faces_sampled(now_s),
                                            aim_ecef, self.assumed_rcs_m2) is not None:
                out.append(other)
        return out

    def plan(self, aim_ecef, pos_cov_ecef, now_s: float, *, confirmed: bool, fresh: bool, misses: int,
             tag: list) -> Optional[DwellRequest]:
        """A dwell at ``aim_ecef`` (predicted position, covariance ``pos_cov_ecef``), or ``None``
        when no radar can see it. ``fresh``: a tentative track not seen again since initiation
        (sized for ``confirm_pd``, never doubled); ``misses``: consecutive missed looks."""
        best = self.best_transmitter(aim_ecef, now_s)
        if best is None:
            return None
        radar, snr1 = best
        par = self.params[radar]
        rx = self.receivers(radar, aim_ecef, now_s) if (self.mimo and confirmed) else [radar]
        pd = self.confirm_pd if fresh else self.pd_target
        n = pulses_for(required_snr_sw1(pd, par.pfa), snr1, self.losses, par.max_pulses)
        if not fresh:
            n = min(n * 2 ** (int(misses) % 3), par.max_pulses)
        site = self.ships[radar].site_sampled(now_s)
        d = np.asarray(aim_ecef, dtype=float) - site
        h = d / np.linalg.norm(d)  # d rho / dp of the monostatic channel is h (rho = R_B / 2)
        sigma_rho = math.sqrt(max(float(h @ np.asarray(pos_cov_ecef) @ h), 0.0))
        kind = "confirm" if not confirmed else ("mimo" if len(rx) > 1 else "track")
        return DwellRequest(kind=kind, earliest_s=now_s, aim_ecef=np.asarray(aim_ecef, dtype=float),
                            transmitters=[TxOrder(radar, n)], receivers=rx,
                            window_half_m=max(5.0 * sigma_rho, self.min_window_half_m),
                            predicted_snr=snr1 * n if len(rx) == 1 else None, tag=list(tag))
