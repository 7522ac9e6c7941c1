"""Fold-free, nearly isometric morph: the convex morph refined by a barrier energy.

Every in-between frame is an embedding of a triangulated disc, as in method
'convex' (`isotween.foldfree.convex`: each component completed to a disc
inside a fixed 32-gon, its exterior and holes meshed compatibly), and then
made as isometric as the embedding allows:

1. Rest triangles at time t. Every face of the disc gets a rest triangle
   whose edge lengths are (1 - t)|e(0)| + t|e(1)|: the lengths AIAP aims at
   (``edge_length_deviation`` zero; docs/how-it-works.md). A convex
   combination of two valid length triples satisfies the triangle inequality, so the rest
   triangle always exists.
2. Energy. The symmetric Dirichlet energy ``A (|J|^2 + |J^-1|^2)`` of each
   face's map from its rest triangle (Smith and Schaefer 2015, "Bijective
   parameterization with free boundaries"), weight 1 on the component's
   faces and ``SCAFFOLD`` on the completing faces (the scaffold of Jiang,
   Schaefer, Schaefer and Panozzo 2017, "Simplicial complex augmentation
   framework for bijective maps"): the scaffold may deform, never flip. The
   energy is infinite when a triangle degenerates.
3. Projected Newton (Teran et al. 2005: each face's Hessian with respect to
   its Jacobian projected to positive semi-definite), one sparse Cholesky-
   like solve (``splu``) per iteration, the 32-gon fixed.
4. Flip-preventing line search (Smith and Schaefer 2015, Sec. 4.1): the step
   is at most 0.9 of the first time at which a triangle's signed area (a
   quadratic in the step) reaches zero (`max_step`), then halved until the
   energy decreases enough (Armijo). Every iterate is therefore an
   embedding of the disc: no triangle flips and no ring of a region
   crosses itself or another ring of the region, in any frame.
5. Start: whichever of the convex frame at t and the previous refined frame
   (an embedding of the same disc with the same boundary: warm start and
   temporal coherence) has the lower energy. Stop when an iteration lowers
   the energy above its minimum by less than ``TOL`` (relative), after
   ``MAX_ITER`` iterations, or when its share of the component's iteration
   budget is spent: ``WORK`` vertex-iterations, i.e. WORK / N Newton
   iterations for a disc of N vertices (what is left over the frames left;
   every frame gets at least one iteration, and its last iterate is an
   embedding). Only very large meshes reach the budget. The budget counts
   work, not seconds, so the result is the same on every machine.

The rigid motion of the convex morph (best rotation of the target onto the
source, interpolated, centroid on a straight line) is kept; the first and
last frames are the inputs exactly. ``info``: ``components`` (per component
``vertices``, ``faces``, ``rotation``, ``iterations``), ``iterations`` (all
Newton iterations).
"""

import numpy as np

from ..errors import MethodError
from ..optimisation.barrier import TOL, SymmetricDirichlet, max_step, minimise
from . import convex

__all__ = ["solve", "max_step", "SCAFFOLD", "MAX_ITER", "TOL", "WORK"]

SCAFFOLD = 1e-2  # weight of the completing (exterior and hole) faces against the region's
MAX_ITER = 20  # Newton iterations per frame at most
WORK = 500_000  # Newton iterations x disc vertices per component, shared out over its frames


def solve(problem):
    """Frames of the refined fold-free morph.

    Parameters
    ----------
    problem : Problem
        Held at the first and the last frame; its shape a triangle mesh with
        every vertex in a face, no target triangle flipped against the source.

    Returns
    -------
    Result
        ``iterations``: Newton iterations of all frames; ``info``:
        ``components`` (per component ``vertices``, ``faces``, ``rotation``,
        ``iterations``).

    Raises
    ------
    MethodError
        As method 'convex' does (`isotween.foldfree.convex.solve`).
    """
    result = convex.per_component(problem, "injective", _component)
    result.iterations = sum(c["iterations"] for c in result.info["components"])
    return result


def _component(zs, zt, f, t):
    """(F, n) complex frames of one component; see `interpolate`."""
    d = convex.disc(zs, zt, f)
    convex_frame = convex.ConvexFrames(d)
    energy = _energy(d)
    budget = max(len(t) - 2, WORK // len(d.ws))  # Newton iterations for all the frames
    out = np.empty((len(t), len(zs)), dtype=complex)
    z = d.ws
    iterations = 0
    for k, tk in enumerate(t):
        if k == 0 or k == len(t) - 1:
            out[k] = convex.place(d, (d.ws if k == 0 else d.wa)[:d.n], tk)
            continue
        energy.rest(tk)
        z0 = convex_frame(tk)
        if energy(z0) < energy(z):
            z = z0
        share = max(1, (budget - iterations) // (len(t) - 1 - k))
        z, used = minimise(energy, z, min(MAX_ITER, share))
        iterations += used
        out[k] = convex.place(d, z[:d.n], tk)
    return out, {"vertices": len(d.ws), "faces": len(d.faces), "rotation": d.theta, "iterations": iterations}


def _energy(d):
    """The symmetric Dirichlet energy of the completed disc ``d`` (steps 1-2), its 32-gon fixed."""
    fixed = np.zeros(len(d.ws), dtype=bool)
    fixed[d.boundary] = True
    weight = np.where(np.arange(len(d.faces)) < d.n_region, 1.0, SCAFFOLD)
    try:
        return SymmetricDirichlet(d.ws, d.wa, d.faces, fixed, weight)
    except MethodError as exc:
        raise MethodError(f"the completed disc: {exc}") from None
