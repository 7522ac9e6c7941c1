"""Compute backends of the solver's hot loops, and the one place that picks one.

Two backends do the same arithmetic behind one interface (``edge_init``, ``edge_frames``,
``edge_pass``, ``banded``, ``face_derivatives``):

'numpy'
    The reference (:mod:`isotween.optimisation.reference`): numpy / scipy on
    blocks of edges, LAPACK's tridiagonal solve for Eq. (9), sparse
    factorisations for Eq. (10).
'numba'
    The kernels of :mod:`isotween.optimisation.accelerated` (``pip install
    isotween[fast]``): Eqs. (6), (8) and (9) fused in one pass over the edges
    (midpoint scheme with only the two ends held; other cases take the
    reference pass), Eqs. (12)-(13), and a banded Cholesky for Eq. (10).

:func:`current` is the backend in use: 'numba' when numba is installed and
the environment does not set ``ISOTWEEN_NUMBA=0`` (read here and nowhere
else), otherwise 'numpy'. :func:`use` switches it. Loading numba and its
cached kernels takes about half a second, more than numpy's extra time on a
small problem: :func:`sized` runs such a problem on numpy while numba is not
loaded yet, unless the process said it is :func:`long_lived` (a server, a
batch worker).

Examples
--------
>>> from isotween.optimisation import backend
>>> with backend.use("numpy"):
...     print(backend.current().name)
numpy
"""

from __future__ import annotations

import contextlib
import importlib.util
import os
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import MissingDependencyError, ParameterError
from . import accelerated, reference

if TYPE_CHECKING:
    from collections.abc import Iterator

__all__ = ["BACKENDS", "FIRST_NUMBA", "NumpyBackend", "NumbaBackend", "available", "current", "for_size",
           "long_lived", "sized", "use"]

BACKENDS = ("numpy", "numba")
#: a problem of fewer edge-frames (edges x frames) runs on numpy while numba is not loaded (`sized`): numpy's
#: extra time on it stays under the half second that loading numba and its kernels costs (benchmarks/startup.py)
FIRST_NUMBA = 100_000


class NumpyBackend:
    """The numpy / scipy reference.

    Attributes
    ----------
    name : str
    banded : bool
        Whether this backend factorises Eq. (10) in banded form (here: no).
    """

    name = "numpy"
    banded = False

    def edge_init(self, top, e0, e1, t):
        """Eqs. (12)-(13) with angles propagated along the edge tree.

        Parameters
        ----------
        top : Topology
        e0, e1 : (E,) complex
            Source and target edge vectors.
        t : (F,) float

        Returns
        -------
        (E, F) complex
        """
        s, theta = reference.edge_angles(top, e0, e1)
        return reference.edge_frames(e0, s, theta, t)

    def edge_frames(self, e0, s, theta, t):
        """Eq. (13) from given scales and angles (:func:`~isotween.optimisation.reference.edge_frames`)."""
        return reference.edge_frames(e0, s, theta, t)

    def face_derivatives(self, z, faces, G, w):
        """The fold repair's per-face derivatives (:func:`~isotween.optimisation.reference.face_derivatives`)."""
        return reference.face_derivatives(z, faces, G, w)

    def edge_pass(self, top, t, scheme, fixed, smooth):
        """The edge work of one iteration of Algorithm 2 (Eqs. 8, 6, 9).

        Parameters as :class:`~isotween.optimisation.reference.EdgePass`.

        Returns
        -------
        callable
            ``pass_(z, solve) -> (edges, energy)`` on (n, F) complex frames,
            with ``pass_.reuse(edges)`` (may write into the caller's (E, F)
            array) and ``pass_.close()``.
        """
        return reference.EdgePass(top, t, scheme, fixed, smooth)


class NumbaBackend(NumpyBackend):
    """The numba kernels; the numpy reference where no kernel covers a case."""

    name = "numba"
    banded = True

    def edge_init(self, top, e0, e1, t):
        """As :meth:`NumpyBackend.edge_init`."""
        return accelerated.edge_init(top, e0, e1, t)

    def edge_frames(self, e0, s, theta, t):
        """As :meth:`NumpyBackend.edge_frames`."""
        return accelerated.edge_frames(e0, s, theta, t)

    def edge_pass(self, top, t, scheme, fixed, smooth):
        """As :meth:`NumpyBackend.edge_pass`; fused for the midpoint scheme with only the ends held."""
        if scheme == "midpoint" and fixed[0] and fixed[-1] and not fixed[1:-1].any():
            return _FusedPass(top, t)
        return super().edge_pass(top, t, scheme, fixed, smooth)

    def face_derivatives(self, z, faces, G, w):
        """As :meth:`NumpyBackend.face_derivatives`."""
        return accelerated.face_derivatives(z, faces, G, w)

    def band_cholesky(self, band):
        """See :func:`isotween.optimisation.accelerated.band_cholesky`."""
        return accelerated.band_cholesky(band)

    def banded_positions(self, *args):
        """See :func:`isotween.optimisation.accelerated.banded_positions`."""
        return accelerated.banded_positions(*args)


class _FusedPass:
    """Eqs. (8), (6), (9) in one numba pass: `reference.EdgePass` on all edges at once."""

    def __init__(self, top, t):
        self.first, self.second, self.inv_h = top.first, top.second, 1.0 / np.diff(t)
        self.out = None

    def reuse(self, edges):
        if edges.dtype == complex and edges.flags.c_contiguous:
            self.out = edges

    def __call__(self, z, solve):
        if self.out is None:
            self.out = np.empty((len(self.first), z.shape[1]), dtype=complex)
        return self.out, accelerated.midpoint_edge_pass(z, self.first, self.second, self.inv_h, solve, self.out)

    def close(self):
        self.out = None


#: numba is installed (imported, a third of a second, on the first kernel call, not with isotween)
_HAVE_NUMBA = importlib.util.find_spec("numba") is not None
_INSTANCES = {"numpy": NumpyBackend(), "numba": NumbaBackend()}
_state: dict[str, Any] = {"name": "numba" if _HAVE_NUMBA and os.environ.get("ISOTWEEN_NUMBA", "1") != "0" else "numpy",
                          "chosen": False, "long_lived": False}  # chosen: by `use`, which `sized` leaves alone


def available() -> tuple[str, ...]:
    """Names of the backends that can run here ('numba' needs numba installed).

    Examples
    --------
    >>> from isotween.optimisation import backend
    >>> "numpy" in backend.available()
    True
    """
    return BACKENDS if _HAVE_NUMBA else ("numpy",)


def current() -> NumpyBackend:
    """The backend in use: a :class:`NumpyBackend` or :class:`NumbaBackend`."""
    return _INSTANCES[_state["name"]]


@contextlib.contextmanager
def _restoring(previous: dict) -> Iterator[None]:
    try:
        yield
    finally:
        _state.update(previous)


def use(name: str) -> contextlib.AbstractContextManager[None]:
    """Switch the backend now; used as a ``with`` block, switch back at its end.

    Parameters
    ----------
    name : {'numpy', 'numba'}

    Raises
    ------
    ParameterError
        Unknown name.
    MissingDependencyError
        'numba' without numba installed.
    """
    if name not in BACKENDS:
        raise ParameterError(f"unknown backend {name!r}; choose one of {', '.join(BACKENDS)}")
    if name not in available():
        raise MissingDependencyError("the numba backend needs numba: pip install 'isotween[fast]'")
    previous = {"name": _state["name"], "chosen": _state["chosen"]}
    _state.update(name=name, chosen=True)
    return _restoring(previous)


def _spare_numba(work: int) -> bool:
    """Whether a problem of ``work`` edge-frames runs on numpy rather than load numba (see `sized`)."""
    return (_state["name"] == "numba" and not (_state["chosen"] or _state["long_lived"])
            and accelerated.numba is None and work < FIRST_NUMBA)


def sized(edge_frames: int) -> contextlib.AbstractContextManager[None]:
    """The backend for a problem of this size, as a ``with`` block.

    numpy while the backend in use is 'numba' by default (not chosen with
    `use`), numba is not loaded yet, the process is not `long_lived`, and
    the problem has fewer than `FIRST_NUMBA` edge-frames; otherwise the
    backend in use, unchanged.

    Parameters
    ----------
    edge_frames : int
        Edges times frames of the problem (or work of about that many).
    """
    return use("numpy") if _spare_numba(edge_frames) else contextlib.nullcontext()


def for_size(edge_frames: int) -> NumpyBackend:
    """The backend `sized` would pick for a problem of this size (an instance, to keep)."""
    return _INSTANCES["numpy"] if _spare_numba(edge_frames) else current()


def long_lived() -> None:
    """Say that this process will solve many problems: every one runs on the backend in use.

    A server or a batch worker pays numba's load once (on its first problem)
    and then runs every problem on the faster kernels; a one-off command
    leaves small problems to numpy (`sized`).
    """
    _state["long_lived"] = True
