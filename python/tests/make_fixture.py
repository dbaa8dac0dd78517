#!/usr/bin/env python3
"""Regenerate ``python/tests/fixtures/scenario1_dwells.json``: what the Rust engine computed, for
``test_rust_fixture.py`` to check the Python frames and measurement model against.

    python3 python/tests/make_fixture.py PATH/TO/mimo      # needs polars (reads the tables)

It runs ``mimo simulate --scenario 1 --duration 30`` with this file as the test article
(``--record``: it subscribes to dwells with detections, saves the ``start`` event and every
dwell report, and answers a search detection with a MIMO dwell at it, every radar receiving), then joins each reported measurement with the recorded truth of
the target that made it (``target_hint`` of the measurements table, which a test article never
sees), interpolated to the measurement time. The fixture keeps the start event, the first 60
dwells with a target detection, and for each such measurement the target's ECEF position.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
FIXTURE = HERE / "fixtures" / "scenario1_dwells.json"


def record(path: str) -> None:
    """Act as the test article: save the events; after a search detection, ask for a MIMO dwell
    at it (every radar receiving), so the fixture holds bistatic measurements too."""
    sys.path.insert(0, str(HERE.parent))
    import numpy as np

    from mimo_ta.measurement import ruv_to_position

    events, radars, last_s = [], [], -1.0
    for line in sys.stdin:
        msg = json.loads(line)
        events.extend(msg["events"])
        reply: dict = {}
        for e in msg["events"]:
            if e["event"] == "start":
                radars = [s["radar"] for s in e["ships"]]
                reply = {"name": "recorder", "subscribe": {"dwells": "detections"}}
            elif e["event"] == "dwell_ended" and e["kind"] == "search" and e["measurements"] and e["t_s"] > last_s + 0.5:
                m, part = e["measurements"][0], e["parts"][0]
                site = np.array(part["site_ecef"])
                aim = ruv_to_position(2 * m["range_m"], m["u"], m["v"], site, site, np.array(part["face_from_ecef"]))
                if aim is not None:
                    last_s = e["t_s"]
                    reply = {"requests": [{"dwell": {
                        "kind": "mimo", "earliest_s": e["end_s"], "aim_ecef": aim.tolist(),
                        "transmitters": [{"radar": m["tx"], "n_pulses": 8}], "receivers": radars,
                        "window_half_m": 3000.0}}]}
        sys.stdout.write(json.dumps(reply) + "\n")
        sys.stdout.flush()
    Path(path).write_text(json.dumps(events))


def main(mimo: str) -> None:
    import numpy as np
    import polars as pl

    with tempfile.TemporaryDirectory() as tmp:
        rec = Path(tmp) / "events.json"
        out = Path(tmp) / "run"
        cmd = f"{sys.executable} {Path(__file__).resolve()} --record {rec}"
        subprocess.run([mimo, "simulate", "--scenario", "1", "--duration", "30", "--ta-cmd", cmd, "--quiet", "--out",
                        str(out)], check=True)
        events = json.loads(rec.read_text())
        meas = pl.read_parquet(out / "measurements" / "run-0000.parquet")
        truth = pl.read_parquet(out / "truth" / "run-0000.parquet")
    hint = dict(zip(meas["meas_id"].to_list(), meas["target_hint"].to_list()))

    def truth_at(target: str, t_s: float) -> list:
        rows = truth.filter(pl.col("target") == target).sort("t_s")
        ts = rows["t_s"].to_numpy()
        return [float(np.interp(t_s, ts, rows[c].to_numpy())) for c in ("x_m", "y_m", "z_m")]

    start = events[0]
    dwells, targets = [], {}
    for e in events[1:]:
        if e["event"] != "dwell_ended":
            continue
        found = {m["meas_id"]: hint.get(m["meas_id"]) for m in e["measurements"]}
        found = {k: v for k, v in found.items() if v is not None}
        if not found:
            continue
        dwells.append(e)
        for mid, target in found.items():
            targets[str(mid)] = {"target": target, "truth_ecef": truth_at(target, e["t_s"])}
        if len(dwells) == 60:
            break
    FIXTURE.parent.mkdir(exist_ok=True)
    FIXTURE.write_text(json.dumps({"start": start, "dwells": dwells, "truth": targets}, indent=None) + "\n")
    print(f"wrote {FIXTURE}: {len(dwells)} dwells, {len(targets)} target measurements")


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[1] == "--record":
        record(sys.argv[2])
    elif len(sys.argv) == 2:
        main(sys.argv[1])
    else:
        sys.exit(__doc__)
