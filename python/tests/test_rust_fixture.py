"""Cross-check against the Rust engine: a recorded ``start`` event and dwell reports of a short
scenario-1 run, with the truth of each detected target (``fixtures/scenario1_dwells.json``,
made by ``make_fixture.py``).

* The ships' faces computed here from the ``start`` event equal the ``site_ecef`` and
  ``face_from_ecef`` the engine reported for every part of every dwell.
* The measurement model here, applied to the true target position, reproduces the recorded
  ``(range_m, u, v)`` of monostatic and bistatic measurements within their reported sigma.
"""

import json
import unittest
from pathlib import Path

import numpy as np

from mimo_ta.geo import Ship
from mimo_ta.measurement import h_rho
from mimo_ta.messages import DwellReport, StartInfo, parse_event

FIXTURE = Path(__file__).resolve().parent / "fixtures" / "scenario1_dwells.json"


class RustFixtureTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        d = json.loads(FIXTURE.read_text())
        cls.start = parse_event(d["start"])
        cls.dwells = [parse_event(e) for e in d["dwells"]]
        cls.truth = d["truth"]
        assert isinstance(cls.start, StartInfo) and all(isinstance(r, DwellReport) for r in cls.dwells)

    def test_faces_equal_the_engines(self):
        ships = {s.radar: Ship.from_info(s, self.start.duration_s) for s in self.start.ships}
        n = 0
        for r in self.dwells:
            for p in r.parts:
                face = ships[p.radar].faces_sampled(r.t_s)[p.face]
                np.testing.assert_allclose(face.face_from_ecef, p.face_from_ecef, rtol=0, atol=1e-9)
                self.assertLess(np.linalg.norm(face.origin_ecef - p.site_ecef), 1e-3)
                n += 1
        self.assertGreater(n, 50)

    def test_measurement_model_reproduces_recorded_measurements(self):
        errors, bistatic = [], 0
        for r in self.dwells:
            for m in r.measurements:
                t = self.truth.get(str(m.meas_id))
                if t is None or m.merged:
                    continue
                rx = r.part(m.rx)
                self.assertEqual(rx.face, m.rx_face)
                z = h_rho(np.array(t["truth_ecef"]), r.part(m.tx).site_ecef, rx.site_ecef, rx.face_from_ecef)
                sigma = np.sqrt([m.var_range_m2, m.var_u, m.var_v])
                errors.append((np.array([m.range_m, m.u, m.v]) - z) / sigma)
                bistatic += m.tx != m.rx
        e = np.array(errors)
        self.assertGreater(len(e), 50)
        self.assertGreater(bistatic, 10)
        # Normalized errors: none beyond 6 sigma, and a mean square near 1 per component (the
        # reported variances are the model's Cramer-Rao-like values, docs/model.md §2.6, §4.6).
        self.assertLess(np.abs(e).max(), 6.0)
        ms = (e**2).mean(axis=0)
        for k, name in enumerate(("range", "u", "v")):
            self.assertTrue(0.5 < ms[k] < 2.0, f"mean square normalized {name} error {ms[k]:.2f}")


if __name__ == "__main__":
    unittest.main()
