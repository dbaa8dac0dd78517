"""Covariances mimo accepts: the rule of docs/design.md §7 applied before a covariance leaves
Python (mimo_ta.covariance), in the protocol's track rows and in tracks tables written here."""

import io
import json
import tempfile
import unittest
from pathlib import Path

import numpy as np

from mimo_ta import (CovarianceError, TestArticle, TrackRow, checked_covariance, from_upper_triangle,
                     track_cov21, tracks_columns, upper_triangle)
from mimo_ta.covariance import NEGATIVE_EIGENVALUE_BOUND, _valid

LARGEST = 4311.0  # m^2: the largest eigenvalue of the Stone Soup row the issue found refused


def with_eigenvalues(lam):
    """Q diag(lam) Q^T for a fixed rotation Q that mixes every axis."""
    q, _ = np.linalg.qr(np.random.default_rng(7).normal(size=(6, 6)))
    return q @ np.diag(lam) @ q.T


def near(ratio):
    """A covariance whose smallest eigenvalue is ``ratio`` times its largest."""
    return with_eigenvalues([LARGEST, 900.0, 25.0, 4.0, 1.0, ratio * LARGEST])


def row(cov, tid=1):
    return TrackRow(12.5, tid, "confirmed", 1.3e6, -4.8e6, 3.9e6, 10.0, 0.0, 0.0, cov, 3)


class CovarianceTest(unittest.TestCase):
    def test_minus_1e6_of_the_largest_is_repaired(self):
        m = near(-1e-6)
        self.assertFalse(_valid(0.5 * (m + m.T)), "the case is one mimo's strict test refuses")
        fixed, repaired = checked_covariance(m)
        self.assertTrue(repaired)
        self.assertTrue(_valid(fixed), "the repair passes the strict test")
        lam = np.linalg.eigvalsh(fixed)
        self.assertGreater(lam[0], 0.0)
        self.assertLess(np.abs(fixed - m).max(), 2e-6 * LARGEST, "the repair moves nothing beyond the rounding")
        # Idempotent: the repaired covariance, sent again, is valid as it is.
        self.assertFalse(checked_covariance(upper_triangle(fixed))[1])

    def test_minus_1e2_of_the_largest_is_refused_with_the_eigenvalue(self):
        with self.assertRaises(CovarianceError) as e:
            checked_covariance(near(-1e-2))
        self.assertIn("smallest eigenvalue is -4.311", str(e.exception))
        self.assertIn("-1.000e-02 of it", str(e.exception))
        # The bound itself: just inside is repaired, just outside refused.
        self.assertTrue(checked_covariance(near(-0.9 * NEGATIVE_EIGENVALUE_BOUND))[1])
        with self.assertRaises(CovarianceError):
            checked_covariance(near(-1.1 * NEGATIVE_EIGENVALUE_BOUND))

    def test_valid_21_numbers_pass_bit_for_bit_and_a_matrix_is_symmetrised(self):
        c21 = upper_triangle(with_eigenvalues([LARGEST, 900.0, 25.0, 4.0, 1.0, 0.01]))
        self.assertEqual(track_cov21(c21), c21)
        m = from_upper_triangle(c21)
        skew = m.copy()
        skew[0, 1] += 1e-9
        skew[1, 0] -= 1e-9
        out = from_upper_triangle(track_cov21(skew))
        self.assertEqual(out[0, 1], out[1, 0])
        self.assertAlmostEqual(out[0, 1], m[0, 1], delta=1e-12)

    def test_broken_values_are_refused(self):
        bad = np.eye(6)
        bad[0, 0] = -1.0
        with self.assertRaisesRegex(CovarianceError, "variance 0"):
            checked_covariance(bad)
        bad[0, 0] = np.nan
        with self.assertRaisesRegex(CovarianceError, "finite"):
            checked_covariance(bad)
        with self.assertRaisesRegex(CovarianceError, "21-number"):
            checked_covariance([1.0] * 20)

    def test_track_rows_are_sent_repaired_or_refused(self):
        sent = row(upper_triangle(near(-1e-6))).to_json()["cov"]
        self.assertTrue(_valid(from_upper_triangle(sent)))
        # Beyond repair: sent as it is (symmetrised), for mimo to refuse naming the track.
        far = near(-1e-2)
        self.assertEqual(row(far, tid=4).to_json()["cov"], upper_triangle(0.5 * (far + far.T)))

    def test_the_base_class_counts_repairs_and_says_so_at_the_end(self):
        class Emitter(TestArticle):
            def on_finish(self, t_s):
                self.emit_track(row(near(-1e-6)))
                self.emit_track(row(np.eye(6), tid=2))

        ta = Emitter()
        out = io.StringIO()
        start = {"event": "start", "protocol": 1, "run": 0, "duration_s": 10.0, "scenario": "s",
                 "centre": {"lat_deg": 36.0, "lon_deg": -70.0, "alt_m": 0.0}, "closed_loop": True, "ships": []}
        lines = [json.dumps({"t_s": 0.0, "events": [start]}), json.dumps({"t_s": 10.0, "events": [{"event": "finish", "t_s": 10.0}]})]
        ta.run(io.StringIO("\n".join(lines) + "\n"), out)
        self.assertEqual(ta.repaired_covariances, 1)
        reply = json.loads(out.getvalue().splitlines()[1])
        for t in reply["tracks"]:
            self.assertTrue(_valid(from_upper_triangle(t["cov"])))

    def test_tracks_columns_repair_count_and_refuse(self):
        rows = [row(near(-1e-6)), row(np.eye(6), tid=2), {**row(upper_triangle(np.eye(6)), tid=3).to_json()}]
        cols, repaired = tracks_columns(rows, run=0)
        self.assertEqual(repaired, 1)
        self.assertEqual(cols["track_id"], [1, 2, 3])
        self.assertEqual(cols["run"], [0, 0, 0])
        self.assertTrue(all(len(c) == 21 for c in cols["cov"]))
        with self.assertRaisesRegex(CovarianceError, "row 1 .*track 9"):
            tracks_columns([row(np.eye(6)), row(near(-1e-2), tid=9)], run=0)

    def test_a_written_tracks_table_has_mimos_types_and_metadata(self):
        try:
            import pyarrow.parquet as pq
        except ImportError:  # pragma: no cover - pyarrow is optional
            self.skipTest("pyarrow not installed")
        from mimo_ta import write_tracks_table
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "run-0000.parquet"
            self.assertEqual(write_tracks_table(path, [row(near(-1e-6)), row(np.eye(6), tid=2)], run=0), 1)
            t = pq.read_table(path)
            self.assertEqual(t.schema.metadata[b"mimo.table"], b"tracks")
            cov_type = t.schema.field("cov").type
            self.assertEqual((cov_type.list_size, str(cov_type.value_type)), (21, "double"))
            self.assertEqual(str(t.schema.field("run").type), "uint32")
            self.assertEqual(t.column("last_meas_id").to_pylist(), [None, None])
            for c in t.column("cov").to_pylist():
                self.assertTrue(_valid(from_upper_triangle(c)))


if __name__ == "__main__":
    unittest.main()
