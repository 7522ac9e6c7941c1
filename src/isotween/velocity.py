"""Relative velocity fields (Sec. 3) of a shape sequence."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .optimisation.schemes import midpoint_angle, step_angle
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

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> field = isotween.relative_velocity_field(isotween.interpolate(bar, bar.rotate(1.0), frames=5))
    >>> bool(np.allclose(field.angular_speeds, field.angular_speeds[0, 0]))  # turns at constant speed
    True
    """

    shape: Shape
    times: np.ndarray
    edges: np.ndarray
    velocities: np.ndarray
    angular_speeds: np.ndarray

    def isometric_residual(self) -> np.ndarray:
        """(E, m) complex: e' - c R(pi/2) e, the non-isometric part (Eq. 2-3).

        Examples
        --------
        >>> import numpy as np
        >>> import isotween
        >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
        >>> stretch = isotween.interpolate(bar, bar.scale(2.0), frames=3)
        >>> np.round(np.abs(isotween.relative_velocity_field(stretch).isometric_residual()), 9).tolist()
        [[1.0, 1.0]]
        """
        e0, e1 = self.edges[:, :-1], self.edges[:, 1:]
        return self.velocities - 1j * self.angular_speeds * 0.5 * (e0 + e1)


def relative_velocity_field(seq: Sequence, *, scheme: str = "midpoint") -> RelativeVelocityField:
    """The :class:`RelativeVelocityField` of a :class:`Sequence`.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> field = isotween.relative_velocity_field(isotween.interpolate(bar, bar.rotate(1.0), frames=5))
    >>> field.edges.shape, field.velocities.shape, field.angular_speeds.shape
    ((2, 5), (2, 4), (2, 4))
    >>> bool(np.abs(field.isometric_residual()).max() < 1e-9)  # a rigid turn is isometric
    True
    """
    if not isinstance(seq, Sequence):
        raise TypeError("relative_velocity_field takes an isotween.Sequence")
    e = seq.edge_vectors().T.copy()
    h = np.diff(seq.times)
    de = np.diff(e, axis=1)
    omega = midpoint_angle(e[:, :-1], e[:, 1:])[0] if scheme == "midpoint" else step_angle(e[:, :-1], de)  # Eq. (8)
    return RelativeVelocityField(seq.shape, seq.times.copy(), e, de / h, omega / h)
