#!/usr/bin/env python3
"""Baselines of the learning environment (mimo_ta.gym, python/README.md "Learning environments"):
a random valid action at every step, or the default test article's rule as a policy.

    python3 python/examples/gym_baselines.py --policy rule --seeds 1 2 3 --duration 300
    python3 python/examples/gym_baselines.py --policy random --seeds 1 2 3 --duration 300 --mimo target/release/mimo

Prints one JSON line per episode (mimo score's completeness, breaks and energy, the return, the
steps and steps per second) and the means.
"""

import argparse
import json
import sys
import time
from pathlib import Path

_REPO_PYTHON = Path(__file__).resolve().parents[1]
if (_REPO_PYTHON / "mimo_ta").is_dir():
    sys.path.insert(0, str(_REPO_PYTHON))

import numpy as np  # noqa: E402

from mimo_ta.gym import NetworkEnv  # noqa: E402
from mimo_ta.gym.policies import random_policy, rule_policy  # noqa: E402


def episode(env, policy: str, seed: int) -> dict:
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    total, steps, t0 = 0.0, 0, time.perf_counter()
    while True:
        a = rule_policy(env, obs) if policy == "rule" else random_policy(env, rng)
        obs, r, term, _, info = env.step(a)
        total += r
        steps += 1
        if term:
            break
    wall = time.perf_counter() - t0
    s = info["score"]
    return {"policy": policy, "seed": seed, "completeness": s["completeness"], "breaks": s["breaks"],
            "energy_kj": s["energy_j"] / 1e3, "ta_energy_kj": s["ta_energy_j"] / 1e3, "return": total,
            "steps": steps, "wall_s": round(wall, 2), "steps_per_s": round(steps / wall, 1)}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--policy", choices=("rule", "random"), default="rule")
    ap.add_argument("--scenario", default="1")
    ap.add_argument("--duration", type=float, default=300.0)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--energy-weight", type=float, default=1e-3, help="lambda, reward per kJ")
    ap.add_argument("--tracker", choices=("builtin", "simple"), default="builtin",
                    help="the built-in default tracker (the agent its resource manager) or mimo_ta.simple's")
    ap.add_argument("--mimo", default=None, help="the mimo binary (default: the installed one)")
    a = ap.parse_args()
    scenario = int(a.scenario) if a.scenario.isdigit() else a.scenario
    env = NetworkEnv(scenario=scenario, duration_s=a.duration, energy_weight=a.energy_weight, mimo_bin=a.mimo, tracker=a.tracker)
    rows = []
    try:
        for seed in a.seeds:
            rows.append(episode(env, a.policy, seed))
            print(json.dumps(rows[-1]), flush=True)
    finally:
        env.close()
    mean = {k: float(np.mean([r[k] for r in rows])) for k in ("completeness", "breaks", "energy_kj", "return",
                                                               "steps_per_s")}
    print(json.dumps({"policy": a.policy, "mean": mean}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
