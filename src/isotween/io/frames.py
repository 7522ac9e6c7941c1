"""One file per frame in a folder (``frame_0000.obj``, ``frame_0001.obj``, ...)."""

import re
from pathlib import Path

from ..errors import FileFormatError, ParameterError, require
from ._files import atomic_dir

__all__ = ["write_frames", "FRAME_FORMATS"]

#: formats `write_frames` accepts
FRAME_FORMATS = ("obj", "off", "svg", "json", "npz", "png")


def frame_names(count, fmt):
    """``frame_0000.fmt`` ... (at least four digits, more when needed)."""
    width = max(4, len(str(count - 1)))
    return [f"frame_{k:0{width}d}.{fmt}" for k in range(count)]


def write_frames(seq, directory, format="obj", texture=None, progress=False):
    """Write every frame of a sequence to its own file in ``directory``.

    Parameters
    ----------
    seq : Sequence
    directory : path-like
        Created when missing (its parent must exist).
    format : {'obj', 'off', 'svg', 'json', 'npz', 'png'}
        File format of every frame; ``png`` draws the frame with
        `isotween.render.write_frame_png` (textured when ``texture`` is given).
    texture : path-like, optional
        Image for ``png`` frames.
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    list of Path
        The files written, in frame order.

    Notes
    -----
    All frames are written to a hidden temporary folder first and moved into
    place only when every one succeeded, so an error leaves no partial set.
    Older ``frame_NNNN.<format>`` files in ``directory`` that the new
    sequence does not overwrite are removed, so that the folder reads back
    (`load_sequence`) as exactly this sequence.

    Examples
    --------
    >>> import os, tempfile
    >>> import isotween
    >>> from isotween.io import write_frames
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> seq = isotween.interpolate(bar, bar.rotate(1.0), frames=3)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     files = write_frames(seq, os.path.join(d, "frames"), format="json")
    ...     isotween.load_sequence(os.path.join(d, "frames")).equals(seq, atol=1e-12)
    True
    """
    fmt = str(format).lower().lstrip(".")
    if fmt not in FRAME_FORMATS:
        raise ParameterError(f"unknown frame format '{format}'; use one of {', '.join(FRAME_FORMATS)}")
    if fmt == "png":
        render = require("isotween.render", "cli")
        points = seq.frames.reshape(-1, 2)
        # one view for every frame, so that the images line up
        bbox = (*points.min(axis=0).tolist(), *points.max(axis=0).tolist())

        def writer(shape, path):
            render.write_frame_png(shape, path, texture=texture, bbox=bbox)
    else:
        from .shapes import SHAPE_FORMATS

        writer = SHAPE_FORMATS[f".{fmt}"][1]
    directory = Path(directory)
    names = frame_names(len(seq), fmt)
    indices = range(len(seq))
    if progress:
        from tqdm import tqdm

        indices = tqdm(indices, desc="frames", unit="frame", leave=False, delay=0.5)
    with atomic_dir(directory) as tmp:
        for k in indices:
            writer(seq[k], tmp / names[k])
    pattern = re.compile(rf"frame_\d{{4,}}\.{fmt}")
    keep = set(names)
    for old in directory.iterdir():
        if old.name not in keep and pattern.fullmatch(old.name) and old.is_file():
            try:
                old.unlink()
            except OSError as exc:
                raise FileFormatError(f"cannot remove the old frame {old}: {exc.strerror or exc}") from exc
    return [directory / name for name in names]
