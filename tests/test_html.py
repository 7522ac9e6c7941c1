"""The HTML viewer: its embedded data, and every control of the page driven in headless Chromium."""

import base64
import json
import re
import time
import xml.etree.ElementTree as ET
import zlib

import numpy as np
import pytest

from browser import screenshot
from isotween import Sequence, Shape, interpolate, interpolate_keyframes, render
from isotween.render.html import decode_frames, page_data
from isotween.render.lottie import lottie_data
from shapes import bend, grid_mesh


@pytest.fixture(scope="module")
def bent_bar():
    bar = grid_mesh(13, 4, length=4.0, width=1.0)
    return interpolate(bar, bar.with_vertices(bend(bar.vertices, np.pi / 2)), frames=7)


def embedded_json(path):
    text = path.read_text(encoding="utf-8")
    match = re.search(r'<script type="application/json" id="isotween-data">(.*?)</script>', text, re.S)
    return json.loads(match.group(1))


def unpack(packed, dtype):
    return np.frombuffer(zlib.decompress(base64.b64decode(packed)), dtype=dtype)


def test_page_embeds_frames_and_per_frame_metrics(tmp_path, bent_bar):
    render.write_html(bent_bar, tmp_path / "a.html", title="bar </script><b>")
    text = (tmp_path / "a.html").read_text(encoding="utf-8")
    fetchable = text.replace('xmlns="http://www.w3.org/2000/svg"', "")  # a namespace name, not fetched
    assert "http://" not in fetchable and "https://" not in fetchable  # nothing to fetch
    assert text.count("</script>") == 2  # the title cannot close the data block
    data = embedded_json(tmp_path / "a.html")
    assert data["title"] == "bar </script><b>"
    frames = decode_frames(data["frames"], bent_bar.frames.shape)
    side = np.ptp(bent_bar.frames.reshape(-1, 2), axis=0).max()
    assert np.abs(frames - bent_bar.frames).max() <= side / 65000  # 16-bit levels, within one step
    assert unpack(data["faces"]["data"], "<u2").tolist() == bent_bar.shape.faces.ravel().tolist()
    assert unpack(data["edges"]["data"], "<u2").tolist() == bent_bar.shape.edges.ravel().tolist()
    # per-frame edge length deviation: exact at the inputs, and matching the definition
    L = np.abs(bent_bar.edge_vectors())
    t = bent_bar.times[:, None]
    dev = np.abs(L / ((1 - t) * L[0] + t * L[-1]) - 1).max(axis=1)
    assert np.allclose(data["stats"]["edge"], dev, atol=1e-6)
    assert data["stats"]["edge"][0] == data["stats"]["edge"][-1] == 0
    # the download buttons' files are the library's own
    lottie = zlib.decompress(base64.b64decode(data["downloads"]["lottie"])).decode()
    assert json.loads(lottie) == lottie_data(bent_bar, title="bar </script><b>")


def test_frame_encoding_wraps_exactly():
    # moves of more than half the range between frames overflow int16 deltas; the decoder undoes it
    shape = Shape.from_polyline([[0.0, 0.0], [1.0, 0.0]])
    frames = np.array([[[0, 0], [1, 0]], [[1, 1], [0, 1]], [[0, 1], [1, 0]]], float)
    data = page_data(Sequence(frames, shape))
    assert np.abs(decode_frames(data["frames"], frames.shape) - frames).max() <= 1 / 65000


def test_flipped_faces_per_frame():
    tri = Shape.from_mesh(np.array([[0, 0], [1, 0], [0, 1.0], [1, 1.0]]), np.array([[0, 1, 2], [1, 3, 2]]))
    mirrored = tri.vertices.copy()
    mirrored[3] = [0.2, 0.2]  # folds face 1 over face 0
    seq = Sequence(np.stack([tri.vertices, mirrored, tri.vertices]), tri)
    data = page_data(seq)
    assert data["stats"]["flipped"] == [0, 1, 0]
    assert data["flippedFaces"] == [[], [1], []]


def test_texture_is_embedded_as_png(bent_bar):
    tex = np.zeros((4, 6, 3), np.uint8)
    tex[:, :3] = 255
    data = page_data(bent_bar, texture=tex)
    assert data["texture"].startswith("data:image/png;base64,")
    png = base64.b64decode(data["texture"].split(",", 1)[1])
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    uv = np.array(data["uv"]).reshape(-1, 2)
    assert uv.min() >= 0 and uv.max() <= 1 and len(uv) == bent_bar.shape.n_vertices


def big_sequence(n_side=208, frames=30):
    """A 43k-vertex grid mesh turning and stretching (frames made directly, no solve)."""
    mesh = grid_mesh(n_side, n_side, length=1.0, width=1.0)
    z = mesh.z
    t = np.linspace(0, 1, frames)[:, None]
    zt = (z - 0.5 - 0.5j) * np.exp(1j * np.pi * t) * (1 + 0.3 * t * z.real) + 2 * t
    return Sequence(np.stack([zt.real, zt.imag], axis=-1), mesh)


def test_large_page_stays_small(tmp_path):
    seq = big_sequence()
    assert seq.shape.n_vertices >= 43000 and len(seq) == 30
    render.write_html(seq, tmp_path / "big.html")
    size = (tmp_path / "big.html").stat().st_size
    assert size <= 8 * 2**20, size  # the bound: at most 8 MB


# ---------------------------------------------------------------- headless Chromium
@pytest.fixture
def page(browser):
    page = browser.new_page(viewport={"width": 900, "height": 640}, accept_downloads=True)
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    yield page
    page.close()
    assert errors == []


def wait_ready(page, timeout=60.0):
    """Wait until the page has inflated its data and drawn its first frame (polled from here)."""
    deadline = time.monotonic() + timeout
    while page.evaluate("document.body.dataset.ready") != "1":
        if time.monotonic() > deadline:
            raise TimeoutError("the page never drew its first frame")
        time.sleep(0.02)


def open_page(page, path):
    page.goto(path.as_uri())
    wait_ready(page)


def canvas_pixels(page):
    return screenshot(page, "#view").astype(int)


def test_every_control(tmp_path, page, bent_bar):
    tex = np.zeros((32, 32, 3), np.uint8)
    yy, xx = np.mgrid[0:32, 0:32]
    tex[(xx // 8 + yy // 8) % 2 == 0] = [220, 60, 30]
    tex[(xx // 8 + yy // 8) % 2 == 1] = [30, 90, 200]
    path = tmp_path / "viewer.html"
    render.write_html(bent_bar, path, texture=tex, title="bent bar")
    open_page(page, path)
    assert page.title() == "bent bar"
    assert page.locator("#title").inner_text() == "bent bar"
    # slider and keys
    page.locator("#slider").fill("3")
    assert page.evaluate("window.isotween.frame()") == 3
    page.locator("#view").click()
    page.keyboard.press("End")
    assert page.evaluate("window.isotween.frame()") == 6
    page.keyboard.press("ArrowLeft")
    assert page.evaluate("window.isotween.frame()") == 5
    page.keyboard.press("Home")
    assert page.evaluate("window.isotween.frame()") == 0
    page.keyboard.press("ArrowRight")
    assert page.evaluate("window.isotween.frame()") == 1
    # every view mode draws something different; the texture shows its colours
    modes = page.eval_on_selector_all("#mode option", "os => os.map(o => o.value)")
    assert modes == ["wire", "fill", "texture"]
    shots = {}
    for mode in modes:
        page.select_option("#mode", mode)
        shots[mode] = canvas_pixels(page)
    assert all(np.abs(shots[a] - shots[b]).max() > 100 for a in modes for b in modes if a < b)
    red = (shots["texture"][..., 0] > 180) & (shots["texture"][..., 2] < 80)
    blue = (shots["texture"][..., 2] > 160) & (shots["texture"][..., 0] < 80)
    assert red.sum() > 1000 and blue.sum() > 1000
    # onion skin adds the ghosts of the first and last frames
    page.select_option("#mode", "fill")
    page.evaluate("window.isotween.setFrame(3)")
    plain = canvas_pixels(page)
    page.check("#onion")
    ghosts = canvas_pixels(page)
    assert (np.abs(ghosts - plain).max(axis=2) > 10).sum() > 1000
    page.uncheck("#onion")
    # zoom with the wheel, pan by dragging, fit undoes both
    box = page.locator("#view").bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.wheel(0, -400)
    assert page.evaluate("window.isotween.view().zoom") > 1.5
    page.mouse.down()
    page.mouse.move(box["x"] + box["width"] / 2 + 60, box["y"] + box["height"] / 2 + 30)
    page.mouse.up()
    view = page.evaluate("window.isotween.view()")
    assert abs(view["panX"] - 60) < 2 and abs(view["panY"] - 30) < 2
    page.click("#fit")
    assert page.evaluate("window.isotween.view()") == {"zoom": 1, "panX": 0, "panY": 0}
    assert np.abs(canvas_pixels(page) - plain).max() == 0
    # play advances frames, speed and bounce are read while playing
    page.select_option("#speed", "4")
    page.check("#bounce")
    page.click("#play")
    seen, deadline = set(), time.monotonic() + 5  # a loaded machine may render the first ticks late
    while len(seen) < 3 and time.monotonic() < deadline:
        seen.add(page.evaluate("window.isotween.frame()"))
        time.sleep(0.02)
    page.click("#play")
    assert page.locator("#play").inner_text() == "Play" and len(seen) >= 3
    paused = page.evaluate("window.isotween.frame()")
    time.sleep(0.2)
    assert page.evaluate("window.isotween.frame()") == paused


def test_downloads(tmp_path, page, bent_bar):
    path = tmp_path / "d.html"
    render.write_html(bent_bar, path, title="bar")
    open_page(page, path)
    page.evaluate("window.isotween.setFrame(2)")
    files = {}
    for button in ("dl-png", "dl-svg", "dl-lottie", "dl-anim"):
        with page.expect_download() as info:
            page.click(f"#{button}")
        files[button] = tmp_path / info.value.suggested_filename
        info.value.save_as(files[button])
    assert files["dl-png"].name == "bar-frame2.png" and files["dl-png"].read_bytes()[:4] == b"\x89PNG"
    # the frame SVG holds frame 2's vertices (y mirrored: the bar is y-up)
    root = ET.parse(files["dl-svg"]).getroot()
    ns = "{http://www.w3.org/2000/svg}"
    fill = root.find(f"{ns}path").get("d")
    numbers = np.array([float(x) for x in re.findall(r"-?\d+\.?\d*(?:e-?\d+)?", fill)]).reshape(-1, 2)
    faces = bent_bar.shape.faces
    np.testing.assert_allclose(numbers, bent_bar.frames[2][faces.ravel()] * [1, -1], atol=1e-3)
    assert json.loads(files["dl-lottie"].read_text()) == lottie_data(bent_bar, title="bar")
    assert files["dl-lottie"].name == "bar.lottie.json"
    anim = files["dl-anim"].read_text()
    assert "<animate" in anim and ET.fromstring(anim.encode()).tag == f"{ns}svg"


def test_keyframe_marks_and_large_sequences_without_embedded_animations(tmp_path, page):
    bar = grid_mesh(9, 3, length=4.0, width=1.0)
    keys = [bar, bar.with_vertices(bend(bar.vertices, np.pi / 3)), bar.with_vertices(bend(bar.vertices, -np.pi / 3))]
    seq = interpolate_keyframes(keys, frames=13)
    render.write_html(seq, tmp_path / "k.html")
    open_page(page, tmp_path / "k.html")
    marks = page.eval_on_selector_all("#keyframe-list option", "os => os.map(o => Number(o.value))")
    assert marks == sorted(seq.info["keyframe_indices"]) == [0, 6, 12]
    assert page.locator("#marks span").count() == 3
    render.write_html(big_sequence(60, 4), tmp_path / "m.html", downloads=False)
    open_page(page, tmp_path / "m.html")
    assert page.locator("#dl-lottie").is_disabled() and page.locator("#dl-anim").is_disabled()
    assert "isotween render" in page.locator("#dl-lottie").get_attribute("title")


def test_phone_width_layout(tmp_path, browser, bent_bar):
    render.write_html(bent_bar, tmp_path / "p.html")
    page = browser.new_page(viewport={"width": 375, "height": 740})
    try:
        open_page(page, tmp_path / "p.html")
        box = page.locator("#view").bounding_box()
        assert box["width"] >= 340 and box["height"] >= 240  # was 95 px wide
        assert page.evaluate("document.documentElement.scrollWidth") <= 375  # no sideways scrolling
    finally:
        page.close()
