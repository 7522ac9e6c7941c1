"""As-rigid-as-possible interpolation (Alexa et al. 2000).

Each triangle's affine map from source to target, written for planar vectors u
as A u = P u + Q conj(u), is split by the polar decomposition A = R(theta) S:
theta = arg P in (-pi, pi] (the closest rotation), S = R(-theta) A symmetric.
At time t the triangle's map is A(t) = R(t theta) ((1 - t) I + t S), and the
vertex positions are the least-squares fit of every triangle's three sides to
A(t) applied to its source sides:

    min_z  sum_triangles sum_sides |(z_b - z_a) - A(t) (u_b - u_a)|^2,

a Laplace equation over the triangle sides (each side weighted by the number
of triangles it borders, its target the mean of their predictions), factorised
once for all frames. Each component's centroid moves linearly (as in AIAP):
the problem's centroids, when the triangles join the same components as the
shape's edges.

Plain ARAP takes every triangle's angle in (-pi, pi] on its own; triangles that
turn by more than half a turn then rotate the wrong way round, the artefact that
:mod:`isotween.baselines.arap_baxter` removes.
"""

import numpy as np

from .. import geometry
from ..errors import MethodError
from ..optimisation.assembly import FrameAssembler, centroid_path
from ..optimisation.problem import Result
from ..shape import Shape

__all__ = ["solve", "affine_maps", "predicted_edges"]


def _check_mesh(shape, method):
    if shape.faces is None or not len(shape.faces):
        raise MethodError(
            f"method {method!r} needs a triangle mesh (faces, e.g. from .obj/.off or "
            f"Shape.from_mesh); this shape has {shape.n_edges} edges and no faces"
        )


def affine_maps(faces, z0, z1):
    """Per-triangle affine map A u = P u + Q conj(u) from the positions z0 to z1 (`geometry.affine_maps`).

    Parameters
    ----------
    faces : (T, 3) int
    z0, z1 : (n,) complex
        Source and target vertices.

    Returns
    -------
    P, Q : (T,) complex

    Raises
    ------
    MethodError
        A source triangle has zero area (its map is undefined).
    """
    f = faces
    u1, u2 = (z0[f[:, k]] - z0[f[:, 0]] for k in (1, 2))
    bad = np.flatnonzero(np.abs(u1 * u2.conj() - u1.conj() * u2) <= 1e-12 * (np.abs(u1) ** 2 + np.abs(u2) ** 2))
    if bad.size:
        raise MethodError(f"face {bad[0]} {f[bad[0]].tolist()} has zero area in the source; ARAP cannot map it")
    return geometry.affine_maps(f, z0, z1)


def predicted_edges(source, mesh, theta, P, Q, t):
    """Targets of the least-squares fit: mean predicted vector of every side.

    A(t) u = R(t theta) [((1 - t) + t |P|) u + t e^{-i arg P} Q conj(u)].

    Parameters
    ----------
    source : Shape
        Triangle mesh.
    mesh : Shape
        The same vertices with the triangle sides as edges.
    theta : (T,) float
        Rotation angle of every triangle (arg P up to multiples of 2 pi).
    P, Q : (T,) complex
        Affine maps (:func:`affine_maps`).
    t : (F,) float

    Returns
    -------
    edges : (E, F) complex
    count : (E,) float
        Triangles bordering every edge (its weight in the fit).
    """
    faces = source.faces
    edge, sign = geometry.face_sides(faces, mesh.edges)
    tri = np.repeat(np.arange(len(faces)), 3)
    u = (source.z[faces[:, [1, 2, 0]].ravel()] - source.z[faces.ravel()])[:, None]  # (3T, 1)
    t = np.asarray(t, dtype=float)[None, :]
    stretch = ((1 - t) + t * np.abs(P)[tri, None]) * u
    stretch += t * (np.exp(-1j * np.angle(P)) * Q)[tri, None] * u.conj()
    pred = np.exp(1j * t * theta[tri, None]) * stretch  # (3T, F)
    count = np.bincount(edge, minlength=mesh.n_edges).astype(float)
    out = np.zeros((mesh.n_edges, pred.shape[1]), dtype=complex)
    np.add.at(out, edge, sign[:, None] * pred)
    return out / count[:, None], count


def solve(problem, *, method="arap", propagate=None):
    """Frames of the ARAP interpolation between the problem's first and last frame.

    Parameters
    ----------
    problem : Problem
        Of a triangle mesh, held at the first and the last frame.
    method : str
        Name used in error messages.
    propagate : callable(faces, theta, n_vertices) -> theta, optional
        Makes the angles consistent across triangles (Baxter et al.,
        :func:`isotween.baselines.arap_baxter.propagate_angles`); plain ARAP
        keeps each angle in (-pi, pi].

    Returns
    -------
    Result
        ``z`` (n, F) complex; ``info['rotation_span']``: largest minus
        smallest triangle angle used (radians).
    """
    source, t = problem.shape, problem.times
    _check_mesh(source, method)
    z0, z1 = problem.ends()
    P, Q = affine_maps(source.faces, z0, z1)
    theta = np.angle(P)
    if propagate is not None:
        theta = propagate(source.faces, theta, source.n_vertices)
    mesh = Shape(source.vertices, faces=source.faces)  # the triangle sides, whatever other edges source has
    edges, count = predicted_edges(source, mesh, theta, P, Q, t)
    if np.array_equal(mesh.components, source.components):
        centroids = problem.centroids
    else:  # other edges join the triangles differently: centroids of the triangles' components
        centroids = centroid_path(mesh, z0, z1, t)
    z = FrameAssembler(mesh, weights=count).positions(edges, centroids)
    return Result(z, info={"rotation_span": float(np.ptp(theta))})
