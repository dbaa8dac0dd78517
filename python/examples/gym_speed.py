#!/usr/bin/env python3
"""Steps per second of mimo/Network-v0 and where the time goes (python/README.md, "Speed").

    taskset -c 0 python3 python/examples/gym_speed.py --mimo target/release/mimo --duration 300 --seed 1

Runs the rule policy for one episode of scenario 1 and prints: steps, wall time, the CPU time of
this process and of its children (mimo, the relay, mimo score), steps per second of wall time and
of CPU time (both processes together: the one-core figure, whatever else the machine runs). With
``--profile``, under cProfile (slower), the time of this process in the tracker
(mimo_ta.simple), the observation, the masks and the policy, the online score and the protocol
(JSON and pipes).
"""

import argparse
import cProfile
import json
import os
import pstats
import resource
import sys
import time
from pathlib import Path

_REPO_PYTHON = Path(__file__).resolve().parents[1]
if (_REPO_PYTHON / "mimo_ta").is_dir():
    sys.path.insert(0, str(_REPO_PYTHON))

from mimo_ta.gym import NetworkEnv  # noqa: E402
from mimo_ta.gym.policies import rule_policy  # noqa: E402

PARTS = {  # (file suffix, function): part
    ("simple.py", "on_dwell"): "tracker", ("simple.py", "on_wake"): "tracker", ("simple.py", "on_finish"): "tracker",
    ("simple.py", "on_start"): "tracker",
    ("env.py", "_observe"): "observation", ("env.py", "action_masks"): "masks and policy",
    ("policies.py", "rule_policy"): "masks and policy",
    ("core.py", "advance"): "online score",
    ("core.py", "ingest"): "built-in tracker's rows", ("core.py", "_sync_slots"): "slots",
    ("core.py", "_visibility_all"): "observation: visibility", ("core.py", "predicted_all"): "observation: predictions",
    ("core.py", "_builtin_events"): "events (built-in tracker)",
    ("core.py", "_readline"): "protocol (pipes)", ("core.py", "_send"): "protocol (JSON out, pipes)",
    ("__init__.py", "loads"): "protocol (JSON in)", ("messages.py", "parse_event"): "protocol (JSON in)",
}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tracker", choices=("builtin", "simple"), default="builtin",
                    help="the built-in default tracker (the agent its resource manager) or mimo_ta.simple's")
    ap.add_argument("--mimo", default=None)
    ap.add_argument("--duration", type=float, default=300.0)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--cpu-timer", action="store_true", help="profile CPU time (default: wall time)")
    a = ap.parse_args()
    env = NetworkEnv(scenario=1, duration_s=a.duration, mimo_bin=a.mimo, tracker=a.tracker)
    obs, _ = env.reset(seed=a.seed)
    ch0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    c0, w0 = time.process_time(), time.perf_counter()
    prof = cProfile.Profile(time.process_time) if a.cpu_timer else cProfile.Profile()
    steps = 0
    if a.profile:
        prof.enable()
    while True:
        obs, _, term, _, info = env.step(rule_policy(env, obs))
        steps += 1
        if term:
            break
    prof.disable()
    wall, cpu = time.perf_counter() - w0, time.process_time() - c0
    ch1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    env.close()
    child = (ch1.ru_utime + ch1.ru_stime) - (ch0.ru_utime + ch0.ru_stime)  # mimo, the relay, mimo score
    stats = pstats.Stats(prof).stats if a.profile else {}
    parts: dict = {}
    for (file, _line, fn), (_cc, _nc, _tt, ct, _callers) in stats.items():
        part = PARTS.get((os.path.basename(file), fn))
        if part:
            parts[part] = parts.get(part, 0.0) + ct
    total = sum(v for (f, _l, fn), (_a, _b, _c, v, _d) in stats.items() if fn == "step" and f.endswith("env.py"))
    out = {"steps": steps, "wall_s": round(wall, 2), "python_cpu_s": round(cpu, 2), "children_cpu_s": round(child, 2),
           "steps_per_wall_s": round(steps / wall, 1), "steps_per_cpu_s": round(steps / (cpu + child), 1),
           "profiled_step_s": round(total, 2),
           "parts_s": {k: round(v, 2) for k, v in sorted(parts.items(), key=lambda kv: -kv[1])},
           "completeness": info["score"]["completeness"]}
    print(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
