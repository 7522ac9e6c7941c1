"""Whole sequences in one file (.npz, .json) or as a folder of frame files."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import FileFormatError, IncompatibleShapesError
from ..resources import check_memory
from ..sequence import Sequence
from ._files import check_readable, write_text
from ._json import JsonDocument, dumps_rows
from .json_shape import fields_text, shape_fields, shape_from_fields
from .npz import connectivity_arrays, connectivity_from, open_npz, save_arrays

if TYPE_CHECKING:
    from os import PathLike

__all__ = ["save_sequence", "load_sequence", "is_sequence_file", "check_sequence"]

FORMAT = "isotween-sequence"
VERSION = 1


def _plain(value):
    """JSON-ready copy of ``value`` (arrays to lists, numpy scalars to numbers)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, float) and not np.isfinite(value):
        return str(value)
    if value is None or isinstance(value, (bool, int, float, str)):
        return value
    return str(value)


def _meta(seq):
    return {
        "times": np.asarray(seq.times, dtype=np.float64),
        "energy": np.asarray(seq.energy, dtype=np.float64).reshape(-1),
        "iterations": int(seq.iterations),
        "converged": bool(seq.converged),
        "method": str(seq.method),
        "scheme": str(seq.scheme),
        "timings": _plain(seq.timings),
        "info": _plain(seq.info),
    }


def check_sequence(seq: Sequence, where: str) -> Sequence:
    """Refuse a sequence whose fields disagree, naming the field (what `load_sequence` and every writer check).

    Frames are (F, n, 2), finite, with n the shape's vertex count; times
    have one finite value per frame and do not decrease; energy values are
    finite; ``info['keyframe_indices']`` are frame indices; ``info['paint']``
    gives one paint per path for each key time and its regions name paths.

    Parameters
    ----------
    seq : Sequence
    where : str
        How the error starts (``'x.npz'`` or ``'cannot write x.html'``).

    Returns
    -------
    Sequence
        ``seq`` itself.

    Raises
    ------
    FileFormatError
        Naming ``where`` and the field.
    """
    from ..errors import IsotweenError
    from ..paint import sequence_paint

    frames = np.asarray(seq.frames)
    if frames.ndim != 3 or frames.shape[2] != 2 or frames.shape[0] < 1:
        raise FileFormatError(f"{where}: frames must have shape (frames, n, 2) with at least one frame, "
                              f"got {frames.shape}")
    if frames.shape[1] != seq.shape.n_vertices:
        raise FileFormatError(f"{where}: frames have {frames.shape[1]} vertices but the shape has "
                              f"{seq.shape.n_vertices}")
    if not np.all(np.isfinite(frames)):
        k = int(np.argwhere(~np.isfinite(frames))[0, 0])
        raise FileFormatError(f"{where}: frames: frame {k} has a non-finite coordinate")
    times = np.asarray(seq.times)
    if times.shape != (len(frames),):
        raise FileFormatError(f"{where}: times: {times.size} values for {len(frames)} frames")
    if times.dtype.kind not in "iuf" or not np.all(np.isfinite(times)) or np.any(np.diff(times) < 0):
        raise FileFormatError(f"{where}: times must be finite numbers that do not decrease")
    try:
        energy = np.asarray(seq.energy, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise FileFormatError(f"{where}: energy must be a list of numbers") from None
    if not np.all(np.isfinite(energy)):
        k = int(np.flatnonzero(~np.isfinite(energy))[0])
        raise FileFormatError(f"{where}: energy[{k}] is {energy[k]}, not a finite number")
    info = seq.info
    if not isinstance(info, dict):
        raise FileFormatError(f"{where}: info must be a dict, got {type(info).__name__}")
    keys = info.get("keyframe_indices")
    if keys is not None:
        ok = isinstance(keys, list | tuple | np.ndarray) and all(
            isinstance(k, int | np.integer) and not isinstance(k, bool) and 0 <= k < len(frames) for k in keys)
        if not ok:
            raise FileFormatError(f"{where}: info.keyframe_indices must be frame indices from 0 to "
                                  f"{len(frames) - 1}, got {str(keys)[:80]}")
    if info.get("paint"):
        n_paths = len(seq.shape.paths or [])
        regions = info["paint"].get("regions") if isinstance(info["paint"], dict) else None
        if regions is not None and not (isinstance(regions, list) and all(
                isinstance(r, list) and all(isinstance(i, int) and not isinstance(i, bool) and 0 <= i < n_paths
                                            for i in r) for r in regions)):
            raise FileFormatError(f"{where}: info.paint.regions must list path indices from 0 to {n_paths - 1}, "
                                  f"got {str(regions)[:80]}")
        try:
            sequence_paint(seq)
        except (IsotweenError, KeyError, TypeError, ValueError, IndexError, AttributeError) as exc:
            raise FileFormatError(f"{where}: info.paint: {str(exc)[:200]}") from None
    return seq


def save_sequence(seq: Sequence, path: str | PathLike) -> None:
    """Write a sequence to ``.npz`` or ``.json`` (layout in docs/formats.md).

    Stores the frames, the shared connectivity (edges, faces, uv, paths), the
    source vertices when they differ from frame 0, times, energy history,
    iterations, converged, method, scheme, timings and info. Atomic.

    Examples
    --------
    >>> import os, tempfile
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> seq = isotween.interpolate(bar, bar.rotate(1.0), frames=4)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     isotween.save_sequence(seq, os.path.join(d, "seq.json"))
    ...     back = isotween.load_sequence(os.path.join(d, "seq.json"))
    >>> back.equals(seq)
    True
    """
    ext = Path(path).suffix.lower()
    if ext not in (".npz", ".json"):
        raise FileFormatError(f"{path}: a sequence file must end in .npz or .json")
    if not isinstance(seq, Sequence):
        raise FileFormatError(f"{path}: save_sequence expects an isotween.Sequence, got {type(seq).__name__}")
    check_sequence(seq, f"cannot write {path}")  # what load_sequence would refuse is not written
    meta = _meta(seq)
    shape = seq.shape
    own_vertices = len(seq.frames) == 0 or not np.array_equal(shape.vertices, seq.frames[0])
    if ext == ".npz":
        arrays = {
            "format": np.array(FORMAT),
            "version": np.array(VERSION),
            "frames": seq.frames,
            **connectivity_arrays(shape),
            "times": meta["times"],
            "energy": meta["energy"],
            "iterations": np.array(meta["iterations"]),
            "converged": np.array(meta["converged"]),
            "method": np.array(meta["method"]),
            "scheme": np.array(meta["scheme"]),
            "timings": np.array(json.dumps(meta["timings"])),
            "info": np.array(json.dumps(meta["info"])),
        }
        if own_vertices:
            arrays["vertices"] = shape.vertices
        save_arrays(path, arrays)
        return
    parts = [f'  "format": "{FORMAT}"', f'  "version": {VERSION}']
    frames = [f"[{', '.join(json.dumps(p) for p in f)}]" for f in seq.frames.tolist()]
    parts.append('  "frames": [\n    ' + ",\n    ".join(frames) + "\n  ]" if frames else '  "frames": []')
    if own_vertices:
        parts.append(f'  "vertices": {dumps_rows(shape.vertices.tolist())}')
    parts += fields_text(shape)
    parts.append(f'  "times": {json.dumps(meta["times"].tolist())}')
    parts.append(f'  "energy": {json.dumps(meta["energy"].tolist())}')
    for key in ("iterations", "converged", "method", "scheme", "timings", "info"):
        parts.append(f'  "{key}": {json.dumps(meta[key])}')
    write_text(path, "{\n" + ",\n".join(parts) + "\n}\n")


def is_sequence_file(path: str | PathLike) -> bool:
    """Whether ``path`` holds a sequence: a folder, or an .npz/.json with frames.

    Examples
    --------
    >>> import os, tempfile
    >>> import isotween
    >>> from isotween.io.sequence_file import is_sequence_file
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     isotween.save(bar, os.path.join(d, "bar.npz"))
    ...     isotween.save_sequence(isotween.interpolate(bar, bar.rotate(1.0), frames=3), os.path.join(d, "seq.npz"))
    ...     is_sequence_file(os.path.join(d, "bar.npz")), is_sequence_file(os.path.join(d, "seq.npz"))
    (False, True)
    """
    path = Path(path)
    if path.is_dir():
        return True
    ext = path.suffix.lower()
    if ext == ".npz":
        return "frames" in open_npz(path)
    if ext == ".json":
        data = JsonDocument(path).data
        return isinstance(data, dict) and "frames" in data
    return False


def load_sequence(path: str | PathLike) -> Sequence:
    """Read a sequence written by `save_sequence`, or a folder of frame files.

    A folder is read as one frame per shape file (.obj, .off, .svg, .json,
    .npz), sorted by name with numbers compared by value (``frame_2`` before
    ``frame_10``); every frame must have the same connectivity.

    Returns
    -------
    Sequence

    Raises
    ------
    FileFormatError
        Naming the file and what is missing or malformed.
    IncompatibleShapesError
        When the frames of a folder differ in connectivity (naming the file).

    Examples
    --------
    >>> import os, tempfile
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> seq = isotween.interpolate(bar, bar.rotate(1.0), frames=4)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     isotween.save_sequence(seq, os.path.join(d, "seq.npz"))
    ...     back = isotween.load_sequence(os.path.join(d, "seq.npz"))
    >>> len(back), back.method, back.equals(seq)
    (4, 'aiap', True)
    """
    path = Path(path)
    if path.is_dir():
        return _load_folder(path)
    check_readable(path)
    ext = path.suffix.lower()
    if ext == ".npz":
        return _load_npz(path)
    if ext == ".json":
        return _load_json(path)
    raise FileFormatError(f"{path}: a sequence is a .npz or .json file, or a folder of frame files")


def _frames_array(path, frames, where):
    if frames.ndim != 3 or frames.shape[2] != 2 or frames.shape[0] < 1:
        raise FileFormatError(
            f"{path}: {where} must have shape (frames, n, 2) with at least one frame, got {frames.shape}")
    if not np.all(np.isfinite(frames)):
        k = int(np.argwhere(~np.isfinite(frames))[0, 0])
        raise FileFormatError(f"{path}: {where}: frame {k} has a non-finite coordinate")
    return frames


def _check_times(path, frames, times):
    if times is not None and times.shape != (len(frames),):
        raise FileFormatError(f"{path}: 'times' has {times.size} values for {len(frames)} frames")


def _load_npz(path):
    arrays = open_npz(path)
    if "frames" not in arrays:
        raise FileFormatError(f"{path}: missing the array 'frames' (is it a single shape? use load)")
    frames = arrays["frames"]
    if frames.dtype.kind not in "iuf":
        raise FileFormatError(f"{path}: array 'frames' must hold numbers, got {frames.dtype}")
    frames = _frames_array(path, frames.astype(np.float64), "array 'frames'")
    vertices = arrays.get("vertices", frames[0])
    shape = connectivity_from(path, arrays, vertices)
    if shape.n_vertices != frames.shape[1]:
        raise FileFormatError(f"{path}: frames have {frames.shape[1]} vertices but the shape has {shape.n_vertices}")

    def scalar(name, kind, default):
        if name not in arrays:
            return default
        a = arrays[name]
        if a.ndim != 0:
            raise FileFormatError(f"{path}: array '{name}' must be a single value, got shape {a.shape}")
        try:
            return kind(a.item())
        except (TypeError, ValueError):
            raise FileFormatError(f"{path}: array '{name}' must be a {kind.__name__}, got {a.item()!r}") from None

    def parsed(name):
        try:
            return json.loads(scalar(name, str, "{}"))
        except json.JSONDecodeError as exc:
            raise FileFormatError(f"{path}: array '{name}' is not valid JSON ({exc.msg})") from None

    times = arrays.get("times")
    energy = arrays.get("energy", np.zeros(0))
    for name, a in (("times", times), ("energy", energy)):
        if a is not None and (a.dtype.kind not in "iuf" or a.ndim != 1):
            raise FileFormatError(f"{path}: array '{name}' must be a 1-d array of numbers, got {a.dtype} {a.shape}")
    _check_times(path, frames, times)
    return check_sequence(Sequence(
        frames, shape, times=times, scheme=scalar("scheme", str, "midpoint"),
        energy=[float(e) for e in np.asarray(energy, dtype=np.float64).reshape(-1)],
        iterations=scalar("iterations", int, 0), converged=scalar("converged", bool, True),
        timings=parsed("timings"), method=scalar("method", str, "aiap"), info=parsed("info"),
    ), str(path))


def _load_json(path):
    doc = JsonDocument(path)
    data = doc.require_object()
    if "frames" not in data:
        raise FileFormatError(f"{path}, line 1: missing the key 'frames' (is it a single shape? use load)")
    raw = data["frames"]
    if not isinstance(raw, list) or not raw:
        raise doc.error("expected a non-empty list of frames", "frames")
    rows = []
    for k, frame in enumerate(raw):
        if not isinstance(frame, list):
            raise doc.error("expected a list of [x, y] points", "frames", k)
        rows.append(doc.array(k, 2, "float", container=raw, keys=("frames",)))
        if len(rows[-1]) != len(rows[0]):
            raise doc.error(f"has {len(rows[-1])} points, frame 0 has {len(rows[0])}", "frames", k)
    frames = _frames_array(path, np.stack(rows), "'frames'")
    vertices = doc.array("vertices", 2, "float")
    shape = shape_from_fields(doc, frames[0] if vertices is None else vertices, *shape_fields(doc))
    if shape.n_vertices != frames.shape[1]:
        raise FileFormatError(f"{path}: frames have {frames.shape[1]} points but 'vertices' has {shape.n_vertices}")
    times = doc.array("times", None, "float")
    energy = doc.array("energy", None, "float")
    _check_times(path, frames, times)

    def field(key, types, default):
        value = data.get(key, default)
        if not isinstance(value, types) or (types is int and isinstance(value, bool)):
            raise doc.error(f"has the wrong type ({type(value).__name__})", key)
        return value

    return check_sequence(Sequence(
        frames, shape, times=times, scheme=field("scheme", str, "midpoint"),
        energy=[] if energy is None else energy.tolist(),
        iterations=field("iterations", int, 0), converged=field("converged", bool, True),
        timings=field("timings", dict, {}), method=field("method", str, "aiap"), info=field("info", dict, {}),
    ), str(path))


def _natural_key(name):
    return [int(t) if t.isdigit() else t.lower() for t in re.split(r"(\d+)", name)]


def _load_folder(folder):
    from .shapes import SHAPE_FORMATS, load

    files = sorted(
        (p for p in folder.iterdir()
         if p.is_file() and not p.name.startswith(".") and p.suffix.lower() in SHAPE_FORMATS),
        key=lambda p: _natural_key(p.name),
    )
    if not files:
        raise FileFormatError(f"{folder}: no frame files ({', '.join(SHAPE_FORMATS)}) in this folder")
    first = load(files[0])
    per_file = 8 * first.vertices.size + 8 * first.edges.size + (0 if first.faces is None else 8 * first.faces.size)
    check_memory(2.0 * per_file * len(files), f"reading {len(files)} frame files of {folder}",
                 advice="use fewer frame files")
    shapes = [first] + [load(p) for p in files[1:]]
    ref = shapes[0]
    for p, s in zip(files[1:], shapes[1:], strict=False):
        same_faces = (ref.faces is None) == (s.faces is None) and (
            ref.faces is None or np.array_equal(ref.faces, s.faces)
        )
        if s.n_vertices != ref.n_vertices or not np.array_equal(s.edges, ref.edges) or not same_faces:
            raise IncompatibleShapesError(
                f"{p}: frame has {s.n_vertices} vertices, {s.n_edges} edges, {s.n_faces} faces, but "
                f"{files[0]} has {ref.n_vertices}, {ref.n_edges}, {ref.n_faces} (or they are connected "
                "differently); all frames of a folder need the same connectivity"
            )
    frames = np.stack([s.vertices for s in shapes])
    return Sequence(frames, ref, method="frames", info={"source": str(folder), "files": [p.name for p in files]})
