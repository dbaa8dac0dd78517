"""``mimo/Network-v0``: the resource manager of the MIMO radar network as a Gymnasium environment.

See python/README.md ("Learning environments") for the observation, action and reward, and
docs/decisions/0311-learning-environments.md for the choices behind them.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
import weakref
from typing import NamedTuple, Optional

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from .core import PULSE_LEVELS, SEARCH_SHARES, TRACKERS, NetworkRun

TRACK_FEATURES = (
    # name, unit, low, high
    ("present", "0/1", 0.0, 1.0),
    ("confirmed", "0/1", 0.0, 1.0),
    ("due", "0/1: the default rule's revisit time has come (builtin: the rule proposed a look not made yet)", 0.0, 1.0),
    ("pending", "0/1: a look is ordered and not reported yet", 0.0, 1.0),
    ("east_km", "km, predicted to now, ENU at the scenario centre", -1000.0, 1000.0),
    ("north_km", "km", -1000.0, 1000.0),
    ("up_km", "km", -10.0, 100.0),
    ("v_east_mps", "m/s", -2000.0, 2000.0),
    ("v_north_mps", "m/s", -2000.0, 2000.0),
    ("v_up_mps", "m/s", -2000.0, 2000.0),
    ("pos_std_m", "m, sqrt(trace(P_pos)/3), predicted to now", 0.0, 1e5),
    ("vel_std_mps", "m/s, sqrt(trace(P_vel)/3)", 0.0, 1e4),
    ("age_s", "s since the track started", 0.0, 1e5),
    ("since_update_s", "s since its last update", 0.0, 1e5),
    ("since_look_s", "s since the agent last ordered a look at it (its age if never)", 0.0, 1e5),
    ("until_due_s", "s until the default rule's revisit (negative: overdue; builtin: since proposed, or until "
                    "2 s after the last update)", -100.0, 100.0),
    ("misses", "consecutive missed looks", 0.0, 100.0),
)
RADAR_TRACK_FEATURES = (
    ("visible", "0/1: in the radar's scan limits and above its horizon", 0.0, 1.0),
    ("snr_db", "dB, predicted single-pulse SNR of a monostatic look, 2 m^2 (0 if not visible)", -50.0, 100.0),
)
RADAR_FEATURES = (
    ("search_share", "share of idle time given to background search", 0.0, 1.0),
    ("queued_s", "s of ordered looks (transmit or receive) not reported yet", 0.0, 1e3),
    ("ta_time_fraction", "looks' dwell time so far / time elapsed", 0.0, 1e3),
    ("energy_kj", "kJ spent so far (looks, plus search estimated)", 0.0, 1e7),
)
GLOBAL_FEATURES = (
    ("time_fraction", "t / duration", 0.0, 1.0),
    ("looks_ordered", "looks ordered at this decision point", 0.0, 1e4),
    ("overflow", "live tracks without a slot", 0.0, 1e4),
)


def _box(features, shape) -> spaces.Box:
    low = np.array([f[2] for f in features], dtype=np.float32)
    high = np.array([f[3] for f in features], dtype=np.float32)
    return spaces.Box(np.broadcast_to(low, shape).copy(), np.broadcast_to(high, shape).copy(), dtype=np.float32)


class Action(NamedTuple):
    """A decoded action: ``kind`` is ``wait`` (with ``search_share``), ``defer`` (accept the
    built-in rule's proposals and wait; ``tracker="builtin"`` only) or ``look``."""

    kind: str
    search_share: Optional[float] = None
    slot: Optional[int] = None
    transmitter: Optional[str] = None
    mimo: Optional[bool] = None
    pulses: Optional[int] = None


class SafeSampleDiscrete(spaces.Discrete):
    """``Discrete`` whose ``sample()`` without a mask draws among the actions valid in every
    state — the waits (one per search share) — so that a state-blind sample never names a track
    slot that may be empty. ``sample(mask=env.action_masks().astype(np.int8))`` draws among every
    action valid now."""

    def __init__(self, n: int, n_always_valid: int, seed=None) -> None:
        super().__init__(n, seed=seed)
        self.n_always_valid = int(n_always_valid)

    def sample(self, mask=None, probability=None):
        if mask is None and probability is None:
            mask = np.zeros(self.n, dtype=np.int8)
            mask[: self.n_always_valid] = 1
        return super().sample(mask=mask, probability=probability)


class NetworkEnv(gym.Env):
    """One agent schedules every radar of the network (docs/decisions/0311-learning-environments.md).

    Arguments: ``scenario`` (1–7 or a scenario TOML path), ``duration_s`` (of an episode, s),
    ``max_tracks`` (K, track slots observed), ``energy_weight`` (λ, reward per kJ),
    ``decision_period_s`` (longest simulated time between two decision points), ``mimo_bin``
    (default: :func:`mimo_ta.binary.find_mimo_bin`), ``tracker_config`` (settings of
    ``mimo_ta.simple``), ``extra_args`` (more ``mimo simulate`` options, e.g. ``("--raid", "8")``),
    ``reply_timeout_s`` (``--ta-timeout``: how long mimo waits for the agent), ``workdir`` (where
    runs are written; a temporary directory removed on ``close`` by default), ``tracker``
    (``builtin``: the built-in default test article's tracker, whose rule proposes looks the
    *defer* action accepts, docs/ta-protocol.md §7; ``simple``: ``mimo_ta.simple``'s, in Python).
    ``tracker_config``: with ``builtin``, keys of the built-in's configuration given to mimo as
    ``--set key=value`` (e.g. ``{"resource_manager.mimo": False}``); with ``simple``, its settings.
    """

    metadata = {"render_modes": []}

    def __init__(self, scenario=1, duration_s: float = 300.0, max_tracks: int = 16, energy_weight: float = 1e-3,
                 decision_period_s: float = 1.0, mimo_bin: Optional[str] = None,
                 tracker_config: Optional[dict] = None, extra_args: tuple = (), reply_timeout_s: float = 86400.0,
                 workdir: Optional[str] = None, tracker: str = "builtin") -> None:
        super().__init__()
        if tracker not in TRACKERS:
            raise ValueError(f"tracker: {tracker!r}, expected one of {TRACKERS}")
        self.tracker = tracker
        self.scenario = scenario
        self.duration_s = float(duration_s)
        self.k = int(max_tracks)
        self.energy_weight = float(energy_weight)
        self.decision_period_s = float(decision_period_s)
        self.mimo_bin = mimo_bin
        self.tracker_config = tracker_config
        self.extra_args = tuple(extra_args)
        self.reply_timeout_s = reply_timeout_s
        self._own_workdir = workdir is None
        self.workdir = workdir or tempfile.mkdtemp(prefix="mimo-gym-")
        os.makedirs(self.workdir, exist_ok=True)
        if self._own_workdir:  # removed even if close() is never called
            weakref.finalize(self, shutil.rmtree, self.workdir, True)
        self.run: Optional[NetworkRun] = None
        self._episode = 0
        self._mask_key = self._obs_key = None
        self._mask = self._obs_tracks = None
        # The spaces depend on the radars, which only a run's start message names: a probe run of
        # 1 s (and its reference run) tells them, and refuses a scenario mimo cannot load.
        self.radars = self._probe_radars()
        r = len(self.radars)
        self.shares = SEARCH_SHARES
        self.pulse_levels = PULSE_LEVELS
        # The actions valid in every state: a wait per search share, then (builtin) defer.
        self.n_wait = len(self.shares) + (tracker == "builtin")
        self.defer_action = len(self.shares) if tracker == "builtin" else None
        self.n_looks = self.k * r * 2 * len(self.pulse_levels)
        self.action_space = SafeSampleDiscrete(self.n_wait + self.n_looks, self.n_wait)
        self.observation_space = spaces.Dict({
            "tracks": _box(TRACK_FEATURES + RADAR_TRACK_FEATURES * r,
                           (self.k, len(TRACK_FEATURES) + r * len(RADAR_TRACK_FEATURES))),
            "radars": _box(RADAR_FEATURES, (r, len(RADAR_FEATURES))),
            "globals": _box(GLOBAL_FEATURES, (len(GLOBAL_FEATURES),)),
        })

    def _probe_radars(self) -> list:
        run = NetworkRun(scenario=self.scenario, seed=0, duration_s=min(self.duration_s, 1.0), max_tracks=1,
                         energy_weight=0.0, decision_period_s=1.0, mimo_bin=self.mimo_bin, tracker_config=None,
                         extra_args=self.extra_args, reply_timeout_s=self.reply_timeout_s,
                         workdir=tempfile.mkdtemp(dir=self.workdir), tracker=self.tracker)
        try:
            return list(run.radars)
        finally:
            run.close()
            shutil.rmtree(run.workdir, ignore_errors=True)

    # -- actions ------------------------------------------------------------------------------

    def decode(self, action) -> Action:
        """The meaning of an action index; ``ValueError`` naming ``action`` if outside the space."""
        a = _as_index(action, self.action_space.n)
        if a < len(self.shares):
            return Action("wait", search_share=self.shares[a])
        if a < self.n_wait:
            return Action("defer")
        a -= self.n_wait
        a, p = divmod(a, len(self.pulse_levels))
        a, m = divmod(a, 2)
        slot, r = divmod(a, len(self.radars))
        return Action("look", slot=slot, transmitter=self.radars[r], mimo=bool(m), pulses=self.pulse_levels[p])

    def encode(self, act: Action) -> int:
        if act.kind == "wait":
            return self.shares.index(act.search_share)
        if act.kind == "defer":
            if self.defer_action is None:
                raise ValueError("action: defer needs tracker='builtin'")
            return self.defer_action
        r = self.radars.index(act.transmitter)
        return self.n_wait + ((act.slot * len(self.radars) + r) * 2 + int(act.mimo)) * len(self.pulse_levels) \
            + self.pulse_levels.index(act.pulses)

    def action_masks(self) -> np.ndarray:
        """Booleans, one per action: ``True`` where the action is allowed now (the convention
        of sb3-contrib's ``MaskablePPO``). The same rules as the checks of ``step``
        (:meth:`mimo_ta.gym.core.NetworkRun.look_problem`), computed once per state."""
        run = self.run
        if run is None or run.done:
            mask = np.zeros(self.action_space.n, dtype=bool)
            mask[: self.n_wait] = True
            return mask
        key = (self._episode, run.steps, len(run.looked))
        if self._mask_key == key:
            return self._mask.copy()
        mask = np.zeros(self.action_space.n, dtype=bool)
        mask[: self.n_wait] = True
        npl, nr = len(self.pulse_levels), len(self.radars)
        for slot in range(self.k):
            t = run.track_in(slot)
            if t is None or slot in run.looked or t.pending_since_s is not None:
                continue
            vis = run.visibility(slot)
            for ri, tx in enumerate(self.radars):
                if tx not in vis:
                    continue
                ok = [pl <= run.params[tx].max_pulses for pl in self.pulse_levels]
                base = self.n_wait + (slot * nr + ri) * 2 * npl
                mask[base: base + npl] = ok
                if len(vis) > 1:
                    mask[base + npl: base + 2 * npl] = ok
        self._mask_key, self._mask = key, mask
        return mask.copy()

    # -- the Gymnasium API --------------------------------------------------------------------

    def reset(self, *, seed: Optional[int] = None, options: Optional[dict] = None):
        super().reset(seed=seed)
        self._close_run()
        mimo_seed = int(seed) if seed is not None else int(self.np_random.integers(0, 2**31 - 1))
        self._episode += 1
        self.run = NetworkRun(scenario=self.scenario, seed=mimo_seed, duration_s=self.duration_s,
                              max_tracks=self.k, energy_weight=self.energy_weight,
                              decision_period_s=self.decision_period_s, mimo_bin=self.mimo_bin,
                              tracker_config=self.tracker_config, extra_args=self.extra_args,
                              reply_timeout_s=self.reply_timeout_s,
                              workdir=tempfile.mkdtemp(prefix=f"episode-{self._episode:04d}-", dir=self.workdir),
                              tracker=self.tracker)
        if list(self.run.radars) != self.radars:
            raise ValueError(f"scenario radars {self.run.radars} differ from the environment's {self.radars}")
        return self._observe(), self._info()

    def step(self, action):
        run = self.run
        if run is None or run.done:
            raise RuntimeError("step() after the episode ended: call reset()")
        act = self.decode(action)
        run.step_energy_kj = 0.0
        gained = 0.0
        if act.kind == "wait":
            run.order_search(act.search_share)
            gained = run.wait()
        elif act.kind == "defer":
            gained = run.defer()
        else:
            problem = run.look_problem(act.slot, act.transmitter, act.mimo, act.pulses)
            if problem is not None:
                raise ValueError(f"action {int(action)} ({_describe(act)}) is masked: {problem[0]}: {problem[1]}")
            run.look(act.slot, act.transmitter, act.mimo, act.pulses)
        reward = gained - self.energy_weight * run.step_energy_kj
        terminated = run.done
        obs = self._observe()
        return obs, float(reward), terminated, False, self._info()

    def close(self) -> None:
        self._close_run()
        if self._own_workdir:
            shutil.rmtree(self.workdir, ignore_errors=True)

    def _close_run(self) -> None:
        if self.run is not None:
            self.run.close()
            if not self.run.done:
                shutil.rmtree(self.run.workdir, ignore_errors=True)
            elif self._own_workdir and self.run.workdir:
                shutil.rmtree(self.run.workdir, ignore_errors=True)
            self.run = None

    # -- observation --------------------------------------------------------------------------

    def _info(self) -> dict:
        run = self.run
        info = {"t_s": run.now_s, "seed": run.seed, "energy_kj": run.energy_kj,
                "online_completeness": run.online.completeness_sum}
        if run.done:
            info["score"] = dict(run.score)
        return info

    def _observe(self) -> dict:
        obs = {k: np.zeros(s.shape, dtype=np.float32) for k, s in self.observation_space.spaces.items()}
        run = self.run
        if run.done:
            obs["globals"][0] = 1.0
            return self._clip(obs)
        tr = run.tracker
        now = run.now_s
        nt = len(TRACK_FEATURES)
        born, last_look = run.born, run.last_look
        # Track rows change within a decision point only where a look was ordered.
        same_point = self._obs_key == (self._episode, run.steps)
        if same_point:
            obs["tracks"][:] = self._obs_tracks
        slots, xs, ps, _ = run.predicted_all()
        rows = [k for k, slot in enumerate(slots) if not same_point or slot in run.looked]
        if rows:
            tk = obs["tracks"]
            sel = [slots[k] for k in rows]
            ts = [run.track_in(slot) for slot in sel]
            x, p = xs[rows], ps[rows]
            pos_std = np.sqrt(np.maximum(np.trace(p[:, :3, :3], axis1=1, axis2=2) / 3, 0.0)).tolist()
            vel_std = np.sqrt(np.maximum(np.trace(p[:, 3:, 3:], axis1=1, axis2=2) / 3, 0.0)).tolist()
            table = []
            for t, (e, n, u, ve, vn, vu), ps_, vs_ in zip(ts, x.tolist(), pos_std, vel_std):
                age = now - born[t.id]
                table.append((1.0, t.status == "confirmed", t.next_due_s <= now + 1e-9, t.pending_since_s is not None,
                              e / 1e3, n / 1e3, u / 1e3, ve, vn, vu, ps_, vs_, age, now - t.last_update_s,
                              now - last_look[t.id] if t.id in last_look else age, t.next_due_s - now,
                              t.misses_in_row))
            tk[sel, :nt] = table
            _, seen, snr = run.visibility_arrays()
            seen, snr = seen[:, rows], snr[:, rows]
            tk[sel, nt::2] = seen.T
            tk[sel, nt + 1::2] = np.where(seen, 10.0 * np.log10(np.maximum(snr, 1e-10)), 0.0).T
        for ri, r in enumerate(self.radars):
            obs["radars"][ri] = (run.share[r], sum(run.pending_time[r].values()),
                                 run.ta_time_by_radar_s[r] / max(now, 1e-3), run.energy_by_radar_kj[r])
        if not same_point:
            self._obs_key, self._obs_tracks = (self._episode, run.steps), obs["tracks"].copy()
        held = set(s for s in run.slots if s is not None)
        obs["globals"][:] = (now / run.duration_s, len(run.looked), sum(1 for t in tr.tracks if t not in held))
        return self._clip(obs)

    def _clip(self, obs: dict) -> dict:
        for k, s in self.observation_space.spaces.items():
            x = obs[k]
            np.minimum(np.maximum(x, s.low, out=x), s.high, out=x)
        return obs


def _as_index(action, n: int) -> int:
    a = np.asarray(action)
    if a.shape != () or not np.issubdtype(a.dtype, np.integer) or not 0 <= int(a) < n:
        raise ValueError(f"action {action!r} is outside the action space: an integer in [0, {n})")
    return int(a)


def _describe(act: Action) -> str:
    if act.kind == "wait":
        return f"wait, search share {act.search_share}"
    if act.kind == "defer":
        return "defer to the rule"
    pulses = "rule" if act.pulses == 0 else act.pulses
    return (f"look: track slot {act.slot}, transmitter {act.transmitter}, receivers "
            f"{'MIMO' if act.mimo else 'monostatic'}, pulses {pulses}")
