"""One file per frame in a folder (``frame_0000.obj``, ``frame_0001.obj``, ...)."""

import functools
import re
from pathlib import Path

from ..errors import FileFormatError, ParameterError
from ..paint import sequence_paint
from ._files import atomic_dir

__all__ = ["write_frames", "write_frame_files", "frame_names", "DATA_FRAME_FORMATS", "FRAME_FORMATS"]

#: shape formats `write_frames` writes (pictures of frames: `isotween.outputs`)
DATA_FRAME_FORMATS = ("obj", "off", "svg", "json", "npz")
FRAME_FORMATS = DATA_FRAME_FORMATS


def frame_names(count, fmt):
    """``frame_0000.fmt`` ... (at least four digits, more when needed)."""
    width = max(4, len(str(count - 1)))
    return [f"frame_{k:0{width}d}.{fmt}" for k in range(count)]


def write_frame_files(count, directory, ext, writer, progress=False):
    """Write ``count`` files ``frame_NNNN.<ext>`` into ``directory``, all or none.

    Parameters
    ----------
    count : int
    directory : path-like
        Created when missing (its parent must exist).
    ext : str
        File extension without the dot.
    writer : callable
        ``writer(k, path)`` writes frame ``k`` to ``path`` (a plain file in
        a temporary folder: the folder is what makes the set atomic).
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
    directory = Path(directory)
    names = frame_names(count, ext)
    indices = range(count)
    if progress:
        from tqdm import tqdm

        indices = tqdm(indices, desc="frames", unit="frame", leave=False, delay=0.5)
    with atomic_dir(directory) as tmp:
        for k in indices:
            writer(k, tmp / names[k])
    pattern = re.compile(rf"frame_\d{{4,}}\.{ext}")
    keep = set(names)
    for old in directory.iterdir():
        if old.name not in keep and pattern.fullmatch(old.name) and old.is_file():
            try:
                old.unlink()
            except OSError as exc:
                raise FileFormatError(f"cannot remove the old frame {old}: {exc.strerror or exc}") from exc
    return [directory / name for name in names]


def write_frames(seq, directory, format="obj", progress=False):
    """Write every frame of a sequence to its own shape file in ``directory``.

    Parameters
    ----------
    seq : Sequence
    directory : path-like
        Created when missing (its parent must exist).
    format : {'obj', 'off', 'svg', 'json', 'npz'}
        File format of every frame (pictures: ``isotween.outputs.write_output``
        with ``format='png'``).
    progress : bool
        Show a progress bar on stderr.

    Returns
    -------
    list of Path
        The files written, in frame order (see `write_frame_files`). Each
        frame carries its own paint (`isotween.paint.sequence_paint`), which
        the SVG format writes (the parts of a cut region,
        ``seq.info['joined']``, as one element).
    """
    from .shapes import SHAPE_FORMATS

    fmt = str(format).lower().lstrip(".")
    if fmt not in DATA_FRAME_FORMATS:
        raise ParameterError(f"unknown frame format '{format}'; use one of {', '.join(DATA_FRAME_FORMATS)} "
                             "(png frames: isotween.write_output)")
    save = SHAPE_FORMATS[f".{fmt}"][1]
    if fmt == "svg" and seq.info.get("joined"):  # the parts of a cut region as one element: no seam
        from .svg import write_svg

        save = functools.partial(write_svg, joined=seq.info["joined"])
    regions, paints = sequence_paint(seq)

    def frame(k):  # frame k with its own (interpolated) paint
        shape = seq[k]
        if paints is not None:
            shape.regions, shape.paint = regions, paints[k]
        return shape

    return write_frame_files(len(seq), directory, fmt, lambda k, path: save(frame(k), path), progress=progress)
