"""NumPy ``.npz`` shape files: named arrays, exact to the bit."""

import math
import zipfile
import zlib

import numpy as np

from ..errors import FileFormatError, IsotweenError, ShapeError
from ..resources import check_memory, format_size
from ..shape import Shape
from ._files import atomic_path, check_readable

__all__ = ["read_npz", "write_npz", "open_npz", "connectivity_arrays", "connectivity_from"]


def open_npz(path, max_memory=None):
    """All arrays of an ``.npz`` file as a dict (no pickles).

    The arrays' declared shapes are read from their headers first: an array
    that claims more bytes than its member holds, or arrays that together
    exceed the memory limit (`isotween.resources.check_memory`), are refused
    before anything is allocated.
    """
    path = check_readable(path)
    total = _declared_bytes(path)
    check_memory(total, f"reading {path}", max_memory, advice="use a smaller file")
    try:
        with np.load(path, allow_pickle=False) as data:
            return {k: data[k] for k in data.files}
    except (OSError, ValueError, zipfile.BadZipFile, EOFError, NotImplementedError, KeyError,
            RuntimeError, TypeError, zlib.error) as exc:
        raise FileFormatError(f"{path}: not a valid .npz file ({exc})") from None


def _declared_bytes(path):
    """Total bytes the ``.npy`` members of an ``.npz`` declare; refuses lying headers.

    Raises
    ------
    FileFormatError
        Not a zip file, a member that is not ``.npy``, a header that cannot
        be read, or one whose shape needs more bytes than the member holds.
    """
    total = 0
    try:
        with zipfile.ZipFile(path) as archive:
            for info in archive.infolist():
                if not info.filename.endswith(".npy"):
                    raise FileFormatError(f"{path}: member '{info.filename[:60]}' is not a .npy array")
                with archive.open(info) as fh:
                    version = np.lib.format.read_magic(fh)
                    if version == (1, 0):
                        shape, _, dtype = np.lib.format.read_array_header_1_0(fh)
                    else:
                        shape, _, dtype = np.lib.format.read_array_header_2_0(fh)
                    header = fh.tell()
                if dtype.hasobject:
                    raise FileFormatError(f"{path}: array '{info.filename[:-4]}' holds Python objects (not read)")
                nbytes = math.prod(shape) * dtype.itemsize
                if nbytes > info.file_size - header:
                    raise FileFormatError(
                        f"{path}: array '{info.filename[:-4]}' declares shape {shape} ({format_size(nbytes)}) "
                        f"but its data holds {format_size(max(info.file_size - header, 0))}"
                    )
                total += nbytes
    except FileFormatError:
        raise
    except (OSError, ValueError, zipfile.BadZipFile, EOFError, NotImplementedError, KeyError,
            RuntimeError, TypeError, SyntaxError, OverflowError, zlib.error) as exc:
        raise FileFormatError(f"{path}: not a valid .npz file ({exc})") from None
    return total


def connectivity_arrays(shape):
    """Arrays that store the connectivity of ``shape`` (edges, faces?, uv?, paths?)."""
    out = {"edges": shape.edges}
    if shape.faces is not None:
        out["faces"] = shape.faces
    if shape.uv is not None:
        out["uv"] = shape.uv
    if shape.paths is not None:
        sizes = [len(p) for p, _ in shape.paths]
        out["path_indices"] = np.concatenate([p for p, _ in shape.paths]) if sizes else np.zeros(0, np.int64)
        out["path_sizes"] = np.array(sizes, dtype=np.int64)
        out["path_closed"] = np.array([c for _, c in shape.paths], dtype=bool)
    if shape.y_down:
        out["y_down"] = np.array(True)
    return out


def _get(path, arrays, name, ndim, width=None, kind="f", required=False):
    a = arrays.get(name)
    if a is None:
        if required:
            raise FileFormatError(f"{path}: missing the array '{name}'")
        return None
    ok_kind = a.dtype.kind in ("iu" if kind == "i" else "iuf" if kind == "f" else "b")
    if a.ndim != ndim or (width is not None and a.shape[-1] != width) or not ok_kind:
        want = {"i": "integers", "f": "numbers", "b": "booleans"}[kind]
        shape = f"(k, {width})" if width is not None and ndim == 2 else f"{ndim}-d"
        raise FileFormatError(f"{path}: array '{name}' must hold {want} of shape {shape}, got {a.dtype} {a.shape}")
    return a


def connectivity_from(path, arrays, vertices):
    """Shape with ``vertices`` and the connectivity stored in ``arrays``."""
    edges = _get(path, arrays, "edges", 2, 2, "i")
    faces = _get(path, arrays, "faces", 2, 3, "i")
    uv = _get(path, arrays, "uv", 2, 2, "f")
    paths = None
    if "path_indices" in arrays:
        idx = _get(path, arrays, "path_indices", 1, kind="i")
        sizes = _get(path, arrays, "path_sizes", 1, kind="i", required=True)
        closed = _get(path, arrays, "path_closed", 1, kind="b", required=True)
        if sizes.sum() != len(idx) or len(closed) != len(sizes) or np.any(sizes < 0):
            raise FileFormatError(f"{path}: arrays 'path_indices', 'path_sizes' and 'path_closed' disagree")
        paths = list(zip(np.split(idx, np.cumsum(sizes)[:-1]), closed.tolist(), strict=False))
    if uv is not None and len(uv) != len(vertices):
        raise FileFormatError(f"{path}: array 'uv' has {len(uv)} rows for {len(vertices)} vertices")
    y_down = _get(path, arrays, "y_down", 0, kind="b")
    try:
        return Shape(vertices, edges, faces, uv=uv, paths=paths, y_down=bool(y_down))
    except ShapeError as exc:
        raise FileFormatError(f"{path}: {exc}") from exc


def read_npz(path):
    """Read a shape from the arrays of a ``.npz`` file.

    The arrays are ``vertices`` (n, 2), ``edges`` (E, 2), and optional
    ``faces`` (F, 3), ``uv`` (n, 2), ``path_indices``, ``path_sizes``,
    ``path_closed``, ``region_paths`` with ``region_sizes`` (the filled
    regions' path indices, region after region) and ``paint`` (a JSON
    string: one `Paint.to_dict` per path).

    Raises
    ------
    FileFormatError
        Naming the file and the missing or malformed array.
    """
    import json

    from ..paint import Paint

    arrays = open_npz(path)
    if "frames" in arrays:
        raise FileFormatError(f"{path}: is a sequence file (it has 'frames'); read it with load_sequence")
    vertices = _get(path, arrays, "vertices", 2, 2, "f", required=True)
    shape = connectivity_from(path, arrays, vertices)
    regions = paint = None
    if "region_sizes" in arrays:
        idx = _get(path, arrays, "region_paths", 1, kind="i", required=True)
        sizes = _get(path, arrays, "region_sizes", 1, kind="i", required=True)
        if sizes.sum() != len(idx) or np.any(sizes < 0):
            raise FileFormatError(f"{path}: arrays 'region_paths' and 'region_sizes' disagree")
        regions = [r.tolist() for r in np.split(idx, np.cumsum(sizes)[:-1])] if len(sizes) else []
    if "paint" in arrays:
        try:
            paint = [Paint.from_dict(p) for p in json.loads(str(arrays["paint"][()]))]
        except (ValueError, TypeError, AttributeError, IsotweenError) as exc:
            raise FileFormatError(f"{path}: array 'paint' is not a list of paints ({str(exc)[:120]})") from None
    if regions is None and paint is None:
        return shape
    try:
        return Shape(shape.vertices, shape.edges, shape.faces, uv=shape.uv, paths=shape.paths, y_down=shape.y_down,
                     regions=regions, paint=paint)
    except ShapeError as exc:
        raise FileFormatError(f"{path}: {exc}") from exc


def write_npz(shape, path):
    """Write a shape as ``.npz`` (exact round trip with `read_npz`, regions and paint included)."""
    import json

    arrays = {"vertices": shape.vertices, **connectivity_arrays(shape)}
    if shape.regions is not None:
        arrays["region_paths"] = np.array([i for r in shape.regions for i in r], dtype=np.int64)
        arrays["region_sizes"] = np.array([len(r) for r in shape.regions], dtype=np.int64)
    if shape.paint is not None:
        arrays["paint"] = np.array(json.dumps([p.to_dict() for p in shape.paint]))
    save_arrays(path, arrays)


def save_arrays(path, arrays):
    """Arrays to an ``.npz`` file (as `np.load` reads it) through a temporary file (atomic).

    Integer, boolean and text arrays are deflated (connectivity shrinks
    several times); floating-point ones are stored as they are: deflate
    takes a frame array's size down by about 6 % at four times the time of
    the whole write (a 21-frame sequence of 1,807 vertices: 645 kB in 7 ms
    against 607 kB in 29 ms with `np.savez_compressed`).
    """
    with atomic_path(path) as tmp, zipfile.ZipFile(tmp, "w", compression=zipfile.ZIP_DEFLATED) as zf:
        for name, value in arrays.items():
            a = np.asanyarray(value)
            member = zipfile.ZipInfo(name + ".npy", date_time=(1980, 1, 1, 0, 0, 0))
            member.compress_type = zipfile.ZIP_STORED if a.dtype.kind in "fc" else zipfile.ZIP_DEFLATED
            with zf.open(member, "w", force_zip64=True) as fh:
                np.lib.format.write_array(fh, a, allow_pickle=False)
