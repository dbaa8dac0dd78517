"""mimo's bistatic measurement as a Stone Soup measurement model (docs/model.md §5.4).

A detection on a receiver face (origin ``rx_position_m``, rotation ``rx_rotation`` whose rows are
the face's x, y and boresight axes) of a transmission from ``tx_position_m`` measures
``(rho, u, v)``: rho = (|p - t| + |p - r|) / 2, the ``range_m`` of the measurements table
(schemas/measurements.json), and the direction cosines of the target in the receiver face.
Monostatic is ``tx_position_m == rx_position_m``. The noise is the covariance the engine reported
with the measurement: ``diag(var_range_m2, var_u, var_v)``.

Positions and the rotation are given in the tracking frame (the local ENU frame at the scenario
centre in :class:`mimo_ta.stonesoup.StoneSoupArticle`); the state is Stone Soup's
``[x, vx, y, vy, z, vz]`` unless ``mapping`` says otherwise. :meth:`MimoBistaticModel.jacobian`
is analytic and :meth:`MimoBistaticModel.inverse_function` the closed form of §5.4, which is what
Stone Soup's measurement initiators call.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from stonesoup.base import Property
from stonesoup.models.base import GaussianModel, ReversibleModel
from stonesoup.models.measurement.base import MeasurementModel
from stonesoup.types.array import CovarianceMatrix, StateVector, StateVectors

from ..measurement import h_rho, jacobian, ruv_to_position

_RHO_UV = np.array([0.5, 1.0, 1.0])


class MimoBistaticModel(MeasurementModel, GaussianModel, ReversibleModel):
    """``(rho, u, v)`` of a Tx -> Rx channel, with the measurement's reported covariance."""

    tx_position_m: np.ndarray = Property(doc="Transmitter array centre in the tracking frame (m)")
    rx_position_m: np.ndarray = Property(doc="Receiver face centre in the tracking frame (m)")
    rx_rotation: np.ndarray = Property(
        doc="Rotation tracking frame -> receiver face (rows: face x, face y, boresight)")
    noise_covar: CovarianceMatrix = Property(doc="Measurement covariance of (rho, u, v): m^2, 1, 1")
    ndim_state: int = Property(default=6, doc="Number of state dimensions")
    mapping: Sequence[int] = Property(default=(0, 2, 4), doc="State indices of x, y, z")

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.tx_position_m = np.asarray(self.tx_position_m, dtype=float).reshape(3)
        self.rx_position_m = np.asarray(self.rx_position_m, dtype=float).reshape(3)
        self.rx_rotation = np.asarray(self.rx_rotation, dtype=float).reshape(3, 3)
        if not isinstance(self.noise_covar, CovarianceMatrix):
            self.noise_covar = CovarianceMatrix(self.noise_covar)

    @property
    def ndim_meas(self) -> int:
        return 3

    def covar(self, **kwargs) -> CovarianceMatrix:
        return self.noise_covar

    def function(self, state, noise=False, **kwargs):
        """``(rho, u, v)`` of the state's position (one state, or many as columns)."""
        sv = state.state_vector
        p = np.asarray(sv[list(self.mapping), :], dtype=float).T  # (N, 3)
        z = h_rho(p, self.tx_position_m, self.rx_position_m, self.rx_rotation).T  # (3, N)
        if isinstance(noise, bool) or noise is None:
            noise = self.rvs(num_samples=z.shape[1], **kwargs) if noise else 0.0
        out = z + noise
        return StateVector(out) if out.shape[1] == 1 else StateVectors(out)

    def jacobian(self, state, **kwargs) -> np.ndarray:
        """``d(rho, u, v)/dx`` at the state: (3, ndim_state), zero outside the position columns."""
        p = np.asarray(state.state_vector[list(self.mapping), 0], dtype=float).reshape(3)
        j = np.zeros((3, self.ndim_state))
        j_pos = jacobian(p, self.tx_position_m, self.rx_position_m, self.rx_rotation)
        j[:, list(self.mapping)] = j_pos * _RHO_UV[:, None]
        return j

    def position_of(self, rho_m: float, u: float, v: float):
        """The position with measurement ``(rho, u, v)``, or ``None`` where there is none
        (``u^2 + v^2 >= 1``, rho not beyond half the baseline, or behind the receiver)."""
        return ruv_to_position(2.0 * float(rho_m), float(u), float(v), self.tx_position_m, self.rx_position_m,
                               self.rx_rotation)

    def inverse_function(self, detection, **kwargs) -> StateVector:
        """The state (position filled in through ``mapping``, zeros elsewhere) whose measurement
        is the detection's; ``ValueError`` when none exists (see :meth:`position_of`)."""
        rho, u, v = (float(x) for x in np.asarray(detection.state_vector, dtype=float).reshape(-1)[:3])
        p = self.position_of(rho, u, v)
        if p is None:
            raise ValueError(f"no position has the measurement (rho={rho} m, u={u}, v={v}) on this channel")
        out = np.zeros((self.ndim_state, 1))
        out[list(self.mapping), 0] = p
        return StateVector(out)
