"""Writing what a user asked for: the one layer above `isotween.io` (data) and `isotween.render` (pictures).

`output_kind` checks an output path once, before any work; `write_output`
turns a sequence into that file (or folder) with the rendering controls of
:data:`RENDER_OPTIONS`. Every file is written once, atomically, by the writer
that makes it (`isotween.io.atomic_path`).
"""

from pathlib import Path

import numpy as np

from .errors import FileFormatError, ParameterError, require
from .io import SHAPE_FORMATS, save_sequence, write_frames
from .io._files import check_path_text
from .io.frames import DATA_FRAME_FORMATS, write_frame_files
from .render.defaults import BACKGROUND, DURATION, FPS, HOLD, SIZE
from .render.outline import mesh_boundary

__all__ = ["write_output", "output_kind", "with_paint", "timed", "OUTPUT_KINDS", "FRAME_FORMATS", "FORMATS",
           "RENDER_OPTIONS", "ANIMATIONS", "TIMED"]

#: file name ending -> kind of output (longest ending first when names overlap)
OUTPUT_KINDS = {
    ".lottie.json": "lottie",
    ".waapi.json": "waapi",
    ".npz": "sequence",
    ".json": "sequence",
    ".gif": "gif",
    ".mp4": "mp4",
    ".webp": "webp",
    ".apng": "apng",
    ".html": "html",
    ".svg": "svg",
    ".css": "css",
    ".png": "strip",
}
#: kinds that play the frames in time (take fps, hold, bounce, loop)
ANIMATIONS = ("gif", "mp4", "webp", "apng", "html", "svg", "lottie", "css", "waapi")
#: animations that last ``duration`` seconds of motion with a ``hold`` at both ends (the page plays the frames)
TIMED = ("gif", "mp4", "webp", "apng", "svg", "lottie", "css", "waapi")
#: ``format`` values: one file per frame in a folder, or ``lottie`` for one Lottie file
FRAME_FORMATS = DATA_FRAME_FORMATS + ("png",)
FORMATS = FRAME_FORMATS + ("lottie",)
#: rendering controls of `write_output` and their defaults (each writer's own where it differs:
#: a strip's cells are 240 px, PNG frames 600 px, an SVG 480 px wide, a page has no size)
RENDER_OPTIONS = {
    "fps": FPS,
    "duration": DURATION,
    "size": SIZE,
    "hold": HOLD,
    "bounce": False,
    "loop": True,
    "title": None,
    "background": BACKGROUND,
}
# which controls each kind takes (the others do not apply to it)
_TAKES = {
    "gif": ("fps", "size", "hold", "bounce", "loop", "background"),
    "webp": ("fps", "size", "hold", "bounce", "loop", "background"),
    "apng": ("fps", "size", "hold", "bounce", "loop", "background"),
    "mp4": ("fps", "size", "hold", "bounce", "background"),
    "svg": ("fps", "size", "hold", "bounce", "loop", "title", "background"),
    "lottie": ("fps", "size", "hold", "bounce", "title", "background"),
    "css": ("fps", "size", "hold", "bounce", "loop", "title", "background"),
    "waapi": ("fps", "size", "hold", "bounce", "loop", "title", "background"),
    "html": ("fps", "bounce", "title", "background"),
    "strip": ("size", "background"),
    "frames": ("size", "background"),
    "sequence": (),
}


def _ending(out):
    name = out.name.lower()
    return next((e for e in OUTPUT_KINDS if name.endswith(e) and len(name) > len(e)), out.suffix.lower())


def output_kind(out, format=None):
    """What `write_output` would write to ``out``, checked before any work is done.

    Parameters
    ----------
    out : path-like
    format : str, optional
        One of :data:`FRAME_FORMATS` (a folder of frame files) or 'lottie'.

    Returns
    -------
    {'sequence', 'gif', 'mp4', 'webp', 'apng', 'html', 'svg', 'lottie', 'css', 'waapi', 'strip', 'frames'}

    Raises
    ------
    FileFormatError
        Unknown ending, a single-shape ending, a folder where a file is
        needed (or the other way round), or a parent folder that does not exist.
    ParameterError
        Unknown ``format``, or a frame ``format`` with a file name.
    """
    out = check_path_text(out)
    if str(out) == "-":
        raise FileFormatError("-: writing to standard output is not supported; name a file or folder")
    ext = _ending(out)
    if format is not None:
        fmt = str(format).lower()
        if fmt not in FORMATS:
            raise ParameterError(f"unknown format '{format}'; use one of {', '.join(FORMATS)}")
        if fmt == "lottie":
            if ext not in (".json", ".lottie.json"):
                raise ParameterError(f"--format lottie writes one .json file, but {out} names a {ext or 'folder'}")
            kind = "lottie"
        elif ext in OUTPUT_KINDS and not out.is_dir():
            raise ParameterError(
                f"--format {format} writes one file per frame into a folder, but {out} names a {ext} file")
        else:
            kind = "frames"
    elif out.is_dir() or not ext:
        kind = "frames"
    elif ext in OUTPUT_KINDS:
        kind = OUTPUT_KINDS[ext]
    elif ext in SHAPE_FORMATS:
        raise FileFormatError(
            f"{out}: a {ext} file holds one shape, not a sequence; write a folder of frames "
            f"(-o FOLDER --format {ext[1:]}) or a .npz/.json sequence"
        )
    else:
        raise FileFormatError(f"{out}: unknown output kind '{ext}'; use one of {', '.join(OUTPUT_KINDS)} "
                              "or a folder with --format")
    parent = out.parent
    if not parent.is_dir():
        raise FileFormatError(
            f"cannot write {out}: {parent} {'is not a folder' if parent.exists() else 'does not exist'}")
    if kind != "frames" and out.is_dir():
        raise FileFormatError(f"cannot write {out}: is a folder")
    if kind == "frames" and out.exists() and not out.is_dir():
        raise FileFormatError(f"cannot write frames to {out}: it is a file, not a folder")
    return kind


def _check_options(options):
    """The given controls (None: the writer's default), checked."""
    unknown = sorted(set(options) - set(RENDER_OPTIONS))
    if unknown:
        raise ParameterError(f"unknown rendering option '{unknown[0]}'; use {', '.join(RENDER_OPTIONS)}")
    return {k: v for k, v in options.items() if v is not None}


def timed(seq, duration, fps=FPS):
    """The sequence resampled so that its motion lasts ``duration`` seconds at ``fps`` ticks per second.

    Frame ``k`` of ``F`` keeps its place in the clip (fraction ``k / (F - 1)``
    of the duration), so an eased sequence (uneven ``times``) stays eased;
    in between, the shapes come from `Sequence.at`.

    Parameters
    ----------
    seq : Sequence
    duration : float or None
        Seconds from the first frame to the last; None or 0: the frames as
        they are, one per tick.
    fps : float

    Returns
    -------
    Sequence
        ``round(duration * fps) + 1`` frames (``seq`` itself when that is
        its length, when it has fewer than two frames, or without a
        duration).

    Examples
    --------
    >>> import isotween
    >>> bar = isotween.Shape.from_polyline([[0, 0], [1, 0]])
    >>> seq = isotween.interpolate(bar, bar.rotate(1.0), frames=5)
    >>> len(timed(seq, 1.0, fps=24)), len(timed(seq, None))
    (25, 5)
    """
    if duration is None or duration == 0 or len(seq) < 2:
        return seq
    if not np.isfinite(duration) or duration < 0:
        raise ParameterError(f"duration must be a number of seconds >= 0, got {duration!r}")
    n = max(int(round(duration * fps)) + 1, 2)
    if n == len(seq):
        return seq
    place = np.linspace(0.0, len(seq) - 1.0, n)
    return seq.resample(times=np.interp(place, np.arange(len(seq)), seq.times))


def write_output(seq, out, format=None, texture=None, quiet=False, kind=None, **options):
    """Write a sequence as the kind of output ``out`` names.

    ``.npz`` / ``.json``: sequence file (`save_sequence`); ``.gif``, ``.webp``,
    ``.apng``, ``.mp4``, ``.html``, ``.svg`` (SMIL), ``.lottie.json``,
    ``.css`` (``@keyframes``, with an ``.html`` page beside it),
    ``.waapi.json`` (Web Animations): animation (`isotween.render`);
    ``.png``: a strip of frames; a folder
    (existing, without extension, or with ``format``): one file per frame
    (``format`` defaulting to ``obj``).

    Parameters
    ----------
    seq : Sequence
    out : path-like
    format : str, optional
        See `output_kind`.
    texture : path-like, optional
        Image mapped through the shape's uv in rendered outputs.
    quiet : bool
        No progress bar.
    kind : str, optional
        The result of an earlier `output_kind` call for the same arguments
        (skips checking the path again).
    **options
        Rendering controls, see :data:`RENDER_OPTIONS` (``size`` is the
        longest side or ``(width, height)``; for a strip, the cell size).
        Controls that do not apply to a kind are ignored. The kinds of
        :data:`TIMED` play ``duration`` seconds of motion (`timed`; 0: one
        frame per tick) with ``hold`` seconds on the first and last frame.

    Returns
    -------
    list of Path
        Files written.
    """
    from .io.sequence_file import check_sequence
    from .sequence import Sequence

    kind = kind or output_kind(out, format)
    out = Path(out)
    opts = _check_options(options)
    if not isinstance(seq, Sequence):
        raise ParameterError(f"write_output expects an isotween.Sequence, got {type(seq).__name__}")
    if kind != "sequence":  # (save_sequence checks it itself)
        check_sequence(seq, f"cannot write {out}")
    if texture is not None and not Path(texture).is_file():
        raise FileFormatError(f"{texture}: no such texture image")
    if kind == "sequence":
        save_sequence(seq, out)
        return [out]
    fmt = str(format or "obj").lower()
    if kind == "frames" and fmt in DATA_FRAME_FORMATS:
        return write_frames(seq, out, format=fmt, progress=not quiet)
    render = require("isotween.render", "cli")
    take = {k: opts[k] for k in _TAKES[kind] if k in opts}
    if kind in TIMED:
        seq = timed(seq, opts.get("duration", DURATION), take.get("fps", FPS))
        take.setdefault("hold", HOLD)
    if kind == "lottie":  # Lottie files are transparent unless a background layer is written
        take.setdefault("background", BACKGROUND)
    if kind == "frames":  # png: one view (the whole sequence's) for every frame, so that the images line up
        from .render._frames import SequenceRenderer
        from .render.frame import save_png

        renderer = SequenceRenderer(seq, take.get("size", 600), texture=texture,
                                    background=take.get("background", BACKGROUND), kind="frames", kept=1)
        return write_frame_files(len(seq), out, "png", lambda k, path: save_png(renderer.image(k), path),
                                 progress=not quiet)
    writers = {  # names, not functions: only the writer used is imported (and, for rasters, matplotlib)
        "gif": "write_gif", "mp4": "write_mp4", "webp": "write_webp", "apng": "write_apng", "html": "write_html",
        "svg": "write_svg_animation", "lottie": "write_lottie", "strip": "write_strip", "css": "write_css",
        "waapi": "write_waapi",
    }
    if kind == "strip" and "size" in take:
        take["cell"] = take.pop("size")
    if kind in ("gif", "mp4", "webp", "apng"):
        take["progress"] = not quiet
    if kind in ("gif", "mp4", "webp", "apng", "html", "strip"):
        take["texture"] = texture
    written = getattr(render, writers[kind])(seq, out, **take)
    return list(written) if isinstance(written, list) else [out]


def with_paint(seq, fill=None, stroke=None, stroke_width=None):
    """A copy of ``seq`` painted in given colours, blended in Oklab from start to end.

    Parameters
    ----------
    seq : Sequence
    fill, stroke : colour or (2,) tuple of colours, optional
        A matplotlib colour ('red', '#ff0000', RGBA tuple), or a pair
        ``(at_start, at_end)``. Fills apply to closed paths (a triangle mesh
        is filled inside its boundary loops), strokes to every path.
    stroke_width : float or (2,) float, optional
        In shape units (default: 0.4 % of the bounding-box diagonal).

    Returns
    -------
    Sequence
        Same frames; ``info['paint']`` holds the two key paints (see
        `isotween.paint.paint_keys`). Without any argument, ``seq`` itself.
    """
    from dataclasses import replace as dc_replace

    from .paint import Paint, paint_keys

    if fill is None and stroke is None and stroke_width is None:
        return seq
    shape = seq.shape
    paths = shape.paths
    if not paths and shape.n_faces:
        paths = [(loop, True) for loop in mesh_boundary(shape.faces)]
    if not paths:
        raise ParameterError("--fill and --stroke need outlines or a triangle mesh; this shape is an edge soup")

    def pair(value, what):
        if value is None:
            return None, None
        two = isinstance(value, (list, tuple)) and len(value) == 2 and not np.isscalar(value[0]) or \
            isinstance(value, (list, tuple)) and len(value) == 2 and all(isinstance(v, str) for v in value)
        return tuple(_colour(v, what) for v in (value if two else (value, value)))

    fills, strokes = pair(fill, "fill"), pair(stroke, "stroke")
    widths = (stroke_width, stroke_width) if stroke_width is None or np.isscalar(stroke_width) else tuple(stroke_width)
    widths = tuple(0.004 * shape.bbox_diagonal() if w is None else float(w) for w in widths)
    old = (shape.paint or [None])[0]
    keys = []
    for end in (0, 1):
        base = old if old is not None and len(shape.paint or []) == len(paths) else Paint(fill=None)
        paint = []
        for _, closed in paths:
            f = fills[end] if fill is not None else base.fill
            s = strokes[end] if stroke is not None else base.stroke
            paint.append(dc_replace(base, fill=f if closed else None, stroke=s,
                                    stroke_width=widths[end] if s is not None else base.stroke_width))
        keys.append(paint)
    painted = shape.with_vertices(shape.vertices)
    painted.paths = paths
    painted.regions = shape.regions if paths is shape.paths else None
    ends = [painted.with_vertices(painted.vertices), painted.with_vertices(painted.vertices)]
    for s, paint in zip(ends, keys, strict=False):
        s.paint = paint
    out = dc_replace(seq, shape=painted, info={**seq.info, **paint_keys(ends, [0.0, 1.0])})
    return out


def _colour(value, what):
    from matplotlib.colors import to_rgba

    try:
        return tuple(float(c) for c in to_rgba(value))
    except (ValueError, TypeError):
        raise ParameterError(f"{what}: {value!r} is not a colour (use a name like 'red' or '#rrggbb')") from None
