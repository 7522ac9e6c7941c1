"""Wavefront OBJ: ``v`` vertices, ``vt`` texture coordinates, ``f`` faces, ``l`` lines."""

import numpy as np

from ..errors import FileFormatError
from ._files import read_text, write_text
from ._mesh import Y_DOWN_NOTE, assemble, chains, edges_need_listing, fan, flip_y, planar, written_y_down, y_up_vertices

__all__ = ["read_obj", "write_obj"]

_MAX_INDEX = 2**62  # beyond any real file; keeps indices in int64


def _float(path, lineno, token):
    try:
        return float(token)
    except ValueError:
        raise FileFormatError(f"{path}, line {lineno}: '{token}' is not a number") from None


def _refs(path, lineno, tokens, n_v, n_vt):
    """Vertex and texture indices (0-based, None when absent) of ``f``/``l`` tokens."""
    if not any("/" in tok for tok in tokens):  # plain vertex numbers: the common case, fast
        try:
            ks = [int(tok) for tok in tokens]
        except ValueError:
            ks = None
        if ks is not None and all(0 < k <= _MAX_INDEX for k in ks):
            return [(k - 1, None) for k in ks]
    out = []
    for tok in tokens:
        parts = tok.split("/")
        idx = []
        for part, count, what in zip(parts[:2], (n_v, n_vt), ("vertex", "texture coordinate"), strict=False):
            if part == "" and what != "vertex":
                idx.append(None)
                continue
            try:
                k = int(part)
            except ValueError:
                raise FileFormatError(f"{path}, line {lineno}: '{tok}' is not a vertex reference") from None
            if k == 0:
                raise FileFormatError(f"{path}, line {lineno}: {what} index 0 (OBJ counts from 1)")
            if abs(k) > _MAX_INDEX:
                raise FileFormatError(f"{path}, line {lineno}: {what} index {k} is out of range")
            # negative indices count back from the last element read so far
            idx.append(k - 1 if k > 0 else count + k)
            if idx[-1] < 0:
                raise FileFormatError(
                    f"{path}, line {lineno}: {what} index {k} goes before the first {what}"
                )
        out.append((idx[0], idx[1] if len(idx) > 1 else None))
    return out


def read_obj(path):
    """Read a planar shape from a Wavefront OBJ file.

    ``v x y [z]`` vertices (z must be 0 or absent), ``vt u v`` texture
    coordinates, ``f`` faces (polygons fan-triangulated), ``l`` polylines as
    edges. Other statements (``vn``, ``o``, ``g``, ``usemtl``, ...) are ignored.

    Parameters
    ----------
    path : path-like

    Returns
    -------
    Shape
        y-up, unless the file is a y-down shape written by `write_obj` (with
        y negated and a note saying so): then y is negated back and the
        shape is y-down, as it was written.
        Edges are the ``l`` edges in file order, then the face sides not listed.
        Without faces, every ``l`` statement is also a path (closed when it
        ends on its first vertex). ``uv`` comes from the ``v/vt`` pairs (or,
        without pairs, from as many ``vt`` as ``v`` in order; a vertex in no
        pair takes the ``vt`` of its own number when the counts match).

    Raises
    ------
    FileFormatError
        Naming the file and line of a malformed statement.
    """
    text = read_text(path)
    xyz, v_lines, vts = [], [], []
    triangles, tri_lines, polylines, poly_lines = [], [], [], []
    uv_pairs = []  # (vertex, texture, line)
    for lineno, raw in enumerate(text.splitlines(), 1):
        tokens = raw.split("#", 1)[0].split()
        if not tokens:
            continue
        key, args = tokens[0], tokens[1:]
        if key == "v":
            if len(args) < 2:
                raise FileFormatError(f"{path}, line {lineno}: expected 'v x y [z]'")
            c = [_float(path, lineno, t) for t in args[:3]]
            xyz.append(c + [0.0] * (3 - len(c)))
            v_lines.append(lineno)
        elif key == "vt":
            if len(args) < 2:
                raise FileFormatError(f"{path}, line {lineno}: expected 'vt u v'")
            vts.append([_float(path, lineno, t) for t in args[:2]])
        elif key in ("f", "l"):
            need = 3 if key == "f" else 2
            if len(args) < need:
                raise FileFormatError(
                    f"{path}, line {lineno}: '{key}' needs at least {need} vertices, got {len(args)}"
                )
            refs = _refs(path, lineno, args, len(xyz), len(vts))
            uv_pairs += [(v, t, lineno) for v, t in refs if t is not None]
            idx = [v for v, _ in refs]
            if key == "f":
                tris = fan(idx)
                triangles += tris
                tri_lines += [lineno] * len(tris)
            else:
                polylines.append(idx)
                poly_lines.append(lineno)
    vertices = planar(path, np.array(xyz, dtype=np.float64).reshape(-1, 3), v_lines)
    uv = _uv(path, len(vertices), np.array(vts, dtype=np.float64).reshape(-1, 2), uv_pairs)
    y_down = written_y_down(text)
    return assemble(path, flip_y(vertices) if y_down else vertices, triangles, tri_lines, polylines, poly_lines,
                    uv=uv, y_down=y_down)


def _uv(path, n, vts, pairs):
    """(n, 2) per-vertex texture coordinates, or None when the file has none."""
    if not len(vts):
        return None
    if not pairs:
        if len(vts) != n:
            raise FileFormatError(
                f"{path}: {len(vts)} texture coordinates for {n} vertices and no 'v/vt' pairs "
                "to match them; isotween needs one uv per vertex"
            )
        return vts
    v, t, lines = (np.array(c, dtype=np.int64) for c in zip(*pairs, strict=False))
    bad = np.flatnonzero((t >= len(vts)) | (v >= n))
    if bad.size:
        k = int(bad[0])
        raise FileFormatError(f"{path}, line {lines[k]}: reference {v[k] + 1}/{t[k] + 1} is out of range")
    uv = np.full((n, 2), np.nan)
    uv[v[::-1]] = vts[t[::-1]]  # the first pair of a vertex wins
    # a vertex met with two different texture coordinates is a UV seam
    clash = np.flatnonzero(np.any(uv[v] != vts[t], axis=1))
    if clash.size:
        k = int(clash[0])
        raise FileFormatError(
            f"{path}, line {lines[k]}: vertex {v[k] + 1} has two different texture coordinates "
            "(a UV seam); isotween needs one uv per vertex"
        )
    missing = np.flatnonzero(np.isnan(uv[:, 0]))
    if missing.size and len(vts) == n:
        # vertices outside every face and line take the vt of the same number
        uv[missing] = vts[missing]
    elif missing.size:
        raise FileFormatError(
            f"{path}: vertex {missing[0] + 1} has no texture coordinate while others have one"
        )
    return uv


def _num(x):
    return repr(float(x))


def write_obj(shape, path):
    """Write a shape as OBJ so that `read_obj` restores it exactly.

    Vertices are written with z = 0 and shortest round-trip decimals; ``uv``
    as one ``vt`` per vertex (references ``i/i``). Edges are written as ``l``
    chains unless they are exactly the face sides in the default order.
    OBJ is y-up: a ``y_down`` shape (read from SVG) is written with y negated,
    so that other programs show it upright, and a comment says so, from which
    `read_obj` restores the y-down shape.
    """
    lines = [f"# isotween shape: {shape.n_vertices} vertices, {shape.n_edges} edges, {shape.n_faces} faces"]
    if shape.y_down:
        lines.append(Y_DOWN_NOTE)
    lines += [f"v {_num(x)} {_num(y)} 0" for x, y in y_up_vertices(shape).tolist()]
    has_uv = shape.uv is not None
    if has_uv:
        lines += [f"vt {_num(u)} {_num(v)}" for u, v in shape.uv.tolist()]

    def ref(i):
        return f"{i + 1}/{i + 1}" if has_uv else str(i + 1)

    if shape.faces is not None:
        lines += ["f " + " ".join(ref(i) for i in f) for f in shape.faces.tolist()]
    if edges_need_listing(shape):
        lines += ["l " + " ".join(ref(i) for i in c) for c in chains(shape.edges)]
    write_text(path, "\n".join(lines) + "\n")
