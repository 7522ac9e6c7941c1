"""Texture images, texture coordinates and a vectorised textured-triangle rasteriser.

Convention: ``uv`` in [0, 1]^2 with u to the right and v up, so (0, 0) is the
bottom-left corner of the image and (1, 1) its top-right corner.
"""

import os

import numpy as np

from ..errors import FileFormatError, MethodError, ParameterError
from ..shape import _as_uv

__all__ = ["load_texture", "texture_uv", "rasterize_triangles", "render_texture"]


#: peak bytes per pixel of loading a texture: the decoded image, its RGBA copy, the array and
#: two float32 RGBA arrays (measured about 37 with Pillow 10-11)
TEXTURE_BYTES_PER_PIXEL = 40


def load_texture(texture):
    """Texture as a float RGBA image.

    Parameters
    ----------
    texture : str, os.PathLike or array_like
        Image file (anything Pillow reads), or an ``(H, W)``, ``(H, W, 3)`` or
        ``(H, W, 4)`` array: uint8 in [0, 255] or float in [0, 1].

    Returns
    -------
    (H, W, 4) float32 array
        Straight (not premultiplied) RGBA in [0, 1].
    """
    if isinstance(texture, (str, os.PathLike)):
        from PIL import Image, UnidentifiedImageError

        from ..io._files import check_readable
        from ..resources import check_memory

        check_readable(texture)
        try:
            with Image.open(texture) as im:
                width, height = im.size
                check_memory(TEXTURE_BYTES_PER_PIXEL * float(width) * height,
                             f"the texture {os.fspath(texture)} ({width} x {height} pixels)",
                             advice="use a smaller image")
                arr = np.asarray(im.convert("RGBA"))
        except FileNotFoundError as exc:
            raise FileFormatError(f"texture file {os.fspath(texture)} does not exist") from exc
        except (UnidentifiedImageError, OSError, Image.DecompressionBombError) as exc:
            raise FileFormatError(f"cannot read texture image {os.fspath(texture)}: {exc}") from exc
        return arr.astype(np.float32) / 255.0
    arr = np.asarray(texture)
    if arr.ndim == 2:
        arr = np.repeat(arr[..., None], 3, axis=2)
    if arr.ndim != 3 or arr.shape[2] not in (3, 4) or min(arr.shape[:2]) < 1:
        raise ParameterError(f"texture array must have shape (H, W), (H, W, 3) or (H, W, 4), got {arr.shape}")
    if np.issubdtype(arr.dtype, np.integer):
        if arr.min() < 0 or arr.max() > 255:
            raise ParameterError("integer texture values must lie in [0, 255]")
        arr = arr.astype(np.float32) / 255.0
    else:
        arr = arr.astype(np.float32)
        if not np.all(np.isfinite(arr)) or arr.min() < 0 or arr.max() > 1:
            raise ParameterError("float texture values must be finite and lie in [0, 1]")
    if arr.shape[2] == 3:
        arr = np.concatenate([arr, np.ones(arr.shape[:2] + (1,), np.float32)], axis=2)
    return arr


def texture_uv(shape, uv=None, source=None):
    """Texture coordinates for every vertex.

    Parameters
    ----------
    shape : Shape
    uv : (n, 2) array_like, optional
        Explicit coordinates; otherwise ``shape.uv``; otherwise ``source``
        normalised into [0, 1]^2 (aspect ratio kept, centred, v pointing the
        way the shape is drawn up: against y when ``shape.y_down``).
    source : (n, 2) array_like, optional
        Geometry the default coordinates come from (the source shape of a
        sequence); ``shape.vertices`` when omitted.

    Returns
    -------
    (n, 2) float64 array
    """
    if shape.faces is None or not len(shape.faces):
        raise MethodError("a texture needs a triangle mesh; this shape has no faces")
    n = shape.n_vertices
    if uv is None:
        uv = shape.uv
    if uv is not None:
        return _as_uv(uv, n)  # the Shape's own check
    p = shape.vertices if source is None else np.asarray(source, dtype=np.float64)
    lo, hi = p.min(axis=0), p.max(axis=0)
    side = float(np.max(hi - lo)) or 1.0
    uv = (p - 0.5 * (lo + hi)) / side + 0.5
    if shape.y_down:  # the image's top row goes where the shape is drawn on top
        uv[:, 1] = 1.0 - uv[:, 1]
    return uv


def rasterize_triangles(points, faces, width, height):
    """Pixels whose centres lie in each triangle, with barycentric coordinates.

    Where triangles overlap (fold-overs) a pixel keeps one of them.

    Parameters
    ----------
    points : (n, 2) float array
        Vertex positions in pixel units: x to the right, y down; pixel (i, j)
        has its centre at (j + 0.5, i + 0.5).
    faces : (F, 3) int array
    width, height : int

    Returns
    -------
    pixel : (k,) int64 array
        Flat index ``i * width + j`` of every covered pixel (each once).
    face : (k,) int64 array
        Triangle covering it.
    bary : (k, 3) float64 array
        Barycentric coordinates of the pixel centre in that triangle.
    """
    tri = np.asarray(points, dtype=np.float64)[faces]  # (F, 3, 2)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    det = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    # barycentrics are affine in the pixel centre: l_i = kx_i * x + ky_i * y + k0_i
    kx1, ky1 = (c[:, 1] - a[:, 1]) * inv, (a[:, 0] - c[:, 0]) * inv
    kx2, ky2 = (a[:, 1] - b[:, 1]) * inv, (b[:, 0] - a[:, 0]) * inv
    k01 = -(kx1 * a[:, 0] + ky1 * a[:, 1])
    k02 = -(kx2 * a[:, 0] + ky2 * a[:, 1])
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    j0 = np.clip(np.ceil(lo[:, 0] - 0.5), 0, width).astype(np.int64)
    j1 = np.clip(np.floor(hi[:, 0] - 0.5), -1, width - 1).astype(np.int64)
    i0 = np.clip(np.ceil(lo[:, 1] - 0.5), 0, height).astype(np.int64)
    i1 = np.clip(np.floor(hi[:, 1] - 0.5), -1, height - 1).astype(np.int64)
    nx, ny = np.maximum(j1 - j0 + 1, 0), np.maximum(i1 - i0 + 1, 0)
    count = np.where(ok, nx * ny, 0)
    total = int(count.sum())
    if total == 0:
        empty = np.zeros(0, np.int64)
        return empty, empty, np.zeros((0, 3))
    # one candidate per (triangle, pixel of its bounding box), laid out flat
    f = np.repeat(np.arange(len(faces)), count)
    local = np.arange(total) - np.repeat(np.cumsum(count) - count, count)
    row, col = np.divmod(local, nx[f])
    row += i0[f]
    col += j0[f]
    x, y = (col + 0.5).astype(np.float32), (row + 0.5).astype(np.float32)
    kx1, ky1, k01, kx2, ky2, k02 = (k.astype(np.float32) for k in (kx1, ky1, k01, kx2, ky2, k02))
    l1 = kx1[f] * x + ky1[f] * y + k01[f]
    l2 = kx2[f] * x + ky2[f] * y + k02[f]
    l0 = 1.0 - l1 - l2
    eps = -1e-5
    inside = np.flatnonzero((l0 >= eps) & (l1 >= eps) & (l2 >= eps))
    pixel = row[inside] * width + col[inside]
    # one winner per pixel (pixels on shared edges are claimed by both neighbours)
    owner = np.full(width * height, -1, np.int64)
    owner[pixel] = np.arange(len(inside))
    keep = inside[owner[owner >= 0]]
    pixel = row[keep] * width + col[keep]
    return pixel, f[keep], np.column_stack([l0[keep], l1[keep], l2[keep]])


def _sample_bilinear(tex, uv):
    """Sample ``tex`` (H, W, 4) at ``uv`` (k, 2) with bilinear filtering, clamped."""
    h, w = tex.shape[:2]
    flat = tex.reshape(-1, 4)
    x = np.clip(uv[:, 0].astype(np.float32) * w - 0.5, 0, w - 1)
    y = np.clip((1 - uv[:, 1].astype(np.float32)) * h - 0.5, 0, h - 1)
    x0, y0 = x.astype(np.int64), y.astype(np.int64)  # floor: both are >= 0
    fx, fy = (x - x0)[:, None], (y - y0)[:, None]
    dx = (x0 < w - 1).astype(np.int64)
    dy = np.where(y0 < h - 1, w, 0)
    i = y0 * w + x0
    top = np.take(flat, i, axis=0)
    top += fx * (np.take(flat, i + dx, axis=0) - top)
    bottom = np.take(flat, i + dy, axis=0)
    bottom += fx * (np.take(flat, i + dy + dx, axis=0) - bottom)
    top += fy * (bottom - top)
    return top


def render_texture(vertices, faces, uv, tex, view, width, height, supersample=2):
    """Warp a texture through a triangle mesh onto a pixel grid.

    Every pixel centre inside a triangle gets the texture sampled at the uv
    interpolated with its barycentric coordinates (the inverse mapping).

    Parameters
    ----------
    vertices : (n, 2) float array
        Frame positions in data units.
    faces : (F, 3) int array
    uv : (n, 2) float array
    tex : (Ht, Wt, 4) float array
        From `load_texture`.
    view : (4,) float
        Data limits ``(x0, x1, y0, y1)`` covered by the image.
    width, height : int
        Output size in pixels.
    supersample : int
        Samples per pixel along each axis (anti-aliasing of the mesh border).

    Returns
    -------
    (height, width, 4) float32 array
        Straight RGBA; alpha 0 outside the mesh.
    """
    s = int(supersample)
    x0, x1, y0, y1 = view
    W, H = width * s, height * s
    pts = np.empty((len(vertices), 2))
    pts[:, 0] = (vertices[:, 0] - x0) * (W / (x1 - x0))
    pts[:, 1] = (y1 - vertices[:, 1]) * (H / (y1 - y0))
    pixel, face, bary = rasterize_triangles(pts, faces, W, H)
    out = np.zeros((height * width, 4), np.float32)
    if len(pixel):
        z = (uv[:, 0] + 1j * uv[:, 1])[faces]  # (F, 3) complex uv of the corners
        zuv = z[face, 0] + bary[:, 1] * (z[face, 1] - z[face, 0]) + bary[:, 2] * (z[face, 2] - z[face, 0])
        puv = np.column_stack([zuv.real, zuv.imag])
        rgba = _sample_bilinear(tex, puv)
        rgba[:, :3] *= rgba[:, 3:]  # premultiply so averaging does not bleed background
        row, col = np.divmod(pixel, W)
        coarse = (row // s) * width + col // s
        for ch in range(4):  # box filter of the s x s samples of every output pixel
            out[:, ch] = np.bincount(coarse, weights=rgba[:, ch], minlength=height * width) / (s * s)
    out = out.reshape(height, width, 4)
    alpha = out[..., 3:]
    out[..., :3] = np.where(alpha > 0, out[..., :3] / np.maximum(alpha, 1e-12), 0)
    return np.clip(out, 0, 1)
