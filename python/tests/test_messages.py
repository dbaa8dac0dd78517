"""Messages: parsing the documented JSON, replies, and the base class's loop."""

import io
import json
import math
import unittest

import numpy as np

from mimo_ta import (DwellRequest, ProtocolError, Subscription, TestArticle, TrackRow, TxOrder, from_upper_triangle,
                     upper_triangle)
from mimo_ta.messages import DwellReport, StartInfo, parse_event

START = {"event": "start", "protocol": 1, "run": 3, "duration_s": 1000.0, "scenario": "scenario-1",
         "centre": {"lat_deg": 36.0, "lon_deg": -70.0, "alt_m": 0.0}, "closed_loop": True,
         "ships": [{"radar": "R1", "lat_deg": 36.09, "lon_deg": -70.0, "array_height_m": 20.0,
                    "heading_deg": 90.0, "speed_mps": 9.0,
                    "params": {"frequency_hz": 3.3e9, "max_pulses": 16, "face_azimuths_deg": [45, 135, 225, 315],
                               "face_tilt_deg": 15.0}}],
         "config": {"k": 1}}
DWELL = {"event": "dwell_ended", "run": 0, "group_id": 81920, "kind": "search", "requested_by": "radar",
         "t_s": 12.3401, "duration_s": 0.0077, "end_s": 12.34395, "aim_ecef": [1.2e6, -4.7e6, 4.1e6], "tag": [],
         "parts": [{"radar": "R1", "dwell_id": 81920, "transmits": True, "receives": True, "face": 2,
                    "beam_u": 0.0113, "beam_v": -0.2268, "n_pulses": 2, "site_ecef": [1.3e6, -4.8e6, 3.7e6],
                    "face_from_ecef": [[-0.63, 0.12, 0.77], [0.1, 0.99, -0.05], [-0.77, 0.03, -0.64]]}],
         "measurements": [{"meas_id": 335544320, "dwell_id": 81920, "t_s": 12.3401, "rx": "R1", "tx": "R1",
                           "rx_face": 2, "range_m": 181234.5, "u": 0.0121, "v": -0.2279, "snr_db": 17.3,
                           "var_range_m2": 41.2, "var_u": 2.1e-6, "var_v": 2.3e-6, "n_primitives": 1,
                           "merged": False}]}


class MessagesTest(unittest.TestCase):
    def test_parses_the_documented_events(self):
        s = parse_event(START)
        self.assertIsInstance(s, StartInfo)
        self.assertEqual((s.run, s.ships[0].radar, s.config), (3, "R1", {"k": 1}))
        self.assertEqual(s.ships[0].radar_params.max_pulses, 16)
        self.assertAlmostEqual(s.ships[0].radar_params.beamwidth_u, 0.0252, delta=1e-4)
        d = parse_event(DWELL)
        self.assertIsInstance(d, DwellReport)
        self.assertEqual(d.parts[0].face_from_ecef.shape, (3, 3))
        self.assertEqual(d.parts[0].face_from_ecef[1, 1], 0.99)
        self.assertEqual(d.measurements[0].range_m, 181234.5)
        self.assertEqual(d.part("R1").dwell_id, 81920)
        self.assertIsNone(d.part("R2"))
        with self.assertRaises(ProtocolError):
            parse_event(dict(START, protocol=2))

    def test_replies_have_the_documented_json(self):
        req = DwellRequest("track", 12.35, np.array([1.2e6, -4.7e6, 4.1e6]), [TxOrder("R1", 4)], ["R1", "R3"], 1000.0,
                           None, [17])
        self.assertEqual(req.to_json(), {"dwell": {
            "kind": "track", "earliest_s": 12.35, "aim_ecef": [1.2e6, -4.7e6, 4.1e6],
            "transmitters": [{"radar": "R1", "n_pulses": 4}], "receivers": ["R1", "R3"], "window_half_m": 1000.0,
            "predicted_snr": None, "tag": [17]}})
        with self.assertRaises(ProtocolError):
            DwellRequest("track", 1.0, [math.nan, 0, 0], [TxOrder("R1", 1)], ["R1"], 1000.0).to_json()
        row = TrackRow(1.0, 5, "confirmed", 1, 2, 3, 4, 5, 6, list(range(21)), 2, None)
        self.assertEqual(row.to_json()["cov"], [float(i) for i in range(21)])
        with self.assertRaises(ProtocolError):
            TrackRow(1.0, 5, "lost", 1, 2, 3, 4, 5, 6, list(range(21)), 2).to_json()
        with self.assertRaises(ProtocolError):
            TrackRow(1.0, 5, "deleted", 1, 2, 3, 4, 5, 6, list(range(20)), 2).to_json()

    def test_upper_triangle_round_trip(self):
        a = np.random.default_rng(1).normal(size=(6, 6))
        p = a @ a.T
        c = upper_triangle(p)
        self.assertEqual(len(c), 21)
        self.assertEqual(c[:6], p[0].tolist())
        self.assertEqual(c[6], p[1, 1])
        np.testing.assert_array_equal(from_upper_triangle(c), p)


class Echo(TestArticle):
    name = "echo"
    subscription = Subscription(dwells="all", batch=True)

    def on_start(self, start):
        self.wake_at(1.0)

    def on_dwell(self, report):
        self.request_dwell(kind="confirm", earliest_s=report.end_s, aim_ecef=report.aim_ecef,
                           transmitters=[("R1", 2)], receivers=["R1"], window_half_m=500.0, tag=[1])

    def on_finish(self, t_s):
        self.wake_at(t_s + 1.0)  # ignored after finish
        self.emit_track(t_s=t_s, track_id=1, status="deleted", x_m=0, y_m=0, z_m=0, vx_mps=0, vy_mps=0,
                        vz_mps=0, cov=[0.0] * 21, n_updates=1)


class ArticleTest(unittest.TestCase):
    def test_one_reply_line_per_message(self):
        lines = [{"t_s": 0.0, "events": [START]}, {"t_s": 12.34395, "events": [DWELL, DWELL]},
                 {"t_s": 1.0, "events": [{"event": "wake", "t_s": 1.0}]},
                 {"t_s": 1000.0, "events": [{"event": "finish", "t_s": 1000.0}]}]
        out = io.StringIO()
        Echo().run(io.StringIO("".join(json.dumps(m) + "\n" for m in lines)), out)
        replies = [json.loads(x) for x in out.getvalue().splitlines()]
        self.assertEqual(len(replies), 4)
        self.assertEqual(replies[0], {"name": "echo", "config": {}, "requests": [{"wake_at": 1.0}],
                                      "subscribe": {"dwells": "all", "primitives": False, "batch": True}})
        self.assertEqual(len(replies[1]["requests"]), 2)
        self.assertEqual(replies[1]["requests"][0]["dwell"]["transmitters"], [{"radar": "R1", "n_pulses": 2}])
        self.assertEqual(replies[2], {})
        self.assertEqual(list(replies[3]), ["tracks"])


if __name__ == "__main__":
    unittest.main()
