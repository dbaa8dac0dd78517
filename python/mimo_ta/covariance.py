"""Track covariances that ``mimo`` accepts (docs/design.md §7 "Covariances").

``mimo`` takes a track's 6x6 ECEF position-velocity covariance as the upper triangle of a
symmetric matrix (21 numbers, row-major). It accepts one as it is when its values are finite,
its variances positive and it is positive semi-definite to rounding (the Cholesky factorisation
of its correlation matrix, with 1e-9 on the diagonal, succeeds); it repairs one whose smallest
eigenvalue is negative by at most ``NEGATIVE_EIGENVALUE_BOUND`` of its largest (what double-
precision Kalman updates leave), and refuses anything else. This module applies the same rule
before a covariance leaves Python, so that a test article or a tracks table written here is
never refused for rounding:

* :func:`checked_covariance` -- a 6x6 matrix (symmetrised) or 21 numbers in, the covariance to
  send out as a 6x6 matrix, and whether it was repaired; :class:`CovarianceError` beyond the
  bound, naming the smallest eigenvalue;
* :func:`track_cov21` -- the same, as the 21 numbers of the ``cov`` column.

A valid covariance given as 21 numbers is returned bit for bit; a repaired one is
``V diag(max(lambda, 1e-9 lambda_max)) V^T`` (eigenvalues raised to a floor of 1e-9 of the
largest: the nearest positive definite matrix with that floor).
"""

from __future__ import annotations

import numpy as np

#: Slack on the correlation matrix's diagonal in the test of a valid covariance.
CORRELATION_SLACK = 1e-9
#: How negative the smallest eigenvalue may be, relative to the largest, to be repaired.
NEGATIVE_EIGENVALUE_BOUND = 1e-4
#: The least eigenvalue of a repaired covariance, relative to the largest.
REPAIR_FLOOR = 1e-9

_TRIU = np.triu_indices(6)


class CovarianceError(ValueError):
    """A covariance ``mimo`` refuses: a non-finite value, a variance that is not positive, or a
    smallest eigenvalue beyond the bound."""


def _as_matrix(cov) -> np.ndarray:
    a = np.asarray(cov, dtype=float)
    if a.shape == (6, 6):
        return 0.5 * (a + a.T)
    flat = a.reshape(-1)
    if flat.size != 21:
        raise CovarianceError(f"a covariance is a 6x6 matrix or its 21-number upper triangle, got shape {a.shape}")
    m = np.zeros((6, 6))
    m[_TRIU] = flat
    return m + np.triu(m, 1).T


def _valid(m: np.ndarray) -> bool:
    """mimo's test of a valid covariance: Cholesky of the correlation matrix plus the slack."""
    sd = np.sqrt(np.diag(m))
    r = m / np.outer(sd, sd) + CORRELATION_SLACK * np.eye(6)
    low = np.zeros((6, 6))
    for i in range(6):
        for j in range(i + 1):
            s = r[i, j] - float(np.dot(low[i, :j], low[j, :j]))
            if i == j:
                if not s > 0.0:
                    return False
                low[i, i] = np.sqrt(s)
            else:
                low[i, j] = s / low[j, j]
    return True


def checked_covariance(cov) -> tuple:
    """``(matrix, repaired)``: the 6x6 covariance to send for ``cov`` (a 6x6 matrix, symmetrised,
    or 21 upper-triangle numbers) and whether it had to be repaired. Raises
    :class:`CovarianceError` for a covariance ``mimo`` would refuse."""
    m = _as_matrix(cov)
    if not np.isfinite(m).all():
        raise CovarianceError("a covariance value is not finite")
    d = np.diag(m)
    if (d <= 0.0).any():
        i = int(np.argmax(d <= 0.0))
        raise CovarianceError(f"variance {i} (diagonal) is {d[i]} (expected a positive number)")
    if _valid(m):
        return m, False
    lam, vec = np.linalg.eigh(m)
    lo, hi = float(lam[0]), float(lam[-1])
    if lo < -NEGATIVE_EIGENVALUE_BOUND * hi:
        raise CovarianceError(
            f"not positive semi-definite: its smallest eigenvalue is {lo:.6e} against a largest of {hi:.6e} "
            f"({lo / hi:.3e} of it; down to -{NEGATIVE_EIGENVALUE_BOUND:g} of it is repaired as rounding)")
    floor = REPAIR_FLOOR * hi
    while True:
        fixed = (vec * np.maximum(lam, floor)) @ vec.T
        fixed = 0.5 * (fixed + fixed.T)
        if _valid(fixed) or floor >= NEGATIVE_EIGENVALUE_BOUND * hi:
            return fixed, True
        floor *= 10.0


def track_cov21(cov) -> list:
    """The ``cov`` column's 21 numbers for ``cov`` (see :func:`checked_covariance`)."""
    a = np.asarray(cov, dtype=float)
    m, repaired = checked_covariance(a)
    if not repaired and a.shape != (6, 6):
        return a.reshape(-1).tolist()  # valid as given: bit for bit
    return m[_TRIU].tolist()


def track_cov21_unchecked(cov) -> list:
    """The 21 numbers of ``cov`` (a 6x6 matrix, symmetrised, or 21 numbers) without the rule."""
    a = np.asarray(cov, dtype=float)
    if a.shape == (6, 6):
        return (0.5 * (a + a.T))[_TRIU].tolist()
    return a.reshape(-1).tolist()
