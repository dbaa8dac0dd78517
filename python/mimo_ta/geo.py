"""Frames: WGS-84 geodetic <-> ECEF, local ENU, array faces, sine space, ship motion.

Mirrors ``crates/mimo-core/src/geo.rs``, ``face.rs`` and ``crates/mimo-scenario/src/ship.rs`` /
``ship_frames.rs`` (docs/model.md §1.1-§1.4, §8.3). Angles in the names say their unit
(``lat_deg``, ``lat_rad``); positions are ECEF metres unless a frame is named; rotations are
3x3 numpy arrays named ``b_from_a`` (they map a vector in frame a into frame b).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

WGS84_A_M = 6_378_137.0
"""WGS-84 semi-major axis (m)."""
WGS84_F = 1.0 / 298.257_223_563
"""WGS-84 flattening."""
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)
"""First eccentricity squared, f(2 - f)."""
WGS84_B_M = WGS84_A_M * (1.0 - WGS84_F)
"""Semi-minor axis (m)."""
EARTH_MEAN_RADIUS_M = 6_371_000.0
"""Mean earth radius of the 4/3-earth horizon (m)."""
K_EFFECTIVE_EARTH = 4.0 / 3.0
"""Effective earth-radius factor (docs/model.md §1.7)."""
SHIP_FRAME_STEP_S = 5.0
"""Sample spacing of a moving ship's faces, as the engine's ``ShipFrames``."""


def prime_vertical_radius_m(lat_rad: float) -> float:
    """N(phi) (docs/model.md §1.1)."""
    return WGS84_A_M / math.sqrt(1.0 - WGS84_E2 * math.sin(lat_rad) ** 2)


def geodetic_to_ecef(lat_deg: float, lon_deg: float, alt_m: float) -> np.ndarray:
    """Geodetic (degrees, metres above the ellipsoid) -> ECEF (m), docs/model.md §1.1."""
    return geodetic_rad_to_ecef(math.radians(lat_deg), math.radians(lon_deg), alt_m)


def geodetic_rad_to_ecef(lat_rad: float, lon_rad: float, alt_m: float) -> np.ndarray:
    """Geodetic (radians, metres) -> ECEF (m)."""
    n = prime_vertical_radius_m(lat_rad)
    sl, cl = math.sin(lat_rad), math.cos(lat_rad)
    so, co = math.sin(lon_rad), math.cos(lon_rad)
    return np.array([(n + alt_m) * cl * co, (n + alt_m) * cl * so, (n * (1.0 - WGS84_E2) + alt_m) * sl])


def ecef_to_geodetic_rad(p_ecef) -> tuple[float, float, float]:
    """ECEF -> (lat_rad, lon_rad, alt_m) by the fixed-point iteration of docs/model.md §1.1."""
    x, y, z = float(p_ecef[0]), float(p_ecef[1]), float(p_ecef[2])
    lon = math.atan2(y, x)
    rho = math.hypot(x, y)
    lat = math.atan2(z, rho * (1.0 - WGS84_E2))

    def height(lat_rad: float) -> float:
        n = prime_vertical_radius_m(lat_rad)
        s, c = math.sin(lat_rad), math.cos(lat_rad)
        return rho / c - n if abs(c) > 1e-3 else abs(z) / abs(s) - n * (1.0 - WGS84_E2)

    for _ in range(8):
        n = prime_vertical_radius_m(lat)
        h = height(lat)
        new_lat = math.atan2(z, rho * (1.0 - WGS84_E2 * n / (n + h)))
        done = abs(new_lat - lat) < 1e-14
        lat = new_lat
        if done:
            break
    return lat, lon, height(lat)


def ecef_to_geodetic(p_ecef) -> tuple[float, float, float]:
    """ECEF -> (lat_deg, lon_deg, alt_m)."""
    lat, lon, h = ecef_to_geodetic_rad(p_ecef)
    return math.degrees(lat), math.degrees(lon), h


def enu_from_ecef(lat_rad: float, lon_rad: float) -> np.ndarray:
    """Rotation ECEF -> ENU at a site; rows east, north, up (docs/model.md §1.2)."""
    sl, cl = math.sin(lat_rad), math.cos(lat_rad)
    so, co = math.sin(lon_rad), math.cos(lon_rad)
    return np.array([[-so, co, 0.0], [-sl * co, -sl * so, cl], [cl * co, cl * so, sl]])


@dataclass(frozen=True)
class EnuFrame:
    """A fixed local ENU frame: origin (ECEF) and rotation ECEF -> ENU."""

    origin_ecef: np.ndarray
    enu_from_ecef: np.ndarray

    @staticmethod
    def at(lat_deg: float, lon_deg: float, alt_m: float = 0.0) -> "EnuFrame":
        lat, lon = math.radians(lat_deg), math.radians(lon_deg)
        return EnuFrame(geodetic_rad_to_ecef(lat, lon, alt_m), enu_from_ecef(lat, lon))

    def to_enu(self, p_ecef) -> np.ndarray:
        """ECEF position(s) (..., 3) -> ENU."""
        return (np.asarray(p_ecef) - self.origin_ecef) @ self.enu_from_ecef.T

    def to_ecef(self, p_enu) -> np.ndarray:
        """ENU position(s) -> ECEF."""
        return self.origin_ecef + np.asarray(p_enu) @ self.enu_from_ecef

    def vec_to_enu(self, v_ecef) -> np.ndarray:
        """Rotate free vector(s) (velocities) ECEF -> ENU."""
        return np.asarray(v_ecef) @ self.enu_from_ecef.T

    def vec_to_ecef(self, v_enu) -> np.ndarray:
        """Rotate free vector(s) ENU -> ECEF."""
        return np.asarray(v_enu) @ self.enu_from_ecef


def face_from_enu(az_rad: float, tilt_rad: float) -> np.ndarray:
    """Rotation ENU -> face for boresight azimuth ``az_rad`` (clockwise from north) and tilt;
    rows x_f (horizontal, to the left), y_f (face-up), n (boresight), docs/model.md §1.3."""
    sa, ca = math.sin(az_rad), math.cos(az_rad)
    se, ce = math.sin(tilt_rad), math.cos(tilt_rad)
    n = np.array([sa * ce, ca * ce, se])
    y = np.array([-sa * se, -ca * se, ce])
    x = np.cross(y, n)
    return np.array([x, y, n])


@dataclass(frozen=True)
class SinePoint:
    """Range and direction cosines of a point seen from a face (docs/model.md §1.4)."""

    range_m: float
    u: float
    v: float
    w: float


@dataclass(frozen=True)
class FaceFrame:
    """A planar array face: its centre (ECEF) and the rotation ECEF -> face (rows x, y, boresight)."""

    origin_ecef: np.ndarray
    face_from_ecef: np.ndarray

    @staticmethod
    def new(lat_rad: float, lon_rad: float, alt_m: float, az_rad: float, tilt_rad: float) -> "FaceFrame":
        """The face of a ship at a site whose boresight azimuth (heading already added) is ``az_rad``."""
        m = face_from_enu(az_rad, tilt_rad) @ enu_from_ecef(lat_rad, lon_rad)
        return FaceFrame(geodetic_rad_to_ecef(lat_rad, lon_rad, alt_m), m)

    def to_sine(self, p_ecef) -> SinePoint:
        """Direction cosines and range of an ECEF point."""
        l = self.face_from_ecef @ (np.asarray(p_ecef, dtype=float) - self.origin_ecef)
        r = float(np.linalg.norm(l))
        return SinePoint(r, l[0] / r, l[1] / r, l[2] / r)

    def from_ruv(self, range_m: float, u: float, v: float) -> np.ndarray:
        """ECEF point from range and direction cosines (in front of the face)."""
        w = math.sqrt(max(1.0 - u * u - v * v, 0.0))
        return self.origin_ecef + self.face_from_ecef.T @ (np.array([u, v, w]) * range_m)


def _lerp_face(a: FaceFrame, b: FaceFrame, w: float) -> FaceFrame:
    return FaceFrame(
        a.origin_ecef + (b.origin_ecef - a.origin_ecef) * w,
        a.face_from_ecef + (b.face_from_ecef - a.face_from_ecef) * w,
    )


class Ship:
    """A ship steaming along a great circle at constant speed (docs/model.md §8.3), its array
    centre ``array_height_m`` above the ellipsoid, with faces at ``face_azimuths_deg`` from the
    bow and ``face_tilt_deg`` up (§1.3). Mirrors ``crates/mimo-scenario/src/ship.rs``; the
    ``*_sampled`` methods mirror ``ShipFrames`` (samples every 5 s, linear interpolation), which
    is what the engine itself uses, so they agree with the ``face_from_ecef`` of dwell reports.
    """

    def __init__(self, lat_deg, lon_deg, array_height_m, heading_deg, speed_mps, face_azimuths_deg, face_tilt_deg,
                 duration_s: float = 0.0):
        self.lat_deg = float(lat_deg)
        self.lon_deg = float(lon_deg)
        self.array_height_m = float(array_height_m)
        self.heading_deg = float(heading_deg)
        self.speed_mps = float(speed_mps)
        self.face_azimuths_deg = [float(a) for a in face_azimuths_deg]
        self.face_tilt_deg = float(face_tilt_deg)
        lat, lon = math.radians(self.lat_deg), math.radians(self.lon_deg)
        self._p0 = geodetic_rad_to_ecef(lat, lon, self.array_height_m)
        psi = math.radians(self.heading_deg)
        direction = enu_from_ecef(lat, lon).T @ np.array([math.sin(psi), math.cos(psi), 0.0])
        axis = np.cross(self._p0, direction)
        self._axis = axis / np.linalg.norm(axis)
        self._omega = self.speed_mps / float(np.linalg.norm(self._p0))
        self._samples: list[list[FaceFrame]] = []
        self.set_duration(duration_s)

    @staticmethod
    def from_info(info, duration_s: float = 0.0) -> "Ship":
        """From a :class:`mimo_ta.messages.ShipInfo` of the ``start`` event."""
        p = info.params
        return Ship(info.lat_deg, info.lon_deg, info.array_height_m, info.heading_deg, info.speed_mps,
                    p["face_azimuths_deg"], p["face_tilt_deg"], duration_s)

    def set_duration(self, duration_s: float) -> None:
        """Sample the faces from 0 to at least ``duration_s`` (as ``ShipFrames::new``)."""
        if self.speed_mps == 0.0:
            self._samples = [self.faces_at(0.0)]
            return
        n = math.ceil(duration_s / SHIP_FRAME_STEP_S) if math.isfinite(duration_s) and duration_s > 0 else 0
        self._samples = [self.faces_at(k * SHIP_FRAME_STEP_S) for k in range(max(n, 1) + 2)]

    def pose_at(self, t_s: float) -> tuple[float, float, float, float]:
        """(lat_rad, lon_rad, alt_m, heading_deg) of the array centre at ``t_s``, exact."""
        if self.speed_mps == 0.0:
            return math.radians(self.lat_deg), math.radians(self.lon_deg), self.array_height_m, self.heading_deg
        s, c = math.sin(self._omega * t_s), math.cos(self._omega * t_s)
        p = self._p0 * c + np.cross(self._axis, self._p0) * s
        lat, lon, _ = ecef_to_geodetic_rad(p)
        enu = enu_from_ecef(lat, lon) @ np.cross(self._axis, p)
        h = math.degrees(math.atan2(enu[0], enu[1]))
        # Stay on the start heading's branch (no jump at +-180 deg); Rust's round() rounds half away from 0.
        k = (self.heading_deg - h) / 360.0
        k = math.floor(k + 0.5) if k >= 0 else -math.floor(-k + 0.5)
        return lat, lon, self.array_height_m, h + 360.0 * k

    def position_at(self, t_s: float) -> np.ndarray:
        """Array centre (ECEF) at ``t_s``, exact."""
        lat, lon, alt, _ = self.pose_at(t_s)
        return geodetic_rad_to_ecef(lat, lon, alt)

    def faces_at(self, t_s: float) -> list[FaceFrame]:
        """Every face at ``t_s``, exact, in the order of ``face_azimuths_deg`` (the face index)."""
        lat, lon, alt, heading = self.pose_at(t_s)
        tilt = math.radians(self.face_tilt_deg)
        return [FaceFrame.new(lat, lon, alt, math.radians(heading + az), tilt) for az in self.face_azimuths_deg]

    def faces_sampled(self, t_s: float) -> list[FaceFrame]:
        """Every face at ``t_s`` as the engine computes them (``ShipFrames``: samples every 5 s,
        interpolated element by element; within 0.1 mm and 1e-9 of :meth:`faces_at`)."""
        n = len(self._samples)
        if n == 1 or not math.isfinite(t_s):
            return list(self._samples[0])
        x = t_s / SHIP_FRAME_STEP_S
        k = min(int(max(math.floor(x), 0.0)), n - 2)
        w = x - k
        return [_lerp_face(a, b, w) for a, b in zip(self._samples[k], self._samples[k + 1])]

    def site_sampled(self, t_s: float) -> np.ndarray:
        """Array centre (ECEF) at ``t_s`` as the engine computes it."""
        return self.faces_sampled(t_s)[0].origin_ecef


def visible_effective_earth(site_ecef, h_site_m: float, p_ecef, h_p_m: float) -> bool:
    """4/3-earth visibility between an antenna and a target (docs/model.md §1.7)."""
    re = K_EFFECTIVE_EARTH * EARTH_MEAN_RADIUS_M
    s = np.asarray(site_ecef, dtype=float)
    p = np.asarray(p_ecef, dtype=float)
    cos_psi = float(np.clip(s @ p / (np.linalg.norm(s) * np.linalg.norm(p)), -1.0, 1.0))
    psi_e = EARTH_MEAN_RADIUS_M * math.acos(cos_psi) / re
    ha, ht = max(h_site_m, 0.0), max(h_p_m, 0.0)
    return psi_e <= math.acos(re / (re + ha)) + math.acos(re / (re + ht))
