"""`load` and `save` of one shape, dispatching on the file extension."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import FileFormatError
from ..shape import Shape
from ._files import check_readable
from .json_shape import read_json, write_json
from .npz import read_npz, write_npz
from .obj import read_obj, write_obj
from .off import read_off, write_off
from .svg import read_svg, write_svg

if TYPE_CHECKING:
    from os import PathLike
    from typing import Any

__all__ = ["load", "save", "SHAPE_FORMATS"]

#: extension -> (reader, writer)
SHAPE_FORMATS = {
    ".obj": (read_obj, write_obj),
    ".off": (read_off, write_off),
    ".svg": (read_svg, write_svg),
    ".json": (read_json, write_json),
    ".npz": (read_npz, write_npz),
}


def _codec(path, verb):
    ext = Path(path).suffix.lower()
    if ext not in SHAPE_FORMATS:
        known = ", ".join(SHAPE_FORMATS)
        raise FileFormatError(f"{path}: cannot {verb} '{ext or 'no extension'}' files; use one of {known}")
    return SHAPE_FORMATS[ext]


def load(path: str | PathLike, **options: Any) -> Shape:
    """Read a shape from ``.obj``, ``.off``, ``.svg``, ``.json`` or ``.npz``.

    Parameters
    ----------
    path : path-like
    **options
        Passed to the reader (``curve_segments`` for SVG).

    Returns
    -------
    Shape

    Raises
    ------
    FileFormatError
        Missing file, unknown extension, or malformed content (naming the
        file and the line or element).

    Examples
    --------
    >>> import os, tempfile
    >>> import isotween
    >>> tri = isotween.Shape.from_polygon([[0, 0], [1, 0], [0, 1]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     isotween.save(tri, os.path.join(d, "tri.obj"))
    ...     back = isotween.load(os.path.join(d, "tri.obj"))
    >>> bool((back.vertices == tri.vertices).all()), back.n_edges
    (True, 3)
    """
    reader = _codec(path, "read")[0]
    return reader(check_readable(path), **options)


def save(shape: Shape, path: str | PathLike) -> None:
    """Write a shape; the extension picks the format (see `load`).

    The file is written atomically; an unwritable path raises `FileFormatError`.

    Examples
    --------
    >>> import os, tempfile
    >>> import isotween
    >>> tri = isotween.Shape.from_polygon([[0, 0], [1, 0], [0, 1]])
    >>> with tempfile.TemporaryDirectory() as d:
    ...     isotween.save(tri, os.path.join(d, "tri.json"))
    ...     back = isotween.load(os.path.join(d, "tri.json"))
    >>> back.equals(tri)
    True
    """
    if not isinstance(shape, Shape):
        raise FileFormatError(f"{path}: save expects an isotween.Shape, got {type(shape).__name__}")
    writer = _codec(path, "write")[1]
    writer(shape, path)
