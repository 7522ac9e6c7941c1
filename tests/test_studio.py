"""isotween studio: the server's checks and API (Starlette's TestClient), and a whole session in Chromium."""

import io
import json
import sys

import numpy as np
import pytest

import isotween
from isotween.studio.deform import arap_deform

pytest.importorskip("starlette", reason="the studio extra is not installed (pip install 'isotween[studio]')")
pytest.importorskip("uvicorn", reason="the studio extra is not installed (pip install 'isotween[studio]')")
pytest.importorskip("multipart", reason="the studio extra is not installed (pip install 'isotween[studio]')")

with __import__("warnings").catch_warnings():  # starlette's note about httpx2
    __import__("warnings").simplefilter("ignore")
    from starlette.testclient import TestClient  # noqa: E402

from isotween.studio.server import create_app  # noqa: E402
from isotween.studio.session import Session  # noqa: E402

TOKEN = "secret-token"
PORT = 8123
H = {"X-Isotween-Token": TOKEN}


def star(k=7, r0=1.0, r1=0.5):
    th = np.linspace(0, 2 * np.pi, 2 * k, endpoint=False)
    r = np.where(np.arange(2 * k) % 2 == 0, r0, r1)
    return isotween.Shape.from_polygon(np.c_[r * np.cos(th), r * np.sin(th)])


@pytest.fixture
def drawings(tmp_path):
    """Two SVG drawings of different point counts (a square and a star)."""
    a, b = tmp_path / "square.svg", tmp_path / "star.svg"
    isotween.save(isotween.Shape.from_polygon([[0, 0], [2, 0], [2, 2], [0, 2]]), a)
    isotween.save(star().translate([3, 0]), b)
    return a, b


def client_for(session, **kw):
    app = create_app(session, TOKEN, port=PORT, **kw)
    return TestClient(app, base_url=f"http://127.0.0.1:{PORT}", raise_server_exceptions=False)


@pytest.fixture
def opened(drawings):
    """A client whose session has the two drawings open."""
    session = Session(drawings)
    client = client_for(session)
    r = client.post("/api/open", json={"paths": [str(p) for p in drawings]}, headers=H)
    assert r.status_code == 200, r.text
    return client, session


# ---------------------------------------------------------------- the checks
def test_token_is_required(drawings):
    client = client_for(Session(drawings))
    for r in (client.get("/api/state"), client.get("/api/state", headers={"X-Isotween-Token": "wrong"}),
              client.get("/?token=wrong"), client.get("/"), client.post("/api/open", json={"example": "bar"}),
              client.get("/api/project")):
        assert r.status_code == 403 and "token" in r.json()["error"]
    assert client.get("/static/app.js").status_code == 200  # the package's own scripts are public
    assert client.get("/static/%2e%2e/session.py").status_code == 404  # nothing but the static folder
    r = client.get(f"/?token={TOKEN}")
    assert r.status_code == 200 and "isotween studio" in r.text
    assert client.cookies.get("isotween_studio_token") == TOKEN
    assert client.get("/api/state").status_code == 200  # with the cookie
    client.cookies.clear()
    assert client.get("/api/state", headers=H).status_code == 200


def test_host_and_origin_are_checked(drawings):
    client = client_for(Session(drawings))
    for host in ("evil.example", f"evil.example:{PORT}", f"127.0.0.1:{PORT + 1}", "127.0.0.1.evil.example"):
        r = client.get("/api/state", headers={**H, "Host": host})
        assert r.status_code == 403 and "127.0.0.1" in r.json()["error"], host
    assert client.get("/api/state", headers={**H, "Host": f"localhost:{PORT}"}).status_code == 200
    for origin in ("http://evil.example", f"http://127.0.0.1:{PORT + 1}", "null"):
        r = client.post("/api/open", json={"example": "bar"}, headers={**H, "Origin": origin})
        assert r.status_code == 403 and "other sites" in r.json()["error"], origin
    r = client.post("/api/options", json={"frames": 5}, headers={**H, "Origin": f"http://127.0.0.1:{PORT}"})
    assert r.status_code == 400 and "open two drawings" in r.json()["error"]  # past the checks


def test_upload_size_is_limited(drawings):
    session = Session(drawings)
    client = client_for(session, max_upload=4096)
    r = client.post("/api/upload", files={"file": ("big.svg", b"<svg>" + b" " * 10000 + b"</svg>")}, headers=H)
    assert r.status_code == 413 and "too large" in r.json()["error"]
    r = client.post("/api/upload", files={"file": ("a.svg", drawings[0].read_bytes())}, headers=H)
    assert r.status_code == 200 and len(r.json()["ids"]) == 1


def test_paths_not_named_on_the_command_line_are_refused(drawings, tmp_path):
    session = Session(drawings[:1])
    client = client_for(session)
    other = tmp_path / "other.svg"
    other.write_bytes(drawings[1].read_bytes())
    for path in (str(other), "/etc/passwd", str(drawings[0]) + "/../" + drawings[1].name):
        r = client.post("/api/open", json={"paths": [str(drawings[0]), path]}, headers=H)
        assert r.status_code == 400 and "only uploads and the files named" in r.json()["error"]
    assert session.doc is None
    assert client.get("/api/state", headers=H).status_code == 200


def test_malformed_requests_and_bad_files_are_answered_cleanly(opened):
    client, session = opened
    doc = json.dumps(session.doc)
    bad = [
        client.post("/api/options", content=b"{not json", headers={**H, "Content-Type": "application/json"}),
        client.post("/api/options", json=[1, 2], headers=H),
        client.post("/api/options", json={"frames": "many"}, headers=H),
        client.post("/api/options", json={"colour": 1}, headers=H),
        client.post("/api/options", json={"method": "magic"}, headers=H),
        client.post("/api/open", json={"inputs": "x"}, headers=H),
        client.post("/api/open", json={"inputs": ["nope", "nada"]}, headers=H),
        client.post("/api/deform", json={"frame": 1, "handles": [[0, "x"]]}, headers=H),
        client.post("/api/edit", json={"frame": 99, "handles": [[0, 1, 1]]}, headers=H),
        client.post("/api/export", json={"kind": "doc"}, headers=H),
        client.post("/api/upload", files={"file": ("broken.svg", b"<svg><path d='M 0 0 L")}, headers=H),
        client.post("/api/upload", files={"file": ("notes.txt", b"hello")}, headers=H),
        client.post("/api/upload", content=b"x", headers={**H, "Content-Type": "multipart/form-data"}),
        client.post("/api/project", content=b'{"format": "something else"}', headers=H),
        client.post("/api/undo", headers=H),
    ]
    for r in bad:
        assert r.status_code == 400, r.text
        assert set(r.json()) == {"error"} and r.json()["error"]
    assert json.dumps(session.doc) == doc  # nothing changed
    assert client.post("/api/options", json={"frames": 7}, headers=H).json()["sequence"]["count"] == 7


def test_a_solve_that_raises_keeps_the_session(opened, monkeypatch):
    client, session = opened
    before = client.get("/api/state", headers=H).json()

    def boom(*args, **kwargs):
        raise RuntimeError("solver exploded")

    monkeypatch.setattr(sys.modules["isotween.interpolate"], "interpolate", boom)
    r = client.post("/api/options", json={"frames": 21}, headers=H)
    assert r.status_code == 500 and "solver exploded" in r.json()["error"] and "unchanged" in r.json()["error"]

    def refuse(*args, **kwargs):
        raise isotween.errors.ParameterError("no, thanks")

    monkeypatch.setattr(sys.modules["isotween.interpolate"], "interpolate", refuse)
    r = client.post("/api/options", json={"frames": 22}, headers=H)
    assert r.status_code == 400 and r.json() == {"error": "no, thanks"}
    monkeypatch.undo()
    after = client.get("/api/state", headers=H).json()
    assert after["document"] == before["document"] and after["sequence"] == before["sequence"]
    assert client.post("/api/options", json={"frames": 21}, headers=H).json()["sequence"]["count"] == 21


def test_a_superseded_solve_is_dropped(opened, monkeypatch):
    client, session = opened
    real = sys.modules["isotween.interpolate"].interpolate

    def meanwhile(*args, **kwargs):
        session.generation += 1  # a newer request arrives during this solve
        return real(*args, **kwargs)

    monkeypatch.setattr(sys.modules["isotween.interpolate"], "interpolate", meanwhile)
    r = client.post("/api/options", json={"frames": 9}, headers=H)
    assert r.status_code == 200 and r.json()["superseded"] is True
    assert session.doc["options"]["frames"] == 13 and len(session.solved.sequence) == 13


# ---------------------------------------------------------------- the session through the API
def test_morph_matches_the_command_line_path(opened, drawings):
    client, session = opened
    src, tgt, _ = isotween.correspond(isotween.load(drawings[0]), isotween.load(drawings[1]))
    expected = isotween.interpolate(src, tgt, 13, fold="fallback")
    assert session.solved.sequence.equals(expected, atol=1e-9)
    state = client.get("/api/state", headers=H).json()
    frames = np.frombuffer(__import__("base64").b64decode(state["sequence"]["frames"]), "<f8")
    assert np.array_equal(frames.reshape(expected.frames.shape), expected.frames)


def test_edit_undo_redo_and_options(opened):
    client, session = opened
    base = session.solved.sequence
    k, handles = 6, [[0, 0.5, -0.8], [5, float(base.frames[6, 5, 0]), float(base.frames[6, 5, 1])]]
    r = client.post("/api/deform", json={"frame": k, "handles": handles, "anchor": 0}, headers=H)
    preview = np.frombuffer(__import__("base64").b64decode(r.json()["vertices"]), "<f8").reshape(-1, 2)
    assert np.allclose(preview[[0, 5]], [[0.5, -0.8], handles[1][1:]])
    state = client.post("/api/edit", json={"frame": k, "handles": handles, "anchor": 0}, headers=H).json()
    assert state["document"]["edited"] == [k] and state["sequence"]["keys"] == [0, k, 12]
    edited = base.shape.with_vertices(session.doc["edits"][str(k)])
    assert np.allclose(edited.vertices, preview)
    expected = isotween.edit(base, frame=k, shape=edited)
    assert np.max(np.abs(session.solved.sequence.frames - expected.frames)) < 1e-9
    state = client.post("/api/undo", headers=H).json()
    assert state["document"]["edited"] == [] and state["redo"] == 1
    assert session.solved.sequence.equals(base, atol=0)
    state = client.post("/api/redo", headers=H).json()
    assert state["document"]["edited"] == [k]
    assert np.max(np.abs(session.solved.sequence.frames - expected.frames)) < 1e-9
    from isotween.optimisation.assembly import _OWNED

    assert base in _OWNED  # the redo's edit reused the first one's factorisation of Eq. (10), kept per morph
    client.post("/api/edit", json={"frame": 3, "handles": [[0, 0.2, -0.9]], "anchor": 0}, headers=H)
    both = {k: edited, 3: base.shape.with_vertices(session.doc["edits"]["3"])}
    assert session.solved.sequence.equals(isotween.edit(base, edits=both), atol=0)  # bit for bit
    client.post("/api/undo", headers=H)
    state = client.post("/api/options", json={"method": "linear", "easing": [0.42, 0, 0.58, 1]}, headers=H).json()
    assert state["document"]["edited"] == [k] and state["sequence"]["method"] == "edit"
    assert session.solved.base.method == "linear" and session.solved.base.times[1] < 1 / 12
    state = client.post("/api/options", json={"frames": 9}, headers=H).json()
    assert state["document"]["edited"] == [] and state["sequence"]["count"] == 9  # edits belong to a frame count


def test_transfer_export_and_project_round_trip(opened, drawings, tmp_path):
    client, session = opened
    third = tmp_path / "triangle.svg"
    isotween.save(isotween.Shape.from_polygon([[0, 0], [1, 0], [0.5, 1]]).translate([0, 3]), third)
    ids = client.post("/api/upload", files={"file": ("triangle.svg", third.read_bytes())}, headers=H).json()["ids"]
    state = client.post("/api/open", json={"inputs": ids, "role": "third"}, headers=H).json()
    assert state["transfer"]["count"] == 13 and state["third_name"] == "triangle.svg"
    client.post("/api/edit", json={"frame": 4, "handles": [[1, 2.5, 0.3]]}, headers=H)
    r = client.post("/api/export", json={"kind": "lottie", "fps": 12, "size": 200}, headers=H)
    lottie = json.loads(r.content)
    # the studio's timing, not the library's rendered defaults: the 13 frames, one per tick, no hold
    assert r.status_code == 200 and lottie["fr"] == 12 and lottie["op"] - lottie["ip"] == 13
    r = client.post("/api/export", json={"kind": "lottie", "fps": 12, "duration": 2.5, "hold": 0.5}, headers=H)
    lottie = json.loads(r.content)  # 2.5 s of motion: 2.5 * 12 + 1 = 31 frames, held 0.5 * 12 = 6 ticks at both ends
    assert r.status_code == 200 and lottie["fr"] == 12 and lottie["op"] - lottie["ip"] == 31 + 2 * 6
    from PIL import Image

    r = client.post("/api/export", json={"kind": "gif", "size": 120}, headers=H)
    with Image.open(io.BytesIO(r.content)) as gif:
        assert gif.n_frames == 13
    r = client.post("/api/export", json={"kind": "npz", "which": "transfer"}, headers=H)
    (tmp_path / "t.npz").write_bytes(r.content)
    assert np.allclose(isotween.load_sequence(tmp_path / "t.npz").frames, session.solved.transfer.frames, atol=1e-12)
    project = client.get("/api/project", headers=H).content
    fresh = Session()
    other = client_for(fresh)
    state = other.post("/api/project", content=project, headers=H).json()
    assert state["document"] == client.get("/api/state", headers=H).json()["document"]
    assert fresh.solved.sequence.equals(session.solved.sequence, atol=1e-12)
    assert fresh.solved.transfer.equals(session.solved.transfer, atol=1e-12)


def near_target(sequence, pair):
    """How far the vertex nearest a landmark's source point in frame 0 is from its target point in the last."""
    (x0, y0), (x1, y1) = pair
    i = int(np.argmin(np.linalg.norm(sequence.frames[0] - [x0, y0], axis=1)))
    return float(np.linalg.norm(sequence.frames[-1][i] - [x1, y1]))


def test_examples_and_landmarks(drawings):
    session = Session()
    client = client_for(session)
    state = client.post("/api/open", json={"example": "bar"}, headers=H).json()
    assert state["sequence"]["count"] == 13 and state["names"] == ["bar (source)", "bar (target)"]
    state = client.post("/api/hints", json={"landmarks": [[[0, 0], [0, 0]]]}, headers=H).json()
    assert state["document"]["landmarks"] == [[[0, 0], [0, 0]]]


def test_landmarks_are_passed_to_correspond(opened, drawings):
    client, session = opened
    a, b = isotween.load(drawings[0]), isotween.load(drawings[1])  # the square's corner (0, 0), a tip of the star
    pair = [[0.0, 0.0], [4.0, 0.0]]
    before = near_target(session.solved.sequence, pair)
    assert before > 0.5  # not where the landmark puts it
    state = client.post("/api/hints", json={"landmarks": [pair]}, headers=H).json()
    assert state["document"]["landmarks"] == [pair] and state["notes"] == []
    src, tgt, _ = isotween.correspond(a, b, landmarks=[pair])
    assert session.solved.sequence.equals(isotween.interpolate(src, tgt, 13, fold="fallback"), atol=1e-9)
    assert near_target(session.solved.sequence, pair) < 1e-9
    doc = json.dumps(session.doc)
    for bad, says in (([[0.0, 0.0], [3.0, 0.0]], "is not on the drawing"),  # the star's centre: off its outline
                      ([[1.0, -1.0], [4.0, 0.0]], "is not on the drawing"),
                      ([[0.0, 0.0]], "point pairs"), ([["x", 0], [4, 0]], "point pairs")):
        r = client.post("/api/hints", json={"landmarks": [pair, bad]}, headers=H)
        assert r.status_code == 400 and says in r.json()["error"], r.text
        assert "\n" not in r.json()["error"]
    assert json.dumps(session.doc) == doc  # a refused landmark changes nothing
    state = client.post("/api/undo", headers=H).json()  # undo removes the landmark
    assert state["document"]["landmarks"] == [] and near_target(session.solved.sequence, pair) == before
    state = client.post("/api/redo", headers=H).json()
    assert state["document"]["landmarks"] == [pair] and near_target(session.solved.sequence, pair) < 1e-9


def test_region_pairs_are_passed_to_correspond(tmp_path):
    a, b = tmp_path / "two.json", tmp_path / "two-moved.json"  # no paint: closed rings are filled regions
    left, right = [[0, 0], [1, 0], [1, 1], [0, 1]], [[3, 0], [4, 0], [4, 1], [3, 1]]
    isotween.save(isotween.Shape.from_polygon([left, right]), a)
    five = [[0, 0], [0.5, 0], [1, 0], [1, 1], [0, 1]]  # other point counts: not compatible as they are
    isotween.save(isotween.Shape.from_polygon([np.add(five, [0, 2]), np.add(five, [3, 2])]), b)
    session = Session([a, b])
    client = client_for(session)
    state = client.post("/api/open", json={"paths": [str(a), str(b)]}, headers=H).json()
    straight = sorted(map(tuple, state["correspondence"]["pairs"]))
    assert straight == [(0, 0), (1, 1)]
    state = client.post("/api/hints", json={"pairs": [[0, 1]]}, headers=H).json()
    assert sorted(map(tuple, state["correspondence"]["pairs"])) == [(0, 1), (1, 0)]
    # a landmark across outlines that do not correspond is refused; once its regions are paired it holds
    client.post("/api/hints", json={"pairs": []}, headers=H)
    doc = json.dumps(session.doc)
    corner = [[0, 0], [3, 2]]  # the left square's corner, the right five-gon's corner
    r = client.post("/api/hints", json={"landmarks": [corner]}, headers=H)
    assert r.status_code == 400 and "does not correspond" in r.json()["error"] and json.dumps(session.doc) == doc
    state = client.post("/api/hints", json={"pairs": [[0, 1]], "landmarks": [corner]}, headers=H).json()
    assert state["document"]["landmarks"] == [corner] and near_target(session.solved.sequence, corner) < 1e-9


# ---------------------------------------------------------------- ARAP drag
def test_arap_deform_is_rigid_when_it_can_be():
    shape = star()
    angle = 0.7
    rotated = shape.rotate(angle).translate([1.0, -2.0]).vertices
    moved = arap_deform(shape, shape.vertices, {0: rotated[0], 7: rotated[7]})
    assert np.allclose(moved, rotated, atol=1e-6)
    local = arap_deform(shape, shape.vertices, {0: [1.3, 0.1]}, radius=0.9)
    far = np.linalg.norm(shape.vertices - shape.vertices[0], axis=1) > 0.9
    assert np.array_equal(local[far], shape.vertices[far]) and np.allclose(local[0], [1.3, 0.1])
    with pytest.raises(isotween.errors.ParameterError, match="out of range"):
        arap_deform(shape, shape.vertices, {99: [0, 0]})


# ---------------------------------------------------------------- a whole session in Chromium
# (the `browser` fixture comes from conftest.py: skipped, with the reason, without chromium or playwright)

def test_a_whole_session_in_chromium(browser, drawings, tmp_path):
    from isotween.studio import StudioServer

    server = StudioServer(drawings).start()
    errors = []
    try:
        page = browser.new_page(viewport={"width": 1280, "height": 800}, accept_downloads=True)
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(server.url)
        page.wait_for_function("window.__studio && window.__studio.ready")
        # open two drawings through the file picker (uploads)
        page.set_input_files("#open-files", [str(p) for p in drawings])
        page.wait_for_function("window.__studio.seq && window.__studio.state.names[0] === 'square.svg'")
        session = server.session
        src, tgt, _ = isotween.correspond(isotween.load(drawings[0]), isotween.load(drawings[1]))
        plain = isotween.interpolate(src, tgt, 13, fold="fallback")
        assert session.solved.sequence.equals(plain, atol=1e-9)
        # a landmark: click a point on an outline of each drawing (the square's corner, a tip of the star)
        page.check("input[name=corr-mode][value=landmark]")
        corner, tip = [0.0, 0.0], [4.0, 0.0]
        page.mouse.click(*page.evaluate("window.__studio.corrOnPage(0, 1, 1)"))  # the square's middle: off its outline
        page.mouse.click(*page.evaluate(f"window.__studio.corrOnPage(1, {tip[0]}, {tip[1]})"))
        page.wait_for_selector("#message.error")
        assert "is not on the drawing" in page.text_content("#message") and session.doc["landmarks"] == []
        assert session.solved.sequence.equals(plain, atol=1e-9)  # refused: the session is as it was
        page.mouse.click(*page.evaluate(f"window.__studio.corrOnPage(0, {corner[0]}, {corner[1]})"))
        page.mouse.click(*page.evaluate(f"window.__studio.corrOnPage(1, {tip[0]}, {tip[1]})"))
        page.wait_for_function("window.__studio.state.document.landmarks.length === 1")
        page.wait_for_function("window.__studio.state.preview === false")
        assert not page.is_visible("#message.error")
        (landmark,) = session.doc["landmarks"]
        assert np.allclose(landmark, [corner, tip], atol=0.05)  # where it was clicked (to a pixel)
        src, tgt, _ = isotween.correspond(isotween.load(drawings[0]), isotween.load(drawings[1]), landmarks=[landmark])
        base = isotween.interpolate(src, tgt, 13, fold="fallback")
        assert session.solved.sequence.equals(base, atol=1e-9)
        assert near_target(plain, [corner, tip]) > 0.5 and near_target(base, [corner, tip]) < 0.05
        # undo removes the landmark, redo brings it back
        page.click("#undo")
        page.wait_for_function("window.__studio.state.document.landmarks.length === 0")
        assert session.solved.sequence.equals(plain, atol=1e-9)
        page.click("#redo")
        page.wait_for_function("window.__studio.state.document.landmarks.length === 1")
        assert session.solved.sequence.equals(base, atol=1e-9)
        # drag a handle on an in-between; on release the frame is held and the sequence re-solved
        k = 6
        page.evaluate(f"window.__studio.setFrame({k})")
        x, y = page.evaluate(f"window.__studio.vertexOnPage({k}, 0)")
        page.mouse.move(x, y)
        page.mouse.down()
        for step in range(1, 6):
            page.mouse.move(x + 8 * step, y + 5 * step)
            page.wait_for_timeout(30)
        page.mouse.up()
        page.wait_for_function("window.__studio.lastEditMs !== null && window.__studio.seq.keys.length === 3")
        assert session.doc["edits"].keys() == {str(k)}
        held = base.shape.with_vertices(session.doc["edits"][str(k)])
        expected = isotween.edit(base, frame=k, shape=held)
        assert np.max(np.abs(session.solved.sequence.frames - expected.frames)) < 1e-9
        drawn = np.array(page.evaluate("Array.from(window.__studio.frames)")).reshape(expected.frames.shape)
        assert np.max(np.abs(drawn - expected.frames)) < 1e-9
        assert np.allclose(drawn[k], held.vertices) and not np.allclose(drawn[k], base.frames[k])
        # undo
        page.click("#undo")
        page.wait_for_function("window.__studio.seq.keys.length === 2")
        drawn = np.array(page.evaluate("Array.from(window.__studio.frames)")).reshape(base.frames.shape)
        assert np.max(np.abs(drawn - base.frames)) < 1e-9 and session.doc["edits"] == {}
        page.click("#redo")
        page.wait_for_function("window.__studio.seq.keys.length === 3")
        # export Lottie and GIF
        files = {}
        for kind in ("lottie", "gif"):
            page.select_option("#export-kind", kind)
            with page.expect_download() as info:
                page.click("#export")
            files[kind] = tmp_path / info.value.suggested_filename
            info.value.save_as(files[kind])
        lottie = json.loads(files["lottie"].read_text())
        # the page's playback timing (13 frames over the 1.5 s Duration) at the export fps (24): 1.5 * 24 + 1 ticks
        assert lottie["op"] - lottie["ip"] == 37 and lottie["fr"] == 24 and lottie["layers"]
        from PIL import Image

        with Image.open(files["gif"]) as gif:
            assert gif.n_frames == 37
        # save the project, change the session, reopen the project
        with page.expect_download() as info:
            page.click("#save-project")
        project = tmp_path / "isotween-project.json"
        info.value.save_as(project)
        saved = json.loads(project.read_text())
        page.fill("#frames", "7")
        page.dispatch_event("#frames", "change")
        page.wait_for_function("window.__studio.seq.count === 7")
        page.set_input_files("#open-project", str(project))
        page.wait_for_function("window.__studio.seq.count === 13 && window.__studio.seq.keys.length === 3")
        assert session.doc == saved["document"]
        assert np.max(np.abs(session.solved.sequence.frames - expected.frames)) < 1e-9
        assert session.doc["landmarks"] == [landmark]
        # the browser logs the refused landmark (HTTP 400) as a failed resource; nothing else
        assert all("status of 400" in e for e in errors) and len(errors) == 1, errors
    finally:
        server.stop()


def test_keyframes_with_an_easing_per_segment_and_an_edit(tmp_path):
    th = np.linspace(0, 2 * np.pi, 20, endpoint=False)
    files = []
    for i, (a, b) in enumerate([(2, 1), (1, 1), (1, 2)]):
        files.append(tmp_path / f"key{i}.svg")
        isotween.save(isotween.Shape.from_polygon(np.c_[a * np.cos(th), b * np.sin(th)] + [3 * i, 0]), files[-1])
    session = Session()
    client = client_for(session)
    ids = client.post("/api/upload", files=[("file", (f.name, f.read_bytes())) for f in files], headers=H).json()["ids"]
    assert len(ids) == 3
    client.post("/api/open", json={"inputs": ids}, headers=H)
    curves = [[0.42, 0, 0.58, 1], [0, 0, 1, 1]]
    state = client.post("/api/options", json={"easing": curves}, headers=H).json()
    assert state["sequence"]["keys"] == [0, 6, 12]
    keys, _ = isotween.correspondence.correspond_keys([isotween.load(f) for f in files])
    from isotween.studio.session import eased

    expected = isotween.interpolate_keyframes(keys, frames=13, easing=eased(curves))
    assert session.solved.sequence.equals(expected, atol=1e-12)
    assert np.allclose(expected.times[6:], np.linspace(0.5, 1, 7))  # the second segment is linear
    state = client.post("/api/edit", json={"frame": 3, "handles": [[0, 0.5, 0.5]]}, headers=H).json()
    assert state["sequence"]["keys"] == [0, 3, 6, 12]
    assert np.array_equal(session.solved.sequence.frames[6], expected.frames[6])  # the keyframe stays held


def test_export_render_options(opened):
    client, session = opened
    from PIL import Image

    r = client.post("/api/export", json={"kind": "gif", "size": 80, "bounce": True, "background": "#202020"},
                    headers=H)
    with Image.open(io.BytesIO(r.content)) as gif:
        assert gif.n_frames > 13 and max(gif.size) == 80
    r = client.post("/api/export", json={"kind": "gif", "size": "big"}, headers=H)
    assert r.status_code == 400 and "size" in r.json()["error"]
    r = client.post("/api/export", json={"kind": "svg", "fps": 10}, headers=H)
    assert r.status_code == 200 and b"<svg" in r.content


def test_a_bad_file_shows_one_message_in_the_page(browser, drawings, tmp_path):
    from isotween.studio import StudioServer

    server = StudioServer(drawings).start()
    errors = []
    try:
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(server.url)
        page.wait_for_function("window.__studio && window.__studio.ready && window.__studio.seq")
        before = server.session.doc
        broken = tmp_path / "broken.svg"
        broken.write_text("<svg><path d='M 0 0 L")
        page.set_input_files("#open-files", [str(broken), str(drawings[1])])
        page.wait_for_selector("#message.error")
        assert "broken.svg" in page.text_content("#message")
        assert server.session.doc is before and page.evaluate("window.__studio.seq.count") == 13
        page.fill("#frames", "9")  # the session goes on
        page.dispatch_event("#frames", "change")
        page.wait_for_function("window.__studio.seq.count === 9")
        assert not page.is_visible("#message.error")
        page.select_option("#method", "arap")  # needs triangles: refused, and the control shows the method in use
        page.wait_for_selector("#message.error")
        assert "needs a triangle mesh" in page.text_content("#message")
        assert page.input_value("#method") == "aiap" and server.session.doc["options"]["method"] == "aiap"
        # the browser logs the refused requests (HTTP 400) as failed resources; nothing else
        assert all("status of 400" in e for e in errors) and len(errors) == 2, errors
    finally:
        server.stop()


def test_the_jupyter_widget_shows_the_studio(browser, drawings):
    pytest.importorskip("anywidget", reason="anywidget is not installed (pip install 'isotween[widget]')")
    from isotween.studio.widget import ESM, widget

    w = widget(drawings, height=600)
    try:
        assert w.url == w.server.url and w.height == 600 and len(w.sequence) == 13
        page = browser.new_page(viewport={"width": 1000, "height": 700})
        errors = []
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.set_content("<div id=cell></div>")
        page.evaluate("""async ([esm, url]) => {
            const module = await import(URL.createObjectURL(new Blob([esm], {type: "text/javascript"})));
            const model = {get: (k) => ({url, height: 600})[k], on() {}, off() {}};
            module.default.render({model, el: document.getElementById("cell")});
        }""", [ESM, w.url])
        frame = page.frame_locator("iframe")
        frame.locator("#frame-label").wait_for()
        page.wait_for_function("document.querySelector('iframe').contentWindow !== null")
        inner = page.frames[1]
        inner.wait_for_function("window.__studio && window.__studio.ready && window.__studio.seq")
        assert inner.evaluate("window.__studio.seq.count") == 13 and errors == []
    finally:
        w.close()


def test_a_saved_sequence_opens_on_its_own(opened, tmp_path):
    client, session = opened
    r = client.post("/api/export", json={"kind": "npz"}, headers=H)
    morph = session.solved.sequence
    ids = client.post("/api/upload", files={"file": ("morph.npz", r.content)}, headers=H).json()["ids"]
    r = client.post("/api/open", json={"inputs": ids + ids}, headers=H)
    assert r.status_code == 400 and "open it on its own" in r.json()["error"]
    state = client.post("/api/open", json={"inputs": ids}, headers=H).json()
    assert state["sequence"]["count"] == 13 and np.array_equal(session.solved.sequence.frames, morph.frames)
    state = client.post("/api/options", json={"frames": 7}, headers=H).json()
    assert np.allclose(session.solved.sequence.frames, morph.resample(7).frames, atol=1e-12)
    state = client.post("/api/edit", json={"frame": 3, "handles": [[0, 0.4, 0.3]]}, headers=H).json()
    assert state["sequence"]["keys"] == [0, 3, 6]
    r = client.post("/api/open", json={"inputs": ids, "role": "third"}, headers=H)
    assert r.status_code == 400 and "not a drawing to transfer onto" in r.json()["error"]


def test_a_busy_port_is_refused_with_one_message(drawings):
    import socket

    from isotween.studio import StudioServer

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        s.listen()
        with pytest.raises(isotween.errors.ParameterError, match="cannot serve on 127.0.0.1"):
            StudioServer(drawings, port=s.getsockname()[1])
    with pytest.raises(isotween.errors.ParameterError, match="only uploads and the files named"):
        Session(drawings[:1]).add_path(str(drawings[1]))


def test_the_command_serves_until_stopped(drawings, tmp_path):
    import os
    import subprocess
    import urllib.request

    env = {**os.environ, "PYTHONPATH": os.pathsep.join(p for p in sys.path if p)}
    r = subprocess.run([sys.executable, "-m", "isotween", "studio", str(tmp_path / "missing.svg"), "--no-browser"],
                       capture_output=True, text=True, env=env, timeout=60)
    assert r.returncode == 2 and "missing.svg: no such file" in r.stderr
    proc = subprocess.Popen([sys.executable, "-m", "isotween", "studio", *map(str, drawings), "--no-browser"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        line = proc.stdout.readline()
        assert line.startswith("isotween studio: http://127.0.0.1:")
        url = line.split(": ", 1)[1].strip()
        api = url.replace("/?token=", "/api/state?token=")
        state = None
        for _ in range(600):  # the server starts after the first morph is solved
            try:
                with urllib.request.urlopen(api, timeout=5) as answer:
                    state = json.load(answer)
                break
            except OSError:
                __import__("time").sleep(0.1)
        assert state is not None and state["names"] == ["square.svg", "star.svg"] and state["sequence"]["count"] == 13
    finally:
        proc.terminate()
        proc.wait(timeout=30)


def two_regions(tmp_path):
    a, b = tmp_path / "two.json", tmp_path / "two-moved.json"  # no paint: closed rings are filled regions
    left, right = [[0, 0], [1, 0], [1, 1], [0, 1]], [[3, 0], [4, 0], [4, 1], [3, 1]]
    isotween.save(isotween.Shape.from_polygon([left, right]), a)
    five = [[0, 0], [0.5, 0], [1, 0], [1, 1], [0, 1]]
    isotween.save(isotween.Shape.from_polygon([np.add(five, [0, 2]), np.add(five, [3, 2])]), b)
    return a, b


def test_quick_outline_preview_then_meshes(tmp_path):
    a, b = two_regions(tmp_path)
    session = Session([a, b])
    session.live_budget = 0  # every quick change of the correspondence answered by its outlines first
    client = client_for(session)
    state = client.post("/api/open", json={"paths": [str(a), str(b)], "quick": True}, headers=H).json()
    assert state["preview"] is True and session.solved.sequence.shape.n_faces == 0
    r = client.post("/api/edit", json={"frame": 3, "handles": [[0, 0.5, 0.5]]}, headers=H)
    assert r.status_code == 400 and "outline preview" in r.json()["error"]
    state = client.post("/api/refine", headers=H).json()
    assert state["preview"] is False and state["undo"] == 0
    src, tgt, _ = isotween.correspond(isotween.load(a), isotween.load(b))
    assert src.n_faces and session.solved.sequence.equals(isotween.interpolate(src, tgt, 13, fold="fallback"),
                                                          atol=1e-9)
    client.post("/api/edit", json={"frame": 3, "handles": [[0, 0.5, 0.5]]}, headers=H)
    assert session.doc["edits"]
    state = client.post("/api/hints", json={"pairs": [[0, 1]], "quick": True}, headers=H).json()
    assert state["preview"] is True and session.doc["edits"] == {}  # edits belong to the old correspondence
    assert sorted(map(tuple, state["correspondence"]["pairs"])) == [(0, 1), (1, 0)]
    state = client.post("/api/hints", json={"pairs": [[0, 0]], "quick": True}, headers=H).json()
    assert state["preview"] is True
    state = client.post("/api/refine", headers=H).json()
    assert state["preview"] is False and session.doc["pairs"] == [[0, 0]]
    src, tgt, _ = isotween.correspond(isotween.load(a), isotween.load(b), pairs=[(0, 0)])
    assert session.solved.sequence.equals(isotween.interpolate(src, tgt, 13, fold="fallback"), atol=1e-9)
    state = client.post("/api/refine", headers=H).json()  # nothing to refine: the same state
    assert state["preview"] is False
    state = client.post("/api/undo", headers=H).json()  # back to the crossed pairs, meshed
    assert state["preview"] is False and session.doc["pairs"] == [[0, 1]]


def test_a_landmark_is_answered_meshed_reusing_the_regions_it_leaves_alone(tmp_path):
    a, b = two_regions(tmp_path)
    session = Session([a, b])
    session.live_budget = 60.0  # as on a fast machine: the meshes within the budget
    client = client_for(session)
    client.post("/api/open", json={"paths": [str(a), str(b)]}, headers=H)
    hits, misses = session.meshes.hits, session.meshes.misses
    landmarks = [[[1.0, 0.5], [0.5, 3.0]]]  # on the left squares: the right pair's rings do not change
    state = client.post("/api/hints", json={"landmarks": landmarks, "quick": True}, headers=H).json()
    assert state["preview"] is False and session.solved.sequence.shape.n_faces > 0
    assert session.meshes.hits == hits + 1 and session.meshes.misses == misses + 1
    expected = isotween.morph(isotween.load(a), isotween.load(b), frames=13,
                              correspond_options={"landmarks": landmarks})
    assert session.solved.sequence.equals(expected, atol=1e-9)
    session.live_budget = 0  # a slow machine: the outlines first, then the same meshes
    state = client.post("/api/hints", json={"landmarks": [], "quick": True}, headers=H).json()
    assert state["preview"] is False  # back to the opened correspondence: all of it known
    landmarks = [[[1.0, 0.25], [0.75, 3.0]]]
    state = client.post("/api/hints", json={"landmarks": landmarks, "quick": True}, headers=H).json()
    assert state["preview"] is True
    state = client.post("/api/refine", headers=H).json()
    expected = isotween.morph(isotween.load(a), isotween.load(b), frames=13,
                              correspond_options={"landmarks": landmarks})
    assert state["preview"] is False and session.solved.sequence.equals(expected, atol=1e-9)


def test_two_drawings_are_morphed_as_isotween_morph_does(tmp_path):
    a, b = tmp_path / "one.json", tmp_path / "two.json"  # the target has a region the source lacks
    isotween.save(isotween.Shape.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]]), a)
    isotween.save(isotween.Shape.from_polygon([[[0, 0], [1, 0], [1, 1], [0, 1]],
                                               [[3, 0], [4, 0], [4, 1], [3, 1]]]), b)
    session = Session([a, b])
    client = client_for(session)
    client.post("/api/open", json={"paths": [str(a), str(b)]}, headers=H)
    expected = isotween.morph(isotween.load(a), isotween.load(b), frames=13)  # the grown square: a point at 0
    assert session.solved.report.vanishing[0] and session.solved.sequence.equals(expected, atol=1e-9)
    k = 6
    state = client.post("/api/edit", json={"frame": k, "handles": [[0, 0.2, -0.3]], "anchor": 0}, headers=H).json()
    assert state["document"]["edited"] == [k]
    raw = session.solved.base  # edits start from the morph before the collapse, which then applies again
    edited = isotween.edit(raw, frame=k, shape=raw.shape.with_vertices(session.doc["edits"][str(k)]))
    isotween.pipeline.collapse_vanishing(edited, session.solved.report)
    assert np.all(np.isfinite(session.solved.sequence.frames)) and session.solved.sequence.equals(edited, atol=1e-9)


def test_strokes_that_would_cross_are_drawn_off_and_on_as_morph_does(tmp_path):
    head = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24" fill="none" stroke="black">'
    shorts = '<path d="M16 7h2"/><path d="M6 7h2"/><path d="M6 17h2"/><path d="M16 17h2"/></svg>'
    a, b = tmp_path / "across.svg", tmp_path / "upright.svg"  # the long bar turns upright through two short ones
    a.write_text(head + '<path d="M2 12h20"/>' + shorts)
    b.write_text(head + '<path d="M12 2v20"/>' + shorts)
    session = Session([a, b])
    client = client_for(session)
    state = client.post("/api/open", json={"paths": [str(a), str(b)]}, headers=H).json()
    expected = isotween.morph(a, b, frames=13)
    assert session.solved.sequence.equals(expected, atol=1e-9)
    assert f"strokes: {expected.info['strokes']}" in state["notes"]
    assert not isotween.metrics.outline_crossings(session.solved.sequence, visible=True).any()
    # the option that keeps every stroke morphing, as `morph(strokes="morph")`
    state = client.post("/api/options", json={"strokes": "morph"}, headers=H).json()
    assert session.solved.sequence.equals(isotween.morph(a, b, frames=13, strokes="morph"), atol=1e-9)
    assert not any(note.startswith("strokes:") for note in state["notes"])
    answer = client.post("/api/options", json={"strokes": "cross"}, headers=H)
    assert answer.status_code == 400 and "strokes" in answer.json()["error"]


def test_pairing_regions_by_clicking_in_chromium(browser, tmp_path):
    from isotween.studio import StudioServer

    a, b = two_regions(tmp_path)
    server = StudioServer([a, b]).start()
    errors = []
    try:
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(server.url)
        page.wait_for_function("window.__studio && window.__studio.ready && window.__studio.seq")
        assert page.evaluate("window.__studio.state.preview") is False
        # the left square of the source with the right square of the target
        page.mouse.click(*page.evaluate("window.__studio.corrOnPage(0, 0.5, 0.5)"))
        page.mouse.click(*page.evaluate("window.__studio.corrOnPage(1, 3.5, 2.5)"))
        page.wait_for_function("window.__studio.state.document.pairs.length === 1")
        page.wait_for_function("window.__studio.state.preview === false")
        assert server.session.doc["pairs"] == [[0, 1]]
        src, tgt, _ = isotween.correspond(isotween.load(a), isotween.load(b), pairs=[(0, 1)])
        assert server.session.solved.sequence.equals(isotween.interpolate(src, tgt, 13, fold="fallback"), atol=1e-9)
        assert page.evaluate("window.__studio.seq.faces") == src.n_faces > 0
        assert errors == []
    finally:
        server.stop()


def test_the_strokes_option_in_chromium(browser, tmp_path):
    from isotween.studio import StudioServer

    head = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 24 24" fill="none" stroke="black">'
    shorts = '<path d="M16 7h2"/><path d="M6 7h2"/><path d="M6 17h2"/><path d="M16 17h2"/></svg>'
    a, b = tmp_path / "across.svg", tmp_path / "upright.svg"
    a.write_text(head + '<path d="M2 12h20"/>' + shorts)
    b.write_text(head + '<path d="M12 2v20"/>' + shorts)
    server = StudioServer([a, b]).start()
    errors = []
    try:
        page = browser.new_page(viewport={"width": 1280, "height": 800})
        page.on("pageerror", lambda e: errors.append(str(e)))
        page.goto(server.url)
        page.wait_for_function("window.__studio && window.__studio.ready && window.__studio.seq")
        assert page.input_value("#strokes") == "untangle"
        page.select_option("#strokes", "morph")
        page.wait_for_function("window.__studio.state.document.options.strokes === 'morph'")
        page.wait_for_function("!window.__studio.state.notes.some(n => n.startsWith('strokes:'))")
        assert server.session.solved.sequence.equals(isotween.morph(a, b, frames=13, strokes="morph"), atol=1e-9)
        assert errors == []
    finally:
        server.stop()


def test_a_long_solve_shows_progress_and_is_superseded(drawings, monkeypatch):
    import threading
    import time
    import urllib.request

    from isotween.studio import StudioServer

    server = StudioServer(drawings).start()
    real = sys.modules["isotween.interpolate"].interpolate

    def slow(source, target, frames, callback=None, **kwargs):
        if frames == 21:  # the superseded request: iterations until told to stop
            for k in range(500):
                time.sleep(0.02)
                callback(k, 1.0, 0.1)
        return real(source, target, frames, callback=callback, **kwargs)

    monkeypatch.setattr(sys.modules["isotween.interpolate"], "interpolate", slow)
    base = server.url.split("/?")[0]

    def call(path, body=None):
        data = None if body is None else json.dumps(body).encode()
        request = urllib.request.Request(base + path, data=data, headers={**H, "X-Isotween-Token": server.token,
                                                                          "Content-Type": "application/json"})
        with urllib.request.urlopen(request, timeout=60) as answer:
            return json.load(answer)

    try:
        answers = {}
        first = threading.Thread(target=lambda: answers.update(first=call("/api/options", {"frames": 21})))
        first.start()
        for _ in range(400):
            progress = call("/api/progress")
            if progress.get("iteration", 0) > 2:
                break
            time.sleep(0.02)
        assert progress["stage"] == "morph" and progress["iteration"] > 2
        started = time.perf_counter()
        assert call("/api/state")["sequence"]["count"] == 13  # still answering, the old morph kept
        assert time.perf_counter() - started < 5  # (not waiting for the solve: that runs for 10 s)
        second = call("/api/options", {"frames": 9})
        first.join(timeout=30)
        assert answers["first"]["superseded"] is True and second["sequence"]["count"] == 9
        assert server.session.doc["options"]["frames"] == 9 and call("/api/progress")["stage"] == "idle"
    finally:
        server.stop()


def test_drawings_in_other_units_get_a_hint_and_fit_puts_them_in_one_box(tmp_path):
    # a square and the star in 20 times larger units: a hint names the Fit switch; with it, the last frame is
    # the star in the square's box and the hint is gone
    a, b = tmp_path / "square.svg", tmp_path / "star.svg"
    isotween.save(isotween.Shape.from_polygon([[0, 0], [2, 0], [2, 2], [0, 2]]), a)
    isotween.save(star().scale(20).translate([300, 0]), b)
    session = Session([a, b])
    client = client_for(session)
    state = client.post("/api/open", json={"paths": [str(a), str(b)]}, headers=H).json()
    assert any("times the size" in n and "Fit" in n for n in state["notes"]), state["notes"]
    state = client.post("/api/options", json={"fit": True}, headers=H).json()
    assert not any("times the size" in n for n in state["notes"])
    last = session.solved.base.frames[-1]
    lo, hi = last.min(axis=0), last.max(axis=0)
    np.testing.assert_allclose(lo + hi, [2, 2], atol=1e-9)  # centred in the square's box
    assert np.all(lo >= -1e-9) and np.all(hi <= 2 + 1e-9) and np.isclose(np.max(hi - lo), 2)  # as large as fits
    # the correspondence panel draws the fitted target, where its matched points are
    drawn = np.vstack([r for item in state["correspondence"]["inputs"][1]["items"] for r in item["rings"]])
    matched = np.vstack([r["target"] for r in state["correspondence"]["rings"]])
    assert drawn.min() >= -1e-9 and drawn.max() <= 2 + 1e-9 and matched.max() <= 2 + 1e-9
