"""A closed-loop test article made of Stone Soup components (docs/ta-protocol.md).

:class:`StoneSoupArticle` feeds each dwell's measurements to a Stone Soup tracker as
:class:`~stonesoup.types.detection.Detection` objects at the dwell's mid-time, each with its own
:class:`~mimo_ta.stonesoup.model.MimoBistaticModel` (the channel's transmitter, receiver face and
reported covariance), and schedules the looks with :mod:`mimo_ta.looks`.

Per dwell, channel by channel (tx, rx) in a fixed order (docs/model.md §6.5):

* the data associator is given the confirmed tracks the channel could have seen: prediction in
  front of the receive face, within ``assoc_beam_fraction`` beamwidths of the transmit and
  receive beam centres and, for a test-article dwell, inside the range window it asked for;
* a track updated by any channel is a hit; a track inside half a beamwidth of a test-article
  dwell's beam (§6.7) that no channel updated is a miss and gets its prediction appended; every
  other track is left alone (a dwell that cannot have seen a track does not give it a miss);
* the detections no track took, from search dwells and from monostatic channels (§6.4), go to
  the initiator. A multi-measurement initiator's holding tracks are restricted the same way:
  those in the beam of a test-article dwell, and those that gate one of the detections.

After each dwell the deleter is run over the tracks the dwell gave a state, and at least once a
simulated second (``deleter_sweep_s``) over every track (with ``timestamp``, so time-based
deleters see coasting) and the initiator's deleter over its holding tracks. Rows:
``confirmed`` after each dwell that updated a track (and when the initiator releases it),
``deleted`` (the prediction at that time) when the deleter drops it or the run ends. Tentative
(holding) tracks are not written.

A Stone Soup component that raises, or a state that is not finite, is a :class:`TrackerFault`:
``run`` logs one line and returns 1, so ``mimo`` stops the run through the protocol's fault path.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any, Callable, Optional

import numpy as np
from stonesoup.types.detection import Detection

from ..article import TestArticle
from ..geo import EnuFrame
from ..looks import LookPlanner, in_beam, revisit_interval_s
from ..covariance import CovarianceError, checked_covariance
from ..messages import Subscription, TrackRow, upper_triangle
from .model import MimoBistaticModel

EPOCH = datetime(2000, 1, 1)
"""Stone Soup time of the scenario's t = 0."""
POS = [0, 2, 4]
VEL = [1, 3, 5]
PENDING_TIMEOUT_S = 2.0
TAG_TRACK, TAG_HOLDING = 1, 2

SETTINGS = {
    "pd_target": 0.9,  # P_D a track look is sized for (docs/model.md §7.2)
    "confirm_pd": 0.9,  # ... and a confirmation look
    "assumed_rcs_m2": 2.0,
    "revisit_v0": 0.2,  # revisit when the angular std reaches this many beamwidths (§7.1)
    "revisit_t_min_s": 0.25,
    "revisit_t_max_s": 2.0,
    "tentative_revisit_s": 0.3,
    "miss_redwell_s": 0.05,
    "min_window_half_m": 1000.0,
    "mimo": 1.0,  # 1: confirmed tracks get MIMO dwells
    "look_beam_fraction": 0.5,  # a look counts within this many beamwidths (§6.7)
    "assoc_beam_fraction": 1.0,  # tracks offered to the associator
    "gate_chi2": 16.27,  # holding tracks offered to the initiator: chi^2_3(0.999)
    "merged_range_sigma_m": 15.0,  # added to a merged measurement (§6.5), with a quarter beamwidth
    "deleter_sweep_s": 1.0,  # every track goes through the deleter at least this often
}


class TrackerFault(RuntimeError):
    """A Stone Soup component raised, or produced a state that is not finite."""


def stamp(t_s: float) -> datetime:
    """The Stone Soup timestamp of a scenario time."""
    return EPOCH + timedelta(seconds=float(t_s))


@dataclass
class Components:
    """The Stone Soup parts of a tracker."""

    predictor: Any
    updater: Any
    data_associator: Any
    initiator: Any
    deleter: Any
    hypothesiser: Any = None

    @staticmethod
    def of_tracker(tracker) -> "Components":
        """The parts of a ready ``MultiTargetTracker`` (its detector is not used)."""
        hyp = tracker.data_associator.hypothesiser
        return Components(hyp.predictor, tracker.updater, tracker.data_associator, tracker.initiator,
                          tracker.deleter, hyp)


@dataclass
class Book:
    """What the article keeps about a track besides its Stone Soup states."""

    id: int
    t_s: float  # time of the last state written (rows must not go back in time)
    next_due_s: float
    misses_in_row: int = 0
    pending_since_s: Optional[float] = None
    last_meas_id: Optional[int] = None
    face: Optional[tuple] = None  # (origin, rotation, beamwidth) in the frame, of the last update


class StoneSoupArticle(TestArticle):
    """A :class:`mimo_ta.TestArticle` running Stone Soup components.

    Give the components (``predictor``, ``updater``, ``data_associator`` — whose hypothesiser
    holds the predictor and updater —, ``initiator``, ``deleter``), or a ready
    ``MultiTargetTracker`` as ``tracker``, or a ``factory(settings) -> Components`` called at
    the start of each run with the settings (``defaults`` merged with ``--set`` overrides) so
    that those can be tuned from the command line and studies."""

    subscription = Subscription(dwells="detections")

    def __init__(self, predictor=None, updater=None, data_associator=None, initiator=None, deleter=None, *,
                 hypothesiser=None, tracker=None, factory: Optional[Callable[[dict], Components]] = None,
                 defaults: Optional[dict] = None, name: str = "stonesoup") -> None:
        super().__init__()
        self.name = name
        self.factory = factory
        self.defaults = {**SETTINGS, **(defaults or {})}
        self.cfg = dict(self.defaults)
        if tracker is not None:
            self.c = Components.of_tracker(tracker)
        elif factory is None:
            if None in (predictor, updater, data_associator, initiator, deleter):
                raise ValueError("give predictor, updater, data_associator, initiator and deleter, a tracker, "
                                 "or a factory")
            self.c = Components(predictor, updater, data_associator, initiator, deleter, hypothesiser)
        self.tracks: dict = {}
        self.ids: dict = {}  # id(track) -> track number
        self.books: dict = {}
        self.holding: dict = {}  # holding track -> Book (tentative tracks inside the initiator)
        self.windows: dict = {}
        self.next_wake_s = math.inf

    def config(self) -> dict:
        return self.cfg

    # -- faults ---------------------------------------------------------------------------------

    def call(self, what: str, fn, *args, **kwargs):
        """Call a Stone Soup component; what it raises becomes a :class:`TrackerFault`."""
        try:
            return fn(*args, **kwargs)
        except Exception as e:  # noqa: BLE001 - any failure of the tracker under test
            raise TrackerFault(f"{what} raised {type(e).__name__}: {e} (t = {self.now_s:.6f} s)") from e

    def finite(self, state, what: str):
        sv = np.asarray(state.state_vector, dtype=float)
        cv = np.asarray(state.covar, dtype=float)
        if not (np.isfinite(sv).all() and np.isfinite(cv).all()):
            raise TrackerFault(f"{what} returned a non-finite state (t = {self.now_s:.6f} s)")
        return state

    def run(self, stdin=None, stdout=None) -> int:
        try:
            return super().run(stdin, stdout)
        except TrackerFault as e:
            self.log(f"{self.name}: the Stone Soup tracker failed: {e}")
            return 1

    # -- events ---------------------------------------------------------------------------------

    def on_start(self, start) -> None:
        for k, v in start.config.items():
            if k not in self.defaults:
                raise ValueError(f"unknown setting {k!r}; known: {sorted(self.defaults)}")
            self.cfg[k] = float(v)
        if self.factory is not None:
            self.c = self.call("the factory", self.factory, dict(self.cfg))
        c = start.centre
        self.enu = EnuFrame.at(c.lat_deg, c.lon_deg, 0.0)
        cfg = self.cfg
        self.planner = LookPlanner.from_start(start, pd_target=cfg["pd_target"], confirm_pd=cfg["confirm_pd"],
                                              assumed_rcs_m2=cfg["assumed_rcs_m2"],
                                              min_window_half_m=cfg["min_window_half_m"], mimo=cfg["mimo"] != 0)
        self.beamwidth = {r: p.beamwidth_u for r, p in self.planner.params.items()}
        self.tracks, self.books, self.holding, self.windows, self.ids = {}, {}, {}, {}, {}
        self.next_id, self.next_hold, self.next_wake_s, self.next_sweep_s = 1, 1, math.inf, 0.0
        if getattr(self.c.initiator, "holding_tracks", None):
            self.c.initiator.holding_tracks = set()

    def on_dwell(self, report) -> None:
        for kind, ident in zip(report.tag[::2], report.tag[1::2]):
            b = self.books.get(ident) if kind == TAG_TRACK else self.holding_book(ident)
            if b is not None:
                b.pending_since_s = None
        own = report.requested_by == "ta"
        window = self.windows.pop(tuple(report.tag), None) if own else None
        ts = stamp(report.t_s)
        parts = {p.radar: p for p in report.parts}
        by_channel: dict = {}
        for m in report.measurements:
            by_channel.setdefault((m.tx, m.rx), []).append(m)
        channels = sorted({(t.radar, r.radar) for t in report.parts if t.transmits for r in report.parts if r.receives})
        live = {tid: trk for tid, trk in self.tracks.items() if trk.timestamp <= ts}
        hit, looked, leftover = set(), set(), []
        for tx, rx in channels:
            dets = [self.detection(m, parts[tx], parts[rx], ts) for m in by_channel.get((tx, rx), [])]
            seen = [tid for tid in live if self.near(live[tid], report, parts[tx], parts[rx], window,
                                                      self.cfg["assoc_beam_fraction"])]
            used = self.associate({live[tid] for tid in seen}, dets, ts, hit) if dets and seen else set()
            if own:
                looked |= {tid for tid in seen if self.near(live[tid], report, parts[tx], parts[rx], window,
                                                            self.cfg["look_beam_fraction"])}
            if report.kind == "search" or tx == rx:
                leftover += [d for d in dets if d not in used]
        for tid in sorted(looked - {self.track_id(t) for t in hit}):
            self.missed(tid, ts, report.end_s)
        for trk in sorted(hit, key=self.track_id):
            self.updated(self.track_id(trk), report.t_s)
        self.initiate(leftover, report, parts, window, ts)
        self.maintain(report.end_s, {self.track_id(t) for t in hit} | looked)
        self.schedule(report.end_s)

    def on_wake(self, t_s: float) -> None:
        if t_s + 1e-9 >= self.next_wake_s:
            self.next_wake_s = math.inf
        self.maintain(t_s)
        self.schedule(t_s)

    def on_finish(self, t_s: float) -> None:
        for tid in sorted(self.tracks):
            self.delete(tid, t_s)

    # -- tracking -------------------------------------------------------------------------------

    def frame_of(self, part) -> tuple:
        """A part's face (origin, rotation) in the tracking frame."""
        return self.enu.to_enu(part.site_ecef), part.face_from_ecef @ self.enu.enu_from_ecef.T

    def detection(self, m, ptx, prx, ts) -> Detection:
        """A measurement as a Stone Soup detection with its channel's model."""
        rx_origin, rx_rot = self.frame_of(prx)
        r = np.diag([m.var_range_m2, m.var_u, m.var_v])
        if m.merged:  # may hold two unresolved targets: inflate (docs/model.md §6.5)
            q = self.beamwidth[m.rx] / 4
            r = r + np.diag([self.cfg["merged_range_sigma_m"] ** 2, q * q, q * q])
        model = MimoBistaticModel(tx_position_m=self.enu.to_enu(ptx.site_ecef), rx_position_m=rx_origin,
                                  rx_rotation=rx_rot, noise_covar=r)
        return Detection(np.array([[m.range_m], [m.u], [m.v]]), timestamp=ts, measurement_model=model,
                         metadata={"meas_id": m.meas_id, "rx": m.rx, "tx": m.tx})

    def position_ecef(self, state, ts) -> np.ndarray:
        """The state's position moved on at its velocity to ``ts`` (for beam checks), ECEF."""
        dt = (ts - state.timestamp).total_seconds()
        sv = np.asarray(state.state_vector, dtype=float).reshape(-1)
        return self.enu.to_ecef(sv[POS] + dt * sv[VEL])

    def near(self, track, report, ptx, prx, window, fraction: float) -> bool:
        """Whether the channel (ptx -> prx) of the dwell could see the track (module docs)."""
        p = self.position_ecef(track.state, stamp(report.t_s))
        if not (in_beam(prx, p, self.beamwidth[prx.radar], fraction)
                and in_beam(ptx, p, self.beamwidth[ptx.radar], fraction)):
            return False
        if window is None:
            return True
        rho = 0.5 * (np.linalg.norm(p - ptx.site_ecef) + np.linalg.norm(p - prx.site_ecef))
        a = report.aim_ecef
        rho_aim = 0.5 * (np.linalg.norm(a - ptx.site_ecef) + np.linalg.norm(a - prx.site_ecef))
        return abs(rho - rho_aim) <= window

    def associate(self, tracks: set, dets: list, ts, hit: set) -> set:
        """Associate one channel's detections with the tracks it could have seen; update the
        associated ones. Returns the detections used."""
        assoc = self.call("the data associator", self.c.data_associator.associate, tracks, set(dets), ts)
        used = set()
        for trk, hyp in assoc.items():
            if hyp:
                post = self.finite(self.call("the updater", self.c.updater.update, hyp), "the updater")
                trk.append(post)
                hit.add(trk)
                used.add(hyp.measurement)
        return used

    def track_id(self, trk) -> int:
        """The number of a confirmed track (kept here: Stone Soup rewrites a track's metadata)."""
        return self.ids[id(trk)]

    def updated(self, tid: int, t_s: float) -> None:
        trk, b = self.tracks[tid], self.books[tid]
        det = trk.state.hypothesis.measurement
        model = det.measurement_model
        b.misses_in_row = 0
        b.last_meas_id = det.metadata.get("meas_id")
        b.face = (model.rx_position_m, model.rx_rotation, self.beamwidth[det.metadata["rx"]])
        b.next_due_s = t_s + self.revisit_s(trk, b)
        self.emit(tid, trk.state, t_s, "confirmed")

    def missed(self, tid: int, ts, end_s: float) -> None:
        trk, b = self.tracks[tid], self.books[tid]
        pred = self.call("the predictor", self.c.predictor.predict, trk.state, timestamp=ts)
        trk.append(self.finite(pred, "the predictor"))
        b.misses_in_row += 1
        b.next_due_s = end_s + self.cfg["miss_redwell_s"]

    def revisit_s(self, trk, b: Book) -> float:
        """§7.1 on the predictor's own prediction of the position covariance."""
        origin, rot, theta = b.face
        p = np.asarray(trk.state.state_vector, dtype=float).reshape(-1)[POS]
        j_uv = MimoBistaticModel(tx_position_m=origin, rx_position_m=origin, rx_rotation=rot,
                                 noise_covar=np.eye(3)).jacobian(_StateOf(p))[1:, POS]

        def pos_cov(t_s: float) -> np.ndarray:
            pred = self.call("the predictor", self.c.predictor.predict, trk.state,
                             timestamp=trk.state.timestamp + timedelta(seconds=t_s))
            return np.asarray(pred.covar, dtype=float)[np.ix_(POS, POS)]

        return revisit_interval_s(pos_cov, j_uv, theta, self.cfg["revisit_v0"], self.cfg["revisit_t_min_s"],
                                  self.cfg["revisit_t_max_s"])

    def holding_book(self, ident: int) -> Optional[Book]:
        for b in self.holding.values():
            if b.id == ident:
                return b
        return None

    def holding_tracks(self) -> Optional[set]:
        hold = getattr(self.c.initiator, "holding_tracks", None)
        return hold if isinstance(hold, set) else None

    def gates(self, trk, dets: list, ts) -> bool:
        """Whether a holding track's prediction gates one of the detections (chi^2_3(0.999))."""
        pred = self.call("the predictor", self.c.predictor.predict, trk.state, timestamp=ts)
        x, p = np.asarray(pred.state_vector, dtype=float), np.asarray(pred.covar, dtype=float)
        for d in dets:
            m = d.measurement_model
            h = m.jacobian(pred)
            nu = np.asarray(d.state_vector, dtype=float).reshape(-1) - m.function(pred).reshape(-1)
            s = h @ p @ h.T + m.covar()
            if float(nu @ np.linalg.solve(s, nu)) <= self.cfg["gate_chi2"] and np.isfinite(x).all():
                return True
        return False

    def initiate(self, dets: list, report, parts: dict, window, ts) -> None:
        """Give the detections no track took to the initiator; number the tracks it confirms."""
        dets = [d for d in dets if d.measurement_model.position_of(*np.asarray(d.state_vector).reshape(-1)) is not None]
        hold = self.holding_tracks()
        rest: set = set()
        if hold is not None:
            offered = self.offered_holding(hold, dets, report, parts, window, ts)
            if not dets and not offered:
                return
            rest = hold - offered
            self.c.initiator.holding_tracks = offered
        elif not dets:
            return
        new = self.call("the initiator", self.c.initiator.initiate, set(dets), ts)
        if hold is not None:
            self.c.initiator.holding_tracks |= rest
        self.sync_holding(report.end_s)
        for trk in sorted(new, key=_first_meas_id):
            self.confirm(trk, report.t_s)

    def offered_holding(self, hold: set, dets: list, report, parts: dict, window, ts) -> set:
        """The holding tracks this dwell could have seen: in the beam of a monostatic channel of
        the article's own dwell, or gating one of the detections."""
        mono = [parts[a] for a in sorted(parts) if parts[a].transmits and parts[a].receives]
        own = report.requested_by == "ta"
        look, assoc = self.cfg["look_beam_fraction"], self.cfg["assoc_beam_fraction"]

        def seen(h) -> bool:
            if own and any(self.near(h, report, p, p, window, look) for p in mono):
                return True
            return bool(dets) and any(self.near(h, report, p, p, None, assoc) for p in mono) and self.gates(h, dets, ts)

        return {h for h in hold if h.timestamp <= ts and seen(h)}

    def sync_holding(self, now_s: float) -> None:
        """Books for new holding tracks (first look 0.3 s on), none for those gone."""
        hold = self.holding_tracks() or set()
        self.holding = {h: b for h, b in self.holding.items() if h in hold}
        for h in sorted(hold - set(self.holding), key=_first_meas_id):
            self.finite(h.state, "the initiator")
            t_s = (h.timestamp - EPOCH).total_seconds()
            self.holding[h] = Book(self.next_hold, t_s, t_s + self.cfg["tentative_revisit_s"])
            self.next_hold += 1
        for h, b in self.holding.items():
            if h.state.timestamp > stamp(b.t_s):  # updated or missed in this dwell: look again soon
                b.t_s = (h.timestamp - EPOCH).total_seconds()
                b.next_due_s = max(b.t_s, now_s) + self.cfg["tentative_revisit_s"]

    def confirm(self, trk, t_s: float) -> None:
        self.finite(trk.state, "the initiator")
        tid = self.next_id
        self.next_id += 1
        self.ids[id(trk)] = tid
        self.tracks[tid] = trk
        self.books[tid] = Book(tid, t_s, t_s)
        if getattr(trk.state, "hypothesis", None) is not None and trk.state.hypothesis.measurement is not None:
            self.updated(tid, t_s)
        else:
            self.emit(tid, trk.state, t_s, "confirmed")

    def maintain(self, now_s: float, changed_ids=()) -> None:
        """Run the deleter over the tracks given a state in this dwell and, at least every
        ``deleter_sweep_s`` of simulated time, over every track (time-based rules) and the
        initiator's deleter over its holding tracks."""
        ts = stamp(now_s)
        sweep = now_s >= self.next_sweep_s
        if sweep:
            self.next_sweep_s = now_s + self.cfg["deleter_sweep_s"]
        tracks = set(self.tracks.values()) if sweep else {self.tracks[i] for i in changed_ids if i in self.tracks}
        if tracks:
            gone = self.call("the deleter", self.c.deleter.delete_tracks, tracks, timestamp=ts)
            for tid in sorted(self.track_id(t) for t in gone):
                self.delete(tid, now_s)
        hold = self.holding_tracks()
        deleter = getattr(self.c.initiator, "deleter", None)
        if sweep and hold and deleter is not None:
            dropped = self.call("the initiator's deleter", deleter.delete_tracks, set(hold), timestamp=ts)
            self.c.initiator.holding_tracks = hold - dropped
            self.sync_holding(now_s)

    def delete(self, tid: int, now_s: float) -> None:
        trk, b = self.tracks.pop(tid), self.books.pop(tid)
        del self.ids[id(trk)]
        t_s = max(now_s, b.t_s)
        pred = self.call("the predictor", self.c.predictor.predict, trk.state, timestamp=stamp(t_s))
        self.emit(tid, self.finite(pred, "the predictor"), t_s, "deleted", b, trk)

    def emit(self, tid: int, state, t_s: float, status: str, b: Optional[Book] = None, trk=None) -> None:
        """A tracks-table row: the state and covariance rotated from the frame to ECEF."""
        b = b or self.books[tid]
        sv = np.asarray(state.state_vector, dtype=float).reshape(-1)
        order = POS + VEL
        rot = self.enu.enu_from_ecef.T
        big = np.zeros((6, 6))
        big[:3, :3] = big[3:, 3:] = rot
        cov = big @ np.asarray(state.covar, dtype=float)[np.ix_(order, order)] @ big.T
        pos, vel = self.enu.to_ecef(sv[POS]), rot @ sv[VEL]
        b.t_s = max(t_s, b.t_s)
        n = sum(1 for s in (trk or self.tracks[tid]) if getattr(s, "hypothesis", None) is not None)
        # Symmetrised, and repaired if the EKF's rounding left it slightly indefinite (the base
        # class counts and says it); beyond the bound it is a fault of the tracker.
        try:
            sent, repaired = checked_covariance(cov)
        except CovarianceError as e:
            raise TrackerFault(f"track {tid}: covariance {e} (t = {t_s:.6f} s)") from e
        self.repaired_covariances += int(repaired)
        cov21 = upper_triangle(sent)
        self.emit_track(TrackRow(b.t_s, tid, status, *pos, *vel, cov21, max(n, 1), b.last_meas_id))

    # -- scheduling -----------------------------------------------------------------------------

    def schedule(self, now_s: float) -> None:
        """A dwell for every due track and holding track, and a wake-up for the next one."""
        if not self.start.closed_loop:
            return
        nxt = math.inf
        items = [(TAG_TRACK, tid, self.tracks[tid], self.books[tid]) for tid in sorted(self.tracks)]
        items += [(TAG_HOLDING, b.id, h, b) for h, b in sorted(self.holding.items(), key=lambda x: x[1].id)]
        for kind, ident, trk, b in items:
            if b.pending_since_s is not None:
                if now_s - b.pending_since_s < PENDING_TIMEOUT_S:
                    nxt = min(nxt, b.pending_since_s + PENDING_TIMEOUT_S)
                    continue
                b.pending_since_s = None
            if b.next_due_s > now_s + 1e-9:
                nxt = min(nxt, b.next_due_s)
            elif self.plan(kind, ident, trk, b, now_s):
                b.pending_since_s = now_s
                nxt = min(nxt, now_s + PENDING_TIMEOUT_S)
            else:
                b.next_due_s = now_s + 1.0  # nobody can see it now: try later
                nxt = min(nxt, b.next_due_s)
        if math.isfinite(nxt) and nxt < self.start.duration_s and (nxt < self.next_wake_s - 1e-9
                                                                   or self.next_wake_s <= now_s):
            self.next_wake_s = nxt
            self.wake_at(max(nxt, now_s))

    def plan(self, kind: int, ident: int, trk, b: Book, now_s: float) -> bool:
        pred = self.finite(self.call("the predictor", self.c.predictor.predict, trk.state, timestamp=stamp(now_s)),
                           "the predictor")
        x = np.asarray(pred.state_vector, dtype=float).reshape(-1)
        rot = self.enu.enu_from_ecef
        cov_ecef = rot.T @ np.asarray(pred.covar, dtype=float)[np.ix_(POS, POS)] @ rot
        tag = [kind, ident]
        req = self.planner.plan(self.enu.to_ecef(x[POS]), cov_ecef, now_s, confirmed=kind == TAG_TRACK,
                                fresh=kind == TAG_HOLDING, misses=b.misses_in_row, tag=tag)
        if req is None:
            return False
        self.windows[tuple(tag)] = req.window_half_m
        self.request_dwell(req)
        return True


class _StateOf:
    """The minimal state a model's ``jacobian`` reads: a position in Stone Soup's order."""

    def __init__(self, p) -> None:
        sv = np.zeros((6, 1))
        sv[POS, 0] = p
        self.state_vector = sv


def _first_meas_id(trk) -> int:
    """The first detection's meas_id: a deterministic order for tracks held in sets."""
    for s in trk:
        hyp = getattr(s, "hypothesis", None)
        det = getattr(hyp, "measurement", None) if hyp is not None else None
        if det is not None and "meas_id" in det.metadata:
            return det.metadata["meas_id"]
    return 0
