#!/usr/bin/env python3
"""A short training run on mimo/Network-v0 with a standard optimiser: CMA-ES (``pip install cma``)
over the weights of a small linear look-scoring policy (evolution strategies are a standard RL
baseline; PyTorch, which Stable-Baselines3 needs, is not installed here — docs/decisions/0311-
learning-environments.md). The weights start at zero: nothing of the default rule is given.

The policy, at each decision point: for every track slot with a valid look, a score
``w · [1, confirmed, due, until_due_s/4, since_update_s/4, since_look_s/4, pos_std_km, misses]``;
if the best score is positive it looks at that track with the radar of best predicted SNR, MIMO
when ``w_mimo · [1, confirmed] > 0``, pulses by the rule or a fixed level chosen by ``w_pulses``;
otherwise it waits, with the search share picked by ``w_search`` — or, with the built-in tracker
(``--tracker builtin``, the default) and ``w_defer > 0``, *defers* (the built-in rule's proposed
looks) once the radars search at that share.

    nice -n 10 python3 python/examples/gym_train_cma.py --generations 4 --popsize 6 --train-duration 60 \\
        --eval-seeds 1 2 3 --eval-duration 300 --mimo target/release/mimo --out weights.json

Prints each generation's best and mean return and, at the end, the evaluation's scores.
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

from mimo_ta.gym import SEARCH_SHARES, Action, NetworkEnv  # noqa: E402
from mimo_ta.gym.env import TRACK_FEATURES  # noqa: E402

NT = len(TRACK_FEATURES)
F = {name: i for i, (name, *_rest) in enumerate(TRACK_FEATURES)}
N_LOOK = 8
N_PARAMS = N_LOOK + 2 + 2 + 1 + 1


def features(row) -> np.ndarray:
    return np.array([1.0, row[F["confirmed"]], row[F["due"]], row[F["until_due_s"]] / 4, row[F["since_update_s"]] / 4,
                     row[F["since_look_s"]] / 4, row[F["pos_std_m"]] / 1e3, row[F["misses"]]])


def linear_policy(env, obs, w) -> int:
    w_look, w_mimo, w_pulses = w[:N_LOOK], w[N_LOOK:N_LOOK + 2], w[N_LOOK + 2:N_LOOK + 4]
    w_search, w_defer = w[N_LOOK + 4], w[N_LOOK + 5]
    mask = env.action_masks()
    best, best_a = 0.0, None
    nr = len(env.radars)
    pulses = 0 if w_pulses[0] >= w_pulses[1] else 4
    for slot in range(env.k):
        row = obs["tracks"][slot]
        if not row[0]:
            continue
        vis = row[NT::2][:nr]
        snr = np.where(vis > 0, row[NT + 1::2][:nr], -np.inf)
        if not np.isfinite(snr).any():
            continue
        tx = env.radars[int(np.argmax(snr))]
        mimo = bool(w_mimo @ [1.0, row[F["confirmed"]]] > 0) and int((vis > 0).sum()) > 1
        a = env.encode(Action("look", slot=slot, transmitter=tx, mimo=mimo, pulses=pulses))
        if not mask[a]:
            continue
        s = float(w_look @ features(row))
        if s > best:
            best, best_a = s, a
    if best_a is not None:
        return best_a
    share = SEARCH_SHARES[int(np.clip((1 - 1 / (1 + np.exp(-w_search))) * len(SEARCH_SHARES), 0,
                                      len(SEARCH_SHARES) - 1))]
    if env.defer_action is not None and w_defer > 0 and np.all(obs["radars"][:, 0] == np.float32(share)):
        return env.defer_action
    return env.encode(Action("wait", search_share=share))


def episode(env, w, seed) -> tuple:
    obs, _ = env.reset(seed=seed)
    total = 0.0
    while True:
        obs, r, term, _, info = env.step(linear_policy(env, obs, w))
        total += r
        if term:
            return total, info["score"]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--generations", type=int, default=4)
    ap.add_argument("--popsize", type=int, default=6)
    ap.add_argument("--train-duration", type=float, default=60.0)
    ap.add_argument("--train-seed", type=int, default=100, help="first training seed (one per generation)")
    ap.add_argument("--eval-seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--eval-duration", type=float, default=300.0)
    ap.add_argument("--energy-weight", type=float, default=1e-3)
    ap.add_argument("--mimo", default=None)
    ap.add_argument("--tracker", choices=("builtin", "simple"), default="builtin",
                    help="the built-in default tracker (the agent its resource manager) or mimo_ta.simple's")
    ap.add_argument("--out", default=None, help="write the best weights here (JSON)")
    a = ap.parse_args()
    import cma

    train = NetworkEnv(scenario=1, duration_s=a.train_duration, energy_weight=a.energy_weight, mimo_bin=a.mimo,
                       tracker=a.tracker)
    es = cma.CMAEvolutionStrategy(np.zeros(N_PARAMS), 1.0, {"popsize": a.popsize, "seed": 1, "verbose": -9})
    t0 = time.perf_counter()
    try:
        for g in range(a.generations):
            seed = a.train_seed + g  # every candidate of a generation on the same episode
            ws = es.ask()
            returns = [episode(train, w, seed)[0] for w in ws]
            es.tell(ws, [-r for r in returns])
            print(json.dumps({"generation": g, "seed": seed, "best_return": max(returns),
                              "mean_return": float(np.mean(returns)), "wall_s": round(time.perf_counter() - t0, 1)}),
                  flush=True)
    finally:
        train.close()
    w = es.result.xfavorite
    if a.out:
        Path(a.out).write_text(json.dumps({"weights": list(map(float, w))}))
    ev = NetworkEnv(scenario=1, duration_s=a.eval_duration, energy_weight=a.energy_weight, mimo_bin=a.mimo,
                    tracker=a.tracker)
    rows = []
    try:
        for seed in a.eval_seeds:
            ret, s = episode(ev, w, seed)
            rows.append({"policy": "cma-linear", "seed": seed, "completeness": s["completeness"],
                         "breaks": s["breaks"], "energy_kj": s["energy_j"] / 1e3, "return": ret})
            print(json.dumps(rows[-1]), flush=True)
    finally:
        ev.close()
    print(json.dumps({"policy": "cma-linear", "weights": list(map(float, w)),
                      "mean": {k: float(np.mean([r[k] for r in rows])) for k in ("completeness", "breaks",
                                                                                 "energy_kj", "return")}}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
