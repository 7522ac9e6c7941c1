"""Relative velocity fields (Sec. 3) of a shape sequence."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .optimisation.schemes import step_angle
from .sequence import Sequence
from .shape import Shape

__all__ = ["RelativeVelocityField", "relative_velocity_field"]


@dataclass
class RelativeVelocityField:
    """The edge vectors of a sequence and their rates of change.

    Attributes
    ----------
    shape : Shape
        Connectivity.
    times : (m+1,) float
    edges : (E, m+1) complex
        Edge vector field E(t_k): p_j - p_i of every edge (i, j) and frame.
    velocities : (E, m) complex
        Relative velocity field E'(t_k) = (e(t_{k+1}) - e(t_k)) / h_k (Eq. 7).
    angular_speeds : (E, m) float
        c_ij(t_k) of the corrected Eq. (8), fitted at the interval's midpoint
        (``scheme='midpoint'``) or at e(t_k) (``scheme='paper'``).
    """

    shape: Shape
    times: np.ndarray
    edges: np.ndarray
    velocities: np.ndarray
    angular_speeds: np.ndarray

    def isometric_residual(self) -> np.ndarray:
        """(E, m) complex: e' - c R(pi/2) e, the non-isometric part (Eq. 2-3)."""
        e0, e1 = self.edges[:, :-1], self.edges[:, 1:]
        return self.velocities - 1j * self.angular_speeds * 0.5 * (e0 + e1)


def relative_velocity_field(seq: Sequence, scheme: str = "midpoint") -> RelativeVelocityField:
    """The :class:`RelativeVelocityField` of a :class:`Sequence`."""
    if not isinstance(seq, Sequence):
        raise TypeError("relative_velocity_field takes an isotween.Sequence")
    e = seq.edge_vectors().T.copy()
    h = np.diff(seq.times)
    de = np.diff(e, axis=1)
    at = e[:, :-1] + 0.5 * de if scheme == "midpoint" else e[:, :-1]
    return RelativeVelocityField(seq.shape, seq.times.copy(), e, de / h, step_angle(at, de) / h)
