"""What every output shares: frame checks, colours, world-to-pixel framing (no plotting library loaded)."""

import math
import re

import numpy as np

from ..errors import ParameterError, ShapeError

__all__ = ["check_frames", "sequence_frames", "check_colour", "bbox_of", "decimals", "image_size", "fit_view",
           "to_pixels"]

PAD = 0.05  # margin around the shape, as a fraction of the bounding box's longer side


def check_frames(frames):
    """Reject frames with non-finite coordinates, naming frame and vertex.

    Parameters
    ----------
    frames : (F, n, 2) or (n, 2) array_like of float
    """
    f = np.asarray(frames, dtype=np.float64)
    bad = ~np.all(np.isfinite(f), axis=-1)
    if bad.any():
        where = np.argwhere(bad)[0]
        if f.ndim == 3:
            raise ShapeError(f"frame {where[0]} vertex {where[1]} has a non-finite coordinate")
        raise ShapeError(f"vertex {where[0]} has a non-finite coordinate")
    return f


def sequence_frames(seq):
    """Validated ``(F, n, 2)`` frames of a Sequence."""
    frames = getattr(seq, "frames", None)
    shape = getattr(seq, "shape", None)
    if frames is None or shape is None:
        raise ParameterError(f"expected an isotween Sequence, got {type(seq).__name__}")
    frames = np.asarray(frames, dtype=np.float64)
    if frames.ndim != 3 or frames.shape[1:] != (shape.n_vertices, 2) or not len(frames):
        raise ShapeError(
            f"sequence frames must have shape (F >= 1, {shape.n_vertices}, 2), got {frames.shape}"
        )
    return check_frames(frames)


def check_colour(colour, what="background"):
    """(4,) RGBA in [0, 1] of a matplotlib colour (name, '#rrggbb', tuple).

    An (r, g, b[, a]) tuple of numbers in [0, 1] and '#rrggbb[aa]' are read
    here; names and other strings by matplotlib (loaded then, not for a
    drawing's own paint).

    Raises
    ------
    ParameterError
        Naming ``what`` and the value that is not a colour.
    """
    if isinstance(colour, str) and re.fullmatch(r"#[0-9a-fA-F]{6}([0-9a-fA-F]{2})?", colour):
        return (*(int(colour[k:k + 2], 16) / 255 for k in range(1, 7, 2)),
                int(colour[7:9], 16) / 255 if len(colour) == 9 else 1.0)
    if isinstance(colour, (tuple, list, np.ndarray)) and len(colour) in (3, 4) and all(
            isinstance(v, (int, float, np.number)) and not isinstance(v, bool) and 0 <= v <= 1 for v in colour):
        return (*(float(v) for v in colour[:3]), float(colour[3]) if len(colour) == 4 else 1.0)
    from matplotlib.colors import to_rgba

    try:
        return to_rgba(colour)
    except (ValueError, TypeError):
        raise ParameterError(f"{what}: {colour!r} is not a colour (use a name like 'red' or '#rrggbb')") from None


def bbox_of(points, margin=0.0):
    """Bounding box ``(x0, y0, x1, y1)`` of points of shape (..., 2), grown by ``margin`` on every side.

    The margin (half a stroke's width) is at most the box's longer side: a
    stroke wider than the drawing leaves it in view, and the box finite.
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    if not len(p):
        raise ShapeError("cannot draw a shape with no vertices")
    lo, hi = p.min(axis=0), p.max(axis=0)
    margin = min(float(margin), float(np.max(hi - lo)))
    return (*(lo - margin), *(hi + margin))


def stroke_margin(paints):
    """Half the widest stroke in ``paints`` (Paint, or nested lists of them, or None): how far ink reaches out."""
    if paints is None:
        return 0.0
    if isinstance(paints, (list, tuple)):
        return max((stroke_margin(p) for p in paints), default=0.0)
    return 0.5 * float(paints.stroke_width) if getattr(paints, "stroke", None) is not None else 0.0


def _as_bbox(bbox):
    b = np.asarray(bbox, dtype=np.float64).ravel()
    if b.shape != (4,) or not np.all(np.isfinite(b)) or b[2] < b[0] or b[3] < b[1]:
        raise ParameterError(f"bbox must be finite (x0, y0, x1, y1) with x0 <= x1, y0 <= y1, got {bbox!r}")
    return b


def _padded(bbox):
    x0, y0, x1, y1 = _as_bbox(bbox)
    side = max(x1 - x0, y1 - y0)
    if side <= 0:
        side = max(abs(x0), abs(y0), 1.0)
    m = PAD * side
    w, h = max(x1 - x0, side * 1e-3), max(y1 - y0, side * 1e-3)
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    return cx, cy, w + 2 * m, h + 2 * m


def image_size(bbox, size, even=False):
    """Pixel size ``(W, H)`` for a bounding box.

    Parameters
    ----------
    bbox : (4,) array_like
        ``(x0, y0, x1, y1)`` of what is drawn.
    size : int or (2,) int
        Longest side in pixels (the other follows the padded box's aspect), or
        exactly ``(W, H)``.
    even : bool
        Round both sides to even numbers (video encoders need it).
    """
    if np.ndim(size) == 0:
        if int(size) != size or size < 8:
            raise ParameterError(f"size must be an integer >= 8 pixels or (width, height), got {size!r}")
        _, _, w, h = _padded(bbox)
        s = int(size)
        wh = (s, max(8, round(s * h / w))) if w >= h else (max(8, round(s * w / h)), s)
    else:
        wh = tuple(int(v) for v in np.ravel(size))
        if len(wh) != 2 or min(wh) < 8 or any(v != s for v, s in zip(wh, np.ravel(size), strict=False)):
            raise ParameterError(f"size must be an integer >= 8 pixels or (width, height), got {size!r}")
    if even:
        wh = tuple(v + (v % 2) for v in wh)
    return wh


def fit_view(bbox, width, height):
    """Data limits ``(x0, x1, y0, y1)`` around ``bbox`` with exactly the pixel aspect.

    The padded box is grown along one axis so that one data unit spans the same
    number of pixels horizontally and vertically.
    """
    cx, cy, w, h = _padded(bbox)
    if w / h < width / height:
        w = h * width / height
    else:
        h = w * height / width
    return cx - w / 2, cx + w / 2, cy - h / 2, cy + h / 2


def decimals(frames):
    """Decimal places that keep about 1e-5 of the shape's size (text outputs: the HTML page, animated SVG).

    Parameters
    ----------
    frames : (..., 2) array of float

    Returns
    -------
    int
        From 0 to 15.
    """
    side = float(np.max(np.ptp(frames.reshape(-1, 2), axis=0))) or 1.0
    return int(np.clip(5 - math.floor(math.log10(side)), 0, 15))
def to_pixels(frames, bbox, width, height, y_down):
    """Map data coordinates to composition pixels (x right, y down).

    Parameters
    ----------
    frames : (..., 2) float array
    bbox : (4,) float
        ``(x0, y0, x1, y1)`` shown, framed by `fit_view`.
    width, height : int
    y_down : bool

    Returns
    -------
    (..., 2) float array
    """
    x0, x1, y0, y1 = fit_view(bbox, width, height)
    out = np.empty_like(frames, dtype=np.float64)
    out[..., 0] = (frames[..., 0] - x0) * (width / (x1 - x0))
    out[..., 1] = ((frames[..., 1] - y0) if y_down else (y1 - frames[..., 1])) * (height / (y1 - y0))
    return out
