#!/usr/bin/env python3
"""The simple test article (``mimo_ta/simple.py``) with a search manager: it turns background
search down once its tracks are held (docs/model.md §7.4).

    mimo simulate --scenario 1 --ta-cmd "python3 python/examples/search_saver_ta.py" --out runs/s1-saver

Search is charged to the test article (every transmit dwell counts, docs/design.md §6), and it is
nearly all of a network's energy when every radar searches every idle moment. The rule:

* **acquiring** — from the start, and for ``settle_s`` after a track was confirmed or a confirmed
  track was lost — the radars search as they do by themselves (the default raster, share 1);
* **held** — at least one confirmed track and none confirmed or lost for ``settle_s`` — every
  radar gives only ``held_share`` of its idle time to search (same raster, beams spaced out).

Settings (``--set key=value``): ``held_share`` (default 0.1), ``settle_s`` (default 20), and every
setting of the simple test article.
"""

import sys
from pathlib import Path

# Use the package of this checkout when run from the repository (else the installed one).
_REPO_PYTHON = Path(__file__).resolve().parents[1]
if (_REPO_PYTHON / "mimo_ta").is_dir():
    sys.path.insert(0, str(_REPO_PYTHON))

from mimo_ta import SearchPlan  # noqa: E402
from mimo_ta.simple import SimpleTa  # noqa: E402

SEARCH_DEFAULTS = {"held_share": 0.1, "settle_s": 20.0}


class SearchSaverTa(SimpleTa):
    name = "search-saver (python)"

    def on_start(self, start) -> None:
        own = {k: float(start.config.pop(k)) for k in list(start.config) if k in SEARCH_DEFAULTS}
        self.search_cfg = {**SEARCH_DEFAULTS, **own}
        super().on_start(start)
        SearchPlan(share=self.search_cfg["held_share"]).check()  # a bad share fails at start, named
        self.confirmed: set = set()
        self.last_change_s = 0.0
        self.ordered_share = 1.0  # the radars' own search runs until told otherwise

    def config(self) -> dict:
        return {**self.cfg, **getattr(self, "search_cfg", SEARCH_DEFAULTS)}

    def emit(self, t, status: str) -> None:
        super().emit(t, status)
        if status == "confirmed" and t.id not in self.confirmed:
            self.confirmed.add(t.id)
            self.last_change_s = self.now_s
        elif status == "deleted" and t.id in self.confirmed:
            self.confirmed.discard(t.id)
            self.last_change_s = self.now_s

    def manage_search(self, now_s: float) -> None:
        if not self.start.closed_loop:
            return
        held = bool(self.confirmed) and now_s >= self.last_change_s + self.search_cfg["settle_s"]
        share = self.search_cfg["held_share"] if held else 1.0
        if share != self.ordered_share:
            self.order_search(SearchPlan(share=share))
            self.ordered_share = share

    def on_dwell(self, report) -> None:
        super().on_dwell(report)
        self.manage_search(report.end_s)

    def on_wake(self, t_s: float) -> None:
        super().on_wake(t_s)
        self.manage_search(t_s)


if __name__ == "__main__":
    sys.exit(SearchSaverTa().run())
