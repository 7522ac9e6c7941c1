"""Fold-free morph of triangulated solids by convex-combination weights.

Floater and Gotsman 1999 ("How to morph tilings injectively"); Surazhsky and
Gotsman 2001 ("Guaranteed intersection-free polygon morphing"):

1. Every connected component of the faces (a filled region with its holes)
   is completed into a triangulated disc with a fixed convex boundary: the
   region's exterior inside a 32-gon around both shapes, and every hole,
   are meshed compatibly in source and target
   (`isotween.correspondence.compatible_mesh.compatible_meshes`) and glued
   to the region along its rings. The target is first brought to the
   source by the best rotation and translation (least squares), which is
   put back, interpolated, in every frame.
2. Every vertex off the 32-gon is a convex combination of its neighbours,
   with normalised mean-value weights (Floater 2003), in each shape.
3. At time t the weights are blended linearly; the sparse linear system
   (32-gon fixed) then has a unique solution that is an embedding (Tutte's
   theorem as extended by Floater), so no triangle flips and no ring
   crosses itself or another ring of its region, in any frame.

Only the input vertices are returned; the first and the last frame are the
inputs exactly. ``info``: ``components`` (per component: ``vertices``,
``faces`` of the completed disc, ``rotation`` in radians).
"""

from typing import NamedTuple

import numpy as np
from scipy.sparse import coo_matrix, identity
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import splu

from ..errors import IncompatibleShapesError, IsotweenError, MethodError, ShapeError
from ..geometry import boundary_loops, mean_value_weights, ring_area, triangle_areas
from ..optimisation.problem import Result

__all__ = ["solve", "per_component", "disc", "Disc", "ConvexFrames", "place", "SIDES"]

SIDES = 32  # vertices of the fixed convex boundary (a regular polygon)
MARGIN = 1.5  # its radius over the largest distance of a ring vertex from its centre
COARSE = 3.0  # edge length of the completing meshes (exterior, holes) over their rings' mean edge


def solve(problem):
    """Frames of the convex-combination morph.

    Parameters
    ----------
    problem : Problem
        Held at the first and the last frame; its shape a triangle mesh with
        every vertex in a face, no target triangle flipped against the source.

    Returns
    -------
    Result
        ``info``: ``components`` (per component ``vertices``, ``faces`` of the
        completed disc, ``rotation`` in radians).

    Raises
    ------
    MethodError
        No faces, vertices in no face (polylines), a target triangle flipped
        against the source, a vertex where two boundary loops meet, or a
        component whose exterior or holes cannot be meshed compatibly (the
        message names the component and why).
    """
    return per_component(problem, "convex", _component)


def per_component(problem, name, solve):
    """Frames of a disc-based morph, one connected component of the faces at a time.

    Parameters
    ----------
    problem : Problem
        As for `solve`.
    name : str
        The method's name, for messages.
    solve : callable(zs, zt, faces, t) -> (frames, extra)
        One component: its (k,) complex source and target vertices, its
        (m, 3) counter-clockwise faces (local indices) and the times; returns
        (F, k) complex frames and a dict for ``info['components']``.

    Returns
    -------
    Result
        ``z`` (n, F) complex; the first and the last frame are the held
        shapes exactly. ``info['components']``: the dicts of ``solve``.

    Raises
    ------
    MethodError
        As for `solve`, naming ``name``.
    """
    source = problem.shape
    zs, zt = problem.ends()
    if source.faces is None or not len(source.faces):
        raise MethodError(f"method {name!r} needs solid regions (a triangle mesh); the shapes have no faces")
    f = source.faces
    loose = np.setdiff1d(np.arange(source.n_vertices), f)
    if loose.size:
        raise MethodError(f"method {name!r} needs solid regions: {loose.size} vertex(es) lie in no face "
                          f"(open polylines or outlines), first: vertex {loose[0]}")
    a_s, a_t = triangle_areas(zs, f), triangle_areas(zt, f)
    if np.any(a_s == 0):
        raise MethodError(f"method {name!r}: triangle {np.flatnonzero(a_s == 0)[0]} of the source has zero area")
    bad = np.flatnonzero(np.sign(a_s) != np.sign(a_t))
    if bad.size:
        raise MethodError(f"method {name!r} needs two valid meshes: {bad.size} target triangle(s) are flipped "
                          f"against the source, first: triangle {bad[0]} {f[bad[0]].tolist()}")
    f = np.where((a_s < 0)[:, None], f[:, ::-1], f)  # counter-clockwise in the source (and target)
    t = problem.times
    frames = np.empty((len(t), len(zs)), dtype=complex)
    n_comp, label = connected_components(
        coo_matrix((np.ones(2 * len(f)), (f[:, [0, 1]].ravel(), f[:, [1, 2]].ravel())),
                   shape=(len(zs),) * 2), directed=False)
    info = {"components": []}
    for c in range(n_comp):
        verts = np.flatnonzero(label == c)
        local = np.full(len(zs), -1)
        local[verts] = np.arange(len(verts))
        fc = local[f[label[f[:, 0]] == c]]
        try:
            z, extra = solve(zs[verts], zt[verts], fc, t)
        except IsotweenError as exc:
            raise MethodError(f"method {name!r}, component {c} (vertex {verts[0]} ...): {exc}") from None
        frames[:, verts] = z
        info["components"].append(extra)
    frames[0], frames[-1] = zs, zt  # the inputs exactly
    return Result(frames.T, info=info)


class Disc(NamedTuple):
    """One component completed to a triangulated disc with a fixed convex boundary.

    The disc's vertices are the component's ``n`` vertices first, then the
    ``SIDES``-gon, then the vertices added inside the exterior and the holes.
    The target is brought to the source by the best rotation and translation;
    `place` puts that motion back, interpolated.

    Attributes
    ----------
    n : int
        Vertices of the component (the first ``n`` of the disc).
    ws, wa : (N,) complex
        The disc in the source and in the (rigidly aligned) target.
    faces : (K, 3) int
        The component's faces first (``n_region`` of them), then the
        completing (scaffold) faces.
    n_region : int
    boundary : (SIDES,) int
        The fixed convex boundary's vertices.
    circle : (SIDES,) complex
        Their positions.
    cs, ct : complex
        Centroids of the component in the source and the target.
    theta : float
        Rotation in radians from the source to the target.
    """

    n: int
    ws: np.ndarray
    wa: np.ndarray
    faces: np.ndarray
    n_region: int
    boundary: np.ndarray
    circle: np.ndarray
    cs: complex
    ct: complex
    theta: float


def disc(zs, zt, f):
    """The completed disc of one component (see `Disc`).

    Parameters
    ----------
    zs, zt : (n,) complex
        The component in the source and the target.
    f : (m, 3) int
        Its faces, counter-clockwise in the source.

    Returns
    -------
    Disc

    Raises
    ------
    MethodError
        Two boundary loops meet at a vertex, or the exterior or a hole
        cannot be meshed compatibly.
    """
    loops = _boundary_loops(f, len(zs))
    outer = int(np.argmax([abs(ring_area(zs[p])) for p in loops]))
    loops = [loops[outer]] + loops[:outer] + loops[outer + 1:]
    cs, ct = zs.mean(), zt.mean()
    rot = np.sum(np.conj(zs - cs) * (zt - ct))
    theta = float(np.angle(rot)) if abs(rot) > 0 else 0.0
    za = (zt - ct) * np.exp(-1j * theta) + cs  # the target brought to the source rigidly
    ring = loops[0]
    radius = MARGIN * max(np.abs(zs[ring] - cs).max(), np.abs(za[ring] - cs).max())
    circle = cs + radius * np.exp(2j * np.pi * np.arange(SIDES) / SIDES)
    # the completed disc: component vertices, then the 32-gon, then the added interior vertices
    ws, wa, faces = [zs], [za], [f]
    count = len(zs) + SIDES
    ws.append(circle)
    wa.append(circle)
    boundary = np.arange(len(zs), count)
    pieces = [(np.r_[boundary, ring], [circle, zs[ring]], [circle, za[ring]])]
    pieces += [(p, [zs[p]], [za[p]]) for p in loops[1:]]
    for given, rs, ra in pieces:
        ms, ma = _mesh(rs, ra)
        k = len(given)
        extra = ms.n_vertices - k
        index = np.r_[given, count + np.arange(extra)]
        faces.append(index[ms.faces])
        ws.append(ms.z[k:])
        wa.append(ma.z[k:])
        count += extra
    return Disc(len(zs), np.concatenate(ws), np.concatenate(wa), np.vstack(faces), len(f), boundary, circle,
                cs, ct, theta)


class ConvexFrames:
    """The disc's convex-combination embedding at any time (steps 2-3 of the module docstring).

    Parameters
    ----------
    d : Disc

    Examples
    --------
    ``ConvexFrames(d)(t)`` is the (N,) complex embedding of the whole disc
    at time ``t``, in the source's placement (before `place`).
    """

    def __init__(self, d):
        Ws, Wa = mean_value_weights(d.ws, d.faces), mean_value_weights(d.wa, d.faces)
        self.disc = d
        self.free = np.setdiff1d(np.arange(len(d.ws)), d.boundary)
        self._eye = identity(len(self.free), format="csc")
        self._As, self._Aa = Ws[self.free][:, self.free], Wa[self.free][:, self.free]
        self._bs, self._ba = Ws[self.free][:, d.boundary] @ d.circle, Wa[self.free][:, d.boundary] @ d.circle

    def __call__(self, tk):
        """(N,) complex embedding of the disc at time ``tk`` (the 32-gon fixed)."""
        A = (self._eye - (1 - tk) * self._As - tk * self._Aa).tocsc()  # blended convex-combination weights
        b = (1 - tk) * self._bs + tk * self._ba
        sol = splu(A).solve(np.c_[b.real, b.imag])
        z = np.empty(len(self.disc.ws), dtype=complex)
        z[self.free] = sol[:, 0] + 1j * sol[:, 1]
        z[self.disc.boundary] = self.disc.circle
        return z


def place(d, z, tk):
    """Positions ``z`` (k,) complex of the disc at time ``tk`` moved by the interpolated rigid motion."""
    return (z - d.cs) * np.exp(1j * tk * d.theta) + d.cs + tk * (d.ct - d.cs)


def _component(zs, zt, f, t):
    """(F, n) complex frames of one component; see `interpolate`."""
    d = disc(zs, zt, f)
    solve = ConvexFrames(d)
    out = np.empty((len(t), len(zs)), dtype=complex)
    for k, tk in enumerate(t):
        out[k] = place(d, solve(tk)[:d.n], tk)  # rigid part, interpolated
    return out, {"vertices": len(d.ws), "faces": len(d.faces), "rotation": d.theta}


def _mesh(rings_s, rings_a):
    """Compatible meshes of corresponding rings (complex arrays); ring vertices kept first.

    Their interior is `COARSE` times coarser than the rings: the completing
    faces only hold the disc together (the injective morph weighs them
    lightly), and their count sets the cost of every Newton step.
    """
    from ..correspondence.compatible_mesh import compatible_meshes

    def xy(rings):
        return [np.c_[r.real, r.imag] for r in rings]

    size = COARSE * float(np.mean(np.abs(np.concatenate([np.diff(np.r_[r, r[:1]]) for r in rings_s]))))
    try:
        ms, ma, _ = compatible_meshes(xy(rings_s), xy(rings_a), mesh_size=size)
    except IncompatibleShapesError as exc:
        raise MethodError(str(exc)) from None
    k = sum(len(r) for r in rings_s)
    if not (np.array_equal(ms.z[:k], np.concatenate(rings_s)) and np.array_equal(ma.z[:k], np.concatenate(rings_a))):
        raise MethodError("the completing mesh moved a ring vertex; the pieces cannot be glued")
    return ms, ma


def _boundary_loops(f, n):
    """`isotween.geometry.boundary_loops`, its ShapeError raised as MethodError."""
    try:
        return boundary_loops(f, n)
    except ShapeError as exc:
        raise MethodError(str(exc)) from None
