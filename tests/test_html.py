"""The HTML viewer: its embedded data, and the page itself driven in headless Chromium.

Chromium is driven through the DevTools protocol over ``--remote-debugging-pipe``
(NUL-terminated JSON on file descriptors 3 and 4), standard library only.
"""

import base64
import fcntl
import json
import os
import re
import shutil
import subprocess
import time

import numpy as np
import pytest

from isotween import Sequence, Shape, interpolate
from isotween import render
from isotween.render.html import page_data

from shapes import bend, grid_mesh

CHROMIUM_FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--remote-debugging-pipe",
    "--window-size=900,640",
]


@pytest.fixture(scope="module")
def bent_bar():
    bar = grid_mesh(13, 4, length=4.0, width=1.0)
    return interpolate(bar, bar.with_vertices(bend(bar.vertices, np.pi / 2)), frames=7)


def embedded_json(path):
    text = path.read_text(encoding="utf-8")
    match = re.search(r'<script type="application/json" id="isotween-data">(.*?)</script>', text, re.S)
    return json.loads(match.group(1))


def test_page_embeds_frames_and_per_frame_metrics(tmp_path, bent_bar):
    render.write_html(bent_bar, tmp_path / "a.html", title="bar </script><b>")
    text = (tmp_path / "a.html").read_text(encoding="utf-8")
    assert "http://" not in text and "https://" not in text  # nothing to fetch
    assert text.count("</script>") == 2  # the title cannot close the data block
    data = embedded_json(tmp_path / "a.html")
    assert data["title"] == "bar </script><b>"
    frames = np.array(data["frames"]).reshape(bent_bar.frames.shape)
    assert np.abs(frames - bent_bar.frames).max() < 1e-4
    assert data["faces"] == bent_bar.shape.faces.ravel().tolist()
    # per-frame edge length deviation: exact at the inputs, and matching the definition
    L = np.abs(bent_bar.edge_vectors())
    t = bent_bar.times[:, None]
    dev = np.abs(L / ((1 - t) * L[0] + t * L[-1]) - 1).max(axis=1)
    assert np.allclose(data["stats"]["edge"], dev, atol=1e-6)
    assert data["stats"]["edge"][0] == data["stats"]["edge"][-1] == 0


def test_flipped_faces_per_frame():
    tri = Shape.from_mesh(np.array([[0, 0], [1, 0], [0, 1.0], [1, 1.0]]), np.array([[0, 1, 2], [1, 3, 2]]))
    mirrored = tri.vertices.copy()
    mirrored[3] = [0.2, 0.2]  # folds face 1 over face 0
    seq = Sequence(np.stack([tri.vertices, mirrored, tri.vertices]), tri)
    data = page_data(seq)
    assert data["stats"]["flipped"] == [0, 1, 0]
    assert data["flippedFaces"] == [[], [1], []]


def test_texture_is_embedded_as_png(tmp_path, bent_bar):
    tex = np.zeros((4, 6, 3), np.uint8)
    tex[:, :3] = 255
    data = page_data(bent_bar, texture=tex)
    assert data["texture"].startswith("data:image/png;base64,")
    png = base64.b64decode(data["texture"].split(",", 1)[1])
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    uv = np.array(data["uv"]).reshape(-1, 2)
    assert uv.min() >= 0 and uv.max() <= 1 and len(uv) == bent_bar.shape.n_vertices


# ---------------------------------------------------------------- headless Chromium
def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable"):
        path = shutil.which(name)
        if path:
            return path
    return None


class DevTools:
    """Minimal DevTools-protocol client over Chromium's debugging pipe."""

    def __init__(self, binary, profile):
        to_child_r, self._to_child = os.pipe()
        self._from_child, from_child_w = os.pipe()

        def wire_fds():  # the browser reads commands on fd 3 and answers on fd 4
            read_end = fcntl.fcntl(to_child_r, fcntl.F_DUPFD, 10)  # out of the way of 3 and 4
            write_end = fcntl.fcntl(from_child_w, fcntl.F_DUPFD, 10)
            os.dup2(read_end, 3)
            os.dup2(write_end, 4)

        self.proc = subprocess.Popen(
            [binary, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", "about:blank"],
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
            pass_fds=(3, 4),
            preexec_fn=wire_fds,
        )
        os.close(to_child_r)
        os.close(from_child_w)
        self._buffer = b""
        self._next_id = 0
        self.events = []
        self.session = None

    def _read_message(self, deadline):
        while b"\0" not in self._buffer:
            if time.monotonic() > deadline:
                raise TimeoutError("no answer from Chromium")
            chunk = os.read(self._from_child, 1 << 16)
            if not chunk:
                raise RuntimeError("Chromium closed the debugging pipe")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def call(self, method, timeout=10.0, **params):
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params}
        if self.session and not method.startswith("Target."):
            message["sessionId"] = self.session
        os.write(self._to_child, json.dumps(message).encode() + b"\0")
        deadline = time.monotonic() + timeout
        while True:
            reply = self._read_message(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
            self.events.append(reply)

    def wait_event(self, method, timeout=10.0):
        deadline = time.monotonic() + timeout
        seen = [e for e in self.events if e.get("method") == method]
        while not seen:
            event = self._read_message(deadline)
            self.events.append(event)
            if event.get("method") == method:
                return event
        return seen[0]

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in result:
            raise AssertionError(f"{expression}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def close(self):
        try:
            self.call("Browser.close", timeout=3.0)
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        os.close(self._to_child)
        os.close(self._from_child)


def _console_errors(events):
    errors = []
    for e in events:
        method, params = e.get("method"), e.get("params", {})
        if method == "Runtime.exceptionThrown":
            errors.append(params["exceptionDetails"].get("text", "exception"))
        elif method == "Runtime.consoleAPICalled" and params.get("type") in ("error", "assert"):
            errors.append(str(params.get("args")))
        elif method == "Log.entryAdded" and params["entry"].get("level") == "error":
            errors.append(params["entry"].get("text"))
    return errors


def test_page_in_headless_chromium(tmp_path, bent_bar):
    binary = _chromium()
    if binary is None:
        pytest.skip("no chromium binary found (Debian: apt-get install chromium)")
    tex = np.zeros((32, 32, 3), np.uint8)
    yy, xx = np.mgrid[0:32, 0:32]
    tex[(xx // 8 + yy // 8) % 2 == 0] = [220, 60, 30]
    tex[(xx // 8 + yy // 8) % 2 == 1] = [30, 90, 200]
    page = tmp_path / "viewer.html"
    render.write_html(bent_bar, page, texture=tex, title="bent bar")

    browser = DevTools(binary, tmp_path / "profile")
    try:
        target = browser.call("Target.createTarget", url="about:blank")["targetId"]
        browser.session = browser.call("Target.attachToTarget", targetId=target, flatten=True)["sessionId"]
        for domain in ("Page", "Runtime", "Log"):
            browser.call(f"{domain}.enable")
        browser.call("Page.navigate", url=page.as_uri())
        browser.wait_event("Page.loadEventFired")
        deadline = time.monotonic() + 5
        while not browser.evaluate("window.isotween && window.isotween.textureReady()"):
            assert time.monotonic() < deadline, "texture never loaded"
            time.sleep(0.05)

        assert browser.evaluate("window.isotween.nFrames") == len(bent_bar)
        assert browser.evaluate("window.isotween.frame()") == 0
        assert browser.evaluate("document.getElementById('mode').value") == "texture"
        first = browser.evaluate("document.getElementById('view').toDataURL()")
        # move the slider as a user would: set its value and dispatch an input event
        browser.evaluate(
            "(() => { const s = document.getElementById('slider'); s.value = '6';"
            " s.dispatchEvent(new Event('input')); })()"
        )
        assert browser.evaluate("window.isotween.frame()") == 6
        last = browser.evaluate("document.getElementById('view').toDataURL()")
        assert last != first
        assert browser.evaluate("document.getElementById('m-frame').textContent") == "6 / 6"
        # textured and wireframe drawings of the same frame differ; going back restores frame 0
        browser.evaluate(
            "(() => { const m = document.getElementById('mode'); m.value = 'wire';"
            " m.dispatchEvent(new Event('change')); })()"
        )
        wire = browser.evaluate("document.getElementById('view').toDataURL()")
        assert wire not in (first, last)
        browser.evaluate("window.isotween.setFrame(0)")
        browser.evaluate(
            "(() => { const m = document.getElementById('mode'); m.value = 'texture';"
            " m.dispatchEvent(new Event('change')); })()"
        )
        assert browser.evaluate("document.getElementById('view').toDataURL()") == first
        # the canvas shows the texture's colours where the bar is
        counts = browser.evaluate(
            "(() => { const c = document.getElementById('view'), d = c.getContext('2d')"
            ".getImageData(0, 0, c.width, c.height).data; let red = 0, blue = 0;"
            " for (let i = 0; i < d.length; i += 4) { if (d[i] > 180 && d[i + 2] < 80) red++;"
            " if (d[i + 2] > 160 && d[i] < 80) blue++; } return [red, blue]; })()"
        )
        assert min(counts) > 2000
        # play advances frames
        browser.evaluate("document.getElementById('play').click()")
        deadline = time.monotonic() + 5  # a loaded machine may render the first ticks late
        while browser.evaluate("window.isotween.frame()") == 0 and time.monotonic() < deadline:
            time.sleep(0.1)
        browser.evaluate("document.getElementById('play').click()")
        assert browser.evaluate("window.isotween.frame()") != 0

        shot = browser.call("Page.captureScreenshot", format="png")["data"]
        (tmp_path / "viewer.png").write_bytes(base64.b64decode(shot))
        assert (tmp_path / "viewer.png").read_bytes()[:4] == b"\x89PNG"
        assert _console_errors(browser.events) == []
    finally:
        browser.close()
