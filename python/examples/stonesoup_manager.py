#!/usr/bin/env python3
"""Stone Soup's sensor managers choosing the looks of the MIMO network (mimo_ta.stonesoup.manager):
each radar an actionable whose actions are the looks the environment allows, the reward the
expected information gain of a look less a price on its energy and radar time.

    python3 python/examples/stonesoup_manager.py --manager greedy --seeds 1 --duration 300 --mimo target/release/mimo

Prints one JSON line per episode with mimo score's figures. Needs the [gym] and [stonesoup] extras.
"""

import argparse
import json
import sys
import time
from pathlib import Path

_REPO_PYTHON = Path(__file__).resolve().parents[1]
if (_REPO_PYTHON / "mimo_ta").is_dir():
    sys.path.insert(0, str(_REPO_PYTHON))

from stonesoup.sensormanager import BruteForceSensorManager, GreedySensorManager  # noqa: E402

from mimo_ta.gym import NetworkEnv  # noqa: E402
from mimo_ta.stonesoup.manager import LookReward, radars_of, run_episode  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--manager", choices=("greedy", "brute-force"), default="greedy")
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--duration", type=float, default=300.0)
    ap.add_argument("--price-per-kj", type=float, default=50.0)
    ap.add_argument("--price-per-s", type=float, default=20.0)
    ap.add_argument("--tracker", choices=("builtin", "simple"), default="builtin",
                    help="the built-in default tracker (the agent its resource manager) or mimo_ta.simple's")
    ap.add_argument("--mimo", default=None)
    a = ap.parse_args()
    env = NetworkEnv(scenario=1, duration_s=a.duration, mimo_bin=a.mimo, tracker=a.tracker)
    cls = GreedySensorManager if a.manager == "greedy" else BruteForceSensorManager
    manager = cls(sensors=radars_of(env), reward_function=LookReward(env=env, price_per_kj=a.price_per_kj,
                                                                       price_per_s=a.price_per_s))
    try:
        for seed in a.seeds:
            t0 = time.perf_counter()
            ret, info = run_episode(env, manager, seed)
            s = info["score"]
            print(json.dumps({"policy": f"stonesoup-{a.manager}", "seed": seed, "completeness": s["completeness"],
                              "breaks": s["breaks"], "energy_kj": s["energy_j"] / 1e3,
                              "ta_energy_kj": s["ta_energy_j"] / 1e3, "return": ret,
                              "wall_s": round(time.perf_counter() - t0, 1)}), flush=True)
    finally:
        env.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
