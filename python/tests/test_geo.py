"""Frames: round trips, known values and the ship's motion (docs/model.md §1, §8.3)."""

import math
import unittest

import numpy as np

from mimo_ta.geo import (WGS84_A_M, WGS84_B_M, EnuFrame, FaceFrame, Ship, ecef_to_geodetic, enu_from_ecef,
                         face_from_enu, geodetic_to_ecef, visible_effective_earth)


class GeodeticTest(unittest.TestCase):
    def test_round_trip_below_a_millimetre(self):
        for lat in (-89.9999, -60.0, -36.5, 0.0, 1e-9, 36.5, 45.0, 75.0, 89.99, 90.0):
            for lon in (-179.0, -75.2, 0.0, 70.0, 180.0):
                for alt in (-100.0, 0.0, 20.0, 6000.0, 20_000.0):
                    p = geodetic_to_ecef(lat, lon, alt)
                    back = ecef_to_geodetic(p)
                    self.assertLess(np.linalg.norm(geodetic_to_ecef(*back) - p), 1e-3)
                    self.assertAlmostEqual(back[2], alt, delta=1e-3)

    def test_known_ecef_values(self):
        np.testing.assert_allclose(geodetic_to_ecef(0.0, 0.0, 0.0), [WGS84_A_M, 0.0, 0.0], atol=1e-9)
        pole = geodetic_to_ecef(90.0, 0.0, 0.0)
        self.assertAlmostEqual(pole[2], WGS84_B_M, delta=1e-6)
        self.assertAlmostEqual(WGS84_B_M, 6_356_752.314245, delta=1e-6)
        np.testing.assert_allclose(geodetic_to_ecef(0.0, 90.0, 100.0), [0.0, WGS84_A_M + 100.0, 0.0], atol=1e-9)
        # 45 N: N(45) = a / sqrt(1 - e2/2), x = N cos45, z = N (1 - e2) sin45.
        e2 = 6.69437999014e-3
        n45 = WGS84_A_M / math.sqrt(1 - e2 / 2)
        np.testing.assert_allclose(geodetic_to_ecef(45.0, 0.0, 0.0),
                                   [n45 * math.sqrt(0.5), 0.0, n45 * (1 - e2) * math.sqrt(0.5)], atol=1e-3)

    def test_enu_is_orthonormal_and_up_is_up(self):
        for lat, lon in ((36.5, -75.2), (0.0, 0.0), (-45.0, 120.0), (89.0, 10.0)):
            r = enu_from_ecef(math.radians(lat), math.radians(lon))
            np.testing.assert_allclose(r @ r.T, np.eye(3), atol=1e-14)
            self.assertAlmostEqual(np.linalg.det(r), 1.0, delta=1e-14)
            f = EnuFrame.at(lat, lon, 0.0)
            up = geodetic_to_ecef(lat, lon, 1000.0)
            np.testing.assert_allclose(f.to_enu(up), [0.0, 0.0, 1000.0], atol=1e-6)
            np.testing.assert_allclose(f.to_ecef(f.to_enu(up)), up, atol=1e-6)
            v = np.array([10.0, -20.0, 3.0])
            np.testing.assert_allclose(f.vec_to_ecef(f.vec_to_enu(v)), v, atol=1e-12)


class FaceTest(unittest.TestCase):
    def test_face_triad_is_right_handed_with_x_to_the_left(self):
        for az in (0.0, 45.0, 135.0, 225.0, 315.0, 17.0):
            for tilt in (0.0, 15.0, 30.0):
                m = face_from_enu(math.radians(az), math.radians(tilt))
                np.testing.assert_allclose(m @ m.T, np.eye(3), atol=1e-14)
                self.assertAlmostEqual(np.linalg.det(m), 1.0, delta=1e-14)
                x, n = m[0], m[2]
                self.assertLess(abs(x[2]), 1e-15)
                self.assertGreater(x @ np.array([-n[1], n[0], 0.0]), 0.0)

    def test_sine_space_round_trip(self):
        f = FaceFrame.new(math.radians(36.0), math.radians(-70.0), 20.0, math.radians(45.0), math.radians(15.0))
        s = f.to_sine(f.from_ruv(100_000.0, 0.0, 0.0))
        self.assertLess(abs(s.u) + abs(s.v), 1e-12)
        self.assertAlmostEqual(s.range_m, 100_000.0, delta=1e-6)
        s = f.to_sine(f.from_ruv(150_000.0, 0.3, -0.2))
        self.assertAlmostEqual(s.u, 0.3, delta=1e-12)
        self.assertAlmostEqual(s.v, -0.2, delta=1e-12)


class ShipTest(unittest.TestCase):
    def test_steaming_ship_keeps_speed_height_and_heading(self):
        for heading in (0.0, 45.0, 90.0, 200.0, 359.0):
            s = Ship(36.0, -70.0, 20.0, heading, 9.0, [45.0, 135.0, 225.0, 315.0], 15.0, 1000.0)
            prev = s.position_at(0.0)
            for i in range(1, 21):
                t = 50.0 * i
                lat, lon, alt, hdg = s.pose_at(t)
                self.assertAlmostEqual(alt, 20.0, delta=1e-6)
                p = s.position_at(t)
                self.assertAlmostEqual(np.linalg.norm(p - prev) / 50.0, 9.0, delta=9.0e-4)
                prev = p
            self.assertLess(abs(s.pose_at(1000.0)[3] - heading), 0.1)

    def test_sampled_faces_match_the_exact_ones(self):
        s = Ship(36.1, -70.2, 20.0, 63.0, 10.0, [45.0, 135.0, 225.0, 315.0], 15.0, 1000.0)
        worst_m, worst_rot = 0.0, 0.0
        for k in range(0, 2000, 7):
            t = k * 0.5003
            for a, b in zip(s.faces_at(t), s.faces_sampled(t)):
                worst_m = max(worst_m, np.linalg.norm(a.origin_ecef - b.origin_ecef))
                worst_rot = max(worst_rot, np.abs(a.face_from_ecef - b.face_from_ecef).max())
        self.assertLess(worst_m, 1e-3)
        self.assertLess(worst_rot, 1e-9)
        # Sample times are exact.
        np.testing.assert_array_equal(s.faces_sampled(30.0)[2].face_from_ecef, s.faces_at(30.0)[2].face_from_ecef)

    def test_faces_follow_heading(self):
        s = Ship(36.0, -70.0, 20.0, 30.0, 0.0, [45.0, 135.0, 225.0, 315.0], 15.0)
        lat, lon = math.radians(36.0), math.radians(-70.0)
        az, el = math.radians(75.0), math.radians(15.0)
        d = np.array([math.sin(az) * math.cos(el), math.cos(az) * math.cos(el), math.sin(el)])
        p = s.position_at(0.0) + enu_from_ecef(lat, lon).T @ d * 50_000.0
        sp = s.faces_at(0.0)[0].to_sine(p)
        self.assertLess(abs(sp.u) + abs(sp.v), 1e-9)

    def test_effective_earth_horizon(self):
        site = geodetic_to_ecef(36.0, -70.0, 20.0)

        def at(dist_km, h):
            lat = 36.0 + math.degrees(dist_km * 1000.0 / 6_371_000.0)
            return visible_effective_earth(site, 20.0, geodetic_to_ecef(lat, -70.0, h), h)

        self.assertTrue(at(420.0, 10_000.0))
        self.assertFalse(at(445.0, 10_000.0))
        self.assertTrue(at(57.0, 100.0))
        self.assertFalse(at(63.0, 100.0))


if __name__ == "__main__":
    unittest.main()
