"""The planar shape model: vertices plus connectivity (edges, optional triangles)."""

import functools
import warnings

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .errors import ShapeError

__all__ = ["Shape"]


def _as_index_array(values, width, what):
    arr = np.asarray(values)
    if arr.size == 0:
        return np.zeros((0, width), dtype=np.int64)
    if arr.ndim != 2 or arr.shape[1] != width:
        raise ShapeError(f"{what} must be an array of shape (k, {width}), got {arr.shape}")
    if not np.issubdtype(arr.dtype, np.integer):
        if not np.all(np.isfinite(arr)) or np.any(arr != np.round(arr)):
            bad = int(np.argwhere(~np.isfinite(arr) | (arr != np.round(arr)))[0, 0])
            raise ShapeError(f"{what} {bad} has a non-integer vertex index: {arr[bad].tolist()}")
    return arr.astype(np.int64)


class Shape:
    """A planar shape: vertices with an edge soup and optional triangles.

    Parameters
    ----------
    vertices : (n, 2) array_like of float
        Vertex positions.
    edges : (E, 2) array_like of int, optional
        Vertex index pairs. Derived from ``faces`` (in first-seen order) when omitted.
    faces : (F, 3) array_like of int, optional
        Triangles, counter-clockwise or not; only needed by face metrics, ARAP
        baselines and textures.
    uv : (n, 2) array_like of float, optional
        Texture coordinates in [0, 1].
    paths : list of ((k,) int array, bool), optional
        Ordered vertex loops (``True``: closed ring) that the edges trace, as made
        by :meth:`from_polygon` and :meth:`from_polyline`. Used by outline
        methods (intrinsic baseline, resampling, SVG output).
    duplicates : {'error', 'merge'}
        What to do with an edge listed twice (in either direction).
    y_down : bool
        The y axis points down (SVG and image coordinates). Only drawing
        depends on it: renderers show such a shape with y growing downwards,
        so it appears as in the file it came from.
    regions : list of list of int, optional
        Filled regions, each a list of indices into ``paths``: its outer ring
        first, then its holes (all closed). Paths in no region are outlines.
    paint : list of Paint, optional
        How each entry of ``paths`` is drawn (fill, stroke, opacity, stroke
        width); holes repeat the paint of their region.

    Attributes
    ----------
    components : (n,) int array
        Connected-component label of every vertex (isolated vertices are their own
        component).
    n_components : int
    """

    def __init__(self, vertices, edges=None, faces=None, uv=None, paths=None, duplicates="error",
                 y_down=False, regions=None, paint=None):
        v = np.array(vertices, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 2:
            raise ShapeError(f"vertices must be an array of shape (n, 2), got {v.shape}")
        bad = np.flatnonzero(~np.all(np.isfinite(v), axis=1))
        if bad.size:
            raise ShapeError(f"vertex {bad[0]} has a non-finite coordinate: {v[bad[0]].tolist()}")
        n = len(v)
        f = None if faces is None else _as_index_array(faces, 3, "face")
        if f is not None and f.size:
            out = np.flatnonzero(np.any((f < 0) | (f >= n), axis=1))
            if out.size:
                raise ShapeError(f"face {out[0]} has a vertex index out of range [0, {n}): {f[out[0]].tolist()}")
            deg = np.flatnonzero((f[:, 0] == f[:, 1]) | (f[:, 1] == f[:, 2]) | (f[:, 2] == f[:, 0]))
            if deg.size:
                raise ShapeError(f"face {deg[0]} repeats a vertex: {f[deg[0]].tolist()}")
        if edges is None:
            if f is None:
                edges = np.zeros((0, 2), dtype=np.int64)
            else:
                edges = _edges_of_faces(f)
        e = _as_index_array(edges, 2, "edge")
        out = np.flatnonzero(np.any((e < 0) | (e >= n), axis=1))
        if out.size:
            raise ShapeError(f"edge {out[0]} has a vertex index out of range [0, {n}): {e[out[0]].tolist()}")
        loops = np.flatnonzero(e[:, 0] == e[:, 1])
        if loops.size:
            raise ShapeError(f"edge {loops[0]} is a self-loop on vertex {e[loops[0], 0]}")
        key = np.sort(e, axis=1)
        _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
        if len(first) < len(e):
            dup = np.flatnonzero(first[inverse.ravel()] != np.arange(len(e)))[0]
            orig = first[inverse.ravel()[dup]]
            if duplicates != "merge":
                raise ShapeError(
                    f"edge {dup} {e[dup].tolist()} duplicates edge {orig}; "
                    "remove it or pass duplicates='merge'"
                )
            warnings.warn(f"merged {len(e) - len(first)} duplicate edge(s), first: edge {dup}", stacklevel=2)
            e = e[np.sort(first)]
        self.vertices = v
        self.edges = e
        self.faces = f
        self.uv = None if uv is None else np.array(uv, dtype=np.float64).reshape(n, 2)
        self.paths = None if paths is None else [(np.asarray(p, dtype=np.int64), bool(c)) for p, c in paths]
        self.y_down = bool(y_down)
        self.regions, self.paint = _check_regions_paint(self.paths, regions, paint)
        graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
        self.n_components, self.components = connected_components(graph, directed=False)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_polygon(cls, rings):
        """Closed loops: one ring, or several (holes, several polygons).

        Parameters
        ----------
        rings : (k, 2) array_like, or list of (k_i, 2) array_like
            Ring vertices in order; the closing edge is implied (do not repeat
            the first point at the end).
        """
        return cls._from_paths(rings, closed=True)

    @classmethod
    def from_polyline(cls, points):
        """Open chain(s): one (k, 2) array or a list of them."""
        return cls._from_paths(points, closed=False)

    @classmethod
    def from_mesh(cls, vertices, faces, uv=None):
        """Triangle mesh; edges are the unique triangle sides."""
        return cls(vertices, faces=faces, uv=uv)

    @classmethod
    def _from_paths(cls, rings, closed):
        if isinstance(rings, np.ndarray) and rings.ndim == 2 or (
            len(rings) and np.ndim(rings[0]) == 1
        ):
            rings = [rings]
        vertices, edges, paths, start = [], [], [], 0
        for r, ring in enumerate(rings):
            ring = np.asarray(ring, dtype=np.float64)
            if ring.ndim != 2 or ring.shape[1] != 2:
                raise ShapeError(f"ring {r} must be an array of shape (k, 2), got {ring.shape}")
            k = len(ring)
            if k < (3 if closed else 2):
                raise ShapeError(f"ring {r} has {k} point(s); a {'closed ring' if closed else 'polyline'} needs at least {3 if closed else 2}")
            idx = np.arange(start, start + k)
            vertices.append(ring)
            edges.append(np.column_stack([idx, np.roll(idx, -1)] if closed else [idx[:-1], idx[1:]]))
            paths.append((idx, closed))
            start += k
        return cls(np.vstack(vertices), np.vstack(edges), paths=paths)

    # ------------------------------------------------------------------ properties
    @property
    def n_vertices(self):
        return len(self.vertices)

    @property
    def n_edges(self):
        return len(self.edges)

    @property
    def n_faces(self):
        return 0 if self.faces is None else len(self.faces)

    @functools.cached_property
    def topology(self):
        """Connectivity data shared by shapes with these edges (:class:`Topology`)."""
        from .topology import Topology

        return Topology(self.edges, self.n_vertices, self.components, self.n_components)

    @property
    def z(self):
        """(n,) complex: the vertices as complex numbers x + iy."""
        return self.vertices[:, 0] + 1j * self.vertices[:, 1]

    def edge_vectors(self, z=None):
        """(E,) complex: ``p_j - p_i`` for every edge (i, j) (of ``z`` if given)."""
        z = self.z if z is None else z
        return z[..., self.edges[:, 1]] - z[..., self.edges[:, 0]]

    def bbox_diagonal(self):
        """Length of the bounding-box diagonal (float)."""
        if not len(self.vertices):
            return 0.0
        d = self.vertices.max(axis=0) - self.vertices.min(axis=0)
        return float(np.sqrt(d @ d))

    def with_vertices(self, vertices):
        """A shape with the same connectivity (and uv, paths) at new positions."""
        s = object.__new__(Shape)
        s.__dict__.update(self.__dict__)
        v = np.asarray(vertices, dtype=np.float64)
        if v.shape != self.vertices.shape:
            raise ShapeError(f"expected vertices of shape {self.vertices.shape}, got {v.shape}")
        s.vertices = v
        return s

    def face_areas(self, vertices=None):
        """(F,) signed triangle areas (positive = counter-clockwise)."""
        v = self.vertices if vertices is None else np.asarray(vertices)
        if self.faces is None:
            return np.zeros(v.shape[:-2] + (0,))
        a, b, c = (v[..., self.faces[:, i], :] for i in range(3))
        ab, ac = b - a, c - a
        return 0.5 * (ab[..., 0] * ac[..., 1] - ab[..., 1] * ac[..., 0])

    def __repr__(self):
        return (
            f"Shape({self.n_vertices} vertices, {self.n_edges} edges, {self.n_faces} faces, "
            f"{self.n_components} component(s))"
        )


def _check_regions_paint(paths, regions, paint):
    """Validated (regions, paint) against ``paths``."""
    if regions is None and paint is None:
        return None, None
    if paths is None:
        raise ShapeError("regions and paint need paths")
    if regions is not None:
        regions = [[int(i) for i in r] for r in regions]
        used = [i for r in regions for i in r]
        for k, r in enumerate(regions):
            if not r:
                raise ShapeError(f"region {k} is empty")
            bad = [i for i in r if not 0 <= i < len(paths) or not paths[i][1]]
            if bad:
                raise ShapeError(f"region {k} names path {bad[0]}, which is not a closed path of the shape")
        if len(set(used)) < len(used):
            raise ShapeError("a path belongs to two regions")
    if paint is not None:
        from .paint import Paint

        paint = list(paint)
        if len(paint) != len(paths):
            raise ShapeError(f"paint has {len(paint)} entries for {len(paths)} paths")
        bad = [k for k, p in enumerate(paint) if not isinstance(p, Paint)]
        if bad:
            raise ShapeError(f"paint {bad[0]} is not a Paint: {paint[bad[0]]!r}")
    return regions, paint


def _edges_of_faces(faces):
    """Unique undirected triangle sides in first-seen order."""
    e = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    _, first = np.unique(np.sort(e, axis=1), axis=0, return_index=True)
    return e[np.sort(first)]
