"""One scaffold around every filled region of a drawing: the empty space between its pieces, triangulated.

The regions' own meshes keep each triangle from flipping, but not two pieces
(or two arms of one piece) from passing through each other. Triangulating
the space around them as well (the scaffold of Jiang, Schaefer, Kovalsky,
Lipman and Zorin, "Simplicial complex augmentation framework for bijective
maps", 2017) closes that gap: the regions' triangles and the scaffold's
together tile a fixed box, so a frame where none of them flips is an
embedding, and no two outline edges of the drawing cross.

The empty space is cut into polygons with holes, each triangulated on its
own (constrained Delaunay, refined to the box's spacing):

- the box around every frame (ring 0) with the outer rings of the regions
  that lie in no hole as its holes;
- every hole of a region, with the outer rings of the regions inside it.

`isotween.foldfree.repair` triangulates it where the pieces are before
the first frame it repairs, carries it from frame to frame with its edges
flipped to Delaunay (`Scaffold.moved`, so pieces can slide past each other)
and triangulates it afresh once its triangles grow thin; it moves it
towards the next frame by `Scaffold.follow` (the harmonic extension of the
pieces' motion), and keeps it from flipping where they need room.
"""

from typing import NamedTuple

import numpy as np

from ..errors import ShapeError
from ..geometry import bbox_diagonal, edge_table

__all__ = ["Scaffold", "Around", "box_around", "scaffold", "separate_regions", "MARGIN", "BOX_SIDE", "OVERLAP"]

MARGIN = 0.5  # the box lies this far (in bounding-box diagonals of all frames) around every frame
BOX_SIDE = 6  # vertices on each side of the box (corners included once)
OVERLAP = 1e-6  # two regions overlapping by more than this share of the smaller one's area lie on each other


class Scaffold(NamedTuple):
    """What `scaffold` returns.

    Attributes
    ----------
    source : (S,) complex
        Positions of the scaffold's own vertices in the source (the box's,
        then the interior's); the regions' vertices are the shape's.
    faces : (G, 3) int
        Triangles over the joint vertices: 0..N-1 the shape's, N.. the
        scaffold's; counter-clockwise in the source.
    fixed : (S,) bool
        The box's vertices: they stay where they are.
    """

    source: np.ndarray
    faces: np.ndarray
    fixed: np.ndarray

    def moved(self, z):
        """The scaffold with every vertex at ``z`` (N + S,) complex, Delaunay again where flipping keeps it.

        The same vertices; edges between two of the scaffold's triangles
        that are no longer Delaunay at ``z`` are flipped where both new
        triangles are positive, so the scaffold stays one as pieces slide
        past each other. ``z`` must leave every triangle positive.
        """
        from ..correspondence._disc import _keys, _lawson

        z = np.asarray(z, dtype=complex)
        faces = _lawson(z, np.array(self.faces), _keys(np.zeros((0, 2), dtype=np.int64)))
        return Scaffold(z[len(z) - len(self.source):], faces, self.fixed)

    def follow(self, frames):
        """(T, S) scaffold positions that follow the regions' frames (T, N) complex.

        The harmonic extension (uniform weights) of the regions' motion
        from ``frames[0]``, the positions the scaffold was built at: exact
        there, a guess elsewhere, which may flip triangles.
        """
        from scipy.sparse import coo_matrix
        from scipy.sparse.linalg import splu

        frames = np.asarray(frames, dtype=complex)
        T, N = frames.shape
        S = len(self.source)
        a, b, _, key, _ = edge_table(self.faces)
        first = np.unique(key, return_index=True)[1]
        a, b = a[first], b[first]
        n = N + S
        W = coo_matrix((np.ones(2 * len(a)), (np.r_[a, b], np.r_[b, a])), shape=(n, n)).tocsr()
        L = (W - coo_matrix((np.asarray(W.sum(axis=1)).ravel(), (np.arange(n), np.arange(n))),
                            shape=(n, n))).tocsr()
        free = N + np.flatnonzero(~self.fixed)
        out = np.broadcast_to(self.source, (T, S)).copy()
        if free.size:
            moved = frames - frames[0]  # the box does not move
            rhs = -(L[free][:, :N] @ moved.T)
            lu = splu(L[free][:, free].tocsc())
            ext = lu.solve(np.ascontiguousarray(rhs.real)) + 1j * lu.solve(np.ascontiguousarray(rhs.imag))
            out[:, ~self.fixed] += ext.T
        return out


class Around:
    """The scaffolds of a sequence's frames: which pieces each frame holds apart, and their scaffold.

    Parameters
    ----------
    shape : Shape
        A meshed shape with ``regions``.
    frames : (T, N) complex
        Its frames: the box lies around all of them (`box_around`), and the
        pieces held apart are those that lie on no other at either end
        (`separate_regions`).
    hidden : callable, optional
        ``hidden(k)``: regions out of sight in frame k (drawn with opacity 0:
        a piece faded out, or not yet in), left out of that frame's scaffold.
    """

    def __init__(self, shape, frames, hidden=None):
        self.shape, self.box = shape, box_around(frames)
        self.keep = separate_regions(shape, np.asarray(frames)[[0, -1]])
        self.hidden = hidden

    def held(self, k):
        """The regions held apart in frame k (a tuple of indices into ``shape.regions``)."""
        gone = self.hidden(k) if self.hidden is not None else ()
        return tuple(r for r in self.keep if r not in gone)

    def __call__(self, k, z):
        """The scaffold around the pieces of frame k at positions ``z`` (N,) complex."""
        return scaffold(self.shape, z, self.box, list(self.held(k)))


def separate_regions(shape, ends):
    """Indices of ``shape.regions`` that lie on no other region at either end, ``ends`` (2, N) complex.

    A piece with no partner grows from (or shrinks to) a small copy, placed
    off the other pieces where it can be (``unmatched='grow'``); one that
    splits off from another piece (``'split'``) starts on it, so it is left
    out of the scaffold, and its overlaps are not collisions. Of two that
    overlap (more than `OVERLAP` of the smaller: an X taken as its two
    crossed bars) the smaller is left out, the later of two alike.
    """
    import shapely

    regions = shape.regions or []
    keep = set(range(len(regions)))
    for z in ends:
        xy = np.c_[z.real, z.imag]
        polys = np.array([shapely.Polygon(xy[shape.paths[r[0]][0]], [xy[shape.paths[h][0]] for h in r[1:]])
                          for r in regions], dtype=object)
        for i, r in enumerate(regions):
            point = shapely.Point(xy[shape.paths[r[0]][0][0]])
            if any(j != i and polys[j].contains(point) for j in range(len(regions))):
                keep.discard(i)
        i, j = shapely.STRtree(polys).query(polys, predicate="intersects")
        i, j = i[i < j], j[i < j]
        area = shapely.area(polys)
        try:
            over = shapely.area(shapely.intersection(polys[i], polys[j])) > OVERLAP * np.minimum(area[i], area[j])
        except shapely.errors.GEOSException:  # an end that is not a valid drawing: its first vertices only
            continue
        keep -= set(np.where(area[i] >= area[j], j, i)[over].tolist())
    return sorted(keep)


def box_around(frames):
    """(B,) complex: a box ring (counter-clockwise, `BOX_SIDE` vertices a side) `MARGIN` around all ``frames``."""
    frames = np.asarray(frames, dtype=complex)
    lo = np.array([frames.real.min(), frames.imag.min()])
    hi = np.array([frames.real.max(), frames.imag.max()])
    pad = MARGIN * bbox_diagonal(np.c_[frames.real.ravel(), frames.imag.ravel()])
    (x0, y0), (x1, y1) = lo - pad, hi + pad
    s = np.linspace(0.0, 1.0, BOX_SIDE)[:-1]
    return np.r_[x0 + (x1 - x0) * s + 1j * y0, x1 + 1j * (y0 + (y1 - y0) * s),
                 x1 - (x1 - x0) * s + 1j * y1, x0 + 1j * (y1 - (y1 - y0) * s)]


def scaffold(shape, z, box, regions=None):
    """The scaffold of ``shape``'s filled regions at positions ``z``, inside ``box``.

    Parameters
    ----------
    shape : Shape
        A meshed shape with ``regions`` (outer ring, then holes: indices
        into ``paths``).
    z : (N,) complex
        Its vertex positions, where no two pieces overlap.
    box : (B,) complex
        The box ring around them (`box_around`).
    regions : list of int, optional
        The regions to hold apart (default all; `separate_regions` leaves
        out those that lie on another at an end).

    Returns
    -------
    Scaffold

    Raises
    ------
    ShapeError
        No filled region, or pieces that overlap or touch at ``z``.
    """
    from ..correspondence._disc import _keys, _refine, _triangulate

    z = np.asarray(z, dtype=complex)
    N = len(z)
    regions = [shape.regions[i] for i in (range(len(shape.regions or [])) if regions is None else regions)]
    if not regions or not shape.n_faces:
        raise ShapeError("a scaffold needs filled regions")
    outer = [np.asarray(shape.paths[r[0]][0]) for r in regions]
    holes = [np.asarray(shape.paths[h][0]) for r in regions for h in r[1:]]
    size = abs(box[1] - box[0])  # the triangles grow to the box's spacing away from the pieces

    children = [[] for _ in range(len(holes) + 1)]  # 0: the box, 1 + j: hole j
    for i, c in enumerate(_containers(z, holes, [r[0] for r in outer])):
        children[c].append(outer[i])
    positions, faces = [box], []
    n = N + len(box)
    none = _keys(np.zeros((0, 2), dtype=np.int64))
    for c, kids in enumerate(children):
        if c == 0 and not kids:
            continue
        ids = ([np.arange(N, N + len(box))] if c == 0 else [holes[c - 1]]) + kids
        p = np.r_[box, z[np.concatenate(ids[1:])]] if c == 0 else z[np.concatenate(ids)]
        start = np.r_[0, np.cumsum([len(r) for r in ids])[:-1]]
        rings = [st + np.arange(len(r)) for st, r in zip(start, ids, strict=True)]
        f = _triangulate(p, rings, np.zeros((0, 2), dtype=np.int64), none, "scaffold")
        p, f = _refine(p, f, none, size)
        k = int(start[-1] + len(ids[-1]))  # ring vertices; the refinement's follow
        local = np.r_[np.concatenate(ids), n + np.arange(len(p) - k)]
        n += len(p) - k
        positions.append(p[k:])
        faces.append(local[f])
    fixed = np.zeros(n - N, dtype=bool)
    fixed[:len(box)] = True
    return Scaffold(np.concatenate(positions), np.concatenate(faces), fixed)


def _containers(z, holes, points):
    """For every point (vertex id), 1 + the smallest hole around it at positions ``z``, or 0 for none."""
    from ..geometry import ring_area, winding_numbers

    out = np.zeros(len(points), dtype=np.int64)
    if not holes:
        return out
    p = z[np.asarray(points)]
    wind = np.asarray(winding_numbers(np.c_[p.real, p.imag], [np.c_[z[h].real, z[h].imag] for h in holes]))
    area = np.array([abs(ring_area(z[h])) for h in holes])
    for i in range(len(points)):
        around = np.flatnonzero(wind[i] != 0)
        if around.size:
            out[i] = 1 + around[np.argmin(area[around])]
    return out
