"""Meshes from outlines: compatible source and target triangle meshes.

By default (``mesher="shapely"``) the pair comes from `compatible_meshes`:
each polygon triangulated on its own, both mapped onto a common disc and
overlaid, so neither mesh has a flipped triangle, by construction; only
permissively licensed code (shapely, numpy, scipy) is used.

``mesher="triangle"`` keeps the earlier path: the source polygon (rings with
holes) is triangulated by Shewchuk's Triangle (the ``triangle`` package, the
``mesh`` extra; free for non-commercial use only) with no extra vertices on
the outline (switch ``Y``), and the interior vertices of the target are the
harmonic extension of the target outline: the cotangent Laplacian of the
source mesh, ``L_II z_I = -L_IB z_B``. It reproduces affine maps exactly, but
on a non-convex target it can flip triangles; a warning names them.
"""

from __future__ import annotations

import numbers
import warnings
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.sparse.linalg import splu

from ..errors import ParameterError, ResourceError, ShapeError, require
from ..geometry import cotangent_laplacian, ring_area
from ..resources import check_memory
from ..shape import Shape
from .compatibility import as_shape, check_compatible
from .compatible_mesh import compatible_meshes

if TYPE_CHECKING:
    from ..shape import ShapeLike

__all__ = ["mesh_pair", "MeshPair"]


class MeshPair(NamedTuple):
    """What `mesh_pair` returns.

    Attributes
    ----------
    source, target : Shape
        Triangle meshes with the same faces; vertices 0..n-1 are the outline
        vertices, in order, ``paths`` the input rings, ``y_down`` the source's.
    flipped : (k,) int array
        Triangles of the target whose orientation differs from the source's
        (always empty with the default mesher).
    """

    source: Shape
    target: Shape
    flipped: np.ndarray


def mesh_pair(source: ShapeLike, target: ShapeLike, max_area: float | None = None,
              min_angle: float = 30.0, mesher: str = "shapely",
              mesh_size: float | None = None, max_memory: float | None = None) -> MeshPair:
    """Compatible triangle meshes of a compatible outline pair.

    Parameters
    ----------
    source, target : Shape
        A compatible pair of polygon shapes: closed rings only (outer
        boundaries and holes, by the even-odd rule), e.g. from `resample`.
        With the default mesher: one polygon, its largest ring the outer
        boundary and the other rings its holes.
    max_area : float, optional
        Largest triangle area. With the default mesher it sets the mesh size
        (the side of an equilateral triangle of area ``max_area``) unless
        ``mesh_size`` is given. Default: none; the outline's mean edge length
        (default mesher) or triangles that grow inwards (Triangle).
    min_angle : float
        Smallest triangle angle in degrees for ``mesher="triangle"`` (at most
        34; Triangle's quality bound). Near short outline edges meeting at
        sharp corners it may not be reached, since no vertex is added on the
        outline. The default mesher reports its smallest angles instead
        (`compatible_meshes`).
    mesher : {'shapely', 'triangle'}
        ``'shapely'``: `compatible_meshes`, no flipped triangle in either
        mesh. ``'triangle'``: Triangle plus a harmonic map (needs
        ``isotween[mesh]``; non-commercial licence).
    mesh_size : float, optional
        Target edge length of the default mesher.
    max_memory : int, optional
        Bytes the Triangle mesh may take (``mesher="triangle"``); default the
        memory available now. The triangle count is estimated from the
        enclosed area and ``max_area`` before meshing (`ResourceError` when
        too many). The default mesher refuses a mesh size past
        `isotween.geometry.MAX_TRIANGLES` triangles before meshing.

    Returns
    -------
    MeshPair
        ``(source, target, flipped)``; with ``mesher="triangle"`` a warning
        names the flipped target triangles if there are any.

    Raises
    ------
    ShapeError
        Open paths, an outline that touches or crosses itself (the message
        names ring and vertex), a hole outside the outer ring, or no enclosed
        area.
    IncompatibleShapesError
        The outlines do not share vertex count and connectivity, or the
        correspondence mirrors a ring.
    ParameterError
        ``max_area``, ``mesh_size``, ``min_angle`` or ``mesher`` out of range;
        with ``mesher="triangle"``, a triangle that stays more than twice
        ``max_area`` (no vertex is added on the outline: resample it more
        finely).
    ResourceError
        The estimated Triangle mesh exceeds the memory limit.
    MissingDependencyError
        shapely (default) or triangle (``mesher="triangle"``) is missing.

    Examples
    --------
    >>> import isotween
    >>> square = isotween.Shape.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
    >>> source, target, flipped = isotween.mesh_pair(square, square.rotate(0.3), max_area=0.05)
    >>> source.n_faces == target.n_faces > 2, flipped.size
    (True, 0)
    """
    if mesher not in ("shapely", "triangle"):
        raise ParameterError(f"mesher must be 'shapely' or 'triangle', got {mesher!r}")
    if max_area is not None and not (isinstance(max_area, numbers.Real) and np.isfinite(max_area) and max_area > 0):
        raise ParameterError(f"max_area must be a positive number, got {max_area!r}")
    if not (isinstance(min_angle, numbers.Real) and 0 <= min_angle <= 34):
        raise ParameterError(f"min_angle must lie between 0 and 34 degrees, got {min_angle!r}")
    if mesher == "triangle":
        return _mesh_pair_triangle(source, target, max_area, min_angle, max_memory)
    source, target = as_shape(source, "source"), as_shape(target, "target")
    check_compatible(source, target)
    _outline(source)
    _check_distinct(source)
    if mesh_size is None and max_area is not None:
        mesh_size = float(np.sqrt(4 * max_area / np.sqrt(3)))
    area = [abs(ring_area(source.z[p])) for p, _ in source.paths]
    paths = [source.paths[i][0] for i in np.argsort(-np.array(area), kind="stable")]  # the outer ring first
    ring_ids = np.concatenate(paths)
    try:
        result = compatible_meshes([source.vertices[p] for p in paths], [target.vertices[p] for p in paths],
                                   mesh_size=mesh_size)
    except ResourceError as exc:
        if max_area is None:
            raise
        raise ResourceError(f"max_area={max_area:g}: {exc}") from None
    # back to the input's vertex numbering: ring vertex i of the result is vertex ring_ids[i]
    n, N = source.n_vertices, result.source.n_vertices
    new_id = np.r_[ring_ids, np.arange(n, N)]
    faces = new_id[result.source.faces]
    vs, vt = np.empty((N, 2)), np.empty((N, 2))
    vs[new_id], vt[new_id] = result.source.vertices, result.target.vertices
    src = Shape(vs, faces=faces, paths=source.paths, y_down=source.y_down)
    return MeshPair(src, src.with_vertices(vt), np.zeros(0, dtype=np.int64))


def _mesh_pair_triangle(source, target, max_area, min_angle, max_memory):
    """The Triangle mesher and harmonic target map (``mesher="triangle"``)."""
    triangle = require("triangle", "mesh")
    source, target = as_shape(source, "source"), as_shape(target, "target")
    check_compatible(source, target)
    segments = _outline(source)
    switches = "pY"
    if max_area is not None:
        switches += "a" + np.format_float_positional(max_area, trim="-")  # no exponent: 'e' is a switch
    switches += "q" + np.format_float_positional(min_angle, trim="-")
    n = source.n_vertices
    if max_area is not None:
        faces = 2.0 * _enclosed_area(source) / max_area + 2.0 * n
        check_memory(_BYTES_PER_FACE * faces, f"meshing with max_area={max_area:g} (about {faces:.3g} triangles)",
                     max_memory, advice="use a larger max_area")
    _check_distinct(source)
    points = np.array(source.vertices)  # triangle needs writeable buffers; shape arrays are read-only
    plain = triangle.triangulate({"vertices": points, "segments": segments}, "p")
    _check_outline(source, segments, plain)
    holes = _hole_points(source, segments, plain)
    data = {"vertices": points, "segments": segments}
    if len(holes):
        data["holes"] = holes
    mesh = triangle.triangulate(data, switches)
    _check_outline(source, segments, mesh)
    vertices, faces = mesh["vertices"], mesh["triangles"].astype(np.int64)
    if max_area is not None:
        _check_max_area(vertices, faces, max_area, segments, source.z)
    z = _harmonic(vertices, faces, n, target.z)
    src = Shape(vertices, faces=faces, paths=source.paths, y_down=source.y_down)
    tgt = src.with_vertices(np.column_stack([z.real, z.imag]))
    a0, a1 = src.face_areas(), tgt.face_areas()
    flipped = np.flatnonzero(np.sign(a1) != np.sign(a0))
    if flipped.size:
        warnings.warn(
            f"the target mesh has {flipped.size} flipped triangle(s) of {len(faces)} "
            f"(first: triangle {flipped[0]}); AIAP interpolation tolerates a few",
            stacklevel=3,
        )
    return MeshPair(src, tgt, flipped)


#: peak bytes per triangle of Triangle plus the harmonic map (measured 1.4-1.6 KB
#: on a 200-gon at 49,000 and 489,000 triangles)
_BYTES_PER_FACE = 2000.0

#: triangles along the outline may exceed max_area by this factor before
#: mesh_pair refuses (no vertex can be added on the outline to split them)
_AREA_SLACK = 2.0


def _enclosed_area(shape):
    """Sum of the absolute areas of the closed rings (an upper bound of the filled area)."""
    return float(sum(abs(ring_area(shape.z[p])) for p, c in shape.paths or [] if c))


def _check_max_area(vertices, faces, max_area, segments, z):
    """Raise when Triangle missed ``max_area`` by more than `_AREA_SLACK` (it adds no outline vertex)."""
    p = vertices[faces]
    area = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                        - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0]))
    over = np.flatnonzero(area > max_area * (1 + 1e-9))
    if area.max() > _AREA_SLACK * max_area:
        longest = float(np.abs(z[segments[:, 1]] - z[segments[:, 0]]).max())
        raise ParameterError(
            f"max_area={max_area:g} cannot be met: {over.size} of {len(faces)} triangles stay larger "
            f"(largest {float(area.max()):.4g}) because no vertex is added on the outline, whose longest "
            f"edge is {longest:.4g}; resample the outline more finely (--resample N) or use a larger max_area"
        )


def _outline(shape):
    """(E, 2) outline segments of a polygon shape; its paths must be closed rings."""
    if shape.faces is not None and len(shape.faces):
        raise ShapeError("the source is already a triangle mesh; mesh_pair takes outlines")
    if not shape.paths:
        raise ShapeError("the source has no outline rings (paths) to mesh")
    for r, (_idx, closed) in enumerate(shape.paths):
        if not closed:
            raise ShapeError(f"ring {r} of the source is an open polyline; meshing needs closed rings")
    segments = np.vstack([np.column_stack([p, np.roll(p, -1)]) for p, _ in shape.paths])
    covered = np.unique(np.concatenate([p for p, _ in shape.paths]))
    if len(segments) != shape.n_edges or len(covered) != shape.n_vertices:
        raise ShapeError("the source has edges or vertices outside its rings; mesh_pair takes polygon outlines")
    return segments


def _ring_of(shape, vertex):
    """(ring, position in the ring) of an outline vertex, for messages."""
    for r, (idx, _) in enumerate(shape.paths):
        hit = np.flatnonzero(idx == vertex)
        if hit.size:
            return r, int(hit[0])
    return None, vertex


def _check_distinct(shape):
    """Raise if two outline vertices coincide (Triangle cannot take repeated vertices)."""
    from scipy.spatial import cKDTree

    close = cKDTree(shape.vertices).query_pairs(1e-9 * shape.bbox_diagonal(), output_type="ndarray")
    if len(close):
        i, j = np.sort(close[np.lexsort(close.T[::-1])[0]])
        (ri, ki), (rj, kj) = _ring_of(shape, i), _ring_of(shape, j)
        x, y = shape.vertices[i]
        raise ShapeError(
            f"the source outline touches itself at ({x:.6g}, {y:.6g}): vertex {ki} of ring {ri} "
            f"and vertex {kj} of ring {rj} coincide"
        )


def _check_outline(shape, segments, mesh):
    """Raise if the mesher merged, split or added outline vertices."""
    n = shape.n_vertices
    v = mesh["vertices"]
    markers = mesh.get("vertex_markers", np.zeros(len(v), dtype=np.int64)).ravel()
    added = np.flatnonzero(markers[n:] != 0) + n
    used = np.zeros(n, dtype=bool)
    tri = mesh.get("triangles", np.zeros((0, 3), dtype=np.int64))
    used[tri[tri < n]] = True
    if added.size:
        x, y = v[added[0]]
        raise ShapeError(f"the source outline touches or crosses itself near ({x:.6g}, {y:.6g})")
    if not used.all():
        k = int(np.flatnonzero(~used)[0])
        r, i = _ring_of(shape, k)
        x, y = shape.vertices[k]
        raise ShapeError(
            f"vertex {i} of ring {r} at ({x:.6g}, {y:.6g}) touches another part of the source outline "
            "or encloses no area"
        )
    if len(mesh.get("segments", ())) != len(segments):  # a vertex on another segment split it
        key = np.sort(segments, axis=1) @ np.array([n, 1])
        out = np.sort(mesh["segments"], axis=1)
        split = out[~np.isin(out @ np.array([n, 1]), key)]
        common = np.intersect1d(split[0], split[1]) if len(split) > 1 else split[0]
        x, y = v[common[0]]
        raise ShapeError(f"the source outline touches itself at ({x:.6g}, {y:.6g})")


def _hole_points(shape, segments, plain):
    """One point inside every hole of the polygon (even-odd rule).

    The triangles of a plain constrained triangulation fall into regions
    bounded by the outline; one triangle per region tells whether the region
    is inside (odd number of rings around it) or a hole (even).
    """
    tri = plain["triangles"].astype(np.int64)
    if not len(tri):
        raise ShapeError("the source outline encloses no area")
    sides = np.sort(tri[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), axis=1)
    owner = np.repeat(np.arange(len(tri)), 3)
    n = shape.n_vertices
    key = sides[:, 0] * n + sides[:, 1]
    seg_key = np.sort(segments, axis=1) @ np.array([n, 1])
    free = ~np.isin(key, seg_key)
    order = np.argsort(key[free], kind="stable")
    k, o = key[free][order], owner[free][order]
    pair = np.flatnonzero(k[1:] == k[:-1])
    adj = coo_matrix((np.ones(len(pair)), (o[pair], o[pair + 1])), shape=(len(tri), len(tri)))
    _, region = connected_components(adj, directed=False)
    _, first = np.unique(region, return_index=True)
    centre = plain["vertices"][tri[first]].mean(axis=1)
    inside = _crossings(centre, shape.vertices[segments]) % 2 == 1
    return centre[~inside]


def _crossings(points, segments):
    """(m,) number of segments a ray from each point towards +x crosses.

    Parameters
    ----------
    points : (m, 2) array
    segments : (E, 2, 2) array
    """
    a, b = segments[:, 0], segments[:, 1]
    px, py = points[:, 0:1], points[:, 1:2]
    straddle = (a[:, 1] > py) != (b[:, 1] > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (py - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return np.sum(straddle & (px < x), axis=1)


def _harmonic(vertices, faces, n, boundary):
    """Harmonic extension of complex boundary values ``boundary`` (n,) to the mesh.

    Cotangent weights of the source mesh; vertices 0..n-1 are fixed.

    Returns
    -------
    (N,) complex array
    """
    N = len(vertices)
    L = cotangent_laplacian(vertices, faces)
    z = np.empty(N, dtype=complex)
    z[:n] = boundary
    if N > n:
        rhs = -(L[n:, :n] @ boundary)
        sol = splu(L[n:, n:].tocsc()).solve(np.column_stack([rhs.real, rhs.imag]))
        z[n:] = sol[:, 0] + 1j * sol[:, 1]
    return z
