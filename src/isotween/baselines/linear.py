"""Linear blending of vertex positions: z(t) = (1 - t) z(0) + t z(1)."""

from ..optimisation.problem import Result

__all__ = ["solve"]


def solve(problem):
    """Frames of the linear blend of the problem's first and last frame.

    Parameters
    ----------
    problem : Problem
        Held at the first and the last frame.

    Returns
    -------
    Result
        ``z`` (n, F) complex (a transposed view of the (F, n) blend).

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> from isotween.baselines import linear
    >>> from isotween.problems import keyed_problem
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> problem = keyed_problem([bar, bar.translate([2, 0])], np.linspace(0, 1, 3), np.array([0, 2]),
    ...                         init=None, scheme="midpoint", tol=5e-4, max_iter=100)
    >>> linear.solve(problem).z[:, 1].tolist()
    [(1+0j), (2+0j)]
    """
    z0, z1 = problem.ends()
    t = problem.times[:, None]
    return Result(((1 - t) * z0[None] + t * z1[None]).T)  # blended frame-major: one contiguous row per frame
