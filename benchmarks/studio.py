"""isotween studio: time from a drag's release to the re-solved morph drawn, in headless Chromium.

For each input the studio server runs in this process (uvicorn), the page is
opened in Chromium, paused on the middle frame, and a vertex is dragged
(five pointer moves, each sending an ARAP preview request) and released. The
page measures from the release (pointerup) to the animation frame after the
re-solved sequence is drawn: the request, the server's ARAP deformation of
the frame and `isotween.edit` of the sequence, the JSON answer, decoding and
drawing. Each run is undone before the next. Medians of --runs drags.

A hint (a forced region pair, as clicking a region on each drawing sends)
is timed the same way for the icon: to the outline preview drawn, and to the
morph of the meshes drawn.

Inputs: an icon (two filled squares into two filled seven-pointed stars,
corresponded and meshed: the studio's path for two drawings), a glyph (the built-in example
'S' into '5', 160-point outlines), and a 10k-vertex triangle mesh (a
100 x 100 grid bar bent by 90 degrees).

Usage: python benchmarks/studio.py [--runs 7] [--no-write]
"""

import argparse
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))

from _results import table, write_section  # noqa: E402

ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
        "--disable-sync"]
TARGET_MS = 100


def inputs(folder):
    """(name, files or None, example or None) of every case."""
    import isotween
    from shapes import bend, grid_mesh

    th = np.linspace(0, 2 * np.pi, 14, endpoint=False)
    r = np.where(np.arange(14) % 2 == 0, 1.0, 0.5)
    star_ring = np.c_[r * np.cos(th), r * np.sin(th)]
    square, star = folder / "squares.json", folder / "stars.json"  # JSON without paint: filled regions, meshed
    isotween.save(isotween.Shape.from_polygon([[[0, 0], [2, 0], [2, 2], [0, 2]], [[3, 0], [4, 0], [4, 1], [3, 1]]]),
                  square)
    isotween.save(isotween.Shape.from_polygon([star_ring + [1, 4], 0.6 * star_ring + [4, 4]]), star)
    mesh = grid_mesh(100, 100, length=4.0, width=1.0)
    bar, bent = folder / "bar.obj", folder / "bent.obj"
    isotween.save(mesh, bar)
    isotween.save(mesh.with_vertices(bend(mesh.vertices, np.pi / 2)), bent)
    return [("icon (2 squares -> 2 stars)", [square, star], None), ("glyph ('S' -> '5')", None, "glyphs"),
            ("10k-vertex mesh (bar bends)", [bar, bent], None)]


def drag(page, k, vertex, dx, dy):
    """One drag on frame k; the release-to-drawn time the page measured (ms)."""
    before = page.evaluate("window.__studio.timings.length")
    page.evaluate(f"window.__studio.setFrame({k})")
    x, y = page.evaluate(f"window.__studio.vertexOnPage({k}, {vertex})")
    page.mouse.move(x, y)
    page.mouse.down()
    for step in range(1, 6):
        page.mouse.move(x + dx * step / 5, y + dy * step / 5)
        page.wait_for_timeout(40)
    page.mouse.up()
    page.wait_for_function(f"window.__studio.timings.length > {before}", timeout=120_000)
    return page.evaluate("window.__studio.lastEditMs")


SUPERSEDE = """async ([k, a, b]) => {
  // two edits of frame k, the second sent while the server runs the first (which it supersedes); the page polls
  // the server's progress every 20 ms: is the first dropped, how long until the second is drawn, and how long
  // does a progress request wait meanwhile (the server's responsiveness)
  const S = window.__studio, token = new URLSearchParams(location.search).get("token");
  const lat = [], stages = new Set();
  let done = false;
  const poll = (async () => {
    while (!done) {
      const t = performance.now();
      const p = await (await fetch("api/progress", { headers: { "X-Isotween-Token": token } })).json();
      lat.push(performance.now() - t);
      stages.add(p.stage);
      await new Promise((r) => setTimeout(r, 20));
    }
  })();
  const started = performance.now();
  let firstDone = false;
  const first = S.act("api/edit", { frame: k, handles: [a], anchor: a[0] })
    .then((x) => { firstDone = true; return x; });
  let during = false;  // the second sent while the server runs the first's edit
  while (!firstDone && !during) {
    during = (await (await fetch("api/progress", { headers: { "X-Isotween-Token": token } })).json()).stage === "edit";
    if (!during) await new Promise((r) => setTimeout(r, 5));
  }
  const second = await S.act("api/edit", { frame: k, handles: [b], anchor: b[0] });
  await new Promise((r) => requestAnimationFrame(() => r()));
  const drawn = performance.now() - started;
  const dropped = (await first) === null;
  done = true;
  await poll;
  lat.sort((x, y) => x - y);
  return { drawn, dropped, during, ok: second !== null, polls: lat.length, median: lat[lat.length >> 1],
           max: lat[lat.length - 1], stages: [...stages] };
}"""


def supersede(page, server, k):
    """Two edits, the second superseding the first, timed with the server's responsiveness (dict)."""
    v = server.session.solved.sequence.frames[k]
    a = [0, float(v[0, 0]) + 0.05, float(v[0, 1]) + 0.05]
    b = [0, float(v[0, 0]) + 0.1, float(v[0, 1]) + 0.08]
    out = page.evaluate(SUPERSEDE, [k, a, b])
    for _ in range(3):  # back to the morph (two undos if the first edit was done before the second came)
        if page.evaluate("window.__studio.seq.keys.length === 2"):
            break
        generation = page.evaluate("window.__studio.state.generation")
        page.click("#undo")
        page.wait_for_function(f"window.__studio.state.generation > {generation} && !window.__studio.busy")
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=7)
    parser.add_argument("--no-write", action="store_true")
    parser.add_argument("--cases", default="icon,glyph,mesh",
                        help="comma-separated cases to run (icon, glyph, mesh); RESULTS.md is written only for all")
    args = parser.parse_args()
    chosen = [c.strip() for c in args.cases.split(",")]
    if sorted(chosen) != ["glyph", "icon", "mesh"]:
        args.no_write = True
    from playwright.sync_api import sync_playwright

    from browser import CHROMIUM
    from isotween.studio import StudioServer

    rows, large = [], None
    load = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory() as tmp, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        for (name, files, example), case in zip(inputs(Path(tmp)), ("icon", "glyph", "mesh"), strict=True):
            if case not in chosen:
                continue
            t0 = time.perf_counter()
            server = StudioServer(files or []).start()
            page = browser.new_page(viewport={"width": 1280, "height": 800})
            page.goto(server.url)
            page.wait_for_function("window.__studio && window.__studio.ready")
            if example:
                page.select_option("#example", example)
            page.wait_for_function("window.__studio.seq !== null && !window.__studio.state.preview",
                                   timeout=300_000)
            page.click("#play") if page.evaluate("window.__studio.playing") else None
            opened = time.perf_counter() - t0
            seq = server.session.solved.sequence
            k, n = len(seq) // 2, seq.shape.n_vertices
            times = []
            for run in range(args.runs + 1):
                ms = drag(page, k, 0, 25 + 3 * run, 15)
                page.click("#undo")
                page.wait_for_function("window.__studio.seq.keys.length === 2")
                if run:  # the first drag warms up (imports, factorisations)
                    times.append(ms)
            med = statistics.median(times)
            lm_first = lm_final = hint = final = "-"
            solved = server.session.solved
            if case != "mesh":  # a landmark on the first outline, a new one each time (3 points along from
                # where the opened correspondence matches it); caches kept: what the landmark leaves alone is reused
                idx = solved.source.paths[0][0]
                marks = []
                for run in range(args.runs + 1):
                    m = (7 * run + 1) % len(idx)
                    pair = [solved.source.vertices[idx[m]].tolist(),
                            solved.target.vertices[idx[(m + 3) % len(idx)]].tolist()]
                    ms = page.evaluate("([p]) => window.__studio.timed('api/hints', {landmarks: [p], quick: true})",
                                       [pair])
                    if ms is None:
                        raise SystemExit(f"{name}: landmark {pair} refused: {page.inner_text('#message')}")
                    if run:
                        marks.append(ms)
                lm_first = f"{statistics.median(h['first'] for h in marks):.0f}"
                lm_final = f"{statistics.median(h['final'] for h in marks):.0f}"
                at_once = sum(h["first"] == h["final"] for h in marks)
                lm_final += f" ({at_once} of {len(marks)} at once)" if at_once else ""
                page.evaluate("window.__studio.timed('api/hints', {landmarks: [], quick: true})")
            if len(solved.report.pairs) >= 2:  # a hint: force a region pair (alternately crossed and straight)
                hints = []
                for run in range(args.runs + 1):
                    pairs = [[0, 1], [1, 0]] if run % 2 == 0 else [[0, 0], [1, 1]]
                    with server.session.lock:  # nothing cached but the loaded inputs
                        for key in [key for key in server.session._cache if key[0] != "shape"]:
                            del server.session._cache[key]
                    server.session.meshes.clear()
                    ms = page.evaluate("([p]) => window.__studio.timed('api/hints', {pairs: p, quick: true})",
                                       [pairs])
                    if run:
                        hints.append(ms)
                hint = f"{statistics.median(h['first'] for h in hints):.0f}"
                final = f"{statistics.median(h['final'] for h in hints):.0f}"
            if case == "mesh":
                runs = [supersede(page, server, k) for _ in range(3)]
                during = [r for r in runs if r["during"]]
                large = [name, n, f"{sum(r['dropped'] and r['ok'] for r in during)} of {len(during)}",
                         f"{statistics.median(r['drawn'] for r in runs):.0f}",
                         f"{statistics.median(r['median'] for r in runs):.0f}",
                         f"{max(r['max'] for r in runs):.0f}",
                         ", ".join(sorted({st for r in runs for st in r["stages"]}))]
                print(" | ".join(map(str, large)), flush=True)
            worst = max([med] + [float(x) for x in (lm_first, hint) if x != "-"])  # the first answers
            rows.append([name, n, seq.shape.n_faces, len(seq), f"{opened:.1f}", f"{med:.0f}",
                         f"{min(times):.0f}-{max(times):.0f}", lm_first, lm_final, hint, final,
                         "yes" if worst <= TARGET_MS else "no"])
            print(" | ".join(map(str, rows[-1])), flush=True)
            page.close()
            server.stop()
        browser.close()
    body = table(["input", "vertices", "triangles", "frames", "open s", "release to drawn ms (median)",
                  "range ms", "landmark to first drawn ms", "landmark to meshes drawn ms",
                  "region pair to first drawn ms", "region pair to meshes drawn ms",
                  f"first answers within {TARGET_MS} ms"], rows)
    body += (f"\n\nMedians of {args.runs} runs after one warm-up run. 'release to drawn': drags, each undone "
             "before the next, timed in the page from pointerup to the animation frame after the re-solved "
             "sequence (server: ARAP deformation of the frame and `isotween.edit`) is drawn. 'landmark': a new "
             "landmark pair each time (a point of the first outline and the target point three along from its "
             "partner), sent as the page sends a clicked pair (quick); the session keeps what the landmark "
             "does not change (loaded inputs, the meshes of the other region pairs). It is answered by the "
             "morph of the compatible meshes at once when the server expects them within its live budget "
             "(60 ms, from the meshing time measured so far; 'at once' counts those), else first by the outline "
             "morph ('first drawn') and then by the meshes ('meshes drawn'). 'region pair': a forced region "
             "pair, alternately crossed and straight, with every correspondence, mesh and morph cache cleared "
             "first (only the loaded inputs kept), for drawings with two regions. 'first answers within' "
             "compares the drag and the first answers to hints with the target. 'open' is the wall time to "
             "start the server and show the first morph (correspondence, meshing and the AIAP solve). "
             "Headless Chromium with "
             "--disable-gpu; server and browser on the same machine, shared with other jobs.")
    load.append(os.getloadavg()[0])
    body += (" Where the time goes (profiled in the server process): a landmark's first answer is its outline "
             "correspondence (`prepare_pair(..., outline=True)`, 20-30 ms on the icon, half of it aligning "
             "the drawings, which a landmark does not change) and the outline morph; its meshes are "
             "`compatible_meshes` of the one region pair the landmark is on (the other pair's meshes come "
             "from the session's mapping, `correspond(meshes=...)`), then the morph with its fold check (its "
             "folding frames repaired, or the fold-free fallback where a repaired frame crosses itself; the "
             "glyph's landmark makes its AIAP morph fold). A forced region pair meshes both pairs afresh "
             "(about 30 ms each). A 10k drag's release is `isotween.edit` (its factorisation of Eq. (10) kept "
             "per morph by the library from the last edit; its positions, edge rotations and the isometric "
             "energy of the result remain), the ARAP drag (its factorisation kept through the drag, the last "
             "move's answer reused) and 3 MB of frames "
             f"to the page. Load average (1 min) of the machine at start and end: {load[0]:.1f}, {load[1]:.1f}.")
    if large is not None:
        body += "\n\n" + table(["input", "vertices", "superseded edits dropped", "second edit drawn ms (median)",
                               "progress answered ms (median)", "progress answered ms (max)",
                               "stages shown"], [large])
        body += ("\n\nA large drawing while it re-solves: two edits of the middle frame, the second sent "
                 "while the server runs the first's `isotween.edit`, timed in the page from the first request "
                 "to the second's morph drawn (3 runs); 'dropped' counts the first edits whose answer said they "
                 "were superseded (of those overtaken while editing). Meanwhile the page "
                 "asks the server for its progress every 20 ms (the stages it saw are listed): how long "
                 "those requests wait says how responsive the server stays. `isotween.edit` has no callback, "
                 "so a superseded edit runs to its end in its thread and its result is dropped; morph solves "
                 "(`interpolate`) are stopped at their next iteration.")
    print(body)
    if not args.no_write:
        write_section("Studio", body, "python benchmarks/studio.py")


if __name__ == "__main__":
    main()
