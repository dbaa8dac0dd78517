"""StoneSoupArticle (mimo_ta.stonesoup) on a recorded scenario-1 run (fixtures/scenario1_dwells.json):
tracks form from Stone Soup's EKF + GNN + multi-measurement initiator; a test-article dwell
whose beam holds a track and returns nothing gives that track one miss and no other track
anything; a beam that holds no track gives no track a miss; a tracker that raises or returns a
non-finite state ends the run with one logged line and status 1.

Skipped only when Stone Soup is not installed (.ci/run installs it).
"""

import contextlib
import io
import json
import sys
import unittest
from pathlib import Path

import numpy as np

from mimo_ta.radar import beam_point

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "examples"))
try:
    from stonesoup.types.prediction import Prediction
    from stonesoup.updater.kalman import ExtendedKalmanUpdater
    from stonesoup_ta import DEFAULTS, ekf_gnn

    from mimo_ta.stonesoup import SETTINGS, StoneSoupArticle, stamp
except ImportError:  # pragma: no cover - depends on the environment
    StoneSoupArticle = None

FIXTURE = HERE / "fixtures" / "scenario1_dwells.json"


def replay(article, fixture):
    article.handle({"t_s": 0.0, "events": [fixture["start"]]})
    for e in fixture["dwells"]:
        article.handle({"t_s": e["end_s"], "events": [e]})


def dwell_at(article, aim_ecef, t_s, tag, radar="R1"):
    """A test-article `track` dwell of `radar` steered at `aim_ecef`, with no measurement."""
    ship, par = article.planner.ships[radar], article.planner.params[radar]
    faces = ship.faces_sampled(t_s)
    face, u, v, _, _ = beam_point(faces, par, aim_ecef)
    part = {"radar": radar, "dwell_id": 999_000, "transmits": True, "receives": True, "face": face, "beam_u": u,
            "beam_v": v, "n_pulses": 4, "site_ecef": faces[face].origin_ecef.tolist(),
            "face_from_ecef": faces[face].face_from_ecef.tolist()}
    end_s = t_s + 0.01
    return {"t_s": end_s, "events": [{
        "event": "dwell_ended", "run": 0, "group_id": 999_000, "kind": "track", "requested_by": "ta", "t_s": t_s,
        "duration_s": 0.02, "end_s": end_s, "aim_ecef": list(map(float, aim_ecef)), "tag": tag, "parts": [part],
        "measurements": []}]}


@unittest.skipIf(StoneSoupArticle is None, "Stone Soup is not installed (pip install 'mimo[stonesoup]')")
class StoneSoupArticleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.fixture = json.loads(FIXTURE.read_text())

    def article(self):
        a = StoneSoupArticle(factory=ekf_gnn, defaults=DEFAULTS, name="stonesoup-test")
        replay(a, self.fixture)
        return a

    def visible_track(self, a, t_s):
        """A confirmed track R1 can steer at, and its position moved on to t_s."""
        for tid in sorted(a.tracks):
            p = a.position_ecef(a.tracks[tid].state, stamp(t_s))
            if beam_point(a.planner.ships["R1"].faces_sampled(t_s), a.planner.params["R1"], p) is not None:
                return tid, p
        self.fail("no confirmed track R1 can see")

    def test_tracks_form_from_the_recorded_detections(self):
        a = self.article()
        self.assertGreaterEqual(len(a.tracks), 3)
        for trk in a.tracks.values():
            self.assertGreaterEqual(sum(1 for s in trk if getattr(s, "hypothesis", None) is not None), 2)

    def test_a_ready_multi_target_tracker_gives_the_same_tracks(self):
        from stonesoup.tracker.simple import MultiTargetTracker

        c = ekf_gnn(dict(DEFAULTS, **SETTINGS))
        tracker = MultiTargetTracker(initiator=c.initiator, deleter=c.deleter, detector=[],
                                     data_associator=c.data_associator, updater=c.updater)
        a = StoneSoupArticle(tracker=tracker, name="stonesoup-test")
        replay(a, self.fixture)
        b = self.article()
        self.assertEqual(sorted(a.tracks), sorted(b.tracks))
        for tid in a.tracks:
            np.testing.assert_array_equal(np.asarray(a.tracks[tid].state_vector), np.asarray(b.tracks[tid].state_vector))

    def test_a_look_that_holds_a_track_and_returns_nothing_is_its_miss_only(self):
        a = self.article()
        t_s = self.fixture["start"]["duration_s"] + 0.5
        tid, p = self.visible_track(a, t_s)
        before = {k: len(v) for k, v in a.tracks.items()}
        a.handle(dwell_at(a, p, t_s, [1, tid]))
        self.assertEqual(len(a.tracks[tid]), before[tid] + 1)
        self.assertIsInstance(a.tracks[tid].state, Prediction)
        self.assertEqual(a.books[tid].misses_in_row, 1)
        for k, n in before.items():
            if k != tid and k in a.tracks:
                self.assertEqual(len(a.tracks[k]), n, f"track {k} outside the beam changed")

    def test_a_look_that_holds_no_track_is_nobodys_miss(self):
        a = self.article()
        t_s = self.fixture["start"]["duration_s"] + 0.5
        tid, p = self.visible_track(a, t_s)
        # Three beamwidths to the side of the track (at its range), where no track is.
        site = a.planner.ships["R1"].site_sampled(t_s)
        d = p - site
        side = np.cross(d, site)
        side *= 3 * a.beamwidth["R1"] * np.linalg.norm(d) / np.linalg.norm(side)
        before = {k: len(v) for k, v in a.tracks.items()}
        a.handle(dwell_at(a, p + side, t_s, [1, tid]))
        self.assertEqual({k: len(v) for k, v in a.tracks.items() if k in before}, before)
        self.assertEqual(a.books[tid].misses_in_row, 0)

    def run_broken(self, mode):
        class Broken(ExtendedKalmanUpdater):
            def update(self, hypothesis, **kwargs):
                if mode == "raise":
                    raise ValueError("broken on purpose")
                post = super().update(hypothesis, **kwargs)
                post.state_vector[2, 0] = float("inf")
                return post

        def factory(settings):
            c = ekf_gnn(settings)
            c.updater = c.initiator.updater = Broken(measurement_model=None)
            return c

        a = StoneSoupArticle(factory=factory, defaults=DEFAULTS, name="broken")
        lines = [json.dumps({"t_s": 0.0, "events": [self.fixture["start"]]})]
        lines += [json.dumps({"t_s": e["end_s"], "events": [e]}) for e in self.fixture["dwells"]]
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stderr(err):
            status = a.run(io.StringIO("\n".join(lines) + "\n"), out)
        self.assertEqual(status, 1)
        self.assertEqual(len(err.getvalue().splitlines()), 1, err.getvalue())
        # Replies stop at the message that failed: fewer lines than messages.
        self.assertLess(len(out.getvalue().splitlines()), len(lines))
        return err.getvalue()

    def test_a_tracker_that_raises_is_one_line_and_status_1(self):
        # The initiator's updater confirms the first holding track before any track updates.
        self.assertIn("raised ValueError: broken on purpose", self.run_broken("raise"))

    def test_a_non_finite_state_is_one_line_and_status_1(self):
        self.assertIn("returned a non-finite state", self.run_broken("inf"))


if __name__ == "__main__":
    unittest.main()
