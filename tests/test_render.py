"""Rendering: frame counts and sizes read back, pixels where the geometry is, texture mapping."""

import os
import sys

import numpy as np
import pytest
from PIL import Image

from isotween import Sequence, Shape, interpolate, render
from isotween.errors import FileFormatError, MethodError, MissingDependencyError, ParameterError, ShapeError
from isotween.render.texture import rasterize_triangles, texture_uv
from shapes import bend, grid_mesh

WHITE = 255


@pytest.fixture(scope="module")
def bent_bar():
    """A real AIAP sequence: a triangulated bar bending by 90 degrees, 7 frames."""
    bar = grid_mesh(13, 4, length=4.0, width=1.0)
    return interpolate(bar, bar.with_vertices(bend(bar.vertices, np.pi / 2)), frames=7)


def square_mesh(n=5, side=1.0):
    x, y = np.meshgrid(np.linspace(0, side, n), np.linspace(0, side, n), indexing="ij")
    v = np.c_[x.ravel(), y.ravel()]
    idx = np.arange(n * n).reshape(n, n)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    return Shape.from_mesh(v, np.vstack([np.c_[a, b, c], np.c_[a, c, d]]))


def sliding_square(frames=6, step=1.0):
    sq = square_mesh()
    shift = np.c_[np.arange(frames) * step, np.zeros(frames)][:, None, :]
    return Sequence(sq.vertices[None] + shift, sq)


def read_rgb(path):
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB")).astype(int)


def ink(img):
    """(H, W) bool: pixels that are not white."""
    return np.any(img < 250, axis=-1)


def test_gif_has_every_frame_at_the_requested_size(tmp_path, bent_bar):
    render.write_gif(bent_bar, tmp_path / "a.gif", fps=10, size=(200, 120))
    with Image.open(tmp_path / "a.gif") as im:
        assert im.n_frames == len(bent_bar) == 7
        assert im.size == (200, 120)
        assert im.info["duration"] == 100
        assert im.info["loop"] == 0
    render.write_gif(bent_bar, tmp_path / "b.gif", size=150, bounce=True, loop=False)
    with Image.open(tmp_path / "b.gif") as im:
        assert im.n_frames == 2 * len(bent_bar) - 2
        assert max(im.size) == 150
        assert "loop" not in im.info


def test_gif_frames_share_one_scale(tmp_path):
    seq = sliding_square(frames=6)
    render.write_gif(seq, tmp_path / "s.gif", size=(300, 100))
    areas, centres = [], []
    with Image.open(tmp_path / "s.gif") as im:
        for k in range(im.n_frames):
            im.seek(k)
            mask = ink(np.asarray(im.convert("RGB")).astype(int))
            areas.append(mask.sum())
            centres.append(np.nonzero(mask)[1].mean())
    # the square keeps its size and moves by the same number of pixels every frame
    assert max(areas) - min(areas) <= 0.03 * max(areas)
    steps = np.diff(centres)
    assert np.all(steps > 20) and np.ptp(steps) < 1.0


def test_strip_size_and_ink_where_the_shape_is(tmp_path):
    seq = sliding_square(frames=7, step=0.5)
    w, h = render.write_strip(seq, tmp_path / "s.png", columns=3, cell=(240, 180))
    img = read_rgb(tmp_path / "s.png")
    assert (w, h) == (720, 540) and img.shape == (540, 720, 3)
    # default: up to 8 frames evenly, here all 7 -> cells 0..6 in 3 columns, cells 7, 8 empty
    cells = [img[r * 180 : (r + 1) * 180, c * 240 : (c + 1) * 240] for r in range(3) for c in range(3)]
    masks = [ink(cell[12:-2, 2:-2]) for cell in cells]  # skip the label row and hairlines
    areas = np.array([m.sum() for m in masks])
    assert np.all(areas[:7] > 0.05 * masks[0].size)
    assert np.ptp(areas[:7]) <= 0.04 * areas[:7].max()
    assert areas[7] == areas[8] == 0
    centres = np.array([np.nonzero(m)[1].mean() for m in masks[:7]])
    assert np.all(np.diff(centres) > 5)  # common scale: the square slides across the cells


def test_a_wide_stroke_is_drawn_whole(tmp_path):
    # a ring drawn with a stroke half as wide as itself: the view grows by half the stroke, so no ink touches the
    # image's edge (the frame is not cut off where the stroke reaches past the vertices)
    from isotween.paint import Paint

    ring = Shape.from_paths([[[0, 0], [4, 0], [4, 4], [0, 4]]], closed=True, regions=[],
                            paint=[Paint(fill=None, stroke=(0, 0, 0, 1), stroke_width=2.0)])
    seq = Sequence(frames=np.stack([ring.vertices] * 3), shape=ring, times=np.linspace(0, 1, 3))
    render.write_gif(seq, tmp_path / "r.gif", size=120)
    with Image.open(tmp_path / "r.gif") as im:
        img = np.asarray(im.convert("RGB"))
    mask = ink(img)
    assert mask.sum() > 0.3 * mask.size
    assert not (mask[0].any() or mask[-1].any() or mask[:, 0].any() or mask[:, -1].any())


def test_strip_picks_frames_evenly(tmp_path, bent_bar):
    w, h = render.write_strip(bent_bar, tmp_path / "a.png", cell=100, frames=[0, -1])
    with Image.open(tmp_path / "a.png") as im:
        assert im.size == (w, h) and w == 2 * 100
    with pytest.raises(ParameterError, match="frame index 9"):
        render.write_strip(bent_bar, tmp_path / "b.png", frames=[0, 9])
    assert not (tmp_path / "b.png").exists()


def _pixel(point, bbox, size):
    """Pixel (row, col) of a point, from the documented 5 % margin around a square bbox."""
    x0, y0, x1, y1 = bbox
    side = (x1 - x0) * 1.1
    scale = size / side
    left, top = x0 - 0.05 * (x1 - x0), y1 + 0.05 * (y1 - y0)
    return int((top - point[1]) * scale), int((point[0] - left) * scale)


def test_polygon_hole_is_left_empty(tmp_path):
    outer = np.array([[0, 0], [10, 0], [10, 10], [0, 10.0]])
    inner = np.array([[3, 3], [7, 3], [7, 7], [3, 7.0]])  # same orientation as the outer ring
    shape = Shape.from_polygon([outer, inner])
    bbox = (0, 0, 10, 10)
    render.write_frame_png(shape, tmp_path / "p.png", size=(220, 220), bbox=bbox)
    img = read_rgb(tmp_path / "p.png")
    assert np.all(img[_pixel((5, 5), bbox, 220)] == WHITE)  # hole (even-odd)
    assert np.all(img[_pixel((1.5, 5), bbox, 220)] < 250)  # band
    assert np.all(img[_pixel((-0.3, 5), bbox, 220)] == WHITE)  # outside


def test_polyline_is_drawn_as_lines(tmp_path):
    line = Shape.from_polyline(np.array([[0, 0], [10, 0], [10, 10.0]]))
    bbox = (0, 0, 10, 10)
    render.write_frame_png(line, tmp_path / "l.png", size=(220, 220), bbox=bbox)
    img = read_rgb(tmp_path / "l.png")
    assert np.all(img[_pixel((5, 0.01), bbox, 220)] < 200)
    assert np.all(img[_pixel((10 - 0.01, 5), bbox, 220)] < 200)
    assert np.all(img[_pixel((5, 5), bbox, 220)] == WHITE)  # not filled


def test_rasteriser_covers_each_pixel_once():
    sq = square_mesh(n=6, side=1.0)
    pts = sq.vertices * [20.0, 10.0] + [3.0, 4.0]  # a 20 x 10 pixel rectangle on pixel borders
    pixel, face, bary = rasterize_triangles(pts, sq.faces, 32, 24)
    assert len(pixel) == len(np.unique(pixel)) == 200
    rows, cols = np.divmod(pixel, 32)
    assert rows.min() == 4 and rows.max() == 13 and cols.min() == 3 and cols.max() == 22
    centres = np.c_[cols + 0.5, rows + 0.5]
    assert np.allclose(np.einsum("kj,kjd->kd", bary, pts[sq.faces[face]]), centres)
    assert np.all(bary > -1e-4)


def test_default_uv_keeps_aspect_ratio():
    bar = grid_mesh(5, 3, length=4.0, width=2.0)
    uv = texture_uv(bar)
    assert np.allclose(uv.min(axis=0), [0.0, 0.25]) and np.allclose(uv.max(axis=0), [1.0, 0.75])
    d = np.diff(bar.vertices, axis=0)
    assert np.allclose(np.diff(uv, axis=0), d / 4.0)  # one scale on both axes


def _texture():
    """64 x 64 smooth but asymmetric image: red grows to the right, green downwards."""
    yy, xx = np.mgrid[0:64, 0:64]
    img = np.zeros((64, 64, 3), np.uint8)
    img[..., 0] = 40 + 3 * xx
    img[..., 1] = 20 + 3 * yy
    img[..., 2] = 128 + (60 * np.sin(xx / 5.0) * np.cos(yy / 7.0)).astype(int)
    return img


def test_texture_follows_a_translation(tmp_path):
    tex = _texture()
    sq = square_mesh(n=7, side=1.0)
    sq.uv = sq.vertices.copy()
    bbox, size = (0.0, 0.0, 2.0, 2.0), 220  # 100 pixels per unit
    render.write_frame_png(sq, tmp_path / "a.png", texture=tex, size=(size, size), bbox=bbox)
    moved = sq.with_vertices(sq.vertices + [0.37, -0.21])  # 37 px right, 21 px down
    render.write_frame_png(moved, tmp_path / "b.png", texture=tex, size=(size, size), bbox=bbox)
    a, b = read_rgb(tmp_path / "a.png"), read_rgb(tmp_path / "b.png")
    assert ink(a).sum() > 9000
    diff = np.abs(b[21:, 37:] - a[:-21, :-37])
    assert diff.mean() < 0.2 and np.quantile(diff, 0.999) <= 2
    # the square shows the texture upright: 100 x 100 pixels of the resized image
    r, c = _pixel((0.0, 1.0), bbox, size)
    block = a[r + 2 : r + 98, c + 2 : c + 98]
    expected = np.asarray(Image.fromarray(tex).resize((100, 100), Image.Resampling.BILINEAR)).astype(int)
    assert np.abs(block - expected[2:98, 2:98]).mean() < 3.0
    flipped = expected[::-1]
    assert np.abs(block - flipped[2:98, 2:98]).mean() > 30.0


def test_textured_gif_keeps_the_colours_of_the_texture(tmp_path, bent_bar):
    tex = np.zeros((8, 8, 3), np.uint8)
    tex[:, :4] = [255, 0, 0]
    tex[:, 4:] = [0, 0, 255]
    render.write_gif(bent_bar, tmp_path / "t.gif", size=160, texture=tex)
    with Image.open(tmp_path / "t.gif") as im:
        assert im.n_frames == 7
        im.seek(6)
        img = np.asarray(im.convert("RGB")).astype(int)
    red = (img[..., 0] > 200) & (img[..., 2] < 60)
    blue = (img[..., 2] > 200) & (img[..., 0] < 60)
    assert red.sum() > 300 and blue.sum() > 300
    # only red, blue and their blends with each other or with the white background
    # (green never above red and blue): no mesh fill colour, no wire lines
    g, others = img[..., 1], np.minimum(img[..., 0], img[..., 2])
    assert np.all(g[ink(img)] <= others[ink(img)] + 12)


def test_mp4_frame_count(tmp_path, bent_bar):
    pytest.importorskip("imageio_ffmpeg")
    imageio = pytest.importorskip("imageio.v2")
    render.write_mp4(bent_bar, tmp_path / "a.mp4", fps=10, size=(161, 99))
    reader = imageio.get_reader(tmp_path / "a.mp4", "ffmpeg")
    try:
        frames = [f for f in reader]
    finally:
        reader.close()
    assert len(frames) == len(bent_bar)
    assert frames[0].shape == (100, 162, 3)  # rounded up to even sizes


def test_mp4_without_imageio_ffmpeg(tmp_path, bent_bar, monkeypatch):
    monkeypatch.setitem(sys.modules, "imageio_ffmpeg", None)
    with pytest.raises(MissingDependencyError, match=r"isotween\[video\]"):
        render.write_mp4(bent_bar, tmp_path / "a.mp4")
    assert os.listdir(tmp_path) == []


def test_failed_write_leaves_no_file(tmp_path, bent_bar, monkeypatch):
    (tmp_path / "a.gif").write_bytes(b"old")

    def broken_save(self, fp, *args, **kwargs):
        with open(fp, "wb") as fh:
            fh.write(b"GIF89a partial")
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(Image.Image, "save", broken_save)
    with pytest.raises(FileFormatError, match="a.gif"):
        render.write_gif(bent_bar, tmp_path / "a.gif")
    with pytest.raises(FileFormatError, match="b.png"):
        render.write_frame_png(bent_bar[0], tmp_path / "b.png")
    assert os.listdir(tmp_path) == ["a.gif"]
    assert (tmp_path / "a.gif").read_bytes() == b"old"


def test_bad_input_is_named(tmp_path, bent_bar):
    line = Shape.from_polyline(np.array([[0, 0], [1, 0], [1, 1.0]]))
    with pytest.raises(MethodError, match="no faces"):
        render.write_frame_png(line, tmp_path / "a.png", texture=_texture())
    with pytest.raises(FileFormatError, match="nope.png"):
        render.write_gif(bent_bar, tmp_path / "a.gif", texture=tmp_path / "nope.png")
    frames = bent_bar.frames.copy()
    frames[3, 5, 1] = np.nan
    with pytest.raises(ShapeError, match="frame 3 vertex 5"):
        render.write_gif(Sequence(frames, bent_bar.shape), tmp_path / "a.gif")
    with pytest.raises(ParameterError, match="style"):
        render.write_frame_png(line, tmp_path / "a.png", style="sketch")
    with pytest.raises(ParameterError, match="fps"):
        render.write_gif(bent_bar, tmp_path / "a.gif", fps=0)
    with pytest.raises(FileFormatError, match="does not exist"):
        render.write_html(bent_bar, tmp_path / "no" / "a.html")
    with pytest.raises(ParameterError, match="format"):
        render.plot_energy(bent_bar, tmp_path / "e.xyz")
    assert os.listdir(tmp_path) == []


def test_energy_plot(tmp_path, bent_bar):
    assert len(bent_bar.energy) >= 1
    render.plot_energy(bent_bar, tmp_path / "e.png", dpi=50)
    with Image.open(tmp_path / "e.png") as im:
        assert im.format == "PNG" and im.size == (450, 180)
    render.plot_energy(bent_bar, tmp_path / "e.svg")
    assert (tmp_path / "e.svg").read_text().lstrip().startswith("<?xml")


def test_draw_frame_on_user_axes(bent_bar):
    from matplotlib.figure import Figure

    fig = Figure()
    ax = fig.add_subplot()
    render.draw_frame(ax, bent_bar[-1], texture=_texture(), source=bent_bar.shape.vertices)
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    lo, hi = bent_bar.frames[-1].min(axis=0), bent_bar.frames[-1].max(axis=0)
    assert x0 <= lo[0] and x1 >= hi[0] and y0 <= lo[1] and y1 >= hi[1]
    assert len(ax.images) == 1


def test_y_down_shape_is_drawn_as_in_its_file(tmp_path):
    # an L: a bar along y = 0 and a leg down to y = 3, in SVG's y-down sense
    ell = Shape.from_polygon([[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3]])
    down = Shape(ell.vertices, ell.edges, paths=ell.paths, y_down=True)
    bbox = (0.0, 0.0, 3.0, 3.0)
    render.write_frame_png(ell, tmp_path / "up.png", size=(120, 120), bbox=bbox)
    render.write_frame_png(down, tmp_path / "down.png", size=(120, 120), bbox=bbox)
    up, dn = ink(read_rgb(tmp_path / "up.png")), ink(read_rgb(tmp_path / "down.png"))
    # the same drawing mirrored top to bottom, with the bar (y = 0..1) on top when y points down
    assert np.mean(up != dn[::-1]) < 0.03 and np.mean(up != dn) > 0.2  # edges may shift a pixel
    rows = np.flatnonzero(dn.any(axis=1))
    assert dn[rows[0] + 3].sum() > 2.5 * dn[rows[-1] - 3].sum()


def test_y_down_default_texture_is_upright(tmp_path):
    tex = np.zeros((8, 8, 3), np.uint8)
    tex[:4] = [255, 0, 0]  # top half red
    tex[4:] = [0, 0, 255]  # bottom half blue
    sq = square_mesh(n=5, side=1.0)
    down = Shape(sq.vertices, sq.edges, sq.faces, y_down=True)
    for shape, name in ((sq, "up.png"), (down, "down.png")):
        render.write_frame_png(shape, tmp_path / name, texture=tex, size=(100, 100))
        img = read_rgb(tmp_path / name)
        red = (img[..., 0] > 200) & (img[..., 2] < 60)
        blue = (img[..., 2] > 200) & (img[..., 0] < 60)
        # whichever way y points, the image appears upright on screen
        assert red[:45].sum() > 1000 and blue[55:].sum() > 1000
        assert red[55:].sum() == 0 and blue[:45].sum() == 0


def _svg_animation(path):
    """{fill-or-line: (static d, [d per frame], dur)} of an animated SVG."""
    import xml.etree.ElementTree as ET

    ns = "{http://www.w3.org/2000/svg}"
    out = {}
    for p in ET.parse(path).getroot().iter(f"{ns}path"):
        anim = p.find(f"{ns}animate")
        kind = "line" if p.get("fill") == "none" else "fill"
        out[kind] = (p.get("d"), anim.get("values").split(";"), anim.get("dur"))
    return out


def _numbers(d):
    import re

    # SVG numbers may drop the leading zero (".5", "-.25")
    return np.array([float(x) for x in re.findall(r"-?(?:\d+\.?\d*|\.\d+)(?:e-?\d+)?", d)]).reshape(-1, 2)


def test_svg_animation_holds_every_frame(tmp_path, bent_bar):
    # the frame-by-frame writer (no curves, no key reduction): every triangle in every frame
    render.write_svg_animation(bent_bar, tmp_path / "bar.svg", curves=False, reduce=False)
    anim = _svg_animation(tmp_path / "bar.svg")
    d0, values, dur = anim["fill"]
    # 7 ticks and the last frame again: it shows for one tick before the loop starts over
    assert set(anim) == {"fill"} and len(values) == 8 and d0 == values[0] and dur == f"{7 / render.FPS:.6g}s"
    assert values[7] == values[6]
    faces = bent_bar.shape.faces
    for k, d in enumerate(values[:7]):
        assert d.count("M") == len(faces) and d.count("Z") == len(faces)
        # every triangle's corners, y mirrored: the bar is y-up
        expected = bent_bar.frames[k][faces.ravel()] * [1, -1]
        np.testing.assert_allclose(_numbers(d), expected, atol=1e-4 * 4.0)


def test_svg_animation_of_outlines_and_soups(tmp_path):
    ring = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], float)
    hole = np.array([[1, 1], [1, 3], [3, 3], [3, 1]], float)
    outline = Shape.from_polygon([ring, hole])
    square = Shape(outline.vertices, outline.edges, paths=outline.paths, y_down=True)
    seq = Sequence(square.vertices[None] + np.arange(3)[:, None, None], square)
    render.write_svg_animation(seq, tmp_path / "ring.svg", fps=6, bounce=True, curves=False, reduce=False)
    anim = _svg_animation(tmp_path / "ring.svg")
    _, values, dur = anim["fill"]
    # the hole is a second subpath of one even-odd path; bounce plays 0 1 2 1 (and 1 again for its tick)
    assert set(anim) == {"fill"} and len(values) == 5 and dur == f"{4 / 6:.6g}s"
    for k, d in zip([0, 1, 2, 1, 1], values, strict=True):
        assert d.count("M") == 2
        np.testing.assert_allclose(_numbers(d), seq.frames[k], atol=1e-4)
    soup = Shape(ring, [[0, 1], [2, 3]])
    render.write_svg_animation(Sequence(np.stack([ring, ring * 2]), soup), tmp_path / "soup.svg", curves=False,
                               reduce=False)
    anim = _svg_animation(tmp_path / "soup.svg")
    _, values, _ = anim["line"]
    assert set(anim) == {"line"} and [d.count("M") for d in values] == [2, 2, 2]
    np.testing.assert_allclose(_numbers(values[1]), (ring * 2 * [1, -1])[[0, 1, 2, 3]], atol=1e-4)


def test_lean_svg_animation_of_a_point_and_bad_tolerances(tmp_path):
    point = Shape.from_polyline([[1.0, 1.0], [1.0, 1.0], [1.0, 1.0]])
    render.write_svg_animation(Sequence(np.ones((3, 3, 2)), point), tmp_path / "p.svg")  # no size: still written
    assert "<path" in (tmp_path / "p.svg").read_text()
    bar = Shape.from_polyline([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]])
    seq = interpolate(bar, bar.rotate(1.0), frames=3)
    for bad in ({"tolerance": 0.0}, {"tolerance": float("nan")}, {"key_tolerance": -1.0}):
        with pytest.raises(ParameterError, match="positive number"):
            render.write_svg_animation(seq, tmp_path / "x.svg", **bad)
    assert not (tmp_path / "x.svg").exists()


# ---------------------------------------------------------------- comparison figures
def test_compared_frames_are_all_or_evenly_spaced():
    from isotween.render.comparison import compared_frames

    assert compared_frames(9, 12).tolist() == list(range(9))  # every frame (was 7 of 9, uneven)
    for n in (45, 205, 14, 100):
        k = compared_frames(n, 12)
        assert k[0] == 0 and 2 <= len(k) <= 12 and len(set(np.diff(k))) == 1  # one step
    assert compared_frames(205, 12)[-1] == 204 and compared_frames(45, 12)[-1] == 44  # ends shown


def test_metrics_figure_keeps_equal_curves_apart_with_integer_counts():
    from isotween.render.comparison import metrics_figure

    bar = grid_mesh(7, 3, length=4.0, width=1.0)
    seq = interpolate(bar, bar.with_vertices(bend(bar.vertices, np.pi / 2)), frames=5)
    fig = metrics_figure({"a": seq, "b": seq})  # two identical sequences
    edge_axes, _, count_axes = fig.axes
    a, b = edge_axes.lines[:2]
    np.testing.assert_array_equal(a.get_ydata(), b.get_ydata())
    assert np.all(a.get_xdata() != b.get_xdata())  # shifted apart: both stay visible
    assert a.get_marker() != b.get_marker() and a.get_linestyle() != b.get_linestyle()
    ticks = count_axes.get_yticks()
    assert np.all(ticks == np.round(ticks))


@pytest.mark.parametrize("colour", ["#ffffff", "#3182BD", "#3182bd80", (0.1, 0.2, 0.3), [1, 0, 0, 0.5],
                                    np.array([0.0, 0.5, 1.0]), "white", "tab:blue", "0.5"])
def test_colours_read_without_matplotlib_are_read_as_matplotlib_reads_them(colour):
    from matplotlib.colors import to_rgba

    from isotween.render._view import check_colour

    assert check_colour(colour) == pytest.approx(to_rgba(colour), abs=0)


@pytest.mark.parametrize("colour", ["#12345g", "#+23456", (1, 2, 3), (0.1, 0.2), "nocolour"])
def test_what_is_not_a_colour_is_named(colour):
    from isotween.render._view import check_colour

    with pytest.raises(ParameterError, match="is not a colour"):
        check_colour(colour, "fill")
