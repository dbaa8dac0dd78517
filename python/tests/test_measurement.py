"""The (R_B, u, v) model: Jacobian against finite differences, inversion (docs/model.md §5.4)."""

import math
import unittest

import numpy as np

from mimo_ta.geo import FaceFrame
from mimo_ta.measurement import h, h_rho, jacobian, ruv_to_position, ruv_to_position_cov


def geometry():
    rx = FaceFrame.new(math.radians(36.0), math.radians(-70.0), 20.0, math.radians(45.0), math.radians(15.0))
    tx = FaceFrame.new(math.radians(36.3), math.radians(-70.4), 20.0, math.radians(80.0), math.radians(15.0))
    pts = np.array([rx.from_ruv(r, u, v) for r, u, v in
                    ((120e3, 0.1, 0.05), (60e3, -0.4, 0.2), (250e3, 0.3, -0.1), (30e3, 0.0, 0.6))])
    return rx, tx.origin_ecef, pts


def central_difference(p, tx, rx, step_m=1.0):
    j = np.zeros((3, 3))
    for i in range(3):
        e = np.zeros(3)
        e[i] = step_m
        j[:, i] = (h(p + e, tx, rx.origin_ecef, rx.face_from_ecef) - h(p - e, tx, rx.origin_ecef,
                                                                         rx.face_from_ecef)) / (2 * step_m)
    return j


class MeasurementTest(unittest.TestCase):
    def test_jacobian_matches_finite_differences_bistatic_and_monostatic(self):
        rx, tx, pts = geometry()
        for t in (tx, rx.origin_ecef):
            for p in pts:
                j = jacobian(p, t, rx.origin_ecef, rx.face_from_ecef)
                fd = central_difference(p, t, rx)
                np.testing.assert_allclose(j[0], fd[0], atol=1e-8)
                np.testing.assert_allclose(j[1:], fd[1:], atol=1e-11)
            # Vectorized over points: the same rows.
            jv = jacobian(pts, t, rx.origin_ecef, rx.face_from_ecef)
            for k, p in enumerate(pts):
                np.testing.assert_allclose(jv[k], jacobian(p, t, rx.origin_ecef, rx.face_from_ecef), rtol=1e-14)

    def test_monostatic_is_twice_the_range_and_the_face_direction(self):
        rx, _, pts = geometry()
        for p in pts:
            s = rx.to_sine(p)
            z = h_rho(p, rx.origin_ecef, rx.origin_ecef, rx.face_from_ecef)
            np.testing.assert_allclose(z, [s.range_m, s.u, s.v], rtol=1e-12)

    def test_back_to_cartesian_inverts_h(self):
        rx, tx, pts = geometry()
        for t in (tx, rx.origin_ecef):
            for p in pts:
                rb, u, v = h(p, t, rx.origin_ecef, rx.face_from_ecef)
                q = ruv_to_position(rb, u, v, t, rx.origin_ecef, rx.face_from_ecef)
                self.assertLess(np.linalg.norm(q - p), 1e-5)
        # Refused: outside the unit disc, or a range sum not beyond the baseline.
        self.assertIsNone(ruv_to_position(1e5, 0.8, 0.7, tx, rx.origin_ecef, rx.face_from_ecef))
        baseline = np.linalg.norm(tx - rx.origin_ecef)
        self.assertIsNone(ruv_to_position(0.5 * baseline, 0.1, 0.1, tx, rx.origin_ecef, rx.face_from_ecef))

    def test_position_covariance_is_the_mapped_measurement_covariance(self):
        """Monte Carlo: perturb (R_B, u, v) with R, convert, compare the sample covariance."""
        rx, tx, pts = geometry()
        rng = np.random.default_rng(7)
        r = np.diag([30.0**2, 2e-6, 3e-6])
        p = pts[0]
        rb, u, v = h(p, tx, rx.origin_ecef, rx.face_from_ecef)
        _, cov = ruv_to_position_cov(rb, u, v, r, tx, rx.origin_ecef, rx.face_from_ecef)
        draws = rng.multivariate_normal([rb, u, v], r, size=20_000)
        qs = np.array([ruv_to_position(*d, tx, rx.origin_ecef, rx.face_from_ecef) for d in draws])
        sample = np.cov(qs.T)
        # Each variance within 5 % (the sampling error of 20 000 draws is about 1 %).
        np.testing.assert_allclose(np.diag(sample), np.diag(cov), rtol=0.05)


if __name__ == "__main__":
    unittest.main()
