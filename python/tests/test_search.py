"""Search plans: the request builder, its JSON (docs/ta-protocol.md §3) and its checks."""

import io
import json
import unittest

from mimo_ta import (DEFAULT_SEARCH_BANDS, AzSector, ProtocolError, SearchBand, SearchOrder, SearchPlan,
                     TestArticle)
from .test_messages import START


class SearchPlanTest(unittest.TestCase):
    def test_the_default_plan_is_the_radars_own_raster(self):
        j = SearchOrder(SearchPlan()).to_json()
        self.assertEqual(j, {"search": {"radar": None, "plan": {
            "bands": [{"el_min_deg": 0.0, "el_max_deg": 2.5, "n_pulses": 2, "every_frames": 1},
                      {"el_min_deg": 2.5, "el_max_deg": 12.0, "n_pulses": 1, "every_frames": 3}],
            "sectors": [], "share": 1.0}}})
        self.assertEqual(len(DEFAULT_SEARCH_BANDS), 2)
        # A plan's default bands are a fresh list: changing one plan leaves the next alone.
        p = SearchPlan()
        p.bands.pop()
        self.assertEqual(len(SearchPlan().bands), 2)

    def test_a_shaped_plan_for_one_radar(self):
        plan = SearchPlan(bands=[SearchBand(0.0, 2.5, 1)], sectors=[AzSector(300.0, 30.0)], frame_period_s=12.0,
                          share=0.25)
        j = SearchOrder(plan, "R2").to_json()["search"]
        self.assertEqual(j["radar"], "R2")
        self.assertEqual(j["plan"]["sectors"], [{"from_deg": 300.0, "to_deg": 30.0}])
        self.assertEqual((j["plan"]["frame_period_s"], j["plan"]["share"]), (12.0, 0.25))
        self.assertEqual(j["plan"]["bands"][0]["every_frames"], 1)
        self.assertEqual(SearchPlan.none().to_json()["bands"], [])

    def test_bad_plans_name_the_field(self):
        cases = [
            (SearchPlan(bands=[SearchBand(-91.0, 2.0, 1)]), "plan.bands[0].el_min_deg"),
            (SearchPlan(bands=[SearchBand(0.0, 2.0, 1), SearchBand(5.0, 3.0, 1)]), "plan.bands[1].el_min_deg"),
            (SearchPlan(bands=[SearchBand(0.0, 90.5, 1)]), "plan.bands[0].el_max_deg"),
            (SearchPlan(bands=[SearchBand(0.0, 2.0, 0)]), "plan.bands[0].n_pulses"),
            (SearchPlan(bands=[SearchBand(0.0, 2.0, 1, 0)]), "plan.bands[0].every_frames"),
            (SearchPlan(bands=[SearchBand(0.0, 2.0, 1.5)]), "plan.bands[0].n_pulses"),
            (SearchPlan(sectors=[AzSector(10.0, 361.0)]), "plan.sectors[0].to_deg"),
            (SearchPlan(sectors=[AzSector(10.0, 10.0)]), "plan.sectors[0] is empty"),
            (SearchPlan(frame_period_s=0.0), "plan.frame_period_s"),
            (SearchPlan(frame_period_s=float("inf")), "plan.frame_period_s"),
            (SearchPlan(share=1.5), "plan.share"),
            (SearchPlan(share=float("nan")), "plan.share"),
        ]
        for plan, field in cases:
            with self.assertRaises(ProtocolError) as e:
                SearchOrder(plan).to_json()
            self.assertTrue(str(e.exception).startswith(field), f"{field}: {e.exception}")


class SearchRequestsTest(unittest.TestCase):
    def test_a_test_article_orders_search_and_search_dwells(self):
        class Ta(TestArticle):
            def on_start(self, start):
                self.order_search(SearchPlan(share=0.5))
                self.order_search(SearchPlan.none(), radar="R1")
                self.request_search_dwell([1e6, -4.7e6, 4.1e6], [("R1", 3)], receivers=["R1", "R2"], tag=[4])

        out = io.StringIO()
        Ta().run(io.StringIO(json.dumps({"t_s": 0.0, "events": [START]}) + "\n"), out)
        reqs = json.loads(out.getvalue())["requests"]
        self.assertEqual(reqs[0]["search"]["plan"]["share"], 0.5)
        self.assertEqual((reqs[1]["search"]["radar"], reqs[1]["search"]["plan"]["bands"]), ("R1", []))
        d = reqs[2]["dwell"]
        self.assertEqual((d["kind"], d["earliest_s"], d["receivers"], d["tag"]), ("search", 0.0, ["R1", "R2"], [4]))
        self.assertEqual(d["transmitters"], [{"radar": "R1", "n_pulses": 3}])

    def test_a_bad_plan_is_refused_when_ordered(self):
        ta = TestArticle()
        with self.assertRaises(ProtocolError):
            ta.order_search(SearchPlan(share=-0.1))


if __name__ == "__main__":
    unittest.main()
