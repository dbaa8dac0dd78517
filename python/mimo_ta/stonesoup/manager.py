"""Stone Soup sensor managers choosing the looks of :class:`mimo_ta.gym.NetworkEnv`.

Each radar of the network is a Stone Soup actionable (:class:`MimoRadar`) whose one action
generator (:class:`LookActionGenerator`) lists the looks the environment allows now with that
radar transmitting — a track slot, monostatic or MIMO, a pulse level — and *no look*. Any
``SensorManager`` that works on actionables and a reward function (``GreedySensorManager``,
``BruteForceSensorManager``, the optimisers of ``stonesoup.sensormanager.optimise``) then chooses
at every decision point; :func:`run_episode` plays the chosen looks and waits.

:class:`LookReward` is the reward: the expected information gain of a look (the D-optimal
criterion: P_D × ½ ln det P⁻ / det P⁺ of the track's predicted position covariance, every
channel of the look an EKF update with the mimo measurement model, docs/model.md §5.4, and noise
from the predicted SNR) **minus a price on the look's transmitted energy and on the radar time it
holds** (every participant's dwell) — Stone Soup's own reward functions price neither.
Needs Stone Soup and the ``[gym]`` extra.
"""

from __future__ import annotations

import datetime
import math
from typing import Any, Optional

import numpy as np
from stonesoup.base import Base, Property
from stonesoup.sensormanager.action import Action, ActionGenerator
from stonesoup.sensormanager.reward import RewardFunction

from ..measurement import jacobian
from ..radar import SPEED_OF_LIGHT_MPS, pd_sw1, predict_pair

from .article import EPOCH  # simulation time t_s is EPOCH + t_s, as the Stone Soup test article


def timestamp_of(t_s: float) -> datetime.datetime:
    return EPOCH + datetime.timedelta(seconds=float(t_s))


class LookAction(Action):
    """A look (``slot`` not None) or no look; ``target_value`` is ``(slot, mimo, pulses)``."""

    slot: Optional[int] = Property(default=None, doc="Track slot of the environment, None: no look.")
    mimo: bool = Property(default=False, doc="Every radar that can see the track receives.")
    pulses: int = Property(default=0, doc="Pulse level: 0 the default rule, else a count.")

    def act(self, current_time, timestamp, init_value, **kwargs):
        return self.target_value


class LookActionGenerator(ActionGenerator):
    """The looks the environment allows now with ``owner.radar`` transmitting, then no look."""

    pulse_levels: tuple = Property(default=(0,), doc="Pulse levels offered (0: the default rule).")

    def _actions(self):
        env, radar = self.owner.env, self.owner.radar
        yield LookAction(generator=self, end_time=self.end_time, target_value=None)
        mask = self.owner.env_mask()
        for slot in range(env.k):
            if env.run.track_in(slot) is None:
                continue
            for mimo in (False, True):
                for p in self.pulse_levels:
                    a = env.encode(_look(slot, radar, mimo, p))
                    if mask[a]:
                        yield LookAction(generator=self, end_time=self.end_time, target_value=(slot, mimo, p),
                                         slot=slot, mimo=mimo, pulses=p)

    def __iter__(self):
        return iter(list(self._actions()))

    def __contains__(self, item):
        return isinstance(item, LookAction) and item.generator is self

    @property
    def default_action(self):
        return LookAction(generator=self, end_time=self.end_time, target_value=None)


class MimoRadar(Base):
    """One radar of the environment as a Stone Soup actionable: ``actions(timestamp)`` gives its
    one generator of looks."""

    env: Any = Property(doc="The mimo_ta.gym.NetworkEnv.")
    radar: str = Property(doc="Radar id, e.g. R1.")
    pulse_levels: tuple = Property(default=(0,), doc="Pulse levels offered.")

    def __hash__(self):
        return hash(("MimoRadar", self.radar, id(self.env)))

    def __eq__(self, other):
        return self is other

    def env_mask(self):
        run = self.env.run
        key = ("stonesoup-mask", run.steps, len(run.looked))
        if getattr(self.env, "_ss_mask_key", None) != key:
            self.env._ss_mask_key, self.env._ss_mask = key, self.env.action_masks()
        return self.env._ss_mask

    def actions(self, timestamp, start_timestamp=None):
        start = start_timestamp or timestamp
        return {LookActionGenerator(owner=self, attribute="look", start_time=start, end_time=timestamp,
                                    pulse_levels=self.pulse_levels)}


class LookReward(RewardFunction):
    """Expected information gain of the looks of a configuration, less the price of their energy
    and radar time. A track given two looks in one configuration counts once."""

    env: Any = Property(doc="The mimo_ta.gym.NetworkEnv.")
    price_per_kj: float = Property(default=50.0, doc="Reward units (nats) per kJ transmitted.")
    price_per_s: float = Property(default=20.0, doc="Reward units per second of radar time (every participant).")
    assumed_rcs_m2: float = Property(default=2.0, doc="RCS the SNR is predicted for.")

    def __call__(self, config, tracks=None, metric_time=None, *args, **kwargs):
        total, seen = 0.0, set()
        for actionable, actions in config.items():
            for a in actions:
                if a.slot is None or a.slot in seen:
                    continue
                seen.add(a.slot)
                total += self.look_value(actionable.radar, a.slot, a.mimo, a.pulses)
        return total

    def look_value(self, tx: str, slot: int, mimo: bool, pulses: int) -> float:
        env = self.env
        run = env.run
        tr = run.tracker
        x, p = run.predicted(slot)
        aim = tr.enu.to_ecef(x[:3])
        par = run.params[tx]
        tx_faces = run._faces(tx)
        mono = predict_pair(par, tx_faces, par, tx_faces, aim, self.assumed_rcs_m2)
        if mono is None:
            return -math.inf
        n = _pulses(run, slot, tx, pulses, mono[0])
        receivers = [tx] + ([r for r in run.radars if r != tx] if mimo else [])
        info = np.zeros((3, 3))
        pd_any = 0.0
        dwell_s = 0.0
        tx_pos = tr.enu.to_enu(tx_faces[mono[1]].origin_ecef)
        for rx in receivers:
            rpar = run.params[rx]
            rx_faces = run._faces(rx)
            pr = predict_pair(par, tx_faces, rpar, rx_faces, aim, self.assumed_rcs_m2)
            if pr is None:
                continue
            snr = pr[0] * n
            face = rx_faces[pr[2]]
            rot = face.face_from_ecef @ tr.enu.enu_from_ecef.T
            h = jacobian(x[:3], tx_pos, tr.enu.to_enu(face.origin_ecef), rot)
            # Accuracy for that SNR (docs/model.md §2.5, §5.4): range to a fraction of a cell,
            # angles to a fraction of a beamwidth, both as 1/sqrt(2 SNR).
            k = 1.0 / math.sqrt(2.0 * max(snr, 1e-3))
            sig_r = SPEED_OF_LIGHT_MPS / (2.0 * rpar.bandwidth_hz) * k
            sig_uv = rpar.beamwidth_u / rpar.monopulse_slope * k
            r_inv = np.diag([1 / (2 * sig_r) ** 2, 1 / sig_uv**2, 1 / sig_uv**2])  # h gives R_B = 2 rho
            pd = pd_sw1(snr, rpar.pfa)
            info += pd * h.T @ r_inv @ h
            pd_any = max(pd_any, pd)
            dwell_s += rpar.dwell_duration_s(n)
        if pd_any == 0.0:
            return -math.inf
        pp = p[:3, :3]
        gain = 0.5 * (np.linalg.slogdet(pp)[1] - np.linalg.slogdet(np.linalg.inv(np.linalg.inv(pp) + info))[1])
        energy_kj = par.dwell_energy_j(n) / 1e3
        return float(gain - self.price_per_kj * energy_kj - self.price_per_s * dwell_s)


def _pulses(run, slot, tx, level, snr1) -> int:
    if level:
        return min(int(level), run.params[tx].max_pulses)
    from ..radar import pointing_loss, pulses_for, required_snr_sw1, straddle_loss

    t = run.track_in(slot)
    fresh = t.status == "tentative" and t.n_updates <= 1
    par = run.params[tx]
    pd = run.tracker.cfg["confirm_pd"] if fresh else run.tracker.cfg["pd_target"]
    n = pulses_for(required_snr_sw1(pd, par.pfa), snr1, pointing_loss(0.2) * straddle_loss(), par.max_pulses)
    return n if fresh else min(n * 2 ** (t.misses_in_row % 3), par.max_pulses)


def _look(slot, radar, mimo, pulses):
    from ..gym import Action as GymAction

    return GymAction("look", slot=slot, transmitter=radar, mimo=mimo, pulses=pulses)


def radars_of(env, pulse_levels=(0,)) -> set:
    """One :class:`MimoRadar` per radar of ``env``."""
    return {MimoRadar(env=env, radar=r, pulse_levels=tuple(pulse_levels)) for r in env.radars}


def run_episode(env, manager, seed: int, search_share: float = 1.0) -> tuple:
    """One episode of ``env`` with ``manager`` choosing the looks at every decision point (its
    ``sensors`` the :func:`radars_of` env); returns (return, info at the end)."""
    from ..gym import Action as GymAction

    env.reset(seed=seed)
    total = 0.0
    wait = env.encode(GymAction("wait", search_share=search_share))
    while True:
        if any(env.run.track_in(s) is not None for s in range(env.k)):
            config = manager.choose_actions(set(), timestamp_of(env.run.now_s))[0]
            for actionable in sorted(config, key=lambda a: a.radar):
                for a in config[actionable]:
                    if a.slot is None:
                        continue
                    idx = env.encode(_look(a.slot, actionable.radar, a.mimo, a.pulses))
                    if env.action_masks()[idx]:  # another radar may have taken the track
                        _, r, _, _, _ = env.step(idx)
                        total += r
        _, r, term, _, info = env.step(wait)
        total += r
        if term:
            return total, info
