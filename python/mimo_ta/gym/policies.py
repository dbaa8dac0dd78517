"""Baseline policies for :class:`mimo_ta.gym.NetworkEnv` (python/examples/ runs them).

* :func:`random_policy` — a uniformly random *valid* action (``action_masks``);
* :func:`rule_policy` — with the built-in tracker, *defer* (the built-in rule itself); with the
  simple tracker, the default test article's rule as a policy of the observation: every
  track whose revisit is due and has no look outstanding gets a look from the radar with the best
  predicted SNR, MIMO reception when confirmed, pulses by the rule (docs/model.md §7.1, §7.2,
  §7.5); then wait, with the radars' own search (share 1). It is ``mimo_ta.simple``'s scheduler
  seen through the environment.
"""

from __future__ import annotations

import numpy as np

from .env import TRACK_FEATURES, Action

_PRESENT, _CONFIRMED, _DUE, _PENDING = 0, 1, 2, 3
_NT = len(TRACK_FEATURES)
_AGE = [f[0] for f in TRACK_FEATURES].index("age_s")


def random_policy(env, rng: np.random.Generator) -> int:
    mask = env.action_masks()
    return int(rng.choice(np.flatnonzero(mask)))


def rule_policy(env, obs: dict, search_share: float = 1.0) -> int:
    """The next action of the default rule at this decision point (call again after each look).
    With the built-in tracker (``tracker="builtin"``) that is *defer*: the built-in rule's own
    proposals, so the episode is the built-in default test article's (docs/ta-protocol.md §7)."""
    if getattr(env, "defer_action", None) is not None and search_share == 1.0:
        return env.defer_action
    tracks = obs["tracks"]
    n_radars = len(env.radars)
    mask = None
    # Oldest track first (the order of track ids, in which the simple test article asks for its
    # looks; mimo places the dwells first come, first served).
    age = tracks[:, _AGE]
    for slot in sorted(range(env.k), key=lambda s: (-float(age[s]), s)):
        row = tracks[slot]
        if not (row[_PRESENT] and row[_DUE]) or row[_PENDING]:  # a look just ordered makes it pending
            continue
        vis = row[_NT::2][:n_radars]
        snr = np.where(vis > 0, row[_NT + 1::2][:n_radars], -np.inf)
        if not np.isfinite(snr).any():
            continue
        tx = env.radars[int(np.argmax(snr))]
        mimo = bool(row[_CONFIRMED]) and int((vis > 0).sum()) > 1
        a = env.encode(Action("look", slot=slot, transmitter=tx, mimo=mimo, pulses=0))
        if mask is None:
            mask = env.action_masks()
        if mask[a]:
            return a
    return env.encode(Action("wait", search_share=search_share))
