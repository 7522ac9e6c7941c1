"""Shared by the OBJ and OFF codecs: turning parsed elements into a Shape and back."""

import re

import numpy as np

from ..errors import FileFormatError, ShapeError
from ..shape import MAX_COORDINATE, Shape

__all__ = ["fan", "assemble", "chains", "face_edges", "edges_need_listing", "planar", "y_up_vertices",
           "Y_DOWN_NOTE", "written_y_down", "flip_y"]

#: the comment line with which the OBJ and OFF writers mark a y-down shape written with y negated;
#: their readers negate y back and return a y-down shape, so the file reads back as it was written
Y_DOWN_NOTE = "# y negated from the y-down (SVG) original, so that up is up"
_Y_DOWN_LINE = re.compile(rf"^{re.escape(Y_DOWN_NOTE)}[ \t\r]*$", re.MULTILINE)


def planar(path, xyz, lines, base=1):
    """Drop the z column of an (n, 3) array; a non-zero z raises, naming its line.

    So does a non-finite coordinate or one beyond `isotween.shape.MAX_COORDINATE`.
    """
    wild = np.flatnonzero(~np.all(np.isfinite(xyz[:, :2]) & (np.abs(xyz[:, :2]) <= MAX_COORDINATE), axis=1))
    if wild.size:
        k = int(wild[0])
        what = ("a non-finite coordinate" if not np.all(np.isfinite(xyz[k, :2]))
                else f"a coordinate beyond +-{MAX_COORDINATE:g}")
        raise FileFormatError(f"{path}, line {lines[k]}: vertex {k + base} has {what}: {xyz[k, :2].tolist()}")
    bad = np.flatnonzero(xyz[:, 2] != 0)
    if bad.size:
        k = int(bad[0])
        raise FileFormatError(
            f"{path}, line {lines[k]}: vertex {k + base} has z = {float(xyz[k, 2])!r}; isotween reads "
            "planar shapes, so z must be 0 (or absent) everywhere"
        )
    return xyz[:, :2]


def written_y_down(text):
    """Whether an OBJ or OFF text holds a y-down shape written with y negated (its `Y_DOWN_NOTE` line)."""
    return _Y_DOWN_LINE.search(text) is not None


def flip_y(vertices):
    """(n, 2) vertices with y negated (never -0.0)."""
    return vertices * np.array([1.0, -1.0]) + 0.0


def y_up_vertices(shape):
    """(n, 2) vertices as drawn with y up: y negated for a ``y_down`` shape.

    Formats without an orientation flag (OBJ, OFF) are y-up by convention;
    writing these coordinates keeps a y-down shape looking as it did.
    """
    return flip_y(shape.vertices) if shape.y_down else shape.vertices


def fan(polygon):
    """Fan triangles (0, i, i+1) of one polygon given as a list of k >= 3 indices."""
    return [(polygon[0], polygon[i], polygon[i + 1]) for i in range(1, len(polygon) - 1)]


def face_edges(faces):
    """(E, 2) unique triangle sides in first-seen order (the Shape default)."""
    e = faces[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)
    _, first = np.unique(np.sort(e, axis=1), axis=0, return_index=True)
    return e[np.sort(first)]


def edges_need_listing(shape):
    """Whether a mesh file must list the edges explicitly to restore them exactly."""
    if shape.faces is None or not len(shape.faces):
        return shape.n_edges > 0
    derived = face_edges(shape.faces)
    return derived.shape != shape.edges.shape or bool(np.any(derived != shape.edges))


def chains(edges):
    """Split an edge list, in its order, into chains of consecutive edges.

    Edge k+1 continues the chain of edge k when it starts where edge k ends and
    the chain has not closed yet. Writing each chain as one polyline (OBJ ``l``)
    and reading the polylines back gives the same edges in the same order.

    Parameters
    ----------
    edges : (E, 2) int array

    Returns
    -------
    list of list of int
        Vertex indices of every chain; a closed chain repeats its first index.
    """
    out = []
    for i, j in np.asarray(edges).tolist():
        cur = out[-1] if out else None
        if cur is not None and cur[-1] == i and (len(cur) == 1 or cur[0] != cur[-1]):
            cur.append(j)
        else:
            out.append([i, j])
    return out


def paths_of_chains(chain_list):
    """Shape paths of polylines: a chain that returns to its start is a closed ring."""
    paths = []
    for c in chain_list:
        if len(c) >= 4 and c[0] == c[-1]:
            paths.append((np.asarray(c[:-1], dtype=np.int64), True))
        else:
            paths.append((np.asarray(c, dtype=np.int64), False))
    return paths


def assemble(path, vertices, triangles, tri_lines, polylines, poly_lines, uv=None, paths=True, base=1, y_down=False):
    """Build a Shape from parsed mesh elements, naming the line of a bad element.

    Parameters
    ----------
    path : path-like
        File name for messages.
    vertices : (n, 2) float array
    triangles : list of (3,) int tuples (0-based)
    tri_lines : list of int
        Line of every triangle.
    polylines : list of list of int
        Explicit edge chains (OBJ ``l``, OFF two-vertex faces), 0-based.
    poly_lines : list of int
        Line of every chain.
    uv : (n, 2) float array, optional
    paths : bool
        Record the chains as shape paths when there are no triangles.
    base : int
        Index of the first vertex in the file (1 for OBJ, 0 for OFF), for messages.
    y_down : bool
        The shape's `~isotween.Shape.y_down` (vertices as given).

    Notes
    -----
    Edges are the chains' edges in file order, then the triangle sides not
    already listed (first-seen order); an edge listed twice is kept once.
    """
    n = len(vertices)
    if n == 0:
        raise FileFormatError(f"{path}: no vertices")
    faces = np.asarray(triangles, dtype=np.int64).reshape(-1, 3) if triangles else None
    faces_flat = faces.ravel() if faces is not None else np.zeros(0, dtype=np.int64)
    chain_flat = np.concatenate([np.asarray(c, dtype=np.int64) for c in polylines]) if polylines else faces_flat[:0]
    for flat, lines, what in (
        (faces_flat, np.repeat(np.asarray(tri_lines, dtype=np.int64), 3), "face"),
        (chain_flat, np.repeat(np.asarray(poly_lines, dtype=np.int64), [len(c) for c in polylines]), "line"),
    ):
        out = np.flatnonzero((flat < 0) | (flat >= n))
        if out.size:
            k = int(out[0])
            raise FileFormatError(
                f"{path}, line {lines[k]}: {what} refers to vertex {int(flat[k]) + base}, "
                f"but the file has {n} vertices"
            )
    if faces is not None:
        deg = np.flatnonzero((faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0]))
        if deg.size:
            f = faces[deg[0]]
            rep = f[0] if f[0] in (f[1], f[2]) else f[1]
            raise FileFormatError(f"{path}, line {tri_lines[deg[0]]}: face repeats vertex {int(rep) + base}")
    listed = []
    if polylines:  # consecutive pairs within each chain, all chains at once
        sizes = np.array([len(c) for c in polylines])
        last = np.cumsum(sizes) - 1
        inner = np.ones(len(chain_flat), dtype=bool)
        inner[last] = False
        stacked = np.column_stack([chain_flat[inner], chain_flat[np.flatnonzero(inner) + 1]])
        loop = np.flatnonzero(stacked[:, 0] == stacked[:, 1])
        if loop.size:
            owner = np.repeat(np.asarray(poly_lines), sizes - 1)
            k = int(loop[0])
            raise FileFormatError(
                f"{path}, line {owner[k]}: line repeats vertex {int(stacked[k, 0]) + base} consecutively")
        listed = [stacked]
    parts = listed + ([face_edges(faces)] if faces is not None else [])
    if parts:
        edges = np.vstack(parts)
        _, first = np.unique(np.sort(edges, axis=1), axis=0, return_index=True)
        edges = edges[np.sort(first)]
    else:
        edges = np.zeros((0, 2), dtype=np.int64)
    shape_paths = paths_of_chains(polylines) if paths and faces is None and polylines else None
    try:
        return Shape(vertices, edges, faces, uv=uv, paths=shape_paths, y_down=y_down)
    except ShapeError as exc:
        raise FileFormatError(f"{path}: {exc}") from exc
