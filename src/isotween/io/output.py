"""`write_output`: the one place that turns a sequence into the file(s) a user asked for."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import FileFormatError, ParameterError, require
from ._files import atomic_path
from .frames import FRAME_FORMATS, write_frames
from .sequence_file import save_sequence

if TYPE_CHECKING:
    from os import PathLike

    from ..sequence import Sequence

__all__ = ["write_output", "output_kind", "OUTPUT_KINDS"]

#: file extension -> kind of output
OUTPUT_KINDS = {
    ".npz": "sequence",
    ".json": "sequence",
    ".gif": "gif",
    ".mp4": "mp4",
    ".html": "html",
    ".png": "strip",
    ".svg": "svg",
}


def output_kind(out: str | PathLike, format: str | None = None) -> str:
    """What `write_output` would write to ``out``, checked before any work is done.

    Parameters
    ----------
    out : path-like
    format : str, optional
        Frame file format; asks for a folder of frames.

    Returns
    -------
    {'sequence', 'gif', 'mp4', 'html', 'strip', 'svg', 'frames'}

    Raises
    ------
    FileFormatError
        Unknown extension, a single-shape extension, or a parent folder that
        does not exist.
    ParameterError
        Unknown ``format``, or ``format`` with a file name.

    Examples
    --------
    >>> from isotween.io.output import output_kind
    >>> output_kind("walk.gif"), output_kind("walk.npz"), output_kind("walk.png")
    ('gif', 'sequence', 'strip')
    """
    out = Path(out)
    ext = out.suffix.lower()
    if format is not None:
        if str(format).lower() not in FRAME_FORMATS:
            raise ParameterError(f"unknown frame format '{format}'; use one of {', '.join(FRAME_FORMATS)}")
        if ext in OUTPUT_KINDS and not out.is_dir():
            raise ParameterError(f"--format {format} writes one file per frame into a folder, but {out} names a {ext} file")
        kind = "frames"
    elif out.is_dir() or not ext:
        kind = "frames"
    elif ext in OUTPUT_KINDS:
        kind = OUTPUT_KINDS[ext]
    elif ext in (".obj", ".off"):
        raise FileFormatError(
            f"{out}: a {ext} file holds one shape, not a sequence; write a folder of frames "
            f"(-o FOLDER --format {ext[1:]}) or a .npz/.json sequence"
        )
    else:
        raise FileFormatError(
            f"{out}: unknown output kind '{ext}'; use .npz, .json, .gif, .mp4, .html, .png, .svg or a folder with --format"
        )
    parent = out.parent
    if not parent.is_dir():
        raise FileFormatError(f"cannot write {out}: {parent} {'is not a folder' if parent.exists() else 'does not exist'}")
    if kind != "frames" and out.is_dir():
        raise FileFormatError(f"cannot write {out}: is a folder")
    if kind == "frames" and out.exists() and not out.is_dir():
        raise FileFormatError(f"cannot write frames to {out}: it is a file, not a folder")
    return kind


def write_output(seq: Sequence, out: str | PathLike, format: str | None = None,
                 texture: str | PathLike | None = None, quiet: bool = False) -> list[Path]:
    """Write a sequence as the kind of output ``out`` names.

    ``.npz`` / ``.json``: sequence file (`save_sequence`); ``.gif``, ``.mp4``,
    ``.html``, ``.svg`` (SMIL): animation (`isotween.render`); ``.png``: a strip of frames;
    a folder (existing, without extension, or with ``format``): one file per
    frame (`write_frames`, ``format`` defaulting to ``obj``).

    Parameters
    ----------
    seq : Sequence
    out : path-like
    format : {'obj', 'off', 'svg', 'json', 'npz', 'png'}, optional
    texture : path-like, optional
        Image mapped through the shape's uv in rendered outputs.
    quiet : bool
        No progress bar.

    Returns
    -------
    list of Path
        Files written.

    Notes
    -----
    Every file is written through a temporary file and renamed into place,
    so an error leaves no partial output.

    Examples
    --------
    >>> import os, tempfile
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> seq = isotween.interpolate(bar, bar.rotate(1.0), frames=3)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     files = isotween.write_output(seq, os.path.join(d, "frames"), format="obj", quiet=True)
    ...     sorted(os.path.basename(f) for f in files)
    ['frame_0000.obj', 'frame_0001.obj', 'frame_0002.obj']
    """
    kind = output_kind(out, format)
    out = Path(out)
    if texture is not None and not Path(texture).is_file():
        raise FileFormatError(f"{texture}: no such texture image")
    if kind == "sequence":
        save_sequence(seq, out)
        return [out]
    if kind == "frames":
        return write_frames(seq, out, format=format or "obj", texture=texture, progress=not quiet)
    render = require("isotween.render", "cli")
    with atomic_path(out) as tmp:
        if kind == "gif":
            render.write_gif(seq, tmp, texture=texture)
        elif kind == "mp4":
            render.write_mp4(seq, tmp, texture=texture)
        elif kind == "html":
            render.write_html(seq, tmp, texture=texture)
        elif kind == "svg":
            render.write_svg_animation(seq, tmp)
        else:
            render.write_strip(seq, tmp, texture=texture)
    return [out]
