#!/usr/bin/env python3
"""The offline route: track a recording's measurements in Python, write the tracks table, score.

    python3 python/examples/offline_tracks.py runs/s1 runs/s1-offline [--mimo PATH]

reads RUN's manifest, dwells and measurements (Parquet, with **polars**: `pip install polars`),
feeds every dwell to the tracker of ``simple_ta.py`` in the order ``mimo`` delivers them (end
time, then group id), as the same protocol events a test article receives in the closed loop,
writes ``OUT/tracks/run-NNNN.parquet`` and a manifest whose ``parent`` is RUN (the layout of a
``mimo track`` output, docs/design.md §2), then runs ``mimo score OUT`` (``--mimo`` names the
binary; default: the environment's ``mimo`` (the wheel's, then the PATH:
``mimo_ta.binary.find_mimo_bin``), else ``target/release`` or ``target/debug`` of the repository).

This is open loop (docs/design.md §1): the recording's dwell schedule is fixed, so it measures
the tracker alone. The dwells table does not record which track a dwell was aimed at, so a look
at a track is taken from the beams, as the built-in trackers do (docs/model.md §6.7): a track
whose prediction lies within half a beamwidth of a receive beam of a non-search dwell was
looked at, and a look without an update is a miss.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

try:
    import polars as pl
except ImportError:  # pragma: no cover - said plainly to the user
    sys.exit("offline_tracks.py reads and writes Parquet with polars: pip install polars")

sys.path.insert(0, str(Path(__file__).resolve().parent))
from simple_ta import SimpleTa  # noqa: E402  (also puts the checkout's mimo_ta on sys.path)

from mimo_ta.binary import find_mimo_bin  # noqa: E402
from mimo_ta.geo import Ship, ecef_to_geodetic  # noqa: E402
from mimo_ta.messages import PROTOCOL_VERSION  # noqa: E402
from mimo_ta.tracks_table import write_tracks_table  # noqa: E402

TRACK_COLUMNS = ["run", "t_s", "track_id", "status", "x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps", "cov",
                 "n_updates", "last_meas_id"]


def start_event(manifest: dict, run: int) -> dict:
    """The ``start`` event of the closed loop, rebuilt from the manifest's resolved scenario."""
    sc = manifest["scenario"]["resolved"]
    ships = [{"radar": s["id"], "lat_deg": s["lat_deg"], "lon_deg": s["lon_deg"],
              "array_height_m": s["array_height_m"], "heading_deg": s["heading_deg"], "speed_mps": s["speed_mps"],
              "params": s["radar"]} for s in sc["ships"]]
    # The point on the ellipsoid below the centroid of the ships' start positions (docs/model.md §6.1).
    from mimo_ta.geo import geodetic_to_ecef
    mean = np.mean([geodetic_to_ecef(s["lat_deg"], s["lon_deg"], s["array_height_m"]) for s in ships], axis=0)
    lat, lon, _ = ecef_to_geodetic(mean)
    return {"event": "start", "protocol": PROTOCOL_VERSION, "run": run, "duration_s": manifest["duration_s"],
            "scenario": sc["name"], "centre": {"lat_deg": lat, "lon_deg": lon, "alt_m": 0.0}, "ships": ships,
            "closed_loop": False, "config": {}}


def dwell_events(dwells: pl.DataFrame, meas: pl.DataFrame, ships: dict, run: int):
    """``(end_s, group_id, dwell_ended event)`` for every dwell group the test article subscribes
    to (``detections``: groups with a measurement, and every dwell it requested), in delivery
    order."""
    by_dwell: dict[int, list] = {}
    for m in meas.sort("meas_id").iter_rows(named=True):
        by_dwell.setdefault(m["dwell_id"], []).append(m)
    wanted = dwells.filter(pl.col("dwell_id").is_in(list(by_dwell)) | (pl.col("requested_by") == "ta"))
    dwells = dwells.filter(pl.col("group_id").is_in(wanted["group_id"].unique().implode()))
    events = []
    for (gid,), parts in dwells.sort("dwell_id").group_by(["group_id"], maintain_order=True):
        rows = list(parts.iter_rows(named=True))
        start_s = min(r["t_s"] for r in rows)
        dur_s = max(r["duration_s"] for r in rows)
        ms = [m for r in rows for m in by_dwell.get(r["dwell_id"], [])]
        mid_s = ms[0]["t_s"] if ms else start_s + 0.5 * dur_s
        report_parts = []
        for r in rows:
            face = ships[r["radar"]].faces_sampled(mid_s)[r["face"]]
            report_parts.append({
                "radar": r["radar"], "dwell_id": r["dwell_id"], "transmits": r["role"] in ("tx", "txrx"),
                "receives": r["role"] in ("rx", "txrx"), "face": r["face"], "beam_u": r["beam_u"],
                "beam_v": r["beam_v"], "n_pulses": r["n_pulses"], "site_ecef": face.origin_ecef.tolist(),
                "face_from_ecef": face.face_from_ecef.tolist()})
        first = rows[0]
        keep = ("meas_id", "dwell_id", "t_s", "rx", "tx", "rx_face", "range_m", "u", "v", "snr_db", "var_range_m2",
                "var_u", "var_v", "n_primitives", "merged")
        events.append((start_s + dur_s, gid, {
            "event": "dwell_ended", "run": run, "group_id": gid, "kind": first["kind"],
            "requested_by": first["requested_by"], "t_s": mid_s, "duration_s": dur_s, "end_s": start_s + dur_s,
            "aim_ecef": [first["aim_x_m"], first["aim_y_m"], first["aim_z_m"]], "tag": [],
            "parts": report_parts, "measurements": [{k: m[k] for k in keep} for m in ms]}))
    events.sort(key=lambda e: (e[0], e[1]))
    return events


def looked_at(ta: SimpleTa, event: dict) -> list:
    """Tracks predicted within half a beamwidth of a receive beam of this dwell (docs/model.md §6.7)."""
    if event["kind"] == "search":
        return []
    out = []
    for t in ta.tracks.values():
        x, _ = ta.predict(t, event["t_s"])
        p = ta.enu.to_ecef(x[:3])
        for part in event["parts"]:
            if not part["receives"]:
                continue
            m = np.array(part["face_from_ecef"])
            l = m @ (p - np.array(part["site_ecef"]))
            r = np.linalg.norm(l)
            half = 0.5 * ta.params[part["radar"]].beamwidth_u
            if l[2] > 0 and math.hypot(l[0] / r - part["beam_u"], l[1] / r - part["beam_v"]) <= half:
                out.append(t.id)
                break
    return out


def make_ta(tracker: str):
    """The test article run offline: ``simple_ta.py``'s, or Stone Soup's EKF + GNN of
    ``stonesoup_ta.py`` (``stonesoup``: Joseph form; ``stonesoup-plain``: Stone Soup's default
    covariance update)."""
    if tracker.startswith("stonesoup"):
        from stonesoup_ta import DEFAULTS, ekf_gnn

        from mimo_ta.stonesoup import StoneSoupArticle
        joseph = tracker == "stonesoup"
        return StoneSoupArticle(factory=lambda s: ekf_gnn(s, joseph), defaults=DEFAULTS, name=f"{tracker}-ekf-gnn")
    return SimpleTa()


def track_run(run_dir: Path, manifest: dict, run: int, tracker: str = "simple") -> list:
    dwells = pl.read_parquet(run_dir / "dwells" / f"run-{run:04d}.parquet")
    meas = pl.read_parquet(run_dir / "measurements" / f"run-{run:04d}.parquet")
    start = start_event(manifest, run)
    ta = make_ta(tracker)
    rows = []

    def send(t_s, event):
        reply = ta.handle({"t_s": t_s, "events": [event]})
        rows.extend(reply.get("tracks", []))

    send(0.0, start)
    ships = {s["radar"]: Ship.from_info(ta.start.ships[i], manifest["duration_s"]) for i, s in enumerate(start["ships"])}
    for end_s, _, ev in dwell_events(dwells, meas, ships, run):
        # Looks at a track are found from simple_ta's predictions; Stone Soup's article keeps its
        # own books (a dwell without a tag is a detection it associates).
        ev["tag"] = looked_at(ta, ev) if isinstance(ta, SimpleTa) else []
        send(end_s, ev)
    send(manifest["duration_s"], {"event": "finish", "t_s": manifest["duration_s"]})
    for r in rows:
        r["run"] = run
    # Covariances the article repaired before it sent them (mimo_ta.covariance).
    return rows, ta.repaired_covariances


def write_tracks(path: Path, rows: list, run: int) -> tuple:
    """Write the rows with mimo_ta's tracks-table writer (mimo's column types and metadata, every
    covariance symmetrised and, where rounding left it slightly indefinite, repaired:
    docs/design.md §7). Returns (rows, covariances repaired)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    repaired = write_tracks_table(path, rows, run)
    return len(rows), repaired


def find_mimo(given: str | None) -> str:
    if given:
        return given
    try:
        return find_mimo_bin()  # the environment's scripts directory (the wheel), then the PATH
    except FileNotFoundError:
        pass
    repo = Path(__file__).resolve().parents[2]
    for profile in ("release", "debug"):
        exe = Path(os.environ.get("CARGO_TARGET_DIR", repo / "target")) / profile / "mimo"
        if exe.is_file():
            return str(exe)
    sys.exit("cannot find the mimo binary: give --mimo PATH (or build it: cargo build -p mimo-cli)")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", type=Path, help="a recording (mimo simulate output)")
    ap.add_argument("out", type=Path, help="output directory (must not exist unless --force)")
    ap.add_argument("--mimo", help="the mimo binary for scoring")
    ap.add_argument("--no-score", action="store_true", help="write the tracks only")
    ap.add_argument("--force", action="store_true", help="replace OUT")
    ap.add_argument("--tracker", choices=("simple", "stonesoup", "stonesoup-plain"), default="simple",
                    help="simple_ta.py's tracker, or Stone Soup's EKF + GNN of stonesoup_ta.py (needs stonesoup; "
                         "-plain: Stone Soup's default covariance update instead of the Joseph form)")
    a = ap.parse_args()
    manifest = json.loads((a.run / "manifest.json").read_text())
    if a.out.exists():
        if not a.force:
            sys.exit(f"error: {a.out} exists (use --force to replace it)")
        shutil.rmtree(a.out)
    t0 = time.time()
    tables = []
    repaired = 0
    for run in range(manifest["runs"]):
        rows, fixed_by_ta = track_run(a.run, manifest, run, a.tracker)
        f = f"tracks/run-{run:04d}.parquet"
        n, fixed = write_tracks(a.out / f, rows, run)
        repaired += fixed + fixed_by_ta
        tables.append({"file": f, "rows": n})
    out_manifest = dict(manifest)
    out_manifest.update({
        "tracker": {"name": f"{a.tracker} (python, offline)", "config": make_ta(a.tracker).config()},
        "schedule": "open loop: the dwells of the parent run, tracked by python/examples/offline_tracks.py",
        "parent": os.path.relpath(a.run.resolve(), a.out.resolve()),  # from OUT itself (docs/design.md §2)
        "tables": {"tracks": tables},
        "timing_s": {"track": time.time() - t0},
    })
    (a.out / "manifest.json").write_text(json.dumps(out_manifest, indent=2) + "\n")
    print(f"wrote {sum(t['rows'] for t in tables)} track rows of {manifest['runs']} run(s) to {a.out} "
          f"in {time.time() - t0:.1f} s; {repaired} covariance(s) slightly not positive semi-definite repaired")
    if a.no_score:
        return 0
    return subprocess.call([find_mimo(a.mimo), "score", str(a.out)])


if __name__ == "__main__":
    sys.exit(main())
