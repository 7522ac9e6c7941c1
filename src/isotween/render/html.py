"""A self-contained interactive viewer: one HTML file, no network, no server."""

import base64
import html
import io
import re
import zlib
from importlib import resources

import numpy as np

from .._text import document_text
from ..errors import FileFormatError
from ..io import atomic_path
from ..io._json import dumps_finite
from ..paint import joined_groups, merge_groups, paint_groups, sequence_paint
from ._framestats import frame_stats
from ._view import bbox_of, check_colour, sequence_frames, stroke_margin
from .defaults import BACKGROUND, FPS
from .outline import mesh_boundary
from .texture import load_texture, texture_uv

__all__ = ["write_html", "page_html"]

#: JSON text made safe inside an HTML <script> element (the same values, as JSON escapes)
_SCRIPT_SAFE = str.maketrans({"<": "\\u003c", ">": "\\u003e", "&": "\\u0026", "\u2028": "\\u2028",
                              "\u2029": "\\u2029"})


def _png_data_url(tex, max_side=1024):
    """Texture (H, W, 4) float as a base64 PNG data URL (downscaled to ``max_side``)."""
    from PIL import Image

    img = Image.fromarray(np.round(tex * 255).astype(np.uint8), "RGBA")
    if max(img.size) > max_side:
        img.thumbnail((max_side, max_side), Image.Resampling.LANCZOS)
    buf = io.BytesIO()
    img.save(buf, format="PNG", optimize=True)
    return "data:image/png;base64," + base64.b64encode(buf.getvalue()).decode("ascii")


def _css(colour, opacity):
    if colour is None:
        return None
    r, g, b, a = colour
    return f"rgba({round(255 * r)},{round(255 * g)},{round(255 * b)},{a * opacity:.4g})"


def paint_data(seq):
    """The sequence's paint for the page: one entry per drawn group, values per frame.

    Returns
    -------
    list of dict or None
        ``paths`` ([indices, closed] of each path of the group), ``fill`` and
        ``stroke`` (F,) CSS colours or None, ``width`` (F,) stroke widths in
        shape units; None without paint.
    """
    regions, paints = sequence_paint(seq)
    if paints is None:
        return None
    shape = seq.shape
    first = shape.with_vertices(shape.vertices)
    first.regions, first.paint = regions, paints[0]
    groups = [group for group, _ in paint_groups(first)]
    # the parts of a cut region drawn as one group (`isotween.paint.joined_groups`)
    groups, _ = merge_groups(groups, joined_groups([g[0] for g in groups], regions or [], paints,
                                                   seq.info.get("joined") or []))
    out = []
    for group in groups:
        track = [frame[group[0]] for frame in paints]
        out.append({
            "paths": [[shape.paths[i][0].tolist(), bool(shape.paths[i][1])] for i in group],
            "fill": [_css(p.fill, p.opacity) for p in track],
            "stroke": [_css(p.stroke, p.opacity) for p in track],
            "width": [round(p.stroke_width, 6) for p in track],
        })
    return out


def _packed(array):
    """Little-endian bytes of an array, zlib-compressed, base64 text (the page inflates them)."""
    raw = np.ascontiguousarray(array).astype(array.dtype.newbyteorder("<"), copy=False).tobytes()
    return base64.b64encode(zlib.compress(raw, 6)).decode("ascii")


def encode_frames(frames):
    """Frames as quantised 16-bit integers, differenced over time (compact and exact to the step).

    Parameters
    ----------
    frames : (F, n, 2) float array

    Returns
    -------
    dict
        ``origin`` (2,), ``step`` (float, data units per integer step: the
        bounding box's longer side / 65000), ``data``: `_packed` int16 array
        (F, n, 2) holding frame 0 and then each frame minus the previous one
        (wrapping arithmetic: a running sum modulo 2^16 restores the levels).
    """
    lo = frames.reshape(-1, 2).min(axis=0)
    side = float(np.ptp(frames.reshape(-1, 2), axis=0).max()) or 1.0
    step = side / 65000.0
    levels = np.round((frames - lo) / step).astype(np.int64) - 32500  # in [-32500, 32500]
    delta = np.diff(levels, axis=0, prepend=np.zeros((1,) + levels.shape[1:], np.int64))
    return {"origin": lo.tolist(), "step": step, "data": _packed(delta.astype(np.int16)), "offset": -32500}


def decode_frames(encoded, shape):
    """Inverse of `encode_frames`: (F, n, 2) float array (within half a step of the input)."""
    raw = zlib.decompress(base64.b64decode(encoded["data"]))
    delta = np.frombuffer(raw, dtype="<i2").reshape(shape).astype(np.int64)
    levels = (np.cumsum(delta, axis=0) + 32768) % 65536 - 32768  # the encoder's int16 wrap undone
    return np.asarray(encoded["origin"]) + (levels - encoded["offset"]) * encoded["step"]


def _indices(array):
    """Index array packed as uint16 (below 65536 vertices) or uint32."""
    array = np.asarray(array, dtype=np.int64).ravel()
    kind = "u2" if array.size == 0 or array.max() < 65536 else "u4"
    return {"type": kind, "data": _packed(array.astype(kind))}


def page_data(seq, texture=None, title=None, fps=FPS, bounce=False, background=BACKGROUND, downloads=None):
    """Everything the viewer needs, as JSON-ready Python values.

    Frames and connectivity are binary (`encode_frames`, `_indices`):
    zlib-compressed, base64, inflated by the browser's DecompressionStream.

    Parameters
    ----------
    seq : Sequence
    texture : path or array, optional
    title : str, optional
    fps : float
        Playback rate at speed 1x.
    bounce : bool
        Whether the bounce box starts ticked.
    background : matplotlib colour
        Colour behind the shape.
    downloads : dict, optional
        ``{'lottie': text, 'svg': text}`` files offered by the page's
        download buttons (compressed into the page).

    Returns
    -------
    dict
    """
    frames = sequence_frames(seq)
    shape = seq.shape
    stats = frame_stats(seq)
    flipped = stats["flipped"] if shape.n_faces else np.zeros((len(frames), 0), bool)
    info = getattr(seq, "info", None) or {}
    keyframes = sorted({0, len(frames) - 1, *[int(k) for k in info.get("keyframe_indices") or []]})
    data = {
        "title": document_text(title) if title else "isotween sequence",
        "method": str(getattr(seq, "method", "")),
        "iterations": int(getattr(seq, "iterations", 0)),
        "converged": bool(getattr(seq, "converged", True)),
        "energy": [float(e) for e in np.asarray(getattr(seq, "energy", []), dtype=np.float64).ravel()],
        "fps": float(fps),
        "bounce": bool(bounce),
        "background": _css(check_colour(background), 1.0),
        "nVertices": int(shape.n_vertices),
        "nFrames": len(frames),
        "frames": encode_frames(frames),
        "keyframes": keyframes,
        "times": np.round(np.asarray(seq.times, dtype=np.float64), 6).tolist(),
        "bbox": [float(x) for x in bbox_of(frames, stroke_margin(sequence_paint(seq)[1]))],
        "yDown": bool(getattr(shape, "y_down", False)),
        "edges": _indices(shape.edges),
        "faces": _indices(shape.faces if shape.n_faces else np.zeros((0, 3), np.int64)),
        "rings": [idx.tolist() for idx, closed in (shape.paths or []) if closed],
        # a mesh's outline: the filled view fills it instead of every triangle (far faster)
        "boundary": [loop.tolist() for loop in mesh_boundary(shape.faces)] if shape.n_faces else [],
        "stats": {
            "edge": np.round(stats["edge_length_deviation"], 7).tolist(),
            "area": np.round(stats["area_deviation"], 7).tolist(),
            "flipped": stats["flipped_faces"].tolist(),
        },
        "flippedFaces": [np.flatnonzero(row).tolist() for row in flipped],
        "uv": [],
        "texture": None,
        "downloads": {k: base64.b64encode(zlib.compress(v.encode("utf-8"), 9)).decode("ascii")
                      for k, v in (downloads or {}).items()},
    }
    data["paint"] = paint_data(seq)
    if texture is not None:
        tex = load_texture(texture)
        data["uv"] = np.round(texture_uv(shape, shape.uv, shape.vertices), 6).ravel().tolist()
        data["texture"] = _png_data_url(tex)
    return data


#: largest animation (SVG or Lottie text, bytes) the page embeds for its download buttons
EMBED_LIMIT = 4_000_000


def _embedded_animations(seq, fps, bounce, title, background):
    """The animated SVG and the Lottie of ``seq`` as text, each when small enough to embed."""
    from .lottie import lottie_data
    from .svg_animation import svg_animation_text

    out = {}
    # a cheap size estimate first: both hold every vertex of every frame as text, ~12 bytes a number
    if seq.frames.size * 12 * (1 + (seq.shape.n_faces > 0)) > EMBED_LIMIT:
        return out
    try:
        out["lottie"] = dumps_finite(lottie_data(seq, fps=fps, bounce=bounce, title=title, background=None),
                                     "the page's Lottie download", separators=(",", ":"))
    except FileFormatError:  # a width or coordinate beyond what Lottie's numbers hold: no Lottie download
        pass
    out["svg"] = svg_animation_text(seq, fps=fps, bounce=bounce, title=title)
    return {k: v for k, v in out.items() if len(v) <= EMBED_LIMIT}


def write_html(seq, path, texture=None, title=None, fps=FPS, bounce=False, background=BACKGROUND, downloads=True):
    """Write an interactive viewer of a sequence as one self-contained HTML file.

    The page embeds all frames (16-bit, 1/65000 of the shape's size, compressed),
    the per-frame distortion numbers and, optionally, the texture as a base64 PNG.
    It draws on a ``<canvas>`` with a frame slider (keyframes marked),
    play/pause, speed, bounce, onion skin (ghosts of the first, last and key
    frames), zoom (wheel) and pan (drag), a wireframe / filled / colours /
    texture switch, and download buttons (the frame as PNG and SVG, the
    animation as Lottie and animated SVG). It needs no network and no server,
    and exposes ``window.isotween = {ready, setFrame(k), frame(), nFrames}``.

    Parameters
    ----------
    seq : Sequence
    path : str or os.PathLike
    texture : path or (H, W, 3|4) array, optional
        Image warped through the triangles (meshes only).
    title : str, optional
    fps : float
        Playback rate at speed 1x.
    bounce : bool
        Whether the page starts in bounce mode.
    background : matplotlib colour
    downloads : bool
        Embed the animated SVG and Lottie for the download buttons (each
        only up to `EMBED_LIMIT` bytes; larger ones: ``isotween render``).
    """
    page = page_html(seq, texture=texture, title=title, fps=fps, bounce=bounce, background=background,
                     downloads=downloads, name=path)
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(page)


def page_html(seq, texture=None, title=None, fps=FPS, bounce=False, background=BACKGROUND, downloads=True, name=None):
    """The viewer page of `write_html` as a string (also shown inline by ``Sequence._repr_html_``).

    Parameters are those of `write_html` but ``path``; ``name`` is the file
    that errors name (a value JSON cannot hold: `FileFormatError`).

    Returns
    -------
    str
        A complete, self-contained HTML document.
    """
    embedded = _embedded_animations(seq, fps, bounce, title, background) if downloads else {}
    data = page_data(seq, texture=texture, title=title, fps=fps, bounce=bounce, background=background,
                     downloads=embedded)
    # inside <script>, '<!--', '<script' and '</script' change how the page is parsed: no '<' is left raw
    payload = dumps_finite(data, name or "the viewer page", separators=(",", ":")).translate(_SCRIPT_SAFE)
    template = resources.files(__package__).joinpath("page.html").read_text(encoding="utf-8")
    values = {"TITLE": html.escape(data["title"]), "DATA": payload}
    return re.sub(r"@@(TITLE|DATA)@@", lambda m: values[m.group(1)], template)
