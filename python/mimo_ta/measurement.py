"""The bistatic (R_B, u, v) measurement model, its Jacobian, and back to Cartesian
(docs/model.md §5.4).

A detection on receiver face (origin ``rx_origin``, rotation ``rx_rot`` with rows x, y,
boresight) of a transmission from ``tx_pos`` measures ``z = (R_B, u, v)``: the range sum
``|p - t| + |p - r|`` and the direction cosines in the receiver face. Monostatic is
``tx_pos == rx_origin``. The tables and the protocol carry ``range_m`` = rho = R_B / 2 and
``var_range_m2`` = sigma_rho^2; :func:`z_and_r_of` turns a measurement into ``z`` and its
covariance ``R`` in R_B (sigma_RB^2 = 4 sigma_rho^2).

Every function is frame-agnostic: give positions and rotations in ECEF, or all in one local
ENU frame (rotate the face with ``rx_rot @ enu_from_ecef.T`` and move its origin with the ENU
transform), and the result is in that frame. Functions taking ``p`` accept one point ``(3,)`` or
many ``(N, 3)`` (vectorized over N).
"""

from __future__ import annotations

import numpy as np


def h(p, tx_pos, rx_origin, rx_rot) -> np.ndarray:
    """``(R_B, u, v)`` of point(s) ``p``: shape ``(3,)`` or ``(N, 3)``."""
    p = np.asarray(p, dtype=float)
    d_t = p - tx_pos
    d_r = p - rx_origin
    l = d_r @ np.asarray(rx_rot).T
    r_r = np.linalg.norm(l, axis=-1)
    r_b = np.linalg.norm(d_t, axis=-1) + r_r
    return np.stack([r_b, l[..., 0] / r_r, l[..., 1] / r_r], axis=-1)


def h_rho(p, tx_pos, rx_origin, rx_rot) -> np.ndarray:
    """``(rho, u, v)`` with rho = R_B / 2, the ``range_m`` of the tables."""
    z = h(p, tx_pos, rx_origin, rx_rot)
    return z * np.array([0.5, 1.0, 1.0])


def jacobian(p, tx_pos, rx_origin, rx_rot) -> np.ndarray:
    """``d(R_B, u, v)/dp``: shape ``(3, 3)`` or ``(N, 3, 3)`` (the velocity columns are zero)."""
    p = np.asarray(p, dtype=float)
    m = np.asarray(rx_rot, dtype=float)
    d_t = p - tx_pos
    d_r = p - rx_origin
    n_t = np.linalg.norm(d_t, axis=-1)[..., None]
    n_r = np.linalg.norm(d_r, axis=-1)[..., None]
    d_rb = d_t / n_t + d_r / n_r
    l = d_r @ m.T
    x, y, z = l[..., 0], l[..., 1], l[..., 2]
    r3 = (n_r[..., 0]) ** 3
    du_face = np.stack([y * y + z * z, -x * y, -x * z], axis=-1) / r3[..., None]
    dv_face = np.stack([-x * y, x * x + z * z, -y * z], axis=-1) / r3[..., None]
    return np.stack([d_rb, du_face @ m, dv_face @ m], axis=-2)


def ruv_to_position(r_b: float, u: float, v: float, tx_pos, rx_origin, rx_rot):
    """The point with measurement ``(R_B, u, v)`` (initiation), or ``None`` when there is none:
    ``u^2 + v^2 >= 1``, R_B not beyond the baseline, or a non-positive denominator."""
    uv2 = u * u + v * v
    if not (np.isfinite(r_b) and np.isfinite(u) and np.isfinite(v)) or uv2 >= 1.0:
        return None
    m = np.asarray(rx_rot, dtype=float)
    d = np.array([u, v, np.sqrt(1.0 - uv2)])
    l_t = m @ (np.asarray(tx_pos, dtype=float) - rx_origin)
    den = 2.0 * (r_b - d @ l_t)
    num = r_b * r_b - l_t @ l_t
    if den <= 0.0 or num < 0.0:
        return None
    return rx_origin + m.T @ (d * (num / den))


def ruv_to_position_cov(r_b: float, u: float, v: float, r_cov, tx_pos, rx_origin, rx_rot):
    """Position and its covariance ``J R J^T`` with ``J = dp/d(R_B, u, v)`` (the inverse of
    :func:`jacobian` at the point), or ``None`` as :func:`ruv_to_position`."""
    p = ruv_to_position(r_b, u, v, tx_pos, rx_origin, rx_rot)
    if p is None:
        return None
    try:
        j = np.linalg.inv(jacobian(p, tx_pos, rx_origin, rx_rot))
    except np.linalg.LinAlgError:
        return None
    c = j @ np.asarray(r_cov, dtype=float) @ j.T
    return p, 0.5 * (c + c.T)


def z_and_r_of(m) -> tuple[np.ndarray, np.ndarray]:
    """A measurement's ``z = (R_B, u, v)`` and its covariance ``R`` (diagonal: 4 var_rho, var_u,
    var_v); ``m`` is a :class:`mimo_ta.messages.Measurement` or anything with its fields."""
    z = np.array([2.0 * m.range_m, m.u, m.v])
    r = np.diag([4.0 * m.var_range_m2, m.var_u, m.var_v])
    return z, r
