"""Solve a `Problem` with the local (Algorithm 2) or the global (Algorithm 1) solver."""

from __future__ import annotations

import time
from typing import TYPE_CHECKING

from ..errors import ParameterError
from .assembly import FrameAssembler
from .global_solver import global_solve
from .local_solver import local_solve

if TYPE_CHECKING:
    from collections.abc import Callable

    import numpy as np

    from .problem import Problem, Result

__all__ = ["SOLVERS", "solve"]

SOLVERS = ("local", "global")


def solve(problem: Problem, *, solver: str = "local", assembly: str = "shared", linear_solver: str = "cg",
          smooth: float = 1.0, factorisation: str = "auto",
          callback: Callable[[int, float, float], object] | None = None,
          folds: Callable[[np.ndarray], int] | None = None) -> Result:
    """Solve a :class:`Problem` with Algorithm 2 ('local') or Algorithm 1 ('global').

    Parameters
    ----------
    problem : Problem
    solver : {'local', 'global'}
        The global solver holds only the first and the last frame and starts
        from Eq. (10) of the initial edges (written into ``problem.z``).
    assembly : {'shared', 'relative', 'per-frame'}
        Local solver: Eq. (10) weights (see :func:`~isotween.optimisation.local_solver.local_solve`).
    linear_solver : {'cg', 'direct'}
        Global solver: conjugate gradients or sparse LU.
    smooth : float
        Local solver: weight of the smooth turn through interior held frames.
    factorisation : {'auto', 'banded', 'cholmod', 'splu'}
        Local solver: factorisation of the shared Eq. (10) Laplacian.
    callback : callable(iteration, energy, max_move), optional
    folds : callable(z) -> int, optional
        Local solver: stop before the first iterate that folds where the
        first does not, and where the first does, once the folds spread (see
        :func:`~isotween.optimisation.local_solver.local_solve`).

    Returns
    -------
    Result
        ``timings['solve']`` and the solver's own ``solve.*`` timings.
    """
    start = time.perf_counter()
    edges = problem.edges
    if edges is None:
        raise ParameterError("the solvers start from initial edges; build the problem with init='edge' or 'linear'")
    if solver == "local":
        result = local_solve(problem, assembly=assembly, smooth=smooth, factorisation=factorisation,
                             callback=callback, folds=folds)
    elif solver == "global":
        if problem.held[1:-1].any() or not (problem.held[0] and problem.held[-1]):
            raise ParameterError("the global solver holds only the first and the last frame")
        p = problem
        free = slice(1, len(p.times) - 1)
        p.z[:, free] = FrameAssembler(p.shape).positions(edges[:, free], p.centroids[:, free])
        result = global_solve(p, linear_solver=linear_solver, callback=callback)
    else:
        raise ParameterError(f"unknown solver {solver!r}; choose one of {', '.join(SOLVERS)}")
    timings = {"solve": time.perf_counter() - start}
    timings.update({f"solve.{k}": v for k, v in result.timings.items()})
    result.timings = timings
    return result
