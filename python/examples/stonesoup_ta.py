#!/usr/bin/env python3
"""A Stone Soup tracker as a test article: EKF + GNN (2-D assignment) + multi-measurement initiator.

    mimo simulate --scenario 1 --ta-cmd "python3 python/examples/stonesoup_ta.py" --out runs/s1-ss

Needs Stone Soup (``pip install 'mimo[stonesoup]'``). Every part is Stone Soup's own; what
``mimo_ta.stonesoup`` adds is the measurement model of mimo's (rho, u, v) detections
(``MimoBistaticModel``, one per detection, built from the dwell report) and the closed loop
(``StoneSoupArticle``: which tracks a dwell could have seen, the looks, the track rows).

* motion: nearly-constant velocity per ENU axis (``ConstantVelocity``, continuous white noise of
  spectral density ``q_m2ps3``), the state ``[x, vx, y, vy, z, vz]`` in the ENU frame at the
  scenario centre;
* filter: ``ExtendedKalmanPredictor`` / ``ExtendedKalmanUpdater`` (the analytic Jacobian of
  docs/model.md §5.4; Joseph-form covariance, symmetrized);
* association: ``DistanceHypothesiser`` (Mahalanobis distance, gate chi^2_3(0.999)) with
  ``GNNWith2DAssignment``, channel by channel;
* initiation: ``MultiMeasurementInitiator`` — a detection no track takes starts a holding track
  (position by the model's inverse, velocity 0 +- 300 m/s); it is confirmed by a second
  detection (2 of 2: one confirmation look 0.3 s later, a miss drops it, as the built-in test
  articles do, docs/model.md §6.4);
* deletion: 3 missed looks in a row, 30 s without an update, or a position covariance trace
  above 3 x (3 km)^2.

Settings change with ``--set key=value`` (``q_m2ps3``, ``gate_chi2``, ``init_speed_sigma_mps`` and
the scheduling settings of ``mimo_ta.stonesoup.SETTINGS``, e.g. ``--set mimo=0``).
"""

from __future__ import annotations

import sys
from datetime import timedelta
from pathlib import Path

import numpy as np

# Use the package of this checkout when run from the repository (else the installed one).
_REPO_PYTHON = Path(__file__).resolve().parents[1]
if (_REPO_PYTHON / "mimo_ta").is_dir():
    sys.path.insert(0, str(_REPO_PYTHON))

from stonesoup.dataassociator.neighbour import GNNWith2DAssignment  # noqa: E402
from stonesoup.deleter.error import CovarianceBasedDeleter  # noqa: E402
from stonesoup.deleter.multi import CompositeDeleter  # noqa: E402
from stonesoup.deleter.time import UpdateTimeDeleter, UpdateTimeStepsDeleter  # noqa: E402
from stonesoup.hypothesiser.distance import DistanceHypothesiser  # noqa: E402
from stonesoup.initiator.simple import MultiMeasurementInitiator  # noqa: E402
from stonesoup.measures import Mahalanobis  # noqa: E402
from stonesoup.models.transition.linear import CombinedLinearGaussianTransitionModel, ConstantVelocity  # noqa: E402
from stonesoup.predictor.kalman import ExtendedKalmanPredictor  # noqa: E402
from stonesoup.types.state import GaussianState  # noqa: E402
from stonesoup.updater.kalman import ExtendedKalmanUpdater  # noqa: E402

from mimo_ta.stonesoup import Components, StoneSoupArticle  # noqa: E402

DEFAULTS = {
    "q_m2ps3": 225.0,  # CWNA spectral density per axis: (15 m/s^2)^2 x 1 s, docs/model.md §6.1
    "gate_chi2": 16.27,  # chi^2_3(0.999)
    "init_speed_sigma_mps": 300.0,
    "max_misses": 3.0,
    "max_coast_s": 30.0,
    "max_coast_tentative_s": 5.0,
    "max_pos_var_m2": 3.0 * 3000.0**2,
}


def ekf_gnn(s: dict, joseph: bool = True) -> Components:
    """Stone Soup's EKF + GNN with a multi-measurement initiator, from the settings ``s``
    (``joseph=False``: Stone Soup's default covariance update, P - K S K^T, as a user's tracker
    would run it; its covariances then need mimo's repair now and then, docs/design.md §7)."""
    cv = ConstantVelocity(s["q_m2ps3"])
    predictor = ExtendedKalmanPredictor(CombinedLinearGaussianTransitionModel([cv, cv, cv]))
    # Each detection carries its own model. Joseph form, symmetrized (docs/model.md §6.2): with
    # range sums known to metres and cross-range to hundreds of metres, the plain P - K S K^T
    # loses positive definiteness within a few hundred updates.
    updater = ExtendedKalmanUpdater(measurement_model=None, use_joseph_cov=joseph, force_symmetric_covariance=joseph)

    def gnn() -> GNNWith2DAssignment:
        return GNNWith2DAssignment(DistanceHypothesiser(predictor, updater, measure=Mahalanobis(),
                                                        missed_distance=float(np.sqrt(s["gate_chi2"]))))

    v2 = s["init_speed_sigma_mps"] ** 2
    initiator = MultiMeasurementInitiator(
        prior_state=GaussianState(np.zeros((6, 1)), np.diag([0.0, v2, 0.0, v2, 0.0, v2])),
        deleter=CompositeDeleter([UpdateTimeStepsDeleter(1),
                                  UpdateTimeDeleter(timedelta(seconds=s["max_coast_tentative_s"]))], intersect=False),
        data_associator=gnn(), updater=updater, min_points=2)
    deleter = CompositeDeleter([
        UpdateTimeStepsDeleter(int(s["max_misses"])),
        UpdateTimeDeleter(timedelta(seconds=s["max_coast_s"])),
        CovarianceBasedDeleter(covar_trace_thresh=s["max_pos_var_m2"], mapping=[0, 2, 4]),
    ], intersect=False)
    tracker = gnn()
    return Components(predictor, updater, tracker, initiator, deleter, tracker.hypothesiser)


if __name__ == "__main__":
    sys.exit(StoneSoupArticle(factory=ekf_gnn, defaults=DEFAULTS, name="stonesoup-ekf-gnn").run())
