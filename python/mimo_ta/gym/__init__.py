"""Learning environments on the benchmark (optional extra ``gym``: ``pip install './python[gym]'``).

* :class:`NetworkEnv` — Gymnasium, registered as ``mimo/Network-v0``: one agent schedules the
  looks and search of every radar;
* :class:`ParallelNetworkEnv` — PettingZoo parallel API, one agent per ship (``mimo_ta.gym.parallel``);
* :mod:`mimo_ta.gym.policies` — baselines: a random agent and the default test article's rule.

python/README.md ("Learning environments") documents them; docs/decisions/0311-learning-
environments.md records the choices.
"""

from .core import PULSE_LEVELS, SEARCH_SHARES, MimoError, NetworkRun
from .env import Action, NetworkEnv

try:
    from gymnasium.envs.registration import register, registry

    if "mimo/Network-v0" not in registry:
        register(id="mimo/Network-v0", entry_point="mimo_ta.gym.env:NetworkEnv")
except ImportError:  # pragma: no cover - gymnasium is the extra's dependency
    pass

__all__ = ["Action", "MimoError", "NetworkEnv", "NetworkRun", "PULSE_LEVELS", "SEARCH_SHARES"]


def __getattr__(name):  # PettingZoo is imported only when the parallel environment is asked for
    if name == "ParallelNetworkEnv":
        from .parallel import ParallelNetworkEnv

        return ParallelNetworkEnv
    raise AttributeError(name)
