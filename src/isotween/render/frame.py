"""Drawing one shape: on a matplotlib axes, or straight to a PNG file."""

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.patches import PathPatch
from matplotlib.path import Path

from ..errors import ParameterError
from ..geometry import ring_area
from ..io import atomic_path
from ..paint import opaque, paint_groups
from ._view import bbox_of, check_colour, check_frames, fit_view, image_size, stroke_margin
from .defaults import BACKGROUND, FILL, FILL_EDGE, WIRE
from .texture import load_texture, render_texture, texture_uv

__all__ = ["draw_frame", "write_frame_png", "FramePainter"]

STYLES = ("auto", "wire", "fill", "texture")


def _closed_rings(shape):
    return [idx for idx, closed in (shape.paths or []) if closed and len(idx) >= 3]


def _faces_path(vertices, faces):
    """One compound path of all triangles, each turned counter-clockwise.

    With equal orientation the non-zero fill rule paints their union, so
    overlapping (folded) triangles stay filled and shared edges show no seams.
    """
    tri = vertices[faces]  # (F, 3, 2)
    d1, d2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    cw = d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0] < 0
    tri[cw] = tri[cw][:, ::-1]
    verts = np.concatenate([tri, tri[:, :1]], axis=1).reshape(-1, 2)
    codes = np.tile([Path.MOVETO, Path.LINETO, Path.LINETO, Path.CLOSEPOLY], len(faces))
    return Path(verts, codes)


def _rings_path(vertices, rings):
    """One compound path of closed rings that fills by the even-odd rule.

    Matplotlib fills with the non-zero rule, so each ring is oriented by its
    nesting depth: counter-clockwise at even depth, clockwise at odd depth.
    """
    loops = [vertices[idx] for idx in rings]
    outlines = [Path(loop) for loop in loops]
    parts, codes = [], []
    for i, loop in enumerate(loops):
        depth = sum(outlines[j].contains_point(loop[0]) for j in range(len(loops)) if j != i)
        area = ring_area(loop)
        if (area > 0) == bool(depth % 2):
            loop = loop[::-1]
        parts.append(np.vstack([loop, loop[:1]]))
        codes.append([Path.MOVETO] + [Path.LINETO] * (len(loop) - 1) + [Path.CLOSEPOLY])
    return Path(np.vstack(parts), np.concatenate(codes))


def rgba_of(colour, opacity):
    """(4,) RGBA with the alpha multiplied by ``opacity``."""
    r, g, b, a = colour
    return (r, g, b, a * opacity)


def _draw_painted(ax, shape, v):
    """Fill and stroke every region and path with its own paint (no default colours)."""
    artists, strokes = [], []
    paths = shape.paths
    groups, z = paint_groups(shape), 0
    while z < len(groups):
        group, paint = groups[z]
        rings = [paths[i][0] for i in group if paths[i][1] and len(paths[i][0]) >= 3]
        if paint.fill is not None and rings and paint.opacity > 0:
            fill = [_rings_path(v, rings)]
            # opaque regions painted alike one after the other (the parts of a cut region) fill as one path: where
            # they meet, anti-aliasing shows no seam; the non-zero rule fills their union, as painting each would
            while opaque(paint) and z + 1 < len(groups) and groups[z + 1][1] == paint:
                z += 1
                more = [paths[i][0] for i in groups[z][0] if paths[i][1] and len(paths[i][0]) >= 3]
                fill += [_rings_path(v, more)] if more else []
            patch = PathPatch(Path.make_compound_path(*fill), facecolor=rgba_of(paint.fill, paint.opacity),
                              edgecolor="none", zorder=1 + 2 * z)
            artists.append(ax.add_artist(patch))
        if paint.stroke is not None and paint.stroke_width > 0 and paint.opacity > 0:
            strokes.append((group, paint, 2 + 2 * z))
        z += 1
    ax.update_datalim(v)
    ax.set_aspect("equal")
    ax.autoscale_view()
    if strokes:
        # stroke widths are in shape units: points per unit from the axes' current scale
        (x0, x1), width_px = ax.get_xlim(), ax.bbox.width
        points_per_unit = abs(width_px / (x1 - x0)) * 72.0 / ax.figure.dpi
        for group, paint, z in strokes:
            parts = []
            for i in group:
                idx, closed = paths[i]
                idx = np.append(idx, idx[0]) if closed else idx
                parts += [v[idx], np.full((1, 2), np.nan)]
            xy = np.concatenate(parts)
            artists.extend(ax.plot(xy[:, 0], xy[:, 1], color=rgba_of(paint.stroke, paint.opacity),
                                   lw=paint.stroke_width * points_per_unit, zorder=z,
                                   solid_capstyle="round", solid_joinstyle="round"))
    return artists


def _resolve_style(shape, style, has_texture):
    if style not in STYLES:
        raise ParameterError(f"style must be one of {', '.join(STYLES)}, got {style!r}")
    if style == "texture" and not has_texture:
        raise ParameterError("style='texture' needs a texture image")
    if style == "auto":
        if has_texture:
            return "texture"
        return "fill" if shape.n_faces or _closed_rings(shape) else "wire"
    return style


def draw_frame(ax, shape, texture=None, uv=None, style="auto", *, source=None, color=None, linewidth=None):
    """Draw one shape on a matplotlib axes.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
    shape : Shape
    texture : str, os.PathLike or (H, W, 3|4) array, optional
        Image warped through the triangles (meshes only).
    uv : (n, 2) array_like, optional
        Texture coordinates; default ``shape.uv``, else the bounding box of
        ``source`` (or of ``shape``) normalised into [0, 1]^2.
    style : {'auto', 'wire', 'fill', 'texture'}
        'wire': every edge as a line. 'fill': triangles (or closed rings, with
        holes by the even-odd rule) filled, edges drawn thin on top. 'texture':
        the texture image. 'auto' picks texture when given, else fill for
        meshes and closed polygons, else wire (edge soups, polylines). A
        shape with ``paint`` is drawn with it under 'auto' and 'fill': each
        region filled and stroked in its own colours (see `paint_groups`).
    source : (n, 2) array_like, optional
        Geometry that defines the default texture coordinates.
    color : matplotlib colour, optional
        Line colour (wire) or fill colour (fill).
    linewidth : float, optional
        Line width in points.

    Returns
    -------
    list of matplotlib artists
    """
    v = check_frames(shape.vertices)
    painted = shape.paint is not None and style in ("fill", "auto") and texture is None and color is None
    style = _resolve_style(shape, style, texture is not None)
    artists = []
    if painted:
        artists = _draw_painted(ax, shape, v)
        if shape.y_down and not ax.yaxis_inverted():
            ax.invert_yaxis()
        return artists
    if style == "texture":
        tex = texture if _is_loaded(texture) else load_texture(texture)
        tuv = texture_uv(shape, uv, source)
        if ax.get_autoscale_on():
            x0, y0, x1, y1 = bbox_of(v)
            ax.update_datalim([(x0, y0), (x1, y1)])
            ax.autoscale_view()
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        w = max(8, int(round(ax.bbox.width)))
        h = max(8, int(round(ax.bbox.height)))
        img = render_texture(v, shape.faces, tuv, tex, (x0, x1, y0, y1), w, h)
        artists.append(
            ax.imshow(img, extent=(x0, x1, y0, y1), origin="upper", interpolation="nearest", zorder=1)
        )
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
    elif style == "fill" and shape.n_faces:
        patch = PathPatch(_faces_path(v, shape.faces), facecolor=color or FILL, edgecolor="none", zorder=1)
        artists.append(ax.add_artist(patch))  # add_patch would walk every segment for limits
        ax.update_datalim(v)
    elif style == "fill" and _closed_rings(shape):
        patch = PathPatch(_rings_path(v, _closed_rings(shape)), facecolor=color or FILL, edgecolor="none", zorder=1)
        artists.append(ax.add_artist(patch))  # add_patch would walk every segment for limits
        ax.update_datalim(v)
    if style != "texture" and shape.n_edges:
        lw = linewidth if linewidth is not None else (1.2 if style == "wire" else 0.5)
        edge_color = (color or WIRE) if style == "wire" else FILL_EDGE
        # one polyline with NaN breaks draws thousands of edges far faster than a LineCollection
        xy = np.concatenate([v[shape.edges], np.full((shape.n_edges, 1, 2), np.nan)], axis=1).reshape(-1, 2)
        artists.extend(ax.plot(xy[:, 0], xy[:, 1], color=edge_color, lw=lw, zorder=2, solid_capstyle="round"))
    ax.set_aspect("equal")
    ax.autoscale_view()
    if shape.y_down and not ax.yaxis_inverted():
        ax.invert_yaxis()
    return artists


def _is_loaded(texture):
    return (isinstance(texture, np.ndarray) and texture.dtype == np.float32 and texture.ndim == 3
            and texture.shape[2] == 4)


class FramePainter:
    """Renders shapes to RGB arrays of a fixed size over a fixed data window.

    One figure is reused for every frame of an animation.

    Parameters
    ----------
    width, height : int
        Image size in pixels.
    bbox : (4,) array_like
        ``(x0, y0, x1, y1)`` that every frame must show (padded, aspect matched).
    dpi : float
        Pixels per inch; line widths are in points, so a higher dpi draws
        thicker lines relative to the image.
    y_down : bool
        Draw y growing downwards (shapes read from SVG, see `Shape.y_down`).
    background : matplotlib colour
        Colour behind the shape (opaque).
    """

    def __init__(self, width, height, bbox, dpi=100, y_down=False, background=BACKGROUND):
        self.width, self.height = int(width), int(height)
        x0, x1, y0, y1 = fit_view(bbox, self.width, self.height)
        self.view = (x0, x1, y1, y0) if y_down else (x0, x1, y0, y1)
        self.figure = Figure(figsize=(self.width / dpi, self.height / dpi), dpi=dpi, facecolor=check_colour(background))
        self.canvas = FigureCanvasAgg(self.figure)
        self.ax = self.figure.add_axes([0, 0, 1, 1])
        self.ax.set_axis_off()

    def render(self, shape, texture=None, uv=None, style="auto", source=None, label=None):
        """(height, width, 3) uint8 image of ``shape``."""
        ax = self.ax
        for artist in [*ax.collections, *ax.images, *ax.patches, *ax.texts, *ax.lines]:
            artist.remove()
        x0, x1, y0, y1 = self.view
        ax.set_xlim(x0, x1)
        ax.set_ylim(y0, y1)
        draw_frame(ax, shape, texture=texture, uv=uv, style=style, source=source)
        if label:
            ax.text(0.02, 0.98, label, transform=ax.transAxes, ha="left", va="top", fontsize=8, color="#444444")
        self.canvas.draw()
        rgba = np.asarray(self.canvas.buffer_rgba())
        if rgba.shape[:2] != (self.height, self.width):
            raise RuntimeError(f"matplotlib drew {rgba.shape[1]}x{rgba.shape[0]}, expected {self.width}x{self.height}")
        return rgba[..., :3].copy()


def write_frame_png(shape, path, texture=None, size=None, bbox=None, *, dpi=100, uv=None, style="auto"):
    """Write one shape as a PNG image.

    Parameters
    ----------
    shape : Shape
    path : str or os.PathLike
    texture : str, os.PathLike or array, optional
        See `draw_frame`.
    size : int or (2,) int, optional
        Longest side in pixels (default 600), or exactly ``(width, height)``.
    bbox : (4,) array_like, optional
        ``(x0, y0, x1, y1)`` to show (default: the shape's bounding box); pass
        the same box for several shapes to draw them at one scale. The image
        shows the box centred, with a margin of 5 % of its longer side on
        every side, grown along one axis to the image's aspect ratio.
    dpi : float
        Pixels per inch (line widths are in points).
    uv : (n, 2) array_like, optional
    style : str
        See `draw_frame`.
    """
    v = check_frames(shape.vertices)
    box = bbox_of(v, stroke_margin(shape.paint)) if bbox is None else bbox
    w, h = image_size(box, 600 if size is None else size)
    tex = None if texture is None else load_texture(texture)
    painter = FramePainter(w, h, box, dpi=dpi, y_down=shape.y_down)
    rgb = painter.render(shape, texture=tex, uv=uv, style=style)
    save_png(rgb, path)


def save_png(rgb, path):
    """Write an (H, W, 3) uint8 array as PNG, atomically."""
    from PIL import Image

    with atomic_path(path) as tmp:
        Image.fromarray(rgb).save(tmp, format="PNG")
