"""The methods the paper compares with, and the fold-free morphs (`isotween.foldfree`), under one interface.

``run(method, source, target, frames)`` returns a :class:`~isotween.Sequence`
like :func:`isotween.interpolate` does, so every method is measured by the same
metrics (:mod:`isotween.metrics`). It builds the
:class:`~isotween.optimisation.problem.Problem` of the two shapes held at the
first and last frame once, with :func:`isotween.problems.keyed_problem` (as
AIAP does), and hands it to the method's ``solve(problem, **options)``, which
returns a :class:`~isotween.optimisation.problem.Result`.

=============  ===========================================  ==================
method         what is blended                              needs
=============  ===========================================  ==================
'linear'       vertex positions                             any shape
'intrinsic'    edge lengths and turning angles              polygons/polylines
               (Sederberg et al. 1993)                      (``shape.paths``)
'arap'         per-triangle rotation and stretch            triangle mesh
               (Alexa et al. 2000)
'arap-baxter'  the same, rotation angles made consistent    triangle mesh
               across triangles (Baxter et al. 2008)
'shapespace'   geodesic of an isometric metric, Gauss-      any shape
               Newton over all frames (Kilian et al. 2007)
'convex'       convex-combination (mean-value) weights in   triangle mesh,
               a disc with a fixed convex boundary; never   every vertex in
               folds (Floater and Gotsman 1999)             a face
'injective'    the 'convex' disc, each frame then made as   as 'convex'
               isometric as an embedding allows (barrier
               energy, Smith and Schaefer 2015); never folds
=============  ===========================================  ==================
"""

import importlib
import time

import numpy as np

from ..errors import MethodError
from ..optimisation.problem import DEFAULT_TOL
from ..times import frame_times

__all__ = ["METHODS", "run", "method_module"]

#: method name -> module with ``solve(problem, **options) -> Result``, imported when the method runs: the paper's
#: comparison methods here, the fold-free morphs that the pipeline falls back to in `isotween.foldfree`
_MODULES = {
    "linear": ".linear",
    "intrinsic": ".intrinsic",
    "arap": ".arap",
    "arap-baxter": ".arap_baxter",
    "shapespace": ".shapespace",
    "convex": "isotween.foldfree.convex",
    "injective": "isotween.foldfree.injective",
}
METHODS = tuple(_MODULES)


def run(method, source, target, n_frames, *, times=None, **options):
    """Interpolate two compatible shapes with a baseline method.

    Parameters
    ----------
    method : str
        One of :data:`METHODS`.
    source, target : Shape
        Same vertex count and connectivity.
    n_frames : int
        Frames, both inputs included.
    times : (n_frames,) array_like, optional
        Increasing frame times from 0 to 1 (default: uniform). Keyword-only,
        as every option.
    **options
        ``tol`` (relative, as in :func:`isotween.interpolate`; default 5e-4)
        and ``max_iter`` (default 100) go into the Problem; ``callback`` and
        a method's own options (its module's ``OPTIONS``) to the method.
        Methods ignore the options they do not take.

    Returns
    -------
    Sequence
        Built from a :class:`~isotween.optimisation.problem.Result`:
        ``method``, ``iterations``, ``energy`` (iterative methods), ``timings``
        and, in ``info``, what the method needs to say (see each module).

    Raises
    ------
    MethodError
        Unknown method, or a shape the method cannot take (the message says
        which input it needs).
    ParameterError
        Bad ``times``, ``tol`` or ``max_iter``.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> from isotween.baselines import run
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> seq = run("linear", bar, bar.translate([2, 0]), 3)
    >>> seq.method, seq.frames[1].tolist()
    ('linear', [[1.0, 0.0], [2.0, 0.0]])
    """
    from ..correspondence.compatibility import as_shape, check_compatible
    from ..problems import check_stopping, keyed_problem

    if method not in _MODULES:
        raise MethodError(f"unknown method {method!r}; choose one of aiap, {', '.join(METHODS)}")
    start = time.perf_counter()
    source, target = as_shape(source, "source"), as_shape(target, "target")
    check_compatible(source, target)
    t = frame_times(n_frames, times)
    options = {k: v for k, v in options.items() if v is not None}
    options.setdefault("tol", DEFAULT_TOL)
    options.setdefault("max_iter", 100)
    check_stopping(options["tol"], options["max_iter"])
    problem = keyed_problem([source, target], t, np.array([0, len(t) - 1]), init=None, scheme="midpoint",
                            tol=options["tol"], max_iter=options["max_iter"])
    module = method_module(method)
    result = module.solve(problem, **_accepted(module, options))
    total = time.perf_counter() - start
    result.timings = {"solve": total, "total": total}
    return result.sequence(problem.shape, problem.times, method=method)


def method_module(method):
    """The module of a method of :data:`METHODS` (its ``solve``), imported on first use."""
    return importlib.import_module(_MODULES[method], __name__)


def __getattr__(name):
    """A comparison method's module (``isotween.baselines.arap``, ...), imported on first use."""
    if f".{name}" in _MODULES.values():
        return importlib.import_module(f".{name}", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _accepted(module, options):
    """The options a method's module names in ``OPTIONS``."""
    names = getattr(module, "OPTIONS", ())
    return {k: v for k, v in options.items() if k in names}
