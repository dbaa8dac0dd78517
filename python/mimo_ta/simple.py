"""A simple test article in Python: EKF + nearest neighbour, monostatic and MIMO dwells.

    mimo simulate --scenario 1 --ta-cmd "python3 -m mimo_ta simple" --out runs/s1-py
    mimo simulate --scenario 1 --ta-cmd "python3 python/examples/simple_ta.py" --out runs/s1-py   # in a checkout

The template to start from (docs/ta-protocol.md; the model in docs/model.md):

* tracks live in a fixed ENU frame at the scenario centre (§6.1); the state is
  [position, velocity], nearly-constant velocity with white-acceleration noise (DWNA,
  sigma_a = 15 m/s^2);
* every measurement of a dwell is (R_B, u, v) in its receiver face (§5.4); each channel (tx, rx)
  of a dwell is gated against every track at once (chi-square 99.9 %), then assigned nearest
  first (smallest d^2); the EKF update relinearizes while a track is young (§6.2);
* a detection of a search dwell, or of a dwell's monostatic channel, that gates no track starts
  a tentative track (one-point initiation: position from (R_B, u, v), velocity 0 +- 300 m/s);
  2 hits out of 3 looks confirm it, 2 misses drop it; a confirmed track is deleted after 3
  missed looks in a row, when its position is lost (covariance) or after 30 s without update
  (§6.4);
* each track is revisited when its predicted angular uncertainty reaches 0.2 beamwidth (at most
  every 4 s, §7.1), by the radar with the best predicted SNR, with pulses sized for P_D = 0.9
  (0.7 for a new tentative track) and doubled after each miss (§7.2); for a confirmed track
  every other radar that can see it receives the echo too (a MIMO dwell, §7.5);
* it emits a track row after every update and a ``deleted`` row when a track ends or the run
  finishes (docs/design.md §3).

Settings can be changed with ``--set key=value`` (e.g. ``--set sigma_a_mps2=20``).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass, field

import numpy as np

from .article import TestArticle
from .geo import EnuFrame, Ship
from .measurement import h, jacobian, ruv_to_position_cov, z_and_r_of
from .messages import DwellRequest, Subscription, TrackRow, TxOrder, upper_triangle
from .radar import pointing_loss, predict_pair, pulses_for, required_snr_sw1, straddle_loss

DEFAULTS = {
    "sigma_a_mps2": 15.0,  # process noise (DWNA), holds a 3 g turn (docs/model.md §6.1)
    "gate_chi2": 16.27,  # chi^2_3(0.999)
    "init_speed_sigma_mps": 300.0,  # velocity std of a new track, per axis
    "pd_target": 0.9,  # detection probability a track look is sized for (§7.2)
    "confirm_pd": 0.7,  # ... and a look at a tentative track not seen again yet
    "assumed_rcs_m2": 2.0,  # RCS assumed when sizing dwells
    "revisit_sharpness": 0.2,  # revisit when the angular std reaches this many beamwidths (§7.1)
    "tentative_revisit_s": 0.3,
    "miss_redwell_s": 0.05,
    "min_window_half_m": 1000.0,
    "max_misses": 3,  # consecutive missed looks that delete a confirmed track
    "max_coast_s": 30.0,  # confirmed track without update
    "max_coast_tentative_s": 5.0,
    "max_pos_var_m2": 3.0 * 3000.0**2,  # trace of the position covariance that deletes a track
    "mimo": 1.0,  # 1: confirmed tracks get MIMO dwells (all radars that see the target receive); 0: monostatic
}
REVISIT_CANDIDATES_S = np.arange(4.0, 0.2, -0.05)  # longest first
PENDING_TIMEOUT_S = 2.0  # a requested dwell not reported by then was rejected: plan again
I3 = np.eye(3)


def transition(dt: float, sigma_a: float) -> tuple[np.ndarray, np.ndarray]:
    """F and DWNA Q of the NCV model over ``dt`` (|dt| for the noise), docs/model.md §6.1."""
    f = np.eye(6)
    f[:3, 3:] = dt * I3
    t = abs(dt)
    return f, sigma_a**2 * np.kron([[t**4 / 4, t**3 / 2], [t**3 / 2, t**2]], I3)


@dataclass
class Track:
    id: int
    x: np.ndarray  # ENU state [p, v] at t_s
    p: np.ndarray  # 6x6 covariance
    t_s: float
    status: str = "tentative"
    n_updates: int = 1
    hits: list = field(default_factory=lambda: [True])  # look outcomes, for M-of-N
    misses_in_row: int = 0
    last_meas_id: int | None = None
    last_update_s: float = 0.0
    face_rot: np.ndarray | None = None  # ENU rotation of the face that last updated it
    face_origin: np.ndarray | None = None
    next_due_s: float = 0.0
    pending_since_s: float | None = None  # a dwell is requested and not reported yet
    updated: bool = False  # in the dwell being processed


class SimpleTa(TestArticle):
    name = "simple-ta (python)"
    subscription = Subscription(dwells="detections")

    def __init__(self) -> None:
        super().__init__()
        self.cfg = dict(DEFAULTS)
        self.tracks: dict[int, Track] = {}
        self.next_id = 1
        self.next_wake_s = math.inf

    def config(self) -> dict:
        return self.cfg

    # -- events ---------------------------------------------------------------------------------

    def on_start(self, start) -> None:
        for k, v in start.config.items():
            if k not in DEFAULTS:
                raise ValueError(f"unknown setting {k!r}; known: {sorted(DEFAULTS)}")
            self.cfg[k] = float(v)
        c = start.centre
        self.enu = EnuFrame.at(c.lat_deg, c.lon_deg, 0.0)
        self.ships = {s.radar: Ship.from_info(s, start.duration_s) for s in start.ships}
        self.params = {s.radar: s.radar_params for s in start.ships}
        self.tracks, self.next_id, self.next_wake_s = {}, 1, math.inf

    def on_dwell(self, report) -> None:
        for tid in report.tag:
            if tid in self.tracks:
                self.tracks[tid].pending_since_s = None
        live = [t for t in self.tracks.values() if t.t_s <= report.t_s + 1e-9]
        for t in live:
            t.updated = False
        parts = {p.radar: p for p in report.parts}
        channels: dict[tuple[str, str], list] = {}
        for m in report.measurements:
            channels.setdefault((m.tx, m.rx), []).append(m)
        initiators = []
        for (tx, rx), meas in sorted(channels.items()):
            if tx not in parts or rx not in parts:
                continue
            left = self.associate(report.t_s, parts[tx], parts[rx], meas, live)
            if report.kind == "search" or tx == rx:
                initiators += [(m, parts[tx], parts[rx]) for m in left]
        for m, ptx, prx in sorted(initiators, key=lambda x: -x[0].snr_db):
            self.initiate(report.t_s, m, ptx, prx)
        # A look aimed at a track that did not update it is a miss (docs/model.md §6.7).
        if report.requested_by == "ta":
            for tid in report.tag:
                t = self.tracks.get(tid)
                if t is not None and not t.updated and t.t_s <= report.t_s + 1e-9:
                    self.missed(t, report.end_s)
        self.maintain(report.end_s)
        if report.measurements or report.tag:
            self.schedule(report.end_s)

    def on_wake(self, t_s: float) -> None:
        if t_s + 1e-9 >= self.next_wake_s:
            self.next_wake_s = math.inf
        self.maintain(t_s)
        self.schedule(t_s)

    def on_finish(self, t_s: float) -> None:
        for t in list(self.tracks.values()):
            self.delete(t, t_s)

    # -- tracking -------------------------------------------------------------------------------

    def face_in_enu(self, part) -> tuple[np.ndarray, np.ndarray]:
        """A dwell part's face (origin, rotation) in the tracking frame."""
        return self.enu.to_enu(part.site_ecef), part.face_from_ecef @ self.enu.enu_from_ecef.T

    def predict(self, t: Track, t_s: float) -> tuple[np.ndarray, np.ndarray]:
        f, q = transition(t_s - t.t_s, self.cfg["sigma_a_mps2"])
        return f @ t.x, f @ t.p @ f.T + q

    def associate(self, t_s, ptx, prx, meas, live) -> list:
        """Gate every track against the channel's measurements at once, update nearest first;
        return the measurements no track took."""
        tx_pos = self.enu.to_enu(ptx.site_ecef)
        rx_origin, rx_rot = self.face_in_enu(prx)
        zs, rs = zip(*(self.z_and_r(m, prx) for m in meas))
        z, r = np.array(zs), np.array(rs)  # (M, 3), (M, 3, 3)
        cands = live  # a track takes at most one measurement per channel
        if not cands:
            return list(meas)
        preds = [self.predict(t, t_s) for t in cands]
        xp = np.array([x for x, _ in preds])  # (N, 6)
        pp = np.array([p for _, p in preds])  # (N, 6, 6)
        zp = h(xp[:, :3], tx_pos, rx_origin, rx_rot)  # (N, 3)
        hp = jacobian(xp[:, :3], tx_pos, rx_origin, rx_rot)  # (N, 3, 3): position columns
        s_pos = hp @ pp[:, :3, :3] @ hp.transpose(0, 2, 1)  # (N, 3, 3)
        s = s_pos[:, None] + r[None]  # (N, M, 3, 3)
        nu = z[None] - zp[:, None]  # (N, M, 3)
        d2 = np.einsum("nmi,nmi->nm", nu, np.linalg.solve(s, nu[..., None])[..., 0])
        taken, used = set(), set()
        for k in np.argsort(d2, axis=None):
            n, m = divmod(int(k), len(meas))
            if d2[n, m] > self.cfg["gate_chi2"]:
                break
            if n in taken or m in used:
                continue
            taken.add(n)
            used.add(m)
            self.update(cands[n], xp[n], pp[n], meas[m], z[m], r[m], t_s, tx_pos, rx_origin, rx_rot)
        gated = (d2 <= self.cfg["gate_chi2"]).any(axis=0)
        return [m for i, m in enumerate(meas) if i not in used and not gated[i]]

    def z_and_r(self, m, prx):
        z, r = z_and_r_of(m)
        if m.merged:  # may hold two unresolved targets: inflate (docs/model.md §6.5)
            theta = self.params[prx.radar].beamwidth_u
            r = r + np.diag([4.0 * 15.0**2, (theta / 4) ** 2, (theta / 4) ** 2])
        return z, r

    def update(self, t, x, p, m, z, r, t_s, tx_pos, rx_origin, rx_rot) -> None:
        """EKF update, iterated while the track is young (docs/model.md §6.2), Joseph form."""
        xi = x
        for _ in range(3 if t.n_updates < 3 else 1):
            hm = np.zeros((3, 6))
            hm[:, :3] = jacobian(xi[:3], tx_pos, rx_origin, rx_rot)
            s = hm @ p @ hm.T + r
            k = np.linalg.solve(s, hm @ p).T
            nu = z - h(xi[:3], tx_pos, rx_origin, rx_rot) - hm @ (x - xi)
            xi = x + k @ nu
        ikh = np.eye(6) - k @ hm
        t.x, t.p = xi, ikh @ p @ ikh.T + k @ r @ k.T
        t.p = 0.5 * (t.p + t.p.T)
        t.t_s = t.last_update_s = t_s
        t.n_updates += 1
        t.last_meas_id = m.meas_id
        t.face_origin, t.face_rot = rx_origin, rx_rot
        t.updated = True
        t.misses_in_row = 0
        if t.status == "tentative":
            t.hits.append(True)
            if sum(t.hits[-3:]) >= 2:
                t.status = "confirmed"
        t.next_due_s = t_s + self.revisit_interval(t)
        self.emit(t, t.status)

    def initiate(self, t_s, m, ptx, prx) -> None:
        """One-point initiation (docs/model.md §6.4), unless a track started in this dwell gates it."""
        tx_pos = self.enu.to_enu(ptx.site_ecef)
        rx_origin, rx_rot = self.face_in_enu(prx)
        z, r = self.z_and_r(m, prx)
        for t in self.tracks.values():
            if t.n_updates == 1 and t.t_s == t_s:  # started in this dwell
                hm = jacobian(t.x[:3], tx_pos, rx_origin, rx_rot)
                nu = z - h(t.x[:3], tx_pos, rx_origin, rx_rot)
                if nu @ np.linalg.solve(hm @ t.p[:3, :3] @ hm.T + r, nu) <= self.cfg["gate_chi2"]:
                    return
        pc = ruv_to_position_cov(z[0], z[1], z[2], r, tx_pos, rx_origin, rx_rot)
        if pc is None:
            return
        pos, cov = pc
        p = np.zeros((6, 6))
        p[:3, :3] = cov
        p[3:, 3:] = self.cfg["init_speed_sigma_mps"] ** 2 * I3
        t = Track(self.next_id, np.concatenate([pos, np.zeros(3)]), p, t_s, last_meas_id=m.meas_id,
                  last_update_s=t_s, face_origin=rx_origin, face_rot=rx_rot)
        t.next_due_s = t_s + self.cfg["tentative_revisit_s"]
        t.updated = True
        self.next_id += 1
        self.tracks[t.id] = t
        self.emit(t, "tentative")

    def missed(self, t: Track, now_s: float) -> None:
        t.misses_in_row += 1
        if t.status == "tentative":
            t.hits.append(False)
            if len(t.hits) >= 3 and sum(t.hits[-3:]) < 2 or t.hits[-2:] == [False, False]:
                self.delete(t, now_s)
                return
            t.next_due_s = now_s + self.cfg["tentative_revisit_s"]
        elif t.misses_in_row >= self.cfg["max_misses"]:
            self.delete(t, now_s)
            return
        else:
            t.next_due_s = now_s + self.cfg["miss_redwell_s"]

    def maintain(self, now_s: float) -> None:
        """Deletion by coasting time and lost position (docs/model.md §6.4)."""
        for t in list(self.tracks.values()):
            coast = self.cfg["max_coast_s"] if t.status == "confirmed" else self.cfg["max_coast_tentative_s"]
            if now_s - t.last_update_s > coast:
                self.delete(t, now_s)
            elif self.predicted_position_variance(t, now_s) > self.cfg["max_pos_var_m2"]:
                self.delete(t, now_s)

    def predicted_position_variance(self, t: Track, t_s: float) -> float:
        """Trace of the predicted position covariance (the position block of F P F^T + Q)."""
        dt = t_s - t.t_s
        p = t.p
        return float(np.trace(p[:3, :3]) + 2 * dt * np.trace(p[:3, 3:]) + dt**2 * np.trace(p[3:, 3:])
                     + 3 * self.cfg["sigma_a_mps2"] ** 2 * dt**4 / 4)

    def delete(self, t: Track, now_s: float) -> None:
        x, p = self.predict(t, max(now_s, t.t_s))
        t.x, t.p, t.t_s = x, p, max(now_s, t.t_s)
        self.emit(t, "deleted")
        del self.tracks[t.id]

    def emit(self, t: Track, status: str) -> None:
        """A tracks-table row: the state and covariance rotated back to ECEF."""
        rot = self.enu.enu_from_ecef.T  # ENU -> ECEF
        big = np.zeros((6, 6))
        big[:3, :3] = big[3:, 3:] = rot
        pos = self.enu.to_ecef(t.x[:3])
        vel = rot @ t.x[3:]
        self.emit_track(TrackRow(t.t_s, t.id, status, *pos, *vel, upper_triangle(big @ t.p @ big.T), t.n_updates,
                                 t.last_meas_id))

    def revisit_interval(self, t: Track) -> float:
        """Largest interval (<= 4 s) at which the predicted angular std in the face that last
        updated the track stays below ``revisit_sharpness`` beamwidths (docs/model.md §7.1)."""
        if t.status != "confirmed":
            return self.cfg["tentative_revisit_s"]
        theta = next(iter(self.params.values())).beamwidth_u
        limit = (self.cfg["revisit_sharpness"] * theta) ** 2
        j = jacobian(t.x[:3], t.face_origin, t.face_origin, t.face_rot)[1:]  # (2, 3): u, v rows
        q = self.cfg["sigma_a_mps2"] ** 2
        T = REVISIT_CANDIDATES_S[:, None, None]
        pp, pv, vv = t.p[:3, :3], t.p[:3, 3:], t.p[3:, 3:]
        # Position block of F P F^T + Q for every candidate T at once.
        ppos = pp + T * (pv + pv.T) + T**2 * vv + q * T**4 / 4 * I3
        puv = j @ ppos @ j.T
        tr, det = puv[:, 0, 0] + puv[:, 1, 1], np.linalg.det(puv)
        lam_max = tr / 2 + np.sqrt(np.maximum(tr**2 / 4 - det, 0.0))
        ok = np.nonzero(lam_max <= limit)[0]
        return float(REVISIT_CANDIDATES_S[ok[0]]) if len(ok) else float(REVISIT_CANDIDATES_S[-1])

    # -- scheduling -----------------------------------------------------------------------------

    def schedule(self, now_s: float) -> None:
        """A dwell for every due track, and a wake-up for the next one."""
        if not self.start.closed_loop:
            return
        nxt = math.inf
        for t in self.tracks.values():
            if t.pending_since_s is not None:
                if now_s - t.pending_since_s < PENDING_TIMEOUT_S:
                    nxt = min(nxt, t.pending_since_s + PENDING_TIMEOUT_S)
                    continue
                t.pending_since_s = None
            if t.next_due_s <= now_s + 1e-9:
                if self.plan(t, now_s):
                    t.pending_since_s = now_s
                    nxt = min(nxt, now_s + PENDING_TIMEOUT_S)
                else:
                    t.next_due_s = now_s + 1.0  # nobody can see it now: try later
                    nxt = min(nxt, t.next_due_s)
            else:
                nxt = min(nxt, t.next_due_s)
        if math.isfinite(nxt) and nxt < self.start.duration_s and (nxt < self.next_wake_s - 1e-9
                                                                   or self.next_wake_s <= now_s):
            self.next_wake_s = nxt
            self.wake_at(max(nxt, now_s))

    def plan(self, t: Track, now_s: float) -> bool:
        """Request one dwell at the track: the radar with the best predicted SNR transmits, with
        pulses for the wanted P_D with pointing and straddle losses (docs/model.md §7.2)."""
        x, p = self.predict(t, now_s)
        aim = self.enu.to_ecef(x[:3])
        best = None
        for radar, ship in self.ships.items():
            par = self.params[radar]
            faces = ship.faces_sampled(now_s)
            pr = predict_pair(par, faces, par, faces, aim, self.cfg["assumed_rcs_m2"])
            if pr is not None and (best is None or pr[0] > best[1]):
                best = (radar, pr[0])
        if best is None:
            return False
        radar, snr1 = best
        par = self.params[radar]
        receivers = [radar]
        if self.cfg["mimo"] and t.status == "confirmed":
            # Every other radar that can see the target listens too (docs/model.md §7.5): their
            # bistatic ranges pin down the cross-range position a single radar measures poorly.
            tx_faces = self.ships[radar].faces_sampled(now_s)
            for other, ship in self.ships.items():
                if other != radar and predict_pair(par, tx_faces, self.params[other], ship.faces_sampled(now_s), aim,
                                                   self.cfg["assumed_rcs_m2"]) is not None:
                    receivers.append(other)
        fresh = t.status == "tentative" and t.n_updates <= 1
        pd = self.cfg["confirm_pd"] if fresh else self.cfg["pd_target"]
        n = pulses_for(required_snr_sw1(pd, par.pfa), snr1, pointing_loss(0.2) * straddle_loss(), par.max_pulses)
        if not fresh:
            n = min(n * 2 ** (t.misses_in_row % 3), par.max_pulses)
        site = self.enu.to_enu(self.ships[radar].site_sampled(now_s))
        hr = np.zeros(6)
        hr[:3] = jacobian(x[:3], site, site, I3)[0]
        sigma_rho = 0.5 * math.sqrt(max(hr @ p @ hr, 0.0))
        self.request_dwell(DwellRequest(
            kind="confirm" if t.status == "tentative" else ("mimo" if len(receivers) > 1 else "track"),
            earliest_s=now_s,
            aim_ecef=aim,
            transmitters=[TxOrder(radar, n)],
            receivers=receivers,
            window_half_m=max(5.0 * sigma_rho, self.cfg["min_window_half_m"]),
            predicted_snr=snr1 * n if len(receivers) == 1 else None,
            tag=[t.id],
        ))
        return True


if __name__ == "__main__":
    sys.exit(SimpleTa().run())
