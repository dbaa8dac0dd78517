"""Stone Soup trackers as ``mimo`` test articles (optional: ``pip install 'mimo[stonesoup]'``).

* :class:`MimoBistaticModel` — mimo's (rho, u, v) measurement on a Tx -> Rx channel as a Stone
  Soup measurement model: function, analytic Jacobian and the closed-form inverse that Stone
  Soup's measurement initiators call (docs/model.md §5.4).
* :class:`StoneSoupArticle` — a :class:`mimo_ta.TestArticle` running a Stone Soup predictor,
  updater, data associator, initiator and deleter (or a ``MultiTargetTracker``) in the closed
  loop, with the default test article's looks (:mod:`mimo_ta.looks`).

:mod:`mimo_ta.stonesoup.manager` (with the ``[gym]`` extra) lets Stone Soup's sensor managers choose
the looks of :class:`mimo_ta.gym.NetworkEnv`, with a reward that prices energy and radar time
(``python/examples/stonesoup_manager.py``).

``python/examples/stonesoup_ta.py`` assembles an EKF + GNN tracker with a multi-measurement
initiator from Stone Soup's parts.
"""

try:
    import stonesoup  # noqa: F401
except ImportError as e:  # pragma: no cover - depends on the environment
    raise ImportError("mimo_ta.stonesoup needs Stone Soup: pip install 'mimo[stonesoup]' "
                      "(or pip install 'stonesoup>=1.9,<1.10')") from e

from .article import EPOCH, SETTINGS, Components, StoneSoupArticle, TrackerFault, stamp
from .model import MimoBistaticModel

__all__ = ["EPOCH", "SETTINGS", "Components", "MimoBistaticModel", "StoneSoupArticle", "TrackerFault", "stamp"]
