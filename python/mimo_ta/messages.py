"""The messages of the test-article protocol, version 1 (docs/ta-protocol.md).

Events from ``mimo`` are parsed from their JSON dicts into dataclasses (:func:`parse_event`);
replies are dataclasses with a ``to_json()`` giving the documented JSON. Vectors (``site_ecef``,
``aim_ecef``) are numpy arrays, ``face_from_ecef`` a 3x3 array whose rows are face x, face y and
boresight. Mirrors ``crates/mimo-sim/src/messages.rs``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Optional, Union

import numpy as np

from .covariance import CovarianceError, track_cov21, track_cov21_unchecked

from .geo import FaceFrame
from .radar import RadarParams

PROTOCOL_VERSION = 1
TRACK_STATUSES = ("tentative", "confirmed", "deleted")
DWELL_KINDS = ("search", "confirm", "track", "mimo")


class ProtocolError(ValueError):
    """A message from ``mimo`` this package cannot read, or a reply it will not send."""


# ---------------------------------------------------------------------------------------------
# Events (mimo -> test article)


@dataclass
class GeoPoint:
    lat_deg: float
    lon_deg: float
    alt_m: float


@dataclass
class ShipInfo:
    """A ship and its radar (docs/ta-protocol.md §2.1)."""

    radar: str
    lat_deg: float
    lon_deg: float
    array_height_m: float
    heading_deg: float
    speed_mps: float
    params: dict
    """Every radar parameter, as sent (see :attr:`radar_params` for the typed form)."""

    @property
    def radar_params(self) -> RadarParams:
        return RadarParams.from_dict(self.params)


@dataclass
class StartInfo:
    """The ``start`` event: everything a test article may know before the run (never truth)."""

    protocol: int
    run: int
    duration_s: float
    scenario: str
    centre: GeoPoint
    ships: list
    closed_loop: bool
    config: dict

    @staticmethod
    def from_json(d: dict) -> "StartInfo":
        if d.get("protocol") != PROTOCOL_VERSION:
            raise ProtocolError(f"protocol {d.get('protocol')} (this package speaks {PROTOCOL_VERSION})")
        return StartInfo(
            protocol=d["protocol"],
            run=d["run"],
            duration_s=d["duration_s"],
            scenario=d["scenario"],
            centre=GeoPoint(**d["centre"]),
            ships=[ShipInfo(**s) for s in d["ships"]],
            closed_loop=d["closed_loop"],
            config=d.get("config") or {},
        )


@dataclass
class PartReport:
    """A radar's part in a finished dwell (docs/ta-protocol.md §2.2)."""

    radar: str
    dwell_id: int
    transmits: bool
    receives: bool
    face: int
    beam_u: float
    beam_v: float
    n_pulses: int
    site_ecef: np.ndarray
    face_from_ecef: np.ndarray

    @staticmethod
    def from_json(d: dict) -> "PartReport":
        return PartReport(d["radar"], d["dwell_id"], d["transmits"], d["receives"], d["face"], d["beam_u"],
                          d["beam_v"], d["n_pulses"], np.array(d["site_ecef"], dtype=float),
                          np.array(d["face_from_ecef"], dtype=float))

    def frame(self) -> FaceFrame:
        """The face frame this part used, at mid-dwell."""
        return FaceFrame(self.site_ecef, self.face_from_ecef)


@dataclass
class Measurement:
    """A clustered, centroided detection (columns of the measurements table without ``run`` and
    ``target_hint``). ``range_m`` is rho = (R_tx + R_rx)/2; ``u``, ``v`` in face ``rx_face`` of
    ``rx``."""

    meas_id: int
    dwell_id: int
    t_s: float
    rx: str
    tx: str
    rx_face: int
    range_m: float
    u: float
    v: float
    snr_db: float
    var_range_m2: float
    var_u: float
    var_v: float
    n_primitives: int
    merged: bool


@dataclass
class Primitive:
    """A threshold crossing (columns of the primitives table without ``run`` and ``target_hint``)."""

    dwell_id: int
    t_s: float
    rx: str
    tx: str
    rx_face: int
    range_cell: int
    range_m: float
    u: float
    v: float
    snr_db: float
    eta_q: float
    merged: bool
    beam_u: float
    beam_v: float
    var_range_m2: float
    var_u: float
    var_v: float


@dataclass
class DwellReport:
    """The ``dwell_ended`` event (docs/ta-protocol.md §2.2). ``t_s`` is the mid-time (every
    measurement carries it), ``end_s`` the time of the event."""

    run: int
    group_id: int
    kind: str
    requested_by: str
    t_s: float
    duration_s: float
    end_s: float
    aim_ecef: np.ndarray
    tag: list
    parts: list
    measurements: list
    primitives: list

    @staticmethod
    def from_json(d: dict) -> "DwellReport":
        return DwellReport(
            run=d["run"],
            group_id=d["group_id"],
            kind=d["kind"],
            requested_by=d["requested_by"],
            t_s=d["t_s"],
            duration_s=d["duration_s"],
            end_s=d["end_s"],
            aim_ecef=np.array(d["aim_ecef"], dtype=float),
            tag=list(d.get("tag", [])),
            parts=[PartReport.from_json(p) for p in d["parts"]],
            measurements=[Measurement(**m) for m in d.get("measurements", [])],
            primitives=[Primitive(**p) for p in d.get("primitives", [])],
        )

    def part(self, radar: str) -> Optional[PartReport]:
        """The part of ``radar``, if it took part."""
        for p in self.parts:
            if p.radar == radar:
                return p
        return None


@dataclass
class Wake:
    t_s: float


@dataclass
class Finish:
    t_s: float


Event = Union[StartInfo, DwellReport, Wake, Finish]


def parse_event(d: dict) -> Event:
    """One event of a message's ``events`` list."""
    kind = d.get("event")
    body = {k: v for k, v in d.items() if k != "event"}
    if kind == "start":
        return StartInfo.from_json(body)
    if kind == "dwell_ended":
        return DwellReport.from_json(body)
    if kind == "wake":
        return Wake(body["t_s"])
    if kind == "finish":
        return Finish(body["t_s"])
    raise ProtocolError(f"unknown event {kind!r}")


# ---------------------------------------------------------------------------------------------
# Replies (test article -> mimo)


def _finite(x: float, what: str) -> float:
    x = float(x)
    if not math.isfinite(x):
        raise ProtocolError(f"{what} is {x}: the protocol carries finite numbers only")
    return x


def _vec3(v, what: str) -> list:
    a = [_finite(x, what) for x in np.asarray(v, dtype=float).reshape(-1)]
    if len(a) != 3:
        raise ProtocolError(f"{what} needs 3 numbers, got {len(a)}")
    return a


@dataclass
class TxOrder:
    """One transmitter of a requested dwell."""

    radar: str
    n_pulses: int

    def to_json(self) -> dict:
        return {"radar": self.radar, "n_pulses": int(self.n_pulses)}


@dataclass
class DwellRequest:
    """A requested dwell (docs/ta-protocol.md §3). Monostatic: one transmitter that is also the
    only receiver; MIMO: several transmitters and/or receivers, all steered at ``aim_ecef``."""

    kind: str
    earliest_s: float
    aim_ecef: np.ndarray
    transmitters: list
    receivers: list
    window_half_m: float
    predicted_snr: Optional[float] = None
    tag: list = field(default_factory=list)

    def to_json(self) -> dict:
        return {"dwell": {
            "kind": self.kind,
            "earliest_s": _finite(self.earliest_s, "earliest_s"),
            "aim_ecef": _vec3(self.aim_ecef, "aim_ecef"),
            "transmitters": [t.to_json() for t in self.transmitters],
            "receivers": list(self.receivers),
            "window_half_m": _finite(self.window_half_m, "window_half_m"),
            "predicted_snr": None if self.predicted_snr is None else _finite(self.predicted_snr, "predicted_snr"),
            "tag": [int(t) for t in self.tag],
        }}


@dataclass
class WakeAt:
    t_s: float

    def to_json(self) -> dict:
        return {"wake_at": _finite(self.t_s, "wake_at")}


@dataclass
class StopLocalTracking:
    radar: str

    def to_json(self) -> dict:
        return {"stop_local_tracking": self.radar}


@dataclass
class SearchBand:
    """One elevation band of a search plan: beams whose elevation (local, at the ship) lies in
    [el_min_deg, el_max_deg), ``n_pulses`` per dwell, swept once every ``every_frames`` frames."""

    el_min_deg: float
    el_max_deg: float
    n_pulses: int
    every_frames: int = 1

    def check(self, where: str) -> None:
        for name in ("el_min_deg", "el_max_deg"):
            x = float(getattr(self, name))
            if not (math.isfinite(x) and -90.0 <= x <= 90.0):
                raise ProtocolError(f"{where}.{name} = {x} is outside -90…90 deg")
        if not self.el_min_deg < self.el_max_deg:
            raise ProtocolError(f"{where}.el_min_deg = {self.el_min_deg} is not below el_max_deg = {self.el_max_deg}")
        for name in ("n_pulses", "every_frames"):
            n = getattr(self, name)
            if isinstance(n, bool) or int(n) != n or n < 1:
                raise ProtocolError(f"{where}.{name} = {n}: a whole number >= 1")

    def to_json(self) -> dict:
        return {"el_min_deg": float(self.el_min_deg), "el_max_deg": float(self.el_max_deg),
                "n_pulses": int(self.n_pulses), "every_frames": int(self.every_frames)}


DEFAULT_SEARCH_BANDS = (SearchBand(0.0, 2.5, 2, 1), SearchBand(2.5, 12.0, 1, 3))
"""The radars' own raster (docs/model.md §7.4): the low band every frame with 2 pulses, the
upper band a third per frame with 1 pulse."""


@dataclass
class AzSector:
    """A true-north azimuth sector, clockwise from ``from_deg`` to ``to_deg`` (degrees in
    [0, 360]; ``from_deg > to_deg`` runs through north)."""

    from_deg: float
    to_deg: float

    def check(self, where: str) -> None:
        for name in ("from_deg", "to_deg"):
            x = float(getattr(self, name))
            if not (math.isfinite(x) and 0.0 <= x <= 360.0):
                raise ProtocolError(f"{where}.{name} = {x} is outside 0…360 deg")
        if self.from_deg == self.to_deg:
            raise ProtocolError(f"{where} is empty: from_deg = to_deg = {self.from_deg}")

    def to_json(self) -> dict:
        return {"from_deg": float(self.from_deg), "to_deg": float(self.to_deg)}


@dataclass
class SearchPlan:
    """A radar's background search (docs/model.md §7.4, docs/ta-protocol.md §3): elevation
    ``bands`` (empty: no search), azimuth ``sectors`` (empty: the whole horizon), the shortest
    ``frame_period_s`` between two frame starts (``None``: no limit) and the ``share`` of idle
    time given to search in [0, 1] (after a search dwell of length d the radar waits
    d·(1 − share)/share; 1: every idle moment, 0: none)."""

    bands: list = field(default_factory=lambda: list(DEFAULT_SEARCH_BANDS))
    sectors: list = field(default_factory=list)
    frame_period_s: Optional[float] = None
    share: float = 1.0

    @staticmethod
    def none() -> "SearchPlan":
        """No background search: a radar with nothing else to do idles."""
        return SearchPlan(bands=[])

    def check(self) -> None:
        """Raise :class:`ProtocolError` naming the field, as ``mimo`` would (it also checks that
        every sector lies inside the radar's faces)."""
        for i, b in enumerate(self.bands):
            b.check(f"plan.bands[{i}]")
        for i, s in enumerate(self.sectors):
            s.check(f"plan.sectors[{i}]")
        if self.frame_period_s is not None:
            p = float(self.frame_period_s)
            if not (math.isfinite(p) and p > 0.0):
                raise ProtocolError(f"plan.frame_period_s = {p} is not a positive finite time (s)")
        share = float(self.share)
        if not (math.isfinite(share) and 0.0 <= share <= 1.0):
            raise ProtocolError(f"plan.share = {share} is outside [0, 1]")

    def to_json(self) -> dict:
        self.check()
        out = {"bands": [b.to_json() for b in self.bands], "sectors": [s.to_json() for s in self.sectors],
               "share": float(self.share)}
        if self.frame_period_s is not None:
            out["frame_period_s"] = float(self.frame_period_s)
        return out


@dataclass
class SearchOrder:
    """Make ``plan`` the background search of ``radar`` (of every radar when ``None``) from now
    on, starting at the first beam of its raster."""

    plan: SearchPlan
    radar: Optional[str] = None

    def to_json(self) -> dict:
        return {"search": {"radar": self.radar, "plan": self.plan.to_json()}}


@dataclass
class TrackRow:
    """One row of the tracks table (docs/design.md §3): ECEF state, ``cov`` the upper triangle
    of the 6x6 position-velocity covariance, row-major (21 numbers; see :func:`upper_triangle`),
    or the 6x6 matrix itself. It is sent as :func:`mimo_ta.covariance.track_cov21` makes it:
    symmetrised, and repaired when rounding left it slightly indefinite (one beyond repair is
    sent as it is, for mimo to refuse)."""

    t_s: float
    track_id: int
    status: str
    x_m: float
    y_m: float
    z_m: float
    vx_mps: float
    vy_mps: float
    vz_mps: float
    cov: list
    n_updates: int
    last_meas_id: Optional[int] = None

    def to_json(self) -> dict:
        if self.status not in TRACK_STATUSES:
            raise ProtocolError(f"track status {self.status!r}, expected one of {TRACK_STATUSES}")
        flat = [_finite(c, "cov") for c in np.asarray(self.cov, dtype=float).reshape(-1)]
        if len(flat) not in (21, 36):
            raise ProtocolError(f"cov needs 21 numbers (or a 6x6 matrix), got {len(flat)}")
        # Symmetrised and, if rounding left it slightly indefinite, repaired as mimo would
        # (mimo_ta.covariance, docs/design.md §7). One mimo refuses whatever is done (a negative
        # variance, beyond the bound) is sent as it is: mimo's error names the track and the
        # smallest eigenvalue.
        try:
            cov = track_cov21(self.cov)
        except CovarianceError:
            cov = track_cov21_unchecked(self.cov)
        return {
            "t_s": _finite(self.t_s, "t_s"),
            "track_id": int(self.track_id),
            "status": self.status,
            "x_m": _finite(self.x_m, "x_m"),
            "y_m": _finite(self.y_m, "y_m"),
            "z_m": _finite(self.z_m, "z_m"),
            "vx_mps": _finite(self.vx_mps, "vx_mps"),
            "vy_mps": _finite(self.vy_mps, "vy_mps"),
            "vz_mps": _finite(self.vz_mps, "vz_mps"),
            "cov": cov,
            "n_updates": int(self.n_updates),
            "last_meas_id": None if self.last_meas_id is None else int(self.last_meas_id),
        }


_TRIU = np.triu_indices(6)


def upper_triangle(p6) -> list:
    """The 21-element upper triangle, row-major, of a 6x6 covariance (the ``cov`` column)."""
    return np.asarray(p6, dtype=float)[_TRIU].tolist()


def from_upper_triangle(cov21) -> np.ndarray:
    """The symmetric 6x6 matrix of a ``cov`` column."""
    m = np.zeros((6, 6))
    m[_TRIU] = np.asarray(cov21, dtype=float)
    return m + np.triu(m, 1).T


@dataclass
class Subscription:
    """What the test article is sent (docs/ta-protocol.md §4): ``dwells`` is ``all``,
    ``detections`` (default) or ``own``."""

    dwells: str = "detections"
    primitives: bool = False
    batch: bool = False

    def to_json(self) -> dict:
        if self.dwells not in ("all", "detections", "own"):
            raise ProtocolError(f"subscription dwells {self.dwells!r}")
        return {"dwells": self.dwells, "primitives": bool(self.primitives), "batch": bool(self.batch)}
