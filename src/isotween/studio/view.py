"""What the studio page draws: sequences and correspondences as JSON-able dicts."""

from __future__ import annotations

import base64
import threading
from collections import OrderedDict
from typing import Any

import numpy as np

from ..render.html import paint_data
from ..render.outline import mesh_boundary

__all__ = ["pack", "sequence_view", "correspondence_view"]

#: matched points shown per ring in the correspondence view
MATCHED_POINTS = 6


def pack(array: Any, dtype: str = "<f8") -> str:
    """A numeric array as base64 of its little-endian bytes (the page reads it as a typed array)."""
    return base64.b64encode(np.ascontiguousarray(array, dtype=dtype).tobytes()).decode("ascii")


#: the drawn paths and packed edges of the last shapes viewed (an edit or a new frame count keeps the shape)
_STATIC: OrderedDict = OrderedDict()
_STATIC_SIZE = 4
_STATIC_LOCK = threading.Lock()


def _static(shape: Any) -> tuple:
    """(paths, packed edges) of ``shape``, kept while it is viewed (a 10k-vertex mesh's boundary takes 50 ms)."""
    with _STATIC_LOCK:
        found = _STATIC.get(id(shape))
    if found is None or found[0] is not shape:
        found = (shape, _paths(shape), pack(np.c_[shape.topology.first, shape.topology.second], "<i4"))
        with _STATIC_LOCK:
            _STATIC[id(shape)] = found
            while len(_STATIC) > _STATIC_SIZE:
                _STATIC.popitem(last=False)
    return found[1], found[2]


def _paths(shape: Any) -> list:
    if shape.paths:
        return [[idx.tolist(), bool(closed)] for idx, closed in shape.paths]
    if shape.n_faces:
        return [[loop.tolist(), True] for loop in mesh_boundary(shape.faces)]
    return []


def _groups(seq: Any) -> list:
    """Drawn groups: paths filled together (even-odd), with their colours per frame."""
    groups = paint_data(seq)
    if groups is not None:
        return groups
    shape, F = seq.shape, len(seq)
    paths = _static(shape)[0]
    out = []
    regions = shape.regions
    used: set = set()
    for r in regions or []:
        out.append({"paths": [paths[i] for i in r], "fill": None, "stroke": None, "width": None})
        used.update(r)
    rest = [p for i, p in enumerate(paths) if i not in used]
    if rest:
        out.append({"paths": rest, "fill": None, "stroke": None, "width": None})
    for g in out:
        for key in ("fill", "stroke", "width"):
            g[key] = [None] * F
    return out


def sequence_view(seq: Any, keys: Any = ()) -> dict:
    """A sequence for the page: frames (base64 float64), times, drawn groups, mesh edges, key frames."""
    shape = seq.shape
    return {
        "frames": pack(seq.frames), "count": len(seq), "n": shape.n_vertices,
        "times": np.asarray(seq.times).tolist(), "y_down": bool(seq.y_down), "groups": _groups(seq),
        "edges": _static(shape)[1],
        "faces": int(shape.n_faces), "keys": sorted({0, len(seq) - 1, *[int(k) for k in keys]}),
        "method": seq.method,
    }


def _items(shape: Any, name: str) -> list:
    from ..correspondence.regions import items_of
    from ..errors import ShapeError

    try:
        items = items_of(shape, name)
    except ShapeError:  # a mesh without paths: its boundary as one region
        loops = mesh_boundary(shape.faces) if shape.n_faces else []
        return [{"kind": "region", "index": 0, "rings": [shape.vertices[loop].tolist() for loop in loops]}]
    return [{"kind": it.kind, "index": int(it.index), "rings": [np.c_[z.real, z.imag].tolist() for z in it.rings]}
            for it in items]


def correspondence_view(solved: Any) -> dict:
    """The inputs with their items, the region pairs, ring start points and a few matched points."""
    src, tgt, report = solved.source, solved.target, solved.report
    a, b = solved.inputs[0], solved.inputs[1]
    pairs = [list(map(int, p)) for p in report.pairs]
    if not pairs and a.regions is not None and b.regions is not None:
        pairs = [[i, i] for i in range(min(len(a.regions), len(b.regions)))]
    rings = []
    for idx, closed in src.paths or []:
        pick = idx[np.linspace(0, len(idx), MATCHED_POINTS, endpoint=False).astype(int)]
        rings.append({"closed": bool(closed), "source": src.vertices[pick].tolist(),
                      "target": tgt.vertices[pick].tolist()})
    return {"inputs": [{"items": _items(a, "source"), "y_down": bool(a.y_down)},
                       {"items": _items(b, "target"), "y_down": bool(b.y_down)}],
            "pairs": pairs, "rings": rings, "summary": report.summary()}
