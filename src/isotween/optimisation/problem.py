"""The solve core's two types: what is solved (`Problem`) and what comes out (`Result`).

A :class:`Problem` is a shape's connectivity, the frame times, which frames
are held (the inputs, or the keyframes) and where, the initial edge vectors
and the component centroids of every frame. Every entry point builds one with
the builders of :mod:`isotween.problems`: :func:`isotween.optimisation.solve.solve`
runs Algorithm 1 or 2 on it, transfer and edit assemble its edges by Eq. (10),
and the baselines (:mod:`isotween.baselines`) interpolate between its held
first and last frame. A :class:`Result` holds complex (n, F) frames and how
they were found, and turns into a :class:`~isotween.Sequence` in one place.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .._defaults import DEFAULT_TOL
from ..errors import ParameterError
from ..geometry import bbox_diagonal
from ..sequence import Sequence

if TYPE_CHECKING:
    from ..shape import Shape

__all__ = ["Problem", "Result", "bbox_diagonal", "pack", "DEFAULT_TOL"]


def pack(z: np.ndarray) -> np.ndarray:
    """(F, n, 2) float64 frames of (n, F) complex positions (one new array).

    Examples
    --------
    >>> import numpy as np
    >>> from isotween.optimisation.problem import pack
    >>> pack(np.array([[1 + 2j, 3 + 4j]])).tolist()
    [[[1.0, 2.0]], [[3.0, 4.0]]]
    """
    xy = np.empty((z.shape[1], z.shape[0], 2))
    xy.view(complex)[..., 0] = z.T
    return xy


@dataclass
class Problem:
    """What the solvers need to know.

    Attributes
    ----------
    shape : Shape
        Connectivity (edges, components).
    times : (F,) float
        Frame times, from 0 to 1.
    held : (F,) bool
        Frames that do not move (at least the first and the last).
    z : (n, F) complex
        Vertex positions; the held frames are read from it.
    edges : (E, F) complex or None
        Initial edge vectors (Eq. 13 or linear; Eq. 15 for transfer and
        edit); exact on the held frames. The local solver may overwrite this
        array. None for methods that start from the held positions alone
        (the baselines).
    centroids : (C, F) complex
        Where every component's centroid is in every frame.
    scheme : {'midpoint', 'paper'}
    tol : float
        Absolute tolerance of Eq. (11) (tau times the bounding-box diagonal).
    max_iter : int
    """

    shape: Shape
    times: np.ndarray
    held: np.ndarray
    z: np.ndarray
    edges: np.ndarray | None
    centroids: np.ndarray
    scheme: str
    tol: float
    max_iter: int

    @property
    def free(self) -> slice | np.ndarray:
        """Columns of the frames solved for: a slice when they are contiguous, else (k,) int."""
        free = np.flatnonzero(~self.held)
        if free.size and free[-1] - free[0] + 1 == free.size:
            return slice(int(free[0]), int(free[-1]) + 1)  # a view, not a copy, of the frames
        return free

    def ends(self) -> tuple[np.ndarray, np.ndarray]:
        """(n,) complex positions of the held first and last frame, for methods that blend two shapes.

        Raises
        ------
        ParameterError
            An interior frame is held, or an end is not: such methods cannot honour it.
        """
        if self.held[1:-1].any() or not (self.held[0] and self.held[-1]):
            raise ParameterError("this method holds only the first and the last frame")
        return self.z[:, 0], self.z[:, -1]


@dataclass
class Result:
    """Frames and how they were found.

    Attributes
    ----------
    z : (n, F) complex
        Vertex positions of every frame.
    energy : list of float
        Isometric energy (Eq. 6, dimensionless) after every iteration.
    iterations : int
    converged : bool
    max_move : float
        The last Eq. (11) move.
    timings : dict of str to float
        Seconds spent per stage.
    info : dict
        What the solver adds (e.g. ``cg_iterations``).
    """

    z: np.ndarray
    energy: list = field(default_factory=list)
    iterations: int = 0
    converged: bool = True
    max_move: float = 0.0
    timings: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    def frames(self) -> np.ndarray:
        """(F, n, 2) float64 array of the frames (see :func:`pack`)."""
        return pack(self.z)

    def sequence(self, shape: Shape, times: np.ndarray, *, method: str, scheme: str = "midpoint",
                 info: dict[str, Any] | None = None) -> Sequence:
        """The :class:`~isotween.Sequence` of these frames.

        Parameters
        ----------
        shape : Shape
        times : (F,) float
        method : str
        scheme : str
        info : dict, optional
            Put into ``Sequence.info`` after the result's own ``info``.
        """
        return Sequence(frames=self.frames(), shape=shape, times=times, scheme=scheme, energy=self.energy,
                        iterations=self.iterations, converged=self.converged, timings=self.timings,
                        method=method, info={**self.info, **(info or {})})
