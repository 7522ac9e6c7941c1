"""The planar shape model: vertices plus connectivity (edges, optional triangles)."""

import functools
import warnings

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .errors import ShapeError

__all__ = ["Shape"]


#: largest coordinate magnitude accepted: squared lengths and the energy's sums
#: of them stay far from overflow (1e100 squared is 1e200)
MAX_COORDINATE = 1e100

_INT64 = np.iinfo(np.int64)


def _as_index_array(values, width, what):
    """(k, width) int64 array of vertex indices, or `ShapeError` naming the bad row."""
    try:
        arr = np.asarray(values)
    except (ValueError, TypeError, OverflowError):
        raise ShapeError(f"{what}: expected a (k, {width}) array of vertex indices, got ragged or mixed rows") from None
    if arr.size == 0:
        return np.zeros((0, width), dtype=np.int64)
    if arr.ndim != 2 or arr.shape[1] != width:
        raise ShapeError(f"{what} must be an array of shape (k, {width}), got {arr.shape}")
    if arr.dtype.kind == "O":  # Python ints beyond int64, or mixed objects
        for row, item in enumerate(arr.tolist()):
            for x in item:
                if isinstance(x, bool) or not isinstance(x, (int, np.integer)) or not _INT64.min <= x <= _INT64.max:
                    raise ShapeError(f"{what} {row} has an invalid vertex index: {x!r}")
        arr = arr.astype(np.int64)
    if arr.dtype.kind not in "iuf":
        raise ShapeError(f"{what} vertex indices must be integers, got {arr.dtype} values")
    if arr.dtype.kind == "f":
        bad = ~np.isfinite(arr) | (arr != np.round(arr)) | (np.abs(arr) > 2.0**62)
        if np.any(bad):
            row = int(np.argwhere(bad)[0, 0])
            raise ShapeError(f"{what} {row} has a non-integer vertex index: {arr[row].tolist()}")
    elif arr.dtype.kind == "u" and arr.max() > _INT64.max:
        row = int(np.argwhere(arr > _INT64.max)[0, 0])
        raise ShapeError(f"{what} {row} has an invalid vertex index: {arr[row].tolist()}")
    return arr.astype(np.int64)


def as_vertices(values, where="", shape=None):
    """Validated (n, 2) float64 vertex array.

    Parameters
    ----------
    values : (n, 2) array_like of real numbers
    where : str
        Prefix of messages (e.g. ``"ring 2: "``).
    shape : tuple, optional
        Required shape (e.g. that of the vertices being replaced).

    Raises
    ------
    ShapeError
        Ragged or non-numeric input, wrong shape, a non-finite coordinate or
        one beyond ``MAX_COORDINATE``; the message names the first bad vertex.
    """
    try:
        raw = np.asarray(values)
    except (ValueError, TypeError):
        raise ShapeError(f"{where}vertices must be an (n, 2) array of numbers, got ragged or mixed rows") from None
    if raw.dtype.kind not in "iuf":
        raise ShapeError(f"{where}vertices must be real numbers, got {raw.dtype} values")
    try:
        v = np.array(raw, dtype=np.float64)
    except OverflowError:
        raise ShapeError(f"{where}a vertex coordinate is too large for a float") from None
    if v.ndim != 2 or v.shape[1] != 2:
        raise ShapeError(f"{where}vertices must be an array of shape (n, 2), got {v.shape}")
    if shape is not None and v.shape != tuple(shape):
        raise ShapeError(f"{where}expected vertices of shape {tuple(shape)}, got {v.shape}")
    bad = np.flatnonzero(~np.all(np.isfinite(v), axis=1))
    if bad.size:
        raise ShapeError(f"{where}vertex {bad[0]} has a non-finite coordinate: {v[bad[0]].tolist()}")
    big = np.flatnonzero(np.any(np.abs(v) > MAX_COORDINATE, axis=1))
    if big.size:
        raise ShapeError(
            f"{where}vertex {big[0]} has a coordinate beyond +-{MAX_COORDINATE:g}: "
            f"{v[big[0]].tolist()}; scale the shape down"
        )
    return v


def _as_uv(uv, n):
    """Validated (n, 2) float64 texture coordinates (finite)."""
    try:
        raw = np.asarray(uv)
    except (ValueError, TypeError):
        raise ShapeError("uv must be an (n, 2) array of numbers, got ragged or mixed rows") from None
    if raw.dtype.kind not in "iuf":
        raise ShapeError(f"uv must be real numbers, got {raw.dtype} values")
    u = np.array(raw, dtype=np.float64)
    if u.shape != (n, 2):
        raise ShapeError(f"uv must have shape ({n}, 2), one row per vertex, got {u.shape}")
    bad = np.flatnonzero(~np.all(np.isfinite(u), axis=1))
    if bad.size:
        raise ShapeError(f"uv of vertex {bad[0]} is not finite: {u[bad[0]].tolist()}")
    return u


def _as_paths(paths, n):
    """Validated list of ((k,) int64 indices, closed) pairs into n vertices.

    The index arrays are checked together (one range check for all paths);
    only a path that fails is looked at on its own, for the message.
    """
    if isinstance(paths, (str, bytes)) or not hasattr(paths, "__iter__"):
        raise ShapeError(f"paths must be a list of (indices, closed) pairs, got {type(paths).__name__}")
    indices, flags = [], []
    for k, item in enumerate(paths):
        try:
            idx, closed = item
            idx = np.asarray(idx)
        except (TypeError, ValueError):
            raise ShapeError(f"path {k} must be an (indices, closed) pair, got {item!r:.60}") from None
        if idx.ndim != 1:
            raise ShapeError(f"path {k}: indices must be a flat list of vertex indices, got shape {idx.shape}")
        if not isinstance(closed, (bool, np.bool_, int, np.integer)):
            raise ShapeError(f"path {k}: closed must be true or false, got {closed!r:.60}")
        indices.append(idx)
        flags.append(bool(closed))
    sizes = [len(i) for i in indices]
    kinds = {i.dtype.kind for i in indices if len(i)}
    if kinds <= {"i", "u"}:
        flat = np.concatenate(indices).astype(np.int64) if indices else np.zeros(0, np.int64)
        bad = np.flatnonzero((flat < 0) | (flat >= n))
        if not bad.size:
            return list(zip(np.split(flat, np.cumsum(sizes)[:-1]), flags)) if indices else []
        k = int(np.searchsorted(np.cumsum(sizes), bad[0], side="right"))
        raise ShapeError(f"path {k} has a vertex index out of range [0, {n}): {int(flat[bad[0]])}")
    out = []
    for k, (idx, closed) in enumerate(zip(indices, flags)):
        idx = _as_index_array(idx.reshape(-1, 1), 1, f"path {k} index")[:, 0]
        out_of_range = np.flatnonzero((idx < 0) | (idx >= n))
        if out_of_range.size:
            raise ShapeError(f"path {k} has a vertex index out of range [0, {n}): {int(idx[out_of_range[0]])}")
        out.append((idx, closed))
    return out


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
        if duplicates not in ("error", "merge"):
            raise ShapeError(f"duplicates must be 'error' or 'merge', got {duplicates!r}")
        v = as_vertices(vertices)
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
        self.uv = None if uv is None else _as_uv(uv, n)
        self.paths = None if paths is None else _as_paths(paths, n)
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
        kind = "closed ring" if closed else "polyline"
        if isinstance(rings, (str, bytes)) or not hasattr(rings, "__len__"):
            raise ShapeError(f"expected a (k, 2) array of points or a list of them, got {type(rings).__name__}")
        if len(rings) == 0:
            raise ShapeError(f"no points: a {kind} needs at least {3 if closed else 2}")
        try:
            single = isinstance(rings, np.ndarray) and rings.ndim == 2 or np.ndim(rings[0]) == 1
        except ValueError:  # ragged rows inside the first ring
            single = False
        if single:
            rings = [rings]
        vertices, edges, paths, start = [], [], [], 0
        for r, ring in enumerate(rings):
            empty = hasattr(ring, "__len__") and not isinstance(ring, (str, bytes)) and len(ring) == 0
            ring = np.zeros((0, 2)) if empty else as_vertices(ring, f"ring {r}: ")
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
        v = as_vertices(vertices, shape=self.vertices.shape)
        s = object.__new__(Shape)
        s.__dict__.update(self.__dict__)
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
