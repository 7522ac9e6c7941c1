"""The planar shape model: vertices plus connectivity (edges, optional triangles)."""

from __future__ import annotations

import functools
import html
import numbers
import warnings
from collections.abc import Sequence, Sized
from typing import TYPE_CHECKING, Any, TypeAlias

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._validate import check_number
from .errors import ParameterError, ShapeError

if TYPE_CHECKING:
    from .topology import Topology

__all__ = ["Shape", "ShapeLike"]


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
            return list(zip(np.split(flat, np.cumsum(sizes)[:-1]), flags, strict=False)) if indices else []
        k = int(np.searchsorted(np.cumsum(sizes), bad[0], side="right"))
        raise ShapeError(f"path {k} has a vertex index out of range [0, {n}): {int(flat[bad[0]])}")
    out = []
    for k, (idx, closed) in enumerate(zip(indices, flags, strict=False)):
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
    drawing : bool
        Read from a drawing (SVG), whose point order means nothing: the
        pipeline always puts drawings in correspondence, even when their
        counts happen to match (`isotween.prepare_pair`). Kept by
        :meth:`with_vertices`; not part of the shape's value.

    Examples
    --------
    >>> from isotween import Shape
    >>> square = Shape([[0, 0], [1, 0], [1, 1], [0, 1]], edges=[[0, 1], [1, 2], [2, 3], [3, 0]])
    >>> square
    Shape(4 vertices, 4 edges, 0 faces, 1 component(s))
    >>> mesh = Shape([[0, 0], [1, 0], [1, 1], [0, 1]], faces=[[0, 1, 2], [0, 2, 3]])
    >>> mesh.edges.tolist()
    [[0, 1], [1, 2], [2, 0], [2, 3], [3, 0]]
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
        from .geometry import edge_keys  # (geometry is no part of the model: imported where used)

        _, first, inverse = np.unique(edge_keys(e[:, 0], e[:, 1]), return_index=True, return_inverse=True)
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
        self.drawing = False
        self.regions, self.paint = _check_regions_paint(self.paths, regions, paint)
        from scipy.sparse import coo_matrix  # here: scipy.sparse takes 0.1 s to import
        from scipy.sparse.csgraph import connected_components

        graph = coo_matrix((np.ones(len(e)), (e[:, 0], e[:, 1])), shape=(n, n))
        self.n_components, self.components = connected_components(graph, directed=False)
        self._freeze()

    # ------------------------------------------------------------------ constructors
    @classmethod
    def from_polygon(cls, rings: ArrayLike | Sequence[ArrayLike]) -> Shape:
        """Closed loops: one ring, or several (holes, several polygons).

        Parameters
        ----------
        rings : (k, 2) array_like, or list of (k_i, 2) array_like
            Ring vertices in order; the closing edge is implied (do not repeat
            the first point at the end).

        Returns
        -------
        Shape
            With one closed path per ring.

        Examples
        --------
        >>> from isotween import Shape
        >>> square = Shape.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]])
        >>> square.n_vertices, square.n_edges
        (4, 4)
        """
        return cls.from_paths(_ring_list(rings), closed=True)

    @classmethod
    def from_polyline(cls, points: ArrayLike | Sequence[ArrayLike]) -> Shape:
        """Open chain(s): one (k, 2) array or a list of them.

        Parameters
        ----------
        points : (k, 2) array_like, or list of (k_i, 2) array_like
            Chain vertices in order.

        Returns
        -------
        Shape
            With one open path per chain.

        Examples
        --------
        >>> from isotween import Shape
        >>> Shape.from_polyline([[0, 0], [1, 0], [2, 1]]).n_edges
        2
        """
        return cls.from_paths(_ring_list(points), closed=False)

    @classmethod
    def from_mesh(cls, vertices: ArrayLike, faces: ArrayLike, uv: ArrayLike | None = None) -> Shape:
        """Triangle mesh; edges are the unique triangle sides.

        Parameters
        ----------
        vertices : (n, 2) array_like of float
        faces : (F, 3) array_like of int
        uv : (n, 2) array_like of float, optional
            Texture coordinates.

        Returns
        -------
        Shape

        Examples
        --------
        >>> from isotween import Shape
        >>> Shape.from_mesh([[0, 0], [1, 0], [0, 1], [1, 1]], [[0, 1, 2], [1, 3, 2]]).n_edges
        5
        """
        return cls(vertices, faces=faces, uv=uv)

    @classmethod
    def coerce(cls, obj: Shape | ArrayLike, name: str = "shape") -> Shape:
        """``obj`` itself if it is a Shape, else the polygon whose vertices it lists.

        This is how every function that takes a Shape also takes a plain
        ``(n, 2)`` polygon array.

        Parameters
        ----------
        obj : Shape or (n, 2) array_like of float
        name : str
            What to call ``obj`` in the error message.

        Returns
        -------
        Shape

        Raises
        ------
        ShapeError
            ``obj`` is neither a Shape nor an (n, 2) array of at least 3 finite points.

        Examples
        --------
        >>> from isotween import Shape
        >>> Shape.coerce([[0, 0], [1, 0], [0, 1]]).n_edges
        3
        """
        if isinstance(obj, cls):
            return obj
        try:
            arr = np.asarray(obj, dtype=np.float64)
        except (TypeError, ValueError):
            arr = None
        if arr is None or arr.ndim != 2 or arr.shape[1] != 2:
            got = type(obj).__name__ if arr is None else f"an array of shape {arr.shape}"
            raise ShapeError(f"{name} must be an isotween.Shape or an (n, 2) polygon array, got {got}")
        try:
            return cls.from_polygon(arr)
        except ShapeError as exc:
            raise ShapeError(f"{name}: {exc}") from exc

    @classmethod
    def from_paths(cls, rings: Sequence[ArrayLike], closed: bool | Sequence[bool] = True, *,
                   y_down: bool = False, regions: list[list[int]] | None = None,
                   paint: list | None = None) -> Shape:
        """One shape from vertex chains: the ring builder behind every outline reader.

        Vertices are numbered ring after ring, in order; each ring becomes one
        entry of ``paths`` and its edges join consecutive points (and the last
        to the first when closed).

        Parameters
        ----------
        rings : list of (k_i, 2) array_like of float, or of (k_i,) complex
            The chains' points in order (a closed ring does not repeat its
            first point).
        closed : bool or list of bool
            Whether each chain is a closed ring (one value for all, or one per
            chain).
        y_down, regions, paint
            As in :class:`Shape`.

        Returns
        -------
        Shape

        Raises
        ------
        ShapeError
            A ring that is not a list of 2-D points, or that has too few points
            (3 for a closed ring, 2 for a chain).

        Examples
        --------
        >>> import numpy as np
        >>> from isotween import Shape
        >>> outer = np.array([[0, 0], [4, 0], [4, 4], [0, 4]])
        >>> s = Shape.from_paths([outer, outer[::-1] * 0.5 + 1, [[5, 0], [6, 1]]],
        ...                      closed=[True, True, False])
        >>> s.n_vertices, s.n_edges, [c for _, c in s.paths]
        (10, 9, [True, True, False])
        """
        rings = list(rings)
        if isinstance(closed, (bool, np.bool_)):
            flags = [bool(closed)] * len(rings)
        else:
            flags = [bool(c) for c in closed]
        if len(flags) != len(rings):
            raise ShapeError(f"closed has {len(flags)} values for {len(rings)} rings")
        points = []
        for r, (ring, c) in enumerate(zip(rings, flags, strict=True)):
            if isinstance(ring, np.ndarray) and np.iscomplexobj(ring) and ring.ndim == 1:
                ring = np.column_stack([ring.real, ring.imag])
            empty = isinstance(ring, Sized) and not isinstance(ring, (str, bytes)) and len(ring) == 0
            ring = np.zeros((0, 2)) if empty else as_vertices(ring, f"ring {r}: ")
            need = 3 if c else 2
            if len(ring) < need:
                kind = "closed ring" if c else "polyline"
                raise ShapeError(f"ring {r} has {len(ring)} point(s); a {kind} needs at least {need}")
            points.append(np.asarray(ring, dtype=np.float64))
        if not points:
            raise ShapeError("no rings given")
        sizes = np.array([len(p) for p in points])
        is_closed = np.array(flags)
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]])
        ends = starts + sizes - 1
        idx = np.arange(int(sizes.sum()))
        nxt = idx + 1
        nxt[ends[is_closed]] = starts[is_closed]  # the closing edge of every ring
        keep = np.ones(len(idx), dtype=bool)
        keep[ends[~is_closed]] = False  # a chain's last point starts no edge
        edges = np.column_stack([idx, nxt])[keep]
        paths = [(idx[s : s + k], c) for s, k, c in zip(starts, sizes, flags, strict=True)]
        return cls(np.vstack(points), edges, paths=paths, y_down=y_down, regions=regions, paint=paint)

    # ------------------------------------------------------------------ properties
    @property
    def n_vertices(self) -> int:
        """Number of vertices."""
        return len(self.vertices)

    @property
    def n_edges(self) -> int:
        """Number of edges."""
        return len(self.edges)

    @property
    def n_faces(self) -> int:
        """Number of triangles (0 without faces)."""
        return 0 if self.faces is None else len(self.faces)

    @functools.cached_property
    def topology(self) -> Topology:
        """Connectivity data shared by shapes with these edges (:class:`Topology`)."""
        from .topology import Topology

        return Topology(self.edges, self.n_vertices, self.components, self.n_components)

    @property
    def z(self) -> NDArray[np.complex128]:
        """(n,) complex: the vertices as complex numbers x + iy."""
        return self.vertices[:, 0] + 1j * self.vertices[:, 1]

    def edge_vectors(self, z: NDArray[np.complex128] | None = None) -> NDArray[np.complex128]:
        """(E,) complex: ``p_j - p_i`` for every edge (i, j) (of ``z`` if given).

        Parameters
        ----------
        z : (..., n) complex array, optional
            Vertex positions (any leading frame axes); default :attr:`z`.

        Returns
        -------
        (..., E) complex array

        Examples
        --------
        >>> from isotween import Shape
        >>> Shape.from_polyline([[0, 0], [1, 0], [1, 2]]).edge_vectors().tolist()
        [(1+0j), 2j]
        """
        z = self.z if z is None else z
        return z[..., self.edges[:, 1]] - z[..., self.edges[:, 0]]

    def bbox_diagonal(self) -> float:
        """Length of the bounding-box diagonal (float).

        Examples
        --------
        >>> from isotween import Shape
        >>> Shape.from_polyline([[0, 0], [3, 4]]).bbox_diagonal()
        5.0
        """
        from .geometry import bbox_diagonal  # the kernel sits above the model: imported at call time

        return bbox_diagonal(self.vertices) if len(self.vertices) else 0.0

    def with_vertices(self, vertices: ArrayLike) -> Shape:
        """A shape with the same connectivity (and uv, paths, paint) at new positions.

        Parameters
        ----------
        vertices : (n, 2) array_like of float
            New positions, one per vertex (copied).

        Returns
        -------
        Shape

        Raises
        ------
        ShapeError
            ``vertices`` does not have the shape of ``self.vertices``.

        Examples
        --------
        >>> from isotween import Shape
        >>> s = Shape.from_polygon([[0, 0], [1, 0], [0, 1]])
        >>> s.with_vertices(s.vertices * 2).vertices.tolist()
        [[0.0, 0.0], [2.0, 0.0], [0.0, 2.0]]
        """
        s = object.__new__(Shape)
        s.__dict__.update(self.__dict__)
        s.__dict__.pop("_hash", None)
        v = np.array(as_vertices(vertices, shape=self.vertices.shape))
        v.flags.writeable = False
        s.vertices = v
        return s

    def with_faces(self, faces: ArrayLike) -> Shape:
        """The same shape (vertices, uv, paths, paint) with other triangles.

        The sides of the old faces give way to those of the new ones; edges
        that are sides of neither (open strokes, outlines outside the mesh)
        stay.

        Parameters
        ----------
        faces : (F, 3) array_like of int

        Returns
        -------
        Shape

        Examples
        --------
        >>> from isotween import Shape
        >>> s = Shape.from_mesh([[0, 0], [1, 0], [1, 1], [0, 1]], [[0, 1, 2], [0, 2, 3]])
        >>> flipped = s.with_faces([[0, 1, 3], [1, 2, 3]])  # the other diagonal
        >>> sorted(map(sorted, flipped.edges.tolist()))
        [[0, 1], [0, 3], [1, 2], [1, 3], [2, 3]]
        """
        f = _as_index_array(faces, 3, "face")
        n = self.n_vertices

        def keys(e: NDArray) -> NDArray:
            return np.sort(e, axis=1) @ np.array([n, 1])

        sides = [_edges_of_faces(f)] + ([] if self.faces is None else [_edges_of_faces(self.faces)])
        loose = self.edges[~np.isin(keys(self.edges), keys(np.vstack(sides)))]
        s = Shape(self.vertices, np.vstack([sides[0], loose]), f, uv=self.uv, paths=self.paths,
                  y_down=self.y_down, regions=self.regions, paint=self.paint)
        s.drawing = self.drawing
        return s

    def face_areas(self, vertices: ArrayLike | None = None) -> NDArray[np.float64]:
        """(F,) signed triangle areas (positive = counter-clockwise).

        Parameters
        ----------
        vertices : (..., n, 2) array_like of float, optional
            Positions to measure at (any leading frame axes); default the shape's.

        Returns
        -------
        (..., F) float array
            Empty along the last axis for a shape without faces.

        Examples
        --------
        >>> from isotween import Shape
        >>> mesh = Shape.from_mesh([[0, 0], [2, 0], [0, 1]], [[0, 1, 2]])
        >>> mesh.face_areas().tolist(), mesh.face_areas(mesh.scale([1, -1]).vertices).tolist()
        ([1.0], [-1.0])
        """
        v = self.vertices if vertices is None else np.asarray(vertices)
        if self.faces is None:
            return np.zeros(v.shape[:-2] + (0,))
        from .geometry import triangle_areas  # the kernel sits above the model: imported at call time

        return triangle_areas(v, self.faces)

    # ------------------------------------------------------------------ value semantics
    def _freeze(self) -> None:
        """Make every array of the shape read-only, so that its value (and hash) cannot change."""
        for arr in (self.vertices, self.edges, self.faces, self.uv, self.components):
            if arr is not None:
                arr.flags.writeable = False
        if self.paths is not None:
            self.paths = [(idx.view(), closed) for idx, closed in self.paths]  # not the caller's arrays
            for idx, _ in self.paths:
                idx.flags.writeable = False

    def _key(self) -> tuple:
        """Everything that makes up the shape's value, arrays as themselves."""
        paths = None if self.paths is None else tuple((tuple(p.tolist()), c) for p, c in self.paths)
        regions = None if self.regions is None else tuple(tuple(r) for r in self.regions)
        paint = None if self.paint is None else tuple(self.paint)
        return (self.y_down, paths, regions, paint)

    def equals(self, other: object, atol: float = 0.0) -> bool:
        """Whether ``other`` is the same shape, vertices up to ``atol``.

        Connectivity (edges, faces, paths, regions, paint) and ``y_down`` must
        match exactly; vertices and uv may differ by at most ``atol`` in every
        coordinate. Never raises: anything that is not a Shape is unequal.

        Parameters
        ----------
        other : object
        atol : float
            Largest coordinate difference still called equal.

        Returns
        -------
        bool

        Examples
        --------
        >>> from isotween import Shape
        >>> a = Shape.from_polygon([[0, 0], [1, 0], [0, 1]])
        >>> a.equals(a.translate([1e-9, 0]), atol=1e-6), a.equals(a.translate([1e-9, 0]))
        (True, False)
        """
        if other is self:
            return True
        if not isinstance(other, Shape):
            return False

        def same(a: NDArray | None, b: NDArray | None, tol: float | None) -> bool:
            if a is None or b is None:
                return a is b
            if a.shape != b.shape:
                return False
            return bool(np.array_equal(a, b) if tol is None else np.all(np.abs(a - b) <= tol))

        tol = None if atol == 0 else float(atol)
        return (
            same(self.edges, other.edges, None)
            and same(self.faces, other.faces, None)
            and same(self.vertices, other.vertices, tol)
            and same(self.uv, other.uv, tol)
            and self._key() == other._key()
        )

    def __eq__(self, other: object) -> bool:
        """Value equality: same vertices (exactly), connectivity, paths, paint and ``y_down``."""
        if not isinstance(other, Shape):
            return NotImplemented
        return self.equals(other)

    def __hash__(self) -> int:
        """Hash of the value (consistent with ``==``; arrays are read-only)."""
        h = self.__dict__.get("_hash")
        if h is None:
            def digest(a: NDArray | None) -> int | None:
                # + 0.0 turns -0.0 into 0.0, which == calls equal
                return None if a is None else hash(((a + 0.0) if a.dtype.kind == "f" else a).tobytes())

            h = self.__dict__["_hash"] = hash((digest(self.vertices), digest(self.edges), digest(self.faces),
                                               digest(self.uv), self._key()))
        return h

    #: numpy defers to Shape in binary operations, so ``array == shape`` is False, not elementwise
    __array_ufunc__ = None

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> NDArray:
        """The (n, 2) vertices, so that ``np.asarray(shape)`` gives the positions."""
        if copy is False and dtype is not None and np.dtype(dtype) != self.vertices.dtype:
            raise ValueError("a copy is needed to change the dtype of the vertices")
        v = self.vertices if dtype is None else self.vertices.astype(dtype, copy=False)
        return v.copy() if copy else v

    # ------------------------------------------------------------------ similarity transforms
    def transform(self, matrix: ArrayLike) -> Shape:
        """The shape under a linear (2 x 2) or affine (3 x 3, homogeneous) map.

        Points are column vectors: ``p' = A p + b`` for ``matrix = [[A, b], [0, 0, 1]]``.
        A map with negative determinant (a mirror) reverses every face's orientation.

        Parameters
        ----------
        matrix : (2, 2) or (3, 3) array_like of float

        Returns
        -------
        Shape
            A new shape; ``self`` is unchanged.

        Raises
        ------
        ParameterError
            ``matrix`` is not 2 x 2 or 3 x 3, is not finite, or (3 x 3) has a
            last row other than (0, 0, 1).

        Examples
        --------
        >>> from isotween import Shape
        >>> s = Shape.from_polygon([[0, 0], [1, 0], [0, 1]])
        >>> s.transform([[2, 0, 1], [0, 2, 0], [0, 0, 1]]).vertices.tolist()
        [[1.0, 0.0], [3.0, 0.0], [1.0, 2.0]]
        """
        m = np.asarray(matrix, dtype=np.float64)
        if m.shape not in ((2, 2), (3, 3)) or not np.all(np.isfinite(m)):
            raise ParameterError(f"matrix must be a finite 2 x 2 or 3 x 3 array, got shape {m.shape}")
        if m.shape == (3, 3) and not np.array_equal(m[2], [0.0, 0.0, 1.0]):
            raise ParameterError(f"a 3 x 3 matrix must be affine (last row 0, 0, 1), got {m[2].tolist()}")
        v = self.vertices @ m[:2, :2].T
        if m.shape == (3, 3):
            v = v + m[:2, 2]
        return self.with_vertices(v)

    def translate(self, offset: ArrayLike) -> Shape:
        """The shape moved by ``offset``.

        Parameters
        ----------
        offset : (2,) array_like of float, or complex

        Returns
        -------
        Shape

        Examples
        --------
        >>> from isotween import Shape
        >>> Shape.from_polyline([[0, 0], [1, 0]]).translate([2, 3]).vertices.tolist()
        [[2.0, 3.0], [3.0, 3.0]]
        """
        d = _point(offset, "offset")
        return self.with_vertices(self.vertices + d)

    def rotate(self, angle: float, origin: ArrayLike | str = (0.0, 0.0), *, degrees: bool = False) -> Shape:
        """The shape turned by ``angle`` (counter-clockwise for y up) about ``origin``.

        Parameters
        ----------
        angle : float
            Radians, or degrees with ``degrees=True``.
        origin : (2,) array_like of float, complex, or 'centroid'
            Fixed point of the rotation; 'centroid' is the mean of the vertices.
        degrees : bool

        Returns
        -------
        Shape

        Examples
        --------
        >>> import numpy as np
        >>> from isotween import Shape
        >>> s = Shape.from_polyline([[1, 0], [2, 0]]).rotate(90, degrees=True)
        >>> np.round(s.vertices, 12).tolist()
        [[0.0, 1.0], [0.0, 2.0]]
        """
        angle = check_number("angle", angle, low=-np.inf, bound="a finite number")
        a = np.deg2rad(angle) if degrees else angle
        c, s = np.cos(a), np.sin(a)
        return self._about(np.array([[c, -s], [s, c]]), origin)

    def scale(self, factor: float | ArrayLike, origin: ArrayLike | str = (0.0, 0.0)) -> Shape:
        """The shape scaled by ``factor`` (one value, or one per axis) about ``origin``.

        Parameters
        ----------
        factor : float or (2,) array_like of float
        origin : (2,) array_like of float, complex, or 'centroid'

        Returns
        -------
        Shape

        Examples
        --------
        >>> from isotween import Shape
        >>> Shape.from_polyline([[1, 1], [3, 1]]).scale(2, origin=[1, 1]).vertices.tolist()
        [[1.0, 1.0], [5.0, 1.0]]
        """
        try:
            f = np.asarray(factor, dtype=np.float64)
        except (TypeError, ValueError):
            f = None
        if f is not None and f.ndim == 0:
            f = np.full(2, float(f))
        if f is None or f.shape != (2,) or not np.all(np.isfinite(f)):
            raise ParameterError(f"factor must be a finite number or a pair of them, got {factor!r}")
        return self._about(np.diag(f), origin)

    def _about(self, linear: NDArray[np.float64], origin: ArrayLike | str) -> Shape:
        """Apply a (2, 2) linear map with ``origin`` held fixed."""
        o = self.vertices.mean(axis=0) if isinstance(origin, str) and origin == "centroid" else _point(origin, "origin")
        m = np.eye(3)
        m[:2, :2] = linear
        m[:2, 2] = o - linear @ o
        return self.transform(m)

    # ------------------------------------------------------------------ notebook display
    def _repr_svg_(self) -> str:
        """SVG drawing of the shape (Jupyter shows it inline)."""
        return shape_svg(self)

    def __repr__(self) -> str:
        return (
            f"Shape({self.n_vertices} vertices, {self.n_edges} edges, {self.n_faces} faces, "
            f"{self.n_components} component(s))"
        )


#: What every function that takes a shape accepts: a Shape or an (n, 2) polygon array.
ShapeLike: TypeAlias = "Shape | ArrayLike"


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
    from .geometry import edge_keys

    e = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    _, first = np.unique(edge_keys(e[:, 0], e[:, 1]), return_index=True)
    return e[np.sort(first)]


def _ring_list(rings: Any) -> list:
    """A list of rings from one (k, 2) ring or a list of them."""
    if isinstance(rings, (str, bytes)) or not hasattr(rings, "__len__"):
        raise ShapeError(f"expected a (k, 2) array of points or a list of them, got {type(rings).__name__}")
    if len(rings) == 0:
        raise ShapeError("no points: a ring needs at least 3, a polyline 2")
    try:
        single = isinstance(rings, np.ndarray) and rings.ndim == 2 or np.ndim(rings[0]) == 1
    except ValueError:  # ragged rows inside the first ring
        single = False
    return [rings] if single else list(rings)


def _point(value: Any, what: str) -> NDArray[np.float64]:
    """A finite (2,) float point from a pair or a complex number."""
    if isinstance(value, numbers.Complex) and not isinstance(value, numbers.Real):
        value = (value.real, value.imag)
    p = np.asarray(value, dtype=np.float64) if np.ndim(value) == 1 else None
    if p is None or p.shape != (2,) or not np.all(np.isfinite(p)):
        raise ParameterError(f"{what} must be a finite (x, y) pair, got {value!r}")
    return p


def shape_svg(shape: Shape, size: int = 240) -> str:
    """A standalone SVG drawing of a shape: faces and closed rings filled, edges stroked.

    Parameters
    ----------
    shape : Shape
    size : int
        Longest side in pixels.

    Returns
    -------
    str
        An ``<svg>`` element; y grows upwards unless ``shape.y_down``.

    Examples
    --------
    >>> from isotween import Shape
    >>> svg = shape_svg(Shape.from_polygon([[0, 0], [1, 0], [0, 1]]))
    >>> svg.startswith("<svg") and svg.endswith("</svg>")
    True
    """
    v = shape.vertices
    if not shape.y_down:
        v = v * [1.0, -1.0]
    lo, hi = (v.min(axis=0), v.max(axis=0)) if len(v) else (np.zeros(2), np.ones(2))
    extent = float(max(np.max(hi - lo), 1e-12 * max(float(np.abs(v).max(initial=1.0)), 1.0)))
    pad = 0.05 * extent
    x0, y0 = lo - pad
    w, h = hi - lo + 2 * pad
    w, h = max(float(w), 2 * pad), max(float(h), 2 * pad)
    scale = size / max(w, h)
    stroke = 1.5 / scale  # about 1.5 pixels

    def d(loops: list[NDArray[np.int64]], close: bool) -> str:
        parts = []
        for loop in loops:
            xy = " L".join(f"{x:.6g} {y:.6g}" for x, y in v[loop])
            parts.append(f"M{xy}{'Z' if close else ''}")
        return " ".join(parts)

    items = []
    rings = [idx for idx, closed in (shape.paths or ()) if closed]
    if shape.n_faces:
        items.append(f'<path d="{d(list(shape.faces), True)}" fill="#9ecae1" stroke="none"/>')
    elif rings:
        items.append(f'<path d="{d(rings, True)}" fill="#9ecae1" fill-rule="evenodd" stroke="none"/>')
    if shape.n_edges:
        items.append(f'<path d="{d(list(shape.edges), False)}" fill="none" stroke="#08519c" '
                     f'stroke-width="{stroke:.6g}" stroke-linecap="round"/>')
    label = html.escape(repr(shape))
    return (
        f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="{x0:.6g} {y0:.6g} {w:.6g} {h:.6g}" '
        f'width="{w * scale:.0f}" height="{h * scale:.0f}"><title>{label}</title>'
        + "".join(items) + "</svg>"
    )
