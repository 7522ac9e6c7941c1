"""CSS and Web Animations outputs: Chromium, paused at given times, draws what isotween's own renderer draws."""

import json

import numpy as np
import pytest

import isotween
from browser import screenshot
from isotween.examples import load_example
from isotween.outputs import with_paint
from isotween.render import playback_order
from isotween.render._frames import SequenceRenderer
from isotween.render.web import waapi_data, web_animation, write_css, write_waapi

FPS, HOLD, SIZE = 12, 0.25, 240


@pytest.fixture(scope="module", params=["holes", "curls"])
def seq(request):
    source, target, options = load_example(request.param)
    options.pop("texture", None)
    return with_paint(isotween.interpolate(source, target, **options), fill=("tomato", "royalblue"),
                      stroke=("black", "darkgreen"), stroke_width=(0.05, 0.12))


def ticks_to_check(seq):
    order = playback_order(len(seq), FPS, HOLD)
    return order, [int(round(HOLD * FPS)) + 1, len(order) // 2, len(order) - 2]


def compare(page, renderer, frame, what):
    theirs = screenshot(page, "svg").astype(int)
    ours = renderer.image(frame).astype(int)
    assert theirs.shape == ours.shape
    differ = np.abs(theirs - ours).max(axis=2) > 60
    assert differ.mean() < 0.02, (what, frame, differ.mean())  # the bound of the Lottie test


def test_css_animation_paused_at_three_times_matches_our_render(tmp_path, browser, seq):
    files = write_css(seq, tmp_path / "out.css", fps=FPS, hold=HOLD, size=SIZE, background="white")
    assert [f.name for f in files] == ["out.css", "out.html"]
    css = files[0].read_text()
    assert "@keyframes" in css and 'd: path("M' in css and "stroke:" in css
    renderer = SequenceRenderer(seq, SIZE, background="white")
    order, ticks = ticks_to_check(seq)
    page = browser.new_page(viewport={"width": renderer.width + 20, "height": renderer.height + 20})
    errors = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    try:
        page.goto(files[1].as_uri())
        for k in ticks:
            # restart each animation paused, a negative delay in: it shows time t (not t plus the time it ran)
            page.evaluate("t => document.querySelectorAll('svg path').forEach(p => {"
                          " p.style.animation = 'none'; p.getBoundingClientRect(); p.style.animation = '';"
                          " p.style.animationDelay = `-${t}s`; p.style.animationPlayState = 'paused'; })", k / FPS)
            compare(page, renderer, int(order[k]), "css")
    finally:
        page.close()
    assert not errors


def test_web_animations_json_plays_in_chromium(tmp_path, browser, seq):
    path = tmp_path / "out.waapi.json"
    write_waapi(seq, path, fps=FPS, hold=HOLD, size=SIZE, background="white")
    data = json.loads(path.read_text())
    renderer = SequenceRenderer(seq, SIZE, background="white")
    order, ticks = ticks_to_check(seq)
    page = browser.new_page(viewport={"width": renderer.width + 20, "height": renderer.height + 20})
    try:
        page.set_content('<body style="margin:0"></body>')
        page.evaluate("""data => {
            const ns = 'http://www.w3.org/2000/svg', svg = document.createElementNS(ns, 'svg');
            svg.setAttribute('viewBox', `0 0 ${data.width} ${data.height}`);
            svg.setAttribute('width', data.width); svg.setAttribute('height', data.height);
            const rect = document.createElementNS(ns, 'rect');
            rect.setAttribute('width', data.width); rect.setAttribute('height', data.height);
            rect.setAttribute('fill', data.background); svg.appendChild(rect);
            window.anims = data.paths.map(p => {
                const path = document.createElementNS(ns, 'path');
                for (const [k, v] of Object.entries(p.attributes)) path.setAttribute(k, v);
                svg.appendChild(path);
                const a = path.animate(p.keyframes, {...data.timing, iterations: data.timing.iterations ?? Infinity});
                a.pause(); return a;
            });
            document.body.appendChild(svg);
        }""", data)
        for k in ticks:
            page.evaluate("ms => window.anims.forEach(a => { a.currentTime = ms; })", 1000 * k / FPS)
            compare(page, renderer, int(order[k]), "waapi")
    finally:
        page.close()


def test_keys_are_fewer_than_ticks_and_reproduce_the_skipped_ones(seq):
    order = playback_order(len(seq), FPS, HOLD)
    full = web_animation(seq, fps=FPS, hold=HOLD, size=SIZE, reduce=False)
    lean = web_animation(seq, fps=FPS, hold=HOLD, size=SIZE)
    for a, b in zip(full["groups"], lean["groups"], strict=True):
        assert len(a["keys"]) == len(order) + 1
        assert 2 <= len(b["keys"]) < len(a["keys"])  # the holds collapse at least
        assert b["keys"][0]["offset"] == 0 and b["keys"][-1]["offset"] == 1
    data = waapi_data(lean)
    assert data["timing"]["duration"] == pytest.approx(1000 * (len(order) + 1) / FPS - 1000 / FPS)


def test_write_output_names_css_and_waapi_outputs(tmp_path, seq):
    from isotween.outputs import output_kind, write_output

    assert output_kind(tmp_path / "a.css") == "css" and output_kind(tmp_path / "a.waapi.json") == "waapi"
    written = write_output(seq, tmp_path / "a.css", fps=FPS, size=SIZE)
    assert [p.name for p in written] == ["a.css", "a.html"] and all(p.stat().st_size for p in written)
    [path] = write_output(seq, tmp_path / "a.waapi.json", fps=FPS, size=SIZE, loop=False)
    assert json.loads(path.read_text())["timing"]["iterations"] == 1


def test_animated_svg_paused_at_three_times_matches_our_render(tmp_path, browser, seq):
    from isotween.render import write_svg_animation

    renderer = SequenceRenderer(seq, SIZE, background="white")
    path = tmp_path / "a.svg"
    write_svg_animation(seq, path, fps=FPS, hold=HOLD, size=SIZE, background="white")
    text = path.read_text()
    order, ticks = ticks_to_check(seq)
    key_times = text.split('keyTimes="', 1)[1].split('"', 1)[0].split(";")
    assert "C" in text and len(key_times) < len(order)  # curves; the holds at least collapse
    page = browser.new_page(viewport={"width": renderer.width + 20, "height": renderer.height + 20})
    try:
        page.set_content(f'<body style="margin:0">{text.split("?>", 1)[1]}</body>')
        for k in ticks:
            page.evaluate("t => { const s = document.querySelector('svg'); s.pauseAnimations();"
                          " s.setCurrentTime(t); }", k / FPS)
            compare(page, renderer, int(order[k]), "smil")
    finally:
        page.close()


def test_timed_keeps_every_frame_in_its_place_and_the_easing():
    from isotween.outputs import timed

    bar = isotween.Shape.from_polyline([[0, 0], [1, 0], [2, 0]])
    seq = isotween.interpolate(bar, bar.rotate(1.5), frames=5, times=np.linspace(0, 1, 5) ** 2)  # eased in
    assert not np.allclose(np.diff(seq.times), 0.25)  # eased: uneven times
    out = timed(seq, 1.0, fps=24)
    assert len(out) == 25
    np.testing.assert_allclose(out.frames[::6], seq.frames, atol=1e-12)  # frame k at k / 4 of the second
    np.testing.assert_allclose(out.times[::6], seq.times, atol=1e-12)
    assert timed(seq, 0, fps=24) is seq


def test_edge_chains_pass_along_every_edge_once():
    from isotween.render.outline import edge_chains
    from shapes import grid_mesh

    mesh = grid_mesh(9, 4, length=4.0, width=1.0)
    walks = edge_chains(mesh.edges)
    steps = np.concatenate([np.sort(np.column_stack([w[:-1], w[1:]]), axis=1) for w in walks])
    assert len(steps) == mesh.n_edges
    np.testing.assert_array_equal(np.unique(steps, axis=0), np.unique(np.sort(mesh.edges, axis=1), axis=0))
    odd = int((np.bincount(np.asarray(mesh.edges).ravel()) % 2 == 1).sum())
    assert len(walks) <= max(odd // 2, 1) + 2  # close to the least number of open walks
    assert len(walks) < mesh.n_faces / 3  # far fewer subpaths than the triangles of before


def test_animated_svg_of_a_mesh_in_the_default_look_matches_our_render(tmp_path, browser):
    from isotween.render import write_svg_animation
    from shapes import bend, grid_mesh

    bar = grid_mesh(9, 3, length=4.0, width=1.0)
    mesh = isotween.interpolate(bar, bar.with_vertices(bend(bar.vertices, np.pi / 2)), frames=5)
    renderer = SequenceRenderer(mesh, SIZE, background="white")
    path, old = tmp_path / "a.svg", tmp_path / "old.svg"
    write_svg_animation(mesh, path, fps=FPS, hold=HOLD, size=SIZE, background="white")
    write_svg_animation(mesh, old, fps=FPS, hold=HOLD, size=SIZE, background="white", curves=False, reduce=False)
    assert path.stat().st_size * 2 < old.stat().st_size
    order, ticks = ticks_to_check(mesh)
    page = browser.new_page(viewport={"width": renderer.width + 20, "height": renderer.height + 20})
    try:
        page.set_content(f'<body style="margin:0">{path.read_text().split("?>", 1)[1]}</body>')
        for k in ticks:
            page.evaluate("t => { const s = document.querySelector('svg'); s.pauseAnimations();"
                          " s.setCurrentTime(t); }", k / FPS)
            compare(page, renderer, int(order[k]), "smil mesh")
    finally:
        page.close()


def test_animated_svg_of_a_swinging_mesh_splits_its_edges_and_matches_our_render(tmp_path, browser):
    import re

    from isotween.outputs import timed
    from isotween.render import write_svg_animation
    from shapes import bend, grid_mesh

    # a bar bent by 270 degrees: its tip needs a key every tick, its root few; the edges go into paths by need
    fps = 24
    bar = grid_mesh(16, 3, length=4.0, width=1.0)
    mesh = timed(isotween.interpolate(bar, bar.with_vertices(bend(bar.vertices, 1.5 * np.pi)), frames=9), 1.0, fps)
    path, old = tmp_path / "a.svg", tmp_path / "old.svg"
    write_svg_animation(mesh, path, fps=fps, hold=HOLD, size=SIZE, background="white")
    write_svg_animation(mesh, old, fps=fps, hold=HOLD, size=SIZE, background="white", curves=False, reduce=False)
    text = path.read_text()
    edges = text.split('<g fill="none"', 1)[1].split("</g>", 1)[0]
    key_counts = [len(k.split(";")) for k in re.findall(r'keyTimes="([^"]*)"', edges)]
    assert len(key_counts) >= 2 and min(key_counts) < max(key_counts)  # paths of edges with their own keys
    assert "." not in text.split('d="', 1)[1].split('"', 1)[0]  # whole numbers of the file's unit
    assert path.stat().st_size * 3 < old.stat().st_size
    renderer = SequenceRenderer(mesh, SIZE, background="white")
    order = playback_order(len(mesh), fps, HOLD)
    page = browser.new_page(viewport={"width": renderer.width + 20, "height": renderer.height + 20})
    try:
        page.set_content(f'<body style="margin:0">{text.split("?>", 1)[1]}</body>')
        for k in np.linspace(0, len(order) - 1, 7).round().astype(int).tolist():
            page.evaluate("t => { const s = document.querySelector('svg'); s.pauseAnimations();"
                          " s.setCurrentTime(t); }", k / fps)
            compare(page, renderer, int(order[k]), "smil swinging mesh")
    finally:
        page.close()
