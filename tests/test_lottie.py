"""Lottie export.

Valid against the official schema, keyframes that are the frames, and lottie-web in Chromium drawing what isotween's own
renderer draws.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from browser import screenshot
from isotween import Sequence, Shape, interpolate, render
from isotween.examples import load_example
from isotween.outputs import with_paint
from isotween.paint import Paint, sequence_paint
from isotween.render._frames import SequenceRenderer
from isotween.render._view import bbox_of, fit_view, stroke_margin
from isotween.render.curves import TOLERANCE
from isotween.render.keys import TOLERANCE as KEY_TOLERANCE
from isotween.render.lottie import lottie_data
from shapes import bend, grid_mesh

JS = Path(__file__).parent / "js"
PLAYER = JS / "node_modules" / "lottie-web" / "build" / "player" / "lottie.min.js"
SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def painted(vertices, fill, stroke=None, width=0.0, holes=()):
    s = Shape.from_polygon([vertices, *holes])
    k = len(s.paths)
    return Shape(s.vertices, s.edges, paths=s.paths, regions=[list(range(k))],
                 paint=[Paint(fill=fill, stroke=stroke, stroke_width=width)] * k)


def turned(shape, angle, shift):
    z = shape.z * np.exp(1j * angle) + shift
    return np.column_stack([z.real, z.imag])


@pytest.fixture(scope="module")
def morph():
    """A red square with a square hole turning into a blue one, outlined in black."""
    hole = [SQUARE[::-1] * 0.5 + 0.25]
    a = painted(SQUARE * 2, (1, 0, 0, 1), (0, 0, 0, 1), 0.06, [h * 2 for h in hole])
    b_vertices = turned(a, np.pi / 3, 2.5 + 0.5j)
    b = Shape(b_vertices, a.edges, paths=a.paths, regions=a.regions,
              paint=[Paint(fill=(0, 0, 1, 1), stroke=(0, 0, 0, 1), stroke_width=0.12)] * 2)
    return interpolate(a, b, frames=7)


@pytest.fixture(scope="module")
def validator():
    jsonschema = pytest.importorskip("jsonschema")
    from lottie_specs import schema_path

    schema = json.loads(Path(schema_path).read_text() if not callable(schema_path) else Path(schema_path()).read_text())
    return jsonschema.Draft202012Validator(schema)


def mesh_sequence():
    bar = grid_mesh(7, 3, length=4.0, width=1.0)
    return interpolate(bar, bar.with_vertices(bend(bar.vertices, np.pi / 2)), frames=5)


@pytest.mark.parametrize("case", ["painted", "mesh", "outline", "polyline"])
def test_lottie_validates_against_the_official_schema(validator, morph, case):
    if case == "painted":
        data = lottie_data(morph, bounce=True, hold=0.2, background="#fafafa", title="morph")
    elif case == "mesh":
        data = lottie_data(mesh_sequence())
    elif case == "outline":
        s = Shape.from_polygon([SQUARE * 4, SQUARE[::-1] + 1])
        data = lottie_data(Sequence(np.stack([s.vertices, s.vertices * 1.5]), s))
    else:
        s = Shape.from_polyline(SQUARE)
        data = lottie_data(Sequence(np.stack([s.vertices, s.vertices[::-1]]), s))
    errors = sorted(validator.iter_errors(data), key=lambda e: list(e.path))
    assert not errors, [f"{list(e.path)}: {e.message[:200]}" for e in errors[:5]]


def keyframe_points(item):
    ks = item["ks"]
    values = [ks["k"]] if ks["a"] == 0 else [k["s"][0] for k in ks["k"]]
    return np.array([v["v"] for v in values])


def test_keyframes_are_the_frames_and_the_paint(morph):
    fps, hold = 10, 0.2
    # without curves and keyframe reduction, every tick is a keyframe holding exactly its frame
    data = lottie_data(morph, fps=fps, hold=hold, size=300, curves=False, reduce=False)
    order = render.playback_order(len(morph), fps, hold)
    assert data["op"] == len(order) and data["fr"] == fps
    group = data["layers"][0]["shapes"][0]
    paths = [it for it in group["it"] if it["ty"] == "sh"]
    assert len(paths) == 2  # ring and hole in one even-odd group
    fill = next(it for it in group["it"] if it["ty"] == "fl")
    assert fill["r"] == 2
    # back from composition pixels to shape units: every tick is exactly its frame
    box = bbox_of(morph.frames, stroke_margin(sequence_paint(morph)[1]))  # strokes drawn whole
    x0, x1, y0, y1 = fit_view(box, data["w"], data["h"])
    for item, (idx, _) in zip(paths, morph.shape.paths, strict=False):
        px = keyframe_points(item)
        assert px.shape == (len(order), len(idx), 2)
        x = x0 + px[..., 0] * (x1 - x0) / data["w"]
        y = y1 - px[..., 1] * (y1 - y0) / data["h"]
        np.testing.assert_allclose(np.stack([x, y], -1), morph.frames[order][:, idx],
                                   atol=2e-3 * (x1 - x0) / data["w"] * 1000)
    colours = np.array([k["s"] for k in fill["c"]["k"]])
    assert colours[0].tolist() == [1, 0, 0, 1] and colours[-1].tolist() == [0, 0, 1, 1]
    # the middle frame's fill is the Oklab blend (frame 3 of 7: t = 0.5)
    from isotween.paint import lerp_paint

    mid = lerp_paint(morph.shape.paint[0], Paint(fill=(0, 0, 1, 1)), [0.5])[0].fill
    np.testing.assert_allclose(colours[order.tolist().index(3)][:3], mid[:3], atol=1e-4)


def sampled_ticks(item, ticks, per_segment=60):
    """(P, m, 2) points of an ``sh`` item's Bezier path at every tick, the eased keyframes evaluated."""
    ks = item["ks"]
    if ks["a"] == 0:
        values = [ks["k"]] * ticks
    else:
        keys = ks["k"]
        times = [k["t"] for k in keys]
        assert times[0] == 0 and times[-1] == ticks - 1
        values = []
        for t in range(ticks):
            j = min(np.searchsorted(times, t, side="right") - 1, len(keys) - 2)
            a, b = keys[j], keys[j + 1]
            assert a["o"]["x"] == [1 / 3] and a["i"]["x"] == [2 / 3]  # x handles: the easing's x is the time
            u = (t - a["t"]) / (b["t"] - a["t"])
            y = 3 * (1 - u) ** 2 * u * a["o"]["y"][0] + 3 * (1 - u) * u ** 2 * a["i"]["y"][0] + u ** 3
            sa, sb = a["s"][0], b["s"][0]
            assert len(sa["v"]) == len(sb["v"])  # the same vertex count in every keyframe
            blend = {k: (1 - y) * np.array(sa[k]) + y * np.array(sb[k]) for k in ("v", "i", "o")}
            values.append({**blend, "c": sa["c"]})
    u = np.linspace(0, 1, per_segment)[:, None]
    out = []
    for val in values:
        v, i, o = (np.asarray(val[k], dtype=float) for k in ("v", "i", "o"))
        nxt = np.arange(1, len(v) + 1) % len(v) if val["c"] else np.arange(1, len(v))
        p0, p3 = v[:len(nxt)], v[nxt]
        p1, p2 = p0 + o[:len(nxt)], p3 + i[nxt]
        pts = ((1 - u) ** 3)[None] * p0[:, None] + (3 * (1 - u) ** 2 * u)[None] * p1[:, None] \
            + (3 * (1 - u) * u ** 2)[None] * p2[:, None] + (u ** 3)[None] * p3[:, None]
        out.append(pts.reshape(-1, 2))
    return np.array(out)


def test_lean_keyframes_reproduce_every_tick_within_the_tolerance(morph):
    from isotween.render.web import pixel_frames
    from test_curves import polyline_distance

    source, target, options = load_example("holes")
    seq = with_paint(interpolate(source, target, **options), fill=("red", "blue"))
    for s in (morph, seq):
        fps, hold, size = 24, 0.25, 400
        lean, full = lottie_data(s, fps=fps, hold=hold, size=size), \
            lottie_data(s, fps=fps, hold=hold, size=size, curves=False, reduce=False)
        order = render.playback_order(len(s), fps, hold)
        px = pixel_frames(s, size)[0][order]
        tol = (TOLERANCE + KEY_TOLERANCE) * np.hypot(lean["w"], lean["h"])  # curve fit, then keyframe easing
        items = [it for g in lean["layers"][0]["shapes"] for it in g["it"] if it["ty"] == "sh"]
        rings = [px[:, np.append(idx, idx[0]) if closed else idx] for idx, closed in s.shape.paths]
        for item in items:
            assert item["ks"]["a"] == 1 and len(item["ks"]["k"]) < len(order) / 2
            pts = sampled_ticks(item, len(order))
            near = np.min([polyline_distance(pts, r) for r in rings], axis=0)
            assert near.max() <= tol * (1 + 1 / 8), near.max()  # and rounding (`tolerance_digits`)
        # curves pay off on the letters' outlines (hundreds of vertices), holds and slow ends on both
        assert len(json.dumps(lean)) * (5 if s is seq else 1.5) < len(json.dumps(full))


@pytest.fixture(scope="module")
def player():
    """lottie-web's player script, installed by ``npm ci --prefix tests/js`` (as .ci/run does)."""
    if not PLAYER.exists():
        pytest.skip(f"lottie-web is not installed in {JS / 'node_modules'}: run `npm ci --prefix tests/js` "
                    "(needs npm and the network)")
    return PLAYER


@pytest.mark.browser
@pytest.mark.network
@pytest.mark.parametrize("case", ["painted", "mesh"])
def test_lottie_web_draws_what_isotween_draws(tmp_path, browser, player, morph, case):
    seq = morph if case == "painted" else mesh_sequence()
    size = 240
    data = lottie_data(seq, size=size, background="white")
    renderer = SequenceRenderer(seq, size)
    assert (renderer.width, renderer.height) == (data["w"], data["h"])
    page = browser.new_page(viewport={"width": data["w"] + 20, "height": data["h"] + 20})
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    try:
        page.set_content(f'<body style="margin:0;background:#fff"><div id="anim" '
                         f'style="width:{data["w"]}px;height:{data["h"]}px"></div></body>')
        page.add_script_tag(path=str(player))
        render.write_lottie(seq, tmp_path / "a.lottie.json", size=size, background="white")
        text = (tmp_path / "a.lottie.json").read_text()
        assert json.loads(text) == data  # the file is lottie_data
        page.evaluate("text => { window.anim = lottie.loadAnimation({container: document.getElementById('anim'),"
                      " renderer: 'svg', loop: false, autoplay: false, animationData: JSON.parse(text)}); }", text)
        for k in range(len(seq)):
            page.evaluate(f"window.anim.goToAndStop({k}, true)")
            theirs = screenshot(page, "#anim").astype(int)
            ours = renderer.image(k).astype(int)
            assert theirs.shape == ours.shape
            differ = np.abs(theirs - ours).max(axis=2) > 60
            # edges are anti-aliased differently: allow a thin seam of differing pixels
            assert differ.mean() < 0.02, (case, k, differ.mean())
    finally:
        page.close()
    assert not errors
