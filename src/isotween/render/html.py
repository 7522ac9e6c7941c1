"""A self-contained interactive viewer: one HTML file, no network, no server."""

import base64
import html
import io
import json
import math
import re
from importlib import resources

import numpy as np

from ..io import atomic_path
from ..paint import paint_groups, sequence_paint
from ._framestats import frame_stats
from ._frames import sequence_frames
from ._view import bbox_of
from .defaults import FPS
from .frame import check_colour
from .texture import load_texture, texture_uv

__all__ = ["write_html"]


def _decimals(frames):
    """Decimal places that keep about 1e-5 of the shape's size."""
    side = float(np.max(np.ptp(frames.reshape(-1, 2), axis=0))) or 1.0
    return int(np.clip(5 - math.floor(math.log10(side)), 0, 15))


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
    out = []
    for group, _ in paint_groups(first):
        track = [frame[group[0]] for frame in paints]
        out.append({
            "paths": [[shape.paths[i][0].tolist(), bool(shape.paths[i][1])] for i in group],
            "fill": [_css(p.fill, p.opacity) for p in track],
            "stroke": [_css(p.stroke, p.opacity) for p in track],
            "width": [round(p.stroke_width, 6) for p in track],
        })
    return out


def page_data(seq, texture=None, title=None, fps=FPS, bounce=False, background="white"):
    """Everything the viewer needs, as JSON-ready Python values.

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

    Returns
    -------
    dict
    """
    frames = sequence_frames(seq)
    shape = seq.shape
    stats = frame_stats(seq)
    digits = _decimals(frames)
    flipped = stats["flipped"] if shape.n_faces else np.zeros((len(frames), 0), bool)
    data = {
        "title": title or "isotween sequence",
        "method": str(getattr(seq, "method", "")),
        "iterations": int(getattr(seq, "iterations", 0)),
        "converged": bool(getattr(seq, "converged", True)),
        "energy": [float(e) for e in np.asarray(getattr(seq, "energy", []), dtype=np.float64).ravel()],
        "fps": float(fps),
        "bounce": bool(bounce),
        "background": _css(check_colour(background), 1.0),
        "nVertices": int(shape.n_vertices),
        "frames": np.round(frames.reshape(len(frames), -1), digits).tolist(),
        "times": np.round(np.asarray(seq.times, dtype=np.float64), 6).tolist(),
        "bbox": [float(x) for x in bbox_of(frames)],
        "yDown": bool(getattr(shape, "y_down", False)),
        "edges": shape.edges.ravel().tolist(),
        "faces": [] if not shape.n_faces else shape.faces.ravel().tolist(),
        "rings": [idx.tolist() for idx, closed in (shape.paths or []) if closed],
        "stats": {
            "edge": np.round(stats["edge_length_deviation"], 7).tolist(),
            "area": np.round(stats["area_deviation"], 7).tolist(),
            "flipped": stats["flipped_faces"].tolist(),
        },
        "flippedFaces": [np.flatnonzero(row).tolist() for row in flipped],
        "uv": [],
        "texture": None,
    }
    data["paint"] = paint_data(seq)
    if texture is not None:
        tex = load_texture(texture)
        data["uv"] = np.round(texture_uv(shape, shape.uv, shape.vertices), 6).ravel().tolist()
        data["texture"] = _png_data_url(tex)
    return data


def write_html(seq, path, texture=None, title=None, fps=FPS, bounce=False, background="white"):
    """Write an interactive viewer of a sequence as one self-contained HTML file.

    The page embeds all frames (rounded to about 1e-5 of the shape's size), the
    per-frame distortion numbers and, optionally, the texture as a base64 PNG.
    It draws on a ``<canvas>`` with a frame slider, play/pause, speed, bounce,
    and a wireframe / filled / texture switch; the texture is mapped with one
    affine transform and clip per triangle. It needs no network and no server,
    and exposes ``window.isotween = {setFrame(k), frame(), nFrames}``.

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
    """
    data = page_data(seq, texture=texture, title=title, fps=fps, bounce=bounce, background=background)
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    template = resources.files(__package__).joinpath("page.html").read_text(encoding="utf-8")
    values = {"TITLE": html.escape(data["title"]), "DATA": payload}
    page = re.sub(r"@@(TITLE|DATA)@@", lambda m: values[m.group(1)], template)
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(page)
