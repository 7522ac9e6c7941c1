"""Shape transfer (Sec. 5.1): make a target imitate a source's AIAP motion."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ._callable import make_callable
from .correspondence.compatibility import as_shape, check_compatible
from .interpolate import interpolate
from .metrics import isometric_energy
from .problems import assemble, check_movable, held_problem
from .velocity import relative_velocity_field

if TYPE_CHECKING:
    from typing import Any

    from .sequence import Sequence
    from .shape import Shape, ShapeLike

__all__ = ["transfer", "component_similarities"]


def component_similarities(source: Shape, target: Shape) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares similarity a z + b from each component of source to target.

    Returns
    -------
    a, b : (C,) complex

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> from isotween.transfer import component_similarities
    >>> tri = isotween.Shape.from_polygon([[0, 0], [1, 0], [0, 1]])
    >>> a, b = component_similarities(tri, tri.scale(2.0).translate([1, 0]))
    >>> np.round(a, 12).tolist(), np.round(b, 12).tolist()
    ([(2+0j)], [(1+0j)])
    """
    avg = source.topology.avg
    cs, ct = avg @ source.z, avg @ target.z
    ds, dt = source.z - cs[source.components], target.z - ct[source.components]
    num = np.bincount(source.components, (ds.conj() * dt).real) + 1j * np.bincount(
        source.components, (ds.conj() * dt).imag)
    den = np.bincount(source.components, np.abs(ds) ** 2)
    a = np.where(den > 0, num / np.where(den > 0, den, 1.0), 1.0)
    return a, ct - a * cs


def transfer(source_start: ShapeLike, source_end: ShapeLike, target_start: ShapeLike, frames: int = 9, *,
             correspondence: str = "auto", correspond_options: dict | None = None, fit: bool = False,
             **options: Any) -> Sequence:
    """Transfer the AIAP motion from source_start -> source_end onto target_start.

    1. AIAP-interpolate the source pair (Algorithm 2, ``options`` as in
       :func:`isotween.interpolate`) and take its relative velocity field E'(t_k).
    2. Per edge, the similarity S~ with S~ e(t_0) = e~(t_0) (Eq. 12).
    3. Warp the velocities: e~'(t_k) = S~ e'(t_k) (Eq. 14), and minimise
       Eq. (15) from the fixed e~(t_0); the minimum is reached by integrating
       the warped velocities.
    4. Assemble the target frames by Eq. (10): the target's
       :class:`~isotween.optimisation.problem.Problem` (built by
       :func:`isotween.problems.held_problem`) holds the first frame, with
       these edges and centroids, and :func:`isotween.problems.assemble`
       solves it.

    Translation: each component of the target moves like the matching source
    component, mapped by the least-squares similarity (rotation and uniform
    scale) from the source start to the target start: its centroid follows
    c~(t) = c~(0) + a (c(t) - c(0)). So a target that is a similar copy of the
    source gets exactly the similar copy of the source's motion.

    Parameters
    ----------
    source_start, source_end, target_start : Shape, (n, 2) array_like, or path
        Compatible shapes are used as they are; files and shapes with paths
        that are not compatible are first put in correspondence together, as
        outlines (:func:`isotween.pipeline.prepare_keys`), as
        ``correspondence`` says.
    frames : int
    correspondence : {'auto', 'always', 'never'}
        As in :func:`isotween.interpolate`.
    correspond_options : dict, optional
        Options of `isotween.correspondence.correspond_keys` (``points``,
        ``segment``, ``rotation``, ``unmatched``).
    fit : bool
        ``source_end`` and ``target_start`` scaled (strokes too) and moved
        into ``source_start``'s bounding box first
        (`isotween.pipeline.fitted`): drawings from sets drawn in different
        units.
    **options
        Passed to :func:`isotween.interpolate` for the source motion.

    Returns
    -------
    Sequence
        The target's frames; ``energy`` holds one value, the isometric energy
        of these frames (not of the source run: ``info['source']`` holds the
        source sequence with its own history). After correspondence
        ``info['correspondence']`` says what was done.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> seq = isotween.transfer(bar, bar.rotate(1.0), bar.scale(2.0), frames=5)
    >>> source = isotween.interpolate(bar, bar.rotate(1.0), frames=5)
    >>> bool(np.allclose(seq.frames, 2.0 * source.frames))  # a similar copy moves alike
    True
    """
    from .pipeline import needs_correspondence  # the pipeline is a layer above: reached at call time

    names = ["source_start", "source_end", "target_start"]
    inputs = [source_start, source_end, target_start]
    summary = None
    if fit or needs_correspondence(*inputs, correspondence=correspondence, names=names,
                                   options=bool(correspond_options)):
        from .pipeline import _is_path, prepare_keys

        prepared = prepare_keys(inputs, correspondence=correspondence, role="input", fit=fit,
                                names=[str(x) if _is_path(x) else n
                                       for x, n in zip(inputs, names, strict=True)],
                                **(correspond_options or {}))
        inputs, summary = prepared.shapes, prepared.summary()
    shapes = [as_shape(s, n) for s, n in zip(inputs, names, strict=True)]
    check_movable(shapes[0], "source_start")
    check_compatible(*shapes, names=["source_start", "source_end", "target_start"])
    source_start, source_end, target_start = shapes
    seq = interpolate(source_start, source_end, frames=frames, correspondence="never", **options)
    field = relative_velocity_field(seq)
    h = np.diff(field.times)
    S = target_start.edge_vectors() / source_start.edge_vectors()  # Eq. (12)
    warped = S[:, None] * field.velocities  # Eq. (14)
    e = np.empty_like(field.edges)
    e[:, 0] = target_start.edge_vectors()
    e[:, 1:] = e[:, :1] + np.cumsum(warped * h, axis=1)  # Eq. (15) minimised
    a, _ = component_similarities(source_start, target_start)
    avg = source_start.topology.avg
    c = avg @ seq.z.T  # (C, F) source centroids
    centroids = (avg @ target_start.z)[:, None] + a[:, None] * (c - c[:, :1])
    problem = held_problem(target_start, field.times, np.array([0]), target_start.z[:, None], centroids=centroids,
                           edges=e, scheme=seq.scheme)
    done = assemble(problem, 2.0 / (np.abs(e[:, 0]) + np.abs(e[:, -1])))
    done.iterations, done.converged, done.timings = seq.iterations, seq.converged, dict(seq.timings)
    out = done.sequence(target_start, problem.times, method="transfer", scheme=seq.scheme, info={"source": seq})
    out.energy = [isometric_energy(out)]  # of the frames returned, not of the source run
    if summary is not None:
        out.info["correspondence"] = summary
    return out


# `isotween.transfer(...)` calls `transfer`; `import isotween.transfer` still gives this module
make_callable(__name__)
