"""The network as a PettingZoo parallel environment: one agent per ship (its radar's looks and
search), a shared reward (docs/decisions/0311-learning-environments.md).

Each parallel step is one decision point of the run. Every agent chooses one action:

* ``wait`` with a search share for its own radar, *accepting* or *refusing* to receive for the
  other ships' MIMO looks of this step (``2 × len(SEARCH_SHARES)`` actions: accepting first);
* a look at a track slot with its own radar transmitting, monostatic or MIMO, with a pulse level
  (``K × 2 × len(PULSE_LEVELS)`` actions); a ship that looks also accepts to receive.

A MIMO look's receivers are the transmitter and the ships that accepted this step and can see the
track (mimo leaves out any that cannot steer at it). Two ships choosing the same track: the first
in radar order looks, the other's look is dropped (said in its ``info["dropped"]``). Then the
decision is sent and the run goes to the next decision point; every agent gets the same reward
(the Gymnasium environment's: completeness share minus λ × energy).

With the built-in tracker (``tracker="builtin"``, the default; docs/ta-protocol.md §7) a ship that
waits *accepting* also takes the built-in rule's proposed looks that its radar transmits (for
tracks no ship looked at this step); one that refuses or looks takes none. Every ship waiting
accepting with share 1 is the built-in default test article.

Observation of an agent (a dict, with ``action_mask``, the PettingZoo convention): the shared track
picture (the network's tracks, as ships sharing one track file over their link would hold), with
its own radar's visibility and predicted SNR and the number of other radars that can see each
track; its own radar's row; the globals.
"""

from __future__ import annotations

import functools
from typing import Optional

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from .core import PULSE_LEVELS, SEARCH_SHARES
from .env import GLOBAL_FEATURES, RADAR_FEATURES, TRACK_FEATURES, NetworkEnv, _as_index, _box

AGENT_TRACK_FEATURES = (
    ("visible", "0/1: own radar can see it", 0.0, 1.0),
    ("snr_db", "dB, own radar's predicted single-pulse SNR (0 if not visible)", -50.0, 100.0),
    ("others_visible", "how many other radars can see it", 0.0, 64.0),
)


class ParallelNetworkEnv(ParallelEnv):
    """One agent per ship. Arguments as :class:`mimo_ta.gym.NetworkEnv`."""

    metadata = {"render_modes": [], "name": "mimo_network_v0", "is_parallelizable": True}

    def __init__(self, scenario=1, duration_s: float = 300.0, max_tracks: int = 16, energy_weight: float = 1e-3,
                 decision_period_s: float = 1.0, mimo_bin: Optional[str] = None,
                 tracker_config: Optional[dict] = None, extra_args: tuple = (), reply_timeout_s: float = 86400.0,
                 workdir: Optional[str] = None, tracker: str = "builtin") -> None:
        # The single-agent environment holds the run and its observation; agents see parts of it.
        self._env = NetworkEnv(scenario=scenario, duration_s=duration_s, max_tracks=max_tracks,
                               energy_weight=energy_weight, decision_period_s=decision_period_s, mimo_bin=mimo_bin,
                               tracker_config=tracker_config, extra_args=extra_args,
                               reply_timeout_s=reply_timeout_s, workdir=workdir, tracker=tracker)
        self.k = self._env.k
        self.possible_agents = list(self._env.radars)
        self.agents: list = []
        self.n_wait = 2 * len(SEARCH_SHARES)
        self.n_actions = self.n_wait + self.k * 2 * len(PULSE_LEVELS)
        self._act = spaces.Discrete(self.n_actions)
        feats = TRACK_FEATURES + AGENT_TRACK_FEATURES
        self._obs = spaces.Dict({
            "tracks": _box(feats, (self.k, len(feats))),
            "radar": _box(RADAR_FEATURES, (len(RADAR_FEATURES),)),
            "globals": _box(GLOBAL_FEATURES, (len(GLOBAL_FEATURES),)),
            "action_mask": spaces.Box(0, 1, (self.n_actions,), dtype=np.int8),
        })

    @functools.lru_cache(maxsize=None)
    def observation_space(self, agent):
        return self._obs

    @functools.lru_cache(maxsize=None)
    def action_space(self, agent):
        return self._act

    # -- actions ------------------------------------------------------------------------------

    def decode(self, action) -> dict:
        a = _as_index(action, self.n_actions)
        ns = len(SEARCH_SHARES)
        if a < self.n_wait:
            return {"kind": "wait", "accept": a < ns, "search_share": SEARCH_SHARES[a % ns]}
        a -= self.n_wait
        a, p = divmod(a, len(PULSE_LEVELS))
        slot, m = divmod(a, 2)
        return {"kind": "look", "accept": True, "slot": slot, "mimo": bool(m), "pulses": PULSE_LEVELS[p]}

    def encode(self, kind: str, *, accept: bool = True, search_share: float = 1.0, slot: int = 0,
               mimo: bool = False, pulses: int = 0) -> int:
        if kind == "wait":
            return (0 if accept else len(SEARCH_SHARES)) + SEARCH_SHARES.index(search_share)
        return self.n_wait + (slot * 2 + int(mimo)) * len(PULSE_LEVELS) + PULSE_LEVELS.index(pulses)

    def _mask(self, agent: str) -> np.ndarray:
        mask = np.zeros(self.n_actions, dtype=np.int8)
        mask[: self.n_wait] = 1
        run = self._env.run
        if run is None or run.done:
            return mask
        maxp = run.params[agent].max_pulses
        npl = len(PULSE_LEVELS)
        for slot in range(self.k):
            if run.track_in(slot) is None:
                continue
            for m in (0, 1):
                if run.look_problem(slot, agent, bool(m), 1) is None:
                    base = self.n_wait + (slot * 2 + m) * npl
                    mask[base: base + npl] = [pl <= maxp for pl in PULSE_LEVELS]
        return mask

    # -- the PettingZoo API -------------------------------------------------------------------

    def reset(self, seed: Optional[int] = None, options: Optional[dict] = None):
        obs, info = self._env.reset(seed=seed, options=options)
        self.agents = list(self.possible_agents)
        return self._observe(obs), {a: dict(info) for a in self.agents}

    def step(self, actions: dict):
        run = self._env.run
        if run is None or run.done or not self.agents:
            raise RuntimeError("step() after the episode ended: call reset()")
        missing = [a for a in self.agents if a not in actions]
        if missing:
            raise ValueError(f"actions: no action for agent(s) {missing}")
        decoded = {}
        for agent in self.agents:  # everything is checked before anything is sent
            try:
                d = self.decode(actions[agent])
            except ValueError as e:
                raise ValueError(f"actions[{agent!r}]: {e}") from None
            if d["kind"] == "look":
                problem = run.look_problem(d["slot"], agent, d["mimo"], d["pulses"])
                if problem is not None:
                    raise ValueError(f"actions[{agent!r}] = {int(actions[agent])} is masked: {problem[0]}: {problem[1]}")
            decoded[agent] = d
        accepting = [a for a in self.agents if decoded[a]["accept"]]
        run.step_energy_kj = 0.0
        dropped = {}
        for agent in self.agents:
            d = decoded[agent]
            if d["kind"] == "look":
                if d["slot"] in run.looked:
                    dropped[agent] = f"track slot {d['slot']} was given to another ship's look"
                    continue
                run.look(d["slot"], agent, d["mimo"], d["pulses"], receivers=accepting)
        for agent in self.agents:
            if decoded[agent]["kind"] == "wait":
                run.order_search(decoded[agent]["search_share"], agent)
        if run.builtin:  # a ship that waits accepting takes the built-in rule's looks it transmits
            gained = run.defer(set(accepting) - {a for a in self.agents if decoded[a]["kind"] == "look"})
        else:
            gained = run.wait()
        reward = gained - self._env.energy_weight * run.step_energy_kj
        done = run.done
        obs = self._observe(self._env._observe())
        info = self._env._info()
        agents = list(self.agents)
        infos = {a: dict(info, **({"dropped": dropped[a]} if a in dropped else {})) for a in agents}
        rewards = {a: float(reward) for a in agents}
        terms = {a: done for a in agents}
        truncs = {a: False for a in agents}
        if done:
            self.agents = []
        return obs, rewards, terms, truncs, infos

    def close(self) -> None:
        self._env.close()

    def state(self) -> dict:
        """The single-agent observation (the whole network's view)."""
        return self._env._observe()

    def _observe(self, full: dict) -> dict:
        out = {}
        nt = len(TRACK_FEATURES)
        tracks = full["tracks"]
        vis_all = tracks[:, nt::2]
        for i, agent in enumerate(self.possible_agents):
            t = np.zeros(self._obs["tracks"].shape, dtype=np.float32)
            t[:, :nt] = tracks[:, :nt]
            t[:, nt] = tracks[:, nt + 2 * i]
            t[:, nt + 1] = tracks[:, nt + 2 * i + 1]
            t[:, nt + 2] = vis_all.sum(axis=1) - tracks[:, nt + 2 * i]
            out[agent] = {"tracks": t, "radar": full["radars"][i].copy(), "globals": full["globals"].copy(),
                          "action_mask": self._mask(agent)}
        return out

    def __del__(self):
        try:
            self._env.close()
        except Exception:
            pass

