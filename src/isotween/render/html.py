"""A self-contained interactive viewer: one HTML file, no network, no server."""

import base64
import html
import io
import json
import math
import re
from importlib import resources

import numpy as np

from ..io._files import atomic_path
from ._framestats import frame_stats
from ._frames import sequence_frames
from ._view import bbox_of
from .texture import load_texture, texture_uv

__all__ = ["write_html", "page_html"]


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


def page_data(seq, texture=None, title=None, fps=12):
    """Everything the viewer needs, as JSON-ready Python values.

    Parameters
    ----------
    seq : Sequence
    texture : path or array, optional
    title : str, optional
    fps : float
        Playback rate at speed 1x.

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
    if texture is not None:
        tex = load_texture(texture)
        data["uv"] = np.round(texture_uv(shape, shape.uv, shape.vertices), 6).ravel().tolist()
        data["texture"] = _png_data_url(tex)
    return data


def write_html(seq, path, texture=None, title=None, fps=12):
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
    """
    page = page_html(seq, texture=texture, title=title, fps=fps)
    with atomic_path(path) as tmp:
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write(page)


def page_html(seq, texture=None, title=None, fps=12):
    """The viewer page of `write_html` as a string (also shown inline by ``Sequence._repr_html_``).

    Parameters
    ----------
    seq : Sequence
    texture : path or (H, W, 3|4) array, optional
    title : str, optional
    fps : float

    Returns
    -------
    str
        A complete, self-contained HTML document.
    """
    data = page_data(seq, texture=texture, title=title, fps=fps)
    payload = json.dumps(data, separators=(",", ":"), allow_nan=False).replace("</", "<\\/")
    template = resources.files(__package__).joinpath("page.html").read_text(encoding="utf-8")
    values = {"TITLE": html.escape(data["title"]), "DATA": payload}
    return re.sub(r"@@(TITLE|DATA)@@", lambda m: values[m.group(1)], template)
