"""The Stone Soup measurement model of mimo's (rho, u, v) detections (mimo_ta.stonesoup,
docs/model.md §5.4): function, analytic Jacobian against central differences, the inverse
Stone Soup's initiators use (round trip), on monostatic and bistatic geometry; and the NEES of
measurements the engine recorded, against truth, through the model.

Skipped only when Stone Soup is not installed (.ci/run installs it).
"""

import json
import math
import unittest
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from mimo_ta.geo import EnuFrame, FaceFrame
from mimo_ta.measurement import h_rho
from mimo_ta.messages import parse_event

try:
    from stonesoup.types.array import StateVectors
    from stonesoup.types.detection import Detection
    from stonesoup.types.state import GaussianState, State

    from mimo_ta.stonesoup import MimoBistaticModel
except ImportError:  # pragma: no cover - depends on the environment
    MimoBistaticModel = None

FIXTURE = Path(__file__).resolve().parent / "fixtures" / "scenario1_dwells.json"
POS = [0, 2, 4]


def chi2_quantile(p: float, k: int) -> float:
    """Wilson-Hilferty approximation of the chi^2_k quantile (as gating.rs; exact to < 0.1 % here)."""
    z = {0.025: -1.959963984540054, 0.975: 1.959963984540054}[p]
    return k * (1.0 - 2.0 / (9.0 * k) + z * math.sqrt(2.0 / (9.0 * k))) ** 3


def geometries():
    """(name, model, points): a receiver face, a transmitter 45 km away or the receiver itself,
    in an ENU frame at the receiver, and target points in front of the face."""
    enu = EnuFrame.at(36.0, -70.0, 0.0)
    rx = FaceFrame.new(math.radians(36.0), math.radians(-70.0), 20.0, math.radians(45.0), math.radians(15.0))
    tx = FaceFrame.new(math.radians(36.3), math.radians(-70.4), 20.0, math.radians(80.0), math.radians(15.0))
    rot = rx.face_from_ecef @ enu.enu_from_ecef.T
    pts = np.array([enu.to_enu(rx.from_ruv(r, u, v)) for r, u, v in
                    ((120e3, 0.1, 0.05), (60e3, -0.4, 0.2), (250e3, 0.3, -0.1), (30e3, 0.0, 0.6))])
    r = np.diag([25.0, 1e-6, 2e-6])
    out = []
    for name, t in (("bistatic", enu.to_enu(tx.origin_ecef)), ("monostatic", enu.to_enu(rx.origin_ecef))):
        out.append((name, MimoBistaticModel(tx_position_m=t, rx_position_m=enu.to_enu(rx.origin_ecef),
                                            rx_rotation=rot, noise_covar=r), pts))
    return out


def state_at(p, v=(210.0, -30.0, 2.0)):
    sv = np.zeros((6, 1))
    sv[POS, 0] = p
    sv[[1, 3, 5], 0] = v
    return State(sv)


@unittest.skipIf(MimoBistaticModel is None, "Stone Soup is not installed (pip install 'mimo[stonesoup]')")
class StoneSoupModelTest(unittest.TestCase):
    def test_function_is_half_the_range_sum_and_the_receiver_direction(self):
        for name, m, pts in geometries():
            for p in pts:
                z = np.asarray(m.function(state_at(p)), dtype=float).reshape(-1)
                d_t, d_r = p - m.tx_position_m, p - m.rx_position_m
                self.assertAlmostEqual(z[0], 0.5 * (np.linalg.norm(d_t) + np.linalg.norm(d_r)), delta=1e-6, msg=name)
                l = m.rx_rotation @ d_r
                np.testing.assert_allclose(z[1:], l[:2] / np.linalg.norm(l), atol=1e-14, err_msg=name)
            # Many states at once (columns), as sigma-point filters call it.
            sv = np.zeros((6, len(pts)))
            sv[POS, :] = pts.T
            zs = np.asarray(m.function(SimpleNamespace(state_vector=StateVectors(sv))), dtype=float)
            np.testing.assert_allclose(zs.T, h_rho(pts, m.tx_position_m, m.rx_position_m, m.rx_rotation), rtol=1e-15)

    def test_jacobian_matches_central_differences(self):
        for name, m, pts in geometries():
            for p in pts:
                j = m.jacobian(state_at(p))
                self.assertEqual(j.shape, (3, 6))
                np.testing.assert_array_equal(j[:, [1, 3, 5]], 0.0)
                fd = np.zeros((3, 3))
                for i in range(3):
                    e = np.zeros(3)
                    e[i] = 1.0  # m
                    zp = np.asarray(m.function(state_at(p + e)), dtype=float).reshape(-1)
                    zm = np.asarray(m.function(state_at(p - e)), dtype=float).reshape(-1)
                    fd[:, i] = (zp - zm) / 2.0
                np.testing.assert_allclose(j[0, POS], fd[0], atol=1e-8, err_msg=name)
                np.testing.assert_allclose(j[1:, POS], fd[1:], atol=1e-11, err_msg=name)

    def test_inverse_returns_the_point_and_initiates_its_covariance(self):
        for name, m, pts in geometries():
            for p in pts:
                z = m.function(state_at(p))
                det = Detection(z, measurement_model=m)
                x = np.asarray(m.inverse_function(det), dtype=float).reshape(-1)
                np.testing.assert_allclose(x[POS], p, atol=1e-6, err_msg=name)
                np.testing.assert_array_equal(x[[1, 3, 5]], 0.0)
                # Back through the function: the measurement again.
                np.testing.assert_allclose(np.asarray(m.function(State(x.reshape(6, 1))), dtype=float).reshape(-1),
                                           np.asarray(z, dtype=float).reshape(-1), rtol=0, atol=1e-9)
            # No position has u^2 + v^2 >= 1, nor a range sum short of the baseline.
            with self.assertRaises(ValueError):
                m.inverse_function(Detection(np.array([[1e5], [0.8], [0.7]]), measurement_model=m))
        bi = geometries()[0][1]
        half_baseline = 0.5 * np.linalg.norm(bi.tx_position_m - bi.rx_position_m)
        with self.assertRaises(ValueError):
            bi.inverse_function(Detection(np.array([[0.9 * half_baseline], [0.1], [0.1]]), measurement_model=bi))

    def test_stone_soup_initiator_maps_the_noise_through_the_inverse(self):
        from stonesoup.initiator.simple import SimpleMeasurementInitiator

        for name, m, pts in geometries():
            p = pts[0]
            det = Detection(m.function(state_at(p)), measurement_model=m, timestamp=None)
            prior = GaussianState(np.zeros((6, 1)), np.diag([0.0, 9e4, 0.0, 9e4, 0.0, 9e4]))
            (trk,) = SimpleMeasurementInitiator(prior).initiate({det}, None)
            c = np.asarray(trk.covar, dtype=float)
            # Position covariance J R J^T with J = dp/dz the inverse of the Jacobian: mapped back
            # through the Jacobian it is the measurement covariance again.
            h = m.jacobian(trk.state)[:, POS]
            np.testing.assert_allclose(h @ c[np.ix_(POS, POS)] @ h.T, m.covar(), rtol=1e-6, atol=1e-14, err_msg=name)
            np.testing.assert_allclose(np.diag(c)[[1, 3, 5]], 9e4)

    def test_recorded_measurements_against_truth_are_chi2_3(self):
        """NEES of the engine's measurements (a recorded scenario-1 run, make_fixture.py) about
        the model's prediction at the true position, with the reported covariance: over N
        measurements, N times the mean is chi^2_3N (docs/model.md §6.6)."""
        d = json.loads(FIXTURE.read_text())
        start = parse_event(d["start"])
        enu = EnuFrame.at(start.centre.lat_deg, start.centre.lon_deg, 0.0)
        nees, bistatic = [], 0
        for r in (parse_event(e) for e in d["dwells"]):
            for meas in r.measurements:
                t = d["truth"].get(str(meas.meas_id))
                if t is None or meas.merged:
                    continue
                rx, tx = r.part(meas.rx), r.part(meas.tx)
                m = MimoBistaticModel(tx_position_m=enu.to_enu(tx.site_ecef), rx_position_m=enu.to_enu(rx.site_ecef),
                                      rx_rotation=rx.face_from_ecef @ enu.enu_from_ecef.T,
                                      noise_covar=np.diag([meas.var_range_m2, meas.var_u, meas.var_v]))
                nu = np.array([meas.range_m, meas.u, meas.v]) - np.asarray(
                    m.function(state_at(enu.to_enu(np.array(t["truth_ecef"])))), dtype=float).reshape(-1)
                nees.append(float(nu @ np.linalg.solve(m.covar(), nu)))
                bistatic += meas.tx != meas.rx
        n = len(nees)
        self.assertGreater(n, 50)
        self.assertGreater(bistatic, 10)
        lo, hi = chi2_quantile(0.025, 3 * n) / n, chi2_quantile(0.975, 3 * n) / n
        mean = float(np.mean(nees))
        self.assertTrue(lo <= mean <= hi, f"mean NEES {mean:.3f} over {n} measurements outside [{lo:.3f}, {hi:.3f}]")


if __name__ == "__main__":
    unittest.main()
