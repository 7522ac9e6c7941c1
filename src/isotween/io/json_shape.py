"""The isotween JSON shape file (schema in docs/formats.md)."""

import json

import numpy as np

from ..errors import FileFormatError, IsotweenError, ShapeError
from ..shape import Shape
from ._files import write_text
from ._json import JsonDocument, dumps_rows

__all__ = ["read_json", "write_json", "shape_fields", "shape_from_fields"]


def shape_fields(doc, vertices_key="vertices"):
    """Validated connectivity of a JSON document: (edges, faces, uv, paths, y_down).

    Shared by the shape and sequence files. ``paths`` is a list of
    ``{"indices": [...], "closed": bool}`` objects.
    """
    edges = doc.array("edges", 2, "int")
    faces = doc.array("faces", 3, "int")
    uv = doc.array("uv", 2, "float")
    paths = None
    raw = doc.data.get("paths")
    if raw is not None:
        if not isinstance(raw, list):
            raise doc.error("expected a list of {\"indices\": [...], \"closed\": true|false}", "paths")
        paths = []
        for k, item in enumerate(raw):
            if not isinstance(item, dict):
                raise doc.error("expected an object {\"indices\": [...], \"closed\": true|false}", "paths", k)
            idx = doc.array("indices", None, "int", required=True, container=item, keys=("paths", k))
            closed = item.get("closed", False)
            if not isinstance(closed, bool):
                raise doc.error(f"'closed' must be true or false, got {json.dumps(closed)}", "paths", k)
            paths.append((idx, closed))
    y_down = doc.data.get("y_down", False)
    if not isinstance(y_down, bool):
        raise doc.error(f"must be true or false, got {json.dumps(y_down)}", "y_down")
    return edges, faces, uv, paths, y_down


def shape_from_fields(doc, vertices, edges, faces, uv, paths, y_down=False):
    """Build the Shape; edges come from the paths when only paths are given."""
    n = len(vertices)
    for key, rows in (("edges", edges), ("faces", faces)):
        if rows is not None and rows.size:
            bad = np.flatnonzero(np.any((rows < 0) | (rows >= n), axis=1))
            if bad.size:
                raise doc.error(f"vertex index out of range [0, {n}): {rows[bad[0]].tolist()}", key, int(bad[0]))
    for k, (idx, closed) in enumerate(paths or []):
        if idx.size and (idx.min() < 0 or idx.max() >= n):
            raise doc.error(f"vertex index out of range [0, {n})", "paths", k, "indices")
        if len(idx) < (3 if closed else 2):
            kind = "a closed path needs 3" if closed else "an open path needs 2"
            raise doc.error(f"{kind} or more indices, got {len(idx)}", "paths", k, "indices")
    if edges is not None and edges.size:
        loop = np.flatnonzero(edges[:, 0] == edges[:, 1])
        if loop.size:
            raise doc.error(f"edge joins vertex {edges[loop[0], 0]} to itself", "edges", int(loop[0]))
    if edges is None and paths is not None:
        parts = [np.column_stack([p, np.roll(p, -1)] if c else [p[:-1], p[1:]]) for p, c in paths]
        edges = np.vstack(parts) if parts else None
    if uv is not None and len(uv) != len(vertices):
        raise doc.error(f"has {len(uv)} rows for {len(vertices)} vertices", "uv")
    try:
        return Shape(vertices, edges, faces, uv=uv, paths=paths, y_down=y_down)
    except ShapeError as exc:
        raise FileFormatError(f"{doc.path}: {exc}") from exc


def read_json(path):
    """Read a shape from the isotween JSON schema.

    ``{"vertices": [[x, y], ...], "edges": [[i, j], ...], "faces": [[i, j, k], ...],
    "uv": [[u, v], ...], "paths": [{"indices": [...], "closed": true}, ...],
    "y_down": false, "regions": [[0, 1], ...], "paint": [{"fill": [r, g, b, a], "stroke": null,
    "stroke_width": 1.0, "opacity": 1.0}, ...]}``;
    only ``vertices`` is required, indices are 0-based. Without ``edges`` the
    edges follow the paths, else the face sides.

    Raises
    ------
    FileFormatError
        Naming the file, the line and the element (e.g. ``vertices[3]``).
    """
    from ..paint import Paint

    doc = JsonDocument(path)
    data = doc.require_object()
    if "frames" in data:
        raise FileFormatError(f"{path}: is a sequence file (it has 'frames'); read it with load_sequence")
    vertices = doc.array("vertices", 2, "float", required=True)
    shape = shape_from_fields(doc, vertices, *shape_fields(doc))
    regions, paint = data.get("regions"), data.get("paint")
    if regions is None and paint is None:
        return shape
    if regions is not None and not (isinstance(regions, list) and all(
            isinstance(r, list) and all(isinstance(i, int) and not isinstance(i, bool) for i in r) for r in regions)):
        raise doc.error("expected a list of lists of path indices", "regions")
    if paint is not None:
        if not (isinstance(paint, list) and all(isinstance(p, dict) for p in paint)):
            raise doc.error("expected a list of paint objects", "paint")
        try:
            paint = [Paint.from_dict(p) for p in paint]
        except (TypeError, ValueError, IsotweenError) as exc:
            raise doc.error(str(exc)[:200], "paint") from None
    try:
        return Shape(shape.vertices, shape.edges, shape.faces, uv=shape.uv, paths=shape.paths, y_down=shape.y_down,
                     regions=regions, paint=paint)
    except ShapeError as exc:
        raise FileFormatError(f"{path}: {exc}") from exc


def fields_text(shape, indent="  "):
    """JSON members (without braces) for the connectivity of ``shape``."""
    parts = [f'{indent}"edges": {dumps_rows(shape.edges.tolist(), indent)}']
    if shape.faces is not None:
        parts.append(f'{indent}"faces": {dumps_rows(shape.faces.tolist(), indent)}')
    if shape.uv is not None:
        parts.append(f'{indent}"uv": {dumps_rows(shape.uv.tolist(), indent)}')
    if shape.paths is not None:
        rows = [{"indices": p.tolist(), "closed": c} for p, c in shape.paths]
        parts.append(f'{indent}"paths": {dumps_rows(rows, indent)}')
    if shape.y_down:
        parts.append(f'{indent}"y_down": true')
    return parts


def write_json(shape, path):
    """Write a shape in the isotween JSON schema (exact round trip with `read_json`, regions and paint included)."""
    parts = [f'  "vertices": {dumps_rows(shape.vertices.tolist())}'] + fields_text(shape)
    if shape.regions is not None:
        parts.append(f'  "regions": {json.dumps(shape.regions)}')
    if shape.paint is not None:
        parts.append(f'  "paint": {dumps_rows([p.to_dict() for p in shape.paint], "  ")}')
    write_text(path, "{\n" + ",\n".join(parts) + "\n}\n")
