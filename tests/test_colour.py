"""Paint in every output: colours per region, blended in Oklab; WebP and APNG playback."""

import re

import numpy as np
import pytest
from PIL import Image

from browser import screenshot
from isotween import Sequence, Shape, interpolate, io, render
from isotween.paint import Paint, oklab_to_srgb, sequence_paint

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
RED, BLUE = (1.0, 0.0, 0.0, 1.0), (0.0, 0.0, 1.0, 1.0)
# Oklab of sRGB red and blue as published by Ottosson (2020); their midpoint in sRGB is the
# colour a red -> blue morph must show halfway
RED_LAB = np.array([0.627955, 0.224863, 0.125846])
BLUE_LAB = np.array([0.452014, -0.032457, -0.311528])
MID = np.round(255 * oklab_to_srgb(0.5 * (RED_LAB + BLUE_LAB))).astype(int)


def painted(vertices, fill, stroke=None, width=0.0):
    s = Shape.from_polygon(vertices)
    return Shape(s.vertices, s.edges, paths=s.paths, paint=[Paint(fill=fill, stroke=stroke, stroke_width=width)])


@pytest.fixture(scope="module")
def red_to_blue():
    return interpolate(painted(SQUARE, RED), painted(SQUARE + [1.5, 0.0], BLUE), frames=5)


def centre_colour(rgb, seq, k, size):
    """Pixel colour at the centre of frame k's square (view of the whole sequence)."""
    from isotween.render._view import bbox_of, fit_view, image_size

    box = bbox_of(seq.frames)
    w, h = image_size(box, size)
    x0, x1, y0, y1 = fit_view(box, w, h)
    cx, cy = seq.frames[k].mean(axis=0)
    col = int((cx - x0) / (x1 - x0) * w)
    row = int((y1 - cy) / (y1 - y0) * h)
    return rgb[row, col].astype(int)


def test_midpoint_is_the_oklab_blend_not_the_rgb_one():
    assert np.abs(MID - [127, 0, 127]).max() > 20  # the test below tells the two apart
    regions, paints = sequence_paint(Sequence(np.stack([SQUARE] * 3), painted(SQUARE, RED),
                                              info={"paint": {"times": [0, 1], "keys": [
                                                  [Paint(fill=RED).to_dict()], [Paint(fill=BLUE).to_dict()]]}}))
    assert paints[0][0].fill == RED and paints[2][0].fill == BLUE
    assert np.abs(np.round(255 * np.array(paints[1][0].fill[:3])) - MID).max() <= 1


def test_red_square_renders_red_in_png_and_gif(tmp_path):
    shape = painted(SQUARE, RED)
    render.write_frame_png(shape, tmp_path / "r.png", size=100)
    rgb = np.asarray(Image.open(tmp_path / "r.png").convert("RGB"))
    assert rgb[50, 50].tolist() == [255, 0, 0] and rgb[1, 1].tolist() == [255, 255, 255]
    seq = Sequence(np.stack([SQUARE, SQUARE + 0.5]), shape)
    render.write_gif(seq, tmp_path / "r.gif", size=100)
    with Image.open(tmp_path / "r.gif") as im:
        for k in range(im.n_frames):
            im.seek(k)
            assert centre_colour(np.asarray(im.convert("RGB")), seq, k, 100).tolist() == [255, 0, 0]


def test_unpainted_shape_keeps_the_default_look(tmp_path):
    render.write_frame_png(Shape.from_polygon(SQUARE), tmp_path / "d.png", size=100)
    rgb = np.asarray(Image.open(tmp_path / "d.png").convert("RGB"))
    assert rgb[50, 50].tolist() == [0x9E, 0xCA, 0xE1]  # FILL


def test_red_to_blue_middle_frame_has_the_oklab_midpoint(tmp_path, red_to_blue):
    seq = red_to_blue
    assert seq.times[2] == 0.5
    render.write_strip(seq, tmp_path / "s.png", frames=[2], cell=120)
    from isotween.render._frames import SequenceRenderer

    renderer = SequenceRenderer(seq, 120)
    assert np.abs(centre_colour(renderer.image(2), seq, 2, 120) - MID).max() <= 2
    assert centre_colour(renderer.image(0), seq, 0, 120).tolist() == [255, 0, 0]
    assert centre_colour(renderer.image(4), seq, 4, 120).tolist() == [0, 0, 255]
    render.write_gif(seq, tmp_path / "m.gif", size=120)
    with Image.open(tmp_path / "m.gif") as im:
        im.seek(2)
        assert np.abs(centre_colour(np.asarray(im.convert("RGB")), seq, 2, 120) - MID).max() <= 6


def test_paint_survives_the_sequence_file(tmp_path, red_to_blue):
    io.save_sequence(red_to_blue, tmp_path / "q.npz")
    back = io.load_sequence(tmp_path / "q.npz")
    assert sequence_paint(back)[1] == sequence_paint(red_to_blue)[1]


def test_svg_outputs_carry_the_paint(tmp_path, red_to_blue):
    render.write_svg_animation(red_to_blue, tmp_path / "a.svg")
    text = (tmp_path / "a.svg").read_text()
    fills = re.search(r'attributeName="fill" values="([^"]*)"', text).group(1).split(";")
    assert fills[0] == "#ff0000" and fills[-1] == "#0000ff"
    assert np.abs(np.array([int(fills[2][i:i + 2], 16) for i in (1, 3, 5)]) - MID).max() <= 1
    # static SVG: regions with holes as one even-odd path in their colours
    ring, hole = SQUARE * 4, SQUARE * 2 + 1
    s = Shape.from_polygon([ring, hole])
    shape = Shape(s.vertices, s.edges, paths=s.paths, regions=[[0, 1]],
                  paint=[Paint(fill=RED, stroke=BLUE, stroke_width=0.25, opacity=0.5)] * 2)
    io.save(shape, tmp_path / "s.svg")
    text = (tmp_path / "s.svg").read_text()
    assert text.count("<path ") == 1
    for attr in ('fill="#ff0000"', 'fill-opacity="1"', 'opacity="0.5"', 'stroke="#0000ff"', 'stroke-width="0.25"',
                 'fill-rule="evenodd"'):
        assert attr in text
    back = io.load(tmp_path / "s.svg")
    assert back.n_vertices == 8  # both rings, in order


@pytest.mark.parametrize("ext", [".webp", ".apng"])
def test_webp_and_apng_frame_count_and_durations(tmp_path, red_to_blue, ext):
    write = render.write_webp if ext == ".webp" else render.write_apng
    fps, hold = 10, 0.3
    write(red_to_blue, tmp_path / f"a{ext}", fps=fps, hold=hold, bounce=True, size=64)
    order = render.playback_order(5, fps, hold, bounce=True)
    assert order.tolist() == [0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4, 3, 2, 1]
    # repeated ticks may be stored as one longer frame (WebP merges them): compare runs
    runs = [4, 1, 1, 1, 4, 1, 1, 1]
    with Image.open(tmp_path / f"a{ext}") as im:
        durations, shown = [], []
        for k in range(im.n_frames):
            im.seek(k)
            im.load()  # WebP sets the duration on loading the frame
            durations.append(im.info["duration"])
            shown.append(im.convert("RGB").copy())
        assert im.info.get("loop", 0) == 0
    if len(durations) == len(runs):
        assert durations == [100 * r for r in runs]
        middle = shown[2]
    else:
        assert durations == [100] * len(order)
        middle = shown[6]
    # frame 2 of the sequence: the Oklab midpoint
    assert np.abs(centre_colour(np.asarray(middle), red_to_blue, 2, 64) - MID).max() <= 8


def test_background_colour(tmp_path):
    seq = Sequence(np.stack([SQUARE, SQUARE + 0.5]), Shape.from_polygon(SQUARE))
    render.write_apng(seq, tmp_path / "b.apng", background="#102030", size=64, loop=False)
    with Image.open(tmp_path / "b.apng") as im:
        assert np.asarray(im.convert("RGB"))[0, 0].tolist() == [0x10, 0x20, 0x30]
        assert im.info.get("loop") == 1


def test_page_draws_the_paint(tmp_path, red_to_blue, browser):
    render.write_html(red_to_blue, tmp_path / "p.html")
    page = browser.new_page(viewport={"width": 900, "height": 640})
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    try:
        page.goto((tmp_path / "p.html").as_uri())
        assert page.eval_on_selector("#mode", "s => s.value") == "paint"
        for k, expected in ((0, [255, 0, 0]), (2, MID.tolist()), (4, [0, 0, 255])):
            page.evaluate(f"window.isotween.setFrame({k})")
            rgb = screenshot(page, "#view")
            hits = np.all(np.abs(rgb.reshape(-1, 3).astype(int) - expected) <= 3, axis=1)
            assert hits.sum() > 500, (k, expected)
    finally:
        page.close()
    assert not errors


def test_svg_frame_folder_has_each_frames_colour(tmp_path, red_to_blue):
    io.write_frames(red_to_blue, tmp_path / "f", format="svg")
    fills = [re.search(r'fill="(#[0-9a-f]{6})"', (tmp_path / "f" / f"frame_{k:04d}.svg").read_text()).group(1)
             for k in range(5)]
    assert fills[0] == "#ff0000" and fills[4] == "#0000ff"
    assert np.abs(np.array([int(fills[2][i:i + 2], 16) for i in (1, 3, 5)]) - MID).max() <= 1
