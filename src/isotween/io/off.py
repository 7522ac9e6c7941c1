"""Object File Format (OFF, and STOFF with per-vertex texture coordinates)."""

import itertools

import numpy as np

from ..errors import FileFormatError
from ._files import read_text, write_text
from ._mesh import Y_DOWN_NOTE, assemble, chains, edges_need_listing, fan, flip_y, planar, written_y_down, y_up_vertices

__all__ = ["read_off", "write_off"]


_MAX_INDEX = 2**62  # beyond any real file; keeps counts and indices in int64


def _numbers(path, lineno, tokens, kind):
    try:
        values = [kind(t) for t in tokens]
    except ValueError:
        bad = next(t for t in tokens if not _is(kind, t))
        raise FileFormatError(
            f"{path}, line {lineno}: '{bad}' is not {'an integer' if kind is int else 'a number'}") from None
    if kind is int:
        big = [t for t, v in zip(tokens, values, strict=False) if abs(v) > _MAX_INDEX]
        if big:
            raise FileFormatError(f"{path}, line {lineno}: '{big[0]:.40}' is out of range")
    return values


def _rows(text):
    """(line number, tokens) of every non-empty line (comments removed), lazily."""
    start, lineno = 0, 0
    while start <= len(text):
        end = text.find("\n", start)
        end = len(text) if end < 0 else end
        lineno += 1
        tokens = text[start:end].split("#", 1)[0].split()
        if tokens:
            yield lineno, tokens
        start = end + 1


def _is(kind, token):
    try:
        kind(token)
        return True
    except ValueError:
        return False


def read_off(path):
    """Read a planar shape from an OFF (or STOFF) file.

    Header ``OFF`` (or ``STOFF``: every vertex line also carries ``s t``
    texture coordinates), then ``n_vertices n_faces n_edges``, the vertex
    lines ``x y z`` (z must be 0) and the face lines ``k i_1 ... i_k``
    (0-based; trailing colour values are ignored). A face with k >= 3 is
    fan-triangulated; a face with k = 2 is an edge.

    Returns
    -------
    Shape
        y-up, unless the file is a y-down shape written by `write_off` (with
        y negated and a note saying so): then y is negated back and the
        shape is y-down, as it was written.
        Edges are the two-vertex faces in file order, then the triangle sides
        not listed. Without triangles, runs of consecutive edges become the
        shape's paths (closed when a run returns to its start).

    Raises
    ------
    FileFormatError
        Naming the file and line of a malformed header, count, vertex or face.
    """
    text = read_text(path)
    rows = _rows(text)  # (line number, tokens) of the non-empty lines, read as needed
    first = next(rows, None)
    if first is None:
        raise FileFormatError(f"{path}: empty file, expected an 'OFF' header")
    lineno, head = first
    if head[0] not in ("OFF", "STOFF"):
        raise FileFormatError(f"{path}, line {lineno}: expected the header 'OFF' or 'STOFF', got '{head[0]}'")
    textured = head[0] == "STOFF"
    if len(head) > 1:  # counts on the header line
        rows = itertools.chain([(lineno, head[1:])], rows)
    nxt = next(rows, None)
    if nxt is None:
        raise FileFormatError(f"{path}, line {lineno}: missing the counts 'n_vertices n_faces n_edges'")
    lineno, counts = nxt
    counts = _numbers(path, lineno, counts, int)
    if len(counts) < 2 or min(counts[:2]) < 0:
        raise FileFormatError(f"{path}, line {lineno}: expected 'n_vertices n_faces n_edges'")
    n_v, n_f = counts[:2]
    body = list(itertools.islice(rows, n_v + n_f))  # lines after the announced ones are not read
    if len(body) < n_v + n_f:
        at = body[-1][0] if body else lineno
        raise FileFormatError(
            f"{path}, line {at}: the file ends after {len(body)} of the {n_v} vertex and {n_f} face lines announced"
        )
    width = 5 if textured else 3
    xyz, uv, v_lines = [], [], []
    for lineno, tokens in body[:n_v]:
        if len(tokens) < width:
            raise FileFormatError(
                f"{path}, line {lineno}: expected '{'x y z s t' if textured else 'x y z'}', got {len(tokens)} value(s)"
            )
        values = _numbers(path, lineno, tokens[:width], float)
        xyz.append(values[:3])
        uv.append(values[3:5])
        v_lines.append(lineno)
    triangles, tri_lines, polylines, poly_lines = [], [], [], []
    for lineno, tokens in body[n_v : n_v + n_f]:
        k = _numbers(path, lineno, tokens[:1], int)[0]
        if k < 2 or len(tokens) < k + 1:
            raise FileFormatError(f"{path}, line {lineno}: expected 'k i_1 ... i_k' with k >= 2")
        idx = _numbers(path, lineno, tokens[1 : k + 1], int)
        if k == 2:
            polylines.append(idx)
            poly_lines.append(lineno)
        else:
            tris = fan(idx)
            triangles += tris
            tri_lines += [lineno] * len(tris)
    vertices = planar(path, np.array(xyz, dtype=np.float64).reshape(-1, 3), v_lines, base=0)
    # consecutive two-vertex faces that continue each other form one polyline
    if not triangles and polylines:
        merged, merged_lines, k = [], [], 0
        for c in chains(np.array(polylines, dtype=np.int64)):
            merged.append(c)
            merged_lines.append(poly_lines[k])
            k += len(c) - 1
        polylines, poly_lines = merged, merged_lines
    y_down = written_y_down(text)
    return assemble(
        path, flip_y(vertices) if y_down else vertices, triangles, tri_lines, polylines, poly_lines,
        uv=np.array(uv, dtype=np.float64) if textured else None, base=0, y_down=y_down,
    )


def _num(x):
    return repr(float(x))


def write_off(shape, path):
    """Write a shape as OFF (STOFF when it has uv) that `read_off` restores exactly.

    Triangles are written as faces; the edges are added as two-vertex faces
    unless they are exactly the triangle sides in the default order. OFF is
    y-up: a ``y_down`` shape is written with y negated (drawn the same way),
    and a comment after the announced lines says so, from which `read_off`
    restores the y-down shape.
    """
    vertices = y_up_vertices(shape)
    faces = shape.faces if shape.faces is not None else np.zeros((0, 3), dtype=np.int64)
    edges = shape.edges if edges_need_listing(shape) else np.zeros((0, 2), dtype=np.int64)
    lines = ["STOFF" if shape.uv is not None else "OFF",
             f"{shape.n_vertices} {len(faces) + len(edges)} {shape.n_edges}"]
    if shape.uv is not None:
        lines += [f"{_num(x)} {_num(y)} 0 {_num(u)} {_num(v)}"
                  for (x, y), (u, v) in zip(vertices.tolist(), shape.uv.tolist(), strict=False)]
    else:
        lines += [f"{_num(x)} {_num(y)} 0" for x, y in vertices.tolist()]
    lines += [f"3 {a} {b} {c}" for a, b, c in faces.tolist()]
    lines += [f"2 {i} {j}" for i, j in edges.tolist()]
    if shape.y_down:
        lines.append(Y_DOWN_NOTE)
    write_text(path, "\n".join(lines) + "\n")
