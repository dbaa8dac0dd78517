"""Registration estimates in a reply: the documented fields (docs/ta-protocol.md, `registration`),
exactly the columns of the run's registration table but `run` (schemas/registration.json)."""

import json
import pathlib
import unittest

from mimo_ta import TestArticle

SCHEMA = pathlib.Path(__file__).resolve().parents[2] / "schemas" / "registration.json"


class Registering(TestArticle):
    name = "registering"

    def on_finish(self, t_s):
        self.report_registration("R2", t_s, {"range_m": 3.5, "heading_deg": -0.05},
                                 {"var_range_m2": 4.0, "var_u": 1e-6, "var_v": 1e-6, "var_heading_deg2": 1e-4,
                                  "cov_range_heading_m_deg": 0.01}, looks=12)


class RegistrationReplyTest(unittest.TestCase):
    def test_a_finish_reply_carries_the_estimate_with_the_tables_columns(self):
        reply = Registering().handle({"t_s": 300.0, "events": [{"event": "finish", "t_s": 300.0}]})
        rows = reply["registration"]
        self.assertEqual(len(rows), 1)
        row = rows[0]
        columns = [c["name"] for c in json.loads(SCHEMA.read_text())["columns"]]
        self.assertEqual(sorted(row), sorted(c for c in columns if c != "run"))
        self.assertEqual((row["radar"], row["t_s"], row["range_m"], row["u"], row["looks"]), ("R2", 300.0, 3.5, 0.0, 12))
        self.assertEqual(row["cov_range_heading_m_deg"], 0.01)
        self.assertEqual(row["cov_u_v"], 0.0)

    def test_no_estimate_no_field(self):
        reply = TestArticle().handle({"t_s": 300.0, "events": [{"event": "finish", "t_s": 300.0}]})
        self.assertNotIn("registration", reply)


if __name__ == "__main__":
    unittest.main()
