"""As-rigid-as-possible deformation of one frame around handle points (the studio's drag)."""

from __future__ import annotations

import hashlib
import threading
from collections import OrderedDict
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import splu

from ..errors import ParameterError

if TYPE_CHECKING:
    from collections.abc import Mapping

    from numpy.typing import ArrayLike, NDArray

    from ..shape import Shape

__all__ = ["arap_deform"]

#: pull of every free vertex towards its rest place, relative to the mean degree (keeps a
#: component without held vertices where it is instead of making the system singular)
_REGULARISE = 1e-9


class _System:
    """The factorised global step of one frame with one set of held vertices (kept while a drag goes on)."""

    def __init__(self, shape: Shape, fixed: NDArray[np.bool_]):
        n = shape.n_vertices
        top = shape.topology
        self.i, self.j = np.asarray(top.first), np.asarray(top.second)
        ones = np.ones(len(self.i))
        adjacency = sp.coo_matrix((np.r_[ones, ones], (np.r_[self.i, self.j], np.r_[self.j, self.i])),
                                  shape=(n, n)).tocsr()
        degree = np.asarray(adjacency.sum(axis=1)).ravel()
        lap = (sp.diags(degree) - adjacency).tocsr()
        self.free = np.flatnonzero(~fixed)
        self.eps = _REGULARISE * max(float(degree.mean()), 1.0)
        self.lfc = lap[self.free][:, np.flatnonzero(fixed)]
        self.lu = splu((lap[self.free][:, self.free] + self.eps * sp.identity(self.free.size)).tocsc())
        self.lock = threading.Lock()  # one solve at a time on the factor


_SYSTEMS: OrderedDict = OrderedDict()  # (topology, held set) -> _System, the last few
_SYSTEMS_LOCK = threading.Lock()


def _system(shape: Shape, fixed: NDArray[np.bool_]) -> _System:
    key = (id(shape.topology), hashlib.blake2b(np.packbits(fixed).tobytes(), digest_size=16).digest(), len(fixed))
    with _SYSTEMS_LOCK:
        found = _SYSTEMS.get(key)
        if found is not None and found[0] is shape.topology:
            _SYSTEMS.move_to_end(key)
            return found[1]
    system = _System(shape, fixed)
    with _SYSTEMS_LOCK:
        _SYSTEMS[key] = (shape.topology, system)
        while len(_SYSTEMS) > 4:
            _SYSTEMS.popitem(last=False)
    return system


def arap_deform(shape: Shape, vertices: ArrayLike, handles: Mapping[int, ArrayLike], *,
                radius: float | None = None, anchor: int | None = None, iterations: int = 12) -> NDArray[np.float64]:
    """A frame deformed as-rigidly-as-possible with its handles moved.

    The edge-based ARAP energy ``sum_ij |x_i - x_j - R_i (p_i - p_j)|^2`` over the
    shape's edges (uniform weights, one rotation R_i per vertex, a unit complex
    number) is minimised by alternating local rotation fits and one global
    sparse solve, factorised once (Sorkine and Alexa 2007) and kept for the
    next calls with the same connectivity and held vertices (the moves of one drag).

    Parameters
    ----------
    shape : Shape
        Connectivity (edges).
    vertices : (n, 2) array_like of float
        The frame at rest (the positions p).
    handles : dict {int: (2,) array_like}
        Vertex index -> new position; these vertices are held there.
    radius : float, optional
        Region of influence: vertices farther than ``radius`` from the vertex
        ``anchor`` (at rest) are held at rest too. Default: every vertex is free.
    anchor : int, optional
        The dragged handle, centre of the region of influence (default: the
        first handle).
    iterations : int
        Local-global iterations.

    Returns
    -------
    (n, 2) float64 array
        The deformed frame; handles exactly where given.

    Examples
    --------
    >>> import numpy as np
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    >>> moved = arap_deform(bar, bar.vertices, {0: [0, 0], 2: [0, 2]})
    >>> bool(np.allclose(moved[[0, 2]], [[0, 0], [0, 2]]))
    True
    """
    p = np.asarray(vertices, dtype=np.float64)
    n = shape.n_vertices
    if p.shape != (n, 2) or not np.all(np.isfinite(p)):
        raise ParameterError(f"the frame must be {n} finite (x, y) positions, got an array of shape {p.shape}")
    if not handles:
        raise ParameterError("give at least one handle (vertex index -> position)")
    held = {}
    for key, value in handles.items():
        k = int(key)
        if not 0 <= k < n:
            raise ParameterError(f"handle vertex {key} is out of range (0..{n - 1})")
        q = np.asarray(value, dtype=np.float64).reshape(-1)
        if q.shape != (2,) or not np.all(np.isfinite(q)):
            raise ParameterError(f"handle {k}: the position must be two finite numbers")
        held[k] = complex(q[0], q[1])
    z = p[:, 0] + 1j * p[:, 1]
    fixed = np.zeros(n, dtype=bool)
    if radius is not None:
        centre = z[int(anchor) if anchor is not None else next(iter(held))]
        fixed = np.abs(z - centre) > float(radius)
    idx = np.fromiter(held, dtype=np.int64)
    fixed[idx] = True
    x = z.copy()
    x[idx] = np.fromiter(held.values(), dtype=complex)
    if fixed.all():
        return np.c_[x.real, x.imag]
    system = _system(shape, fixed)
    i, j, free, eps, lfc, lu = system.i, system.j, system.free, system.eps, system.lfc, system.lu
    d = z[i] - z[j]  # rest edge vectors
    rhs_fixed = lfc @ x[fixed]
    # first rotations: the rigid fit of the held vertices' moves (Procrustes), the same for every vertex
    held_rest, held_now = z[fixed], x[fixed]
    fit = np.sum((held_now - held_now.mean()) * (held_rest - held_rest.mean()).conj())
    rot = np.full(n, fit / abs(fit) if abs(fit) > 0 else 1.0 + 0j)
    for step in range(max(int(iterations), 1)):
        if step:  # local step: R_i = phase of sum_j (x_i - x_j) conj(p_i - p_j)
            cov = (x[i] - x[j]) * d.conj()
            acc = np.bincount(i, cov.real, n) + 1j * np.bincount(i, cov.imag, n)
            acc += np.bincount(j, cov.real, n) + 1j * np.bincount(j, cov.imag, n)
            mag = np.abs(acc)
            rot = np.where(mag > 0, acc / np.where(mag > 0, mag, 1.0), 1.0)
        # global step: L x = sum_j (R_i + R_j) / 2 (p_i - p_j)
        half = 0.5 * (rot[i] + rot[j]) * d
        b = np.bincount(i, half.real, n) + 1j * np.bincount(i, half.imag, n)
        b -= np.bincount(j, half.real, n) + 1j * np.bincount(j, half.imag, n)
        rhs = b[free] - rhs_fixed + eps * z[free]
        with system.lock:
            x[free] = lu.solve(np.ascontiguousarray(rhs.real)) + 1j * lu.solve(np.ascontiguousarray(rhs.imag))
    return np.c_[x.real, x.imag]
