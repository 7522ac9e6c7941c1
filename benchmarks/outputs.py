"""Sizes of the vector animations before and after curves and keyframe reduction (issue 24), and their pixels.

For the gallery examples (`isotween.examples`, in their colours) and 20 drawing
pairs of the correspondence corpus (benchmarks/corpus.py: the classic icon
morphs when the icon sets are installed, else DejaVu glyph pairs), each
sequence is written as the rendered outputs are by default (1 s of motion at
24 fps, 0.25 s hold at both ends, 480 px): Lottie and animated SVG the old way
(the writers of the last commit before issue 24, read from git; without git,
``curves=False, reduce=False``: a polyline keyframe per tick) and the new way
(Bezier curves, reduced keys; the SVG's mesh edges grouped by the keys they
need), and the CSS animation. Pixels: Chromium draws the new Lottie
(lottie-web) and the new SVG (SMIL, paused) at a few ticks; the fraction of
pixels that differ by more than 60 levels from isotween's own PNG render of
the frame is compared with the bound of tests/test_lottie.py (2 %).

Run: ``PYTHONPATH=src python benchmarks/outputs.py [--pairs 20] [--no-pixels]``
"""

import argparse
import json
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "tests"))

import _results  # noqa: E402
import isotween  # noqa: E402
from isotween.outputs import timed, with_paint  # noqa: E402
from isotween.render import playback_order  # noqa: E402
from isotween.render._frames import SequenceRenderer  # noqa: E402
from isotween.render.defaults import DURATION, FPS, HOLD, SIZE  # noqa: E402
from isotween.render.lottie import lottie_data  # noqa: E402
from isotween.render.svg_animation import write_svg_animation  # noqa: E402
from isotween.render.web import css_text, web_animation  # noqa: E402

PLAYER = HERE.parent / "tests" / "js" / "node_modules" / "lottie-web" / "build" / "player" / "lottie.min.js"
PIXEL_SIZE = 240  # as the browser tests
BOUND = 0.02  # tests/test_lottie.py: at most 2 % of the pixels differ by more than 60 levels


def gallery():
    """(name, painted sequence) of every built-in example."""
    from isotween.examples import example_paint, load_example, names

    for name in names():
        src, tgt, options = load_example(name)
        options.pop("texture", None)
        yield name, with_paint(isotween.interpolate(src, tgt, **options), **example_paint(name))


def corpus_pairs(n):
    """(name, sequence) of ``n`` corpus pairs, drawn in the SVG files' own paint (black fills)."""
    import corpus

    try:
        chosen = [(f"{a.stem[:-5]}->{b.stem[:-5]}", a, b) for a, b in corpus.classic_pairs()][:n]
    except (SystemExit, OSError, Exception):  # no npm, no network: the glyphs need neither
        files = corpus.glyphs()
        rng = np.random.default_rng(20261124)
        chosen = []
        for _ in range(n):
            i, j = rng.choice(len(files), size=2, replace=False)
            chosen.append((f"glyph {corpus.GLYPHS[i % len(corpus.GLYPHS)]}->{corpus.GLYPHS[j % len(corpus.GLYPHS)]}",
                           files[i], files[j]))
    for name, a_file, b_file in chosen:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                a, b = isotween.io.load(a_file), isotween.io.load(b_file)
                src, tgt, _ = isotween.correspond(a, b)
                seq = isotween.interpolate(src, tgt, frames=9, fold="fallback" if src.n_faces else "allow")
            except isotween.errors.IsotweenError as exc:
                print(f"  skipped {name}: {exc}", flush=True)
                continue
        if seq.shape.paint is None:
            seq = with_paint(seq, fill="black")
        yield name, seq


#: the last commit before issue 24: its Lottie and SVG writers are "before"
BEFORE = "43a940c"


def old_writers():
    """``lottie_data`` and ``write_svg_animation`` of commit `BEFORE`, loaded from git; None without git.

    The modules are loaded inside the package (``isotween.render._before_*``) so that their relative
    imports resolve; everything they import still exists under the same name.
    """
    import importlib.util
    import subprocess

    out = []
    for name in ("svg_animation", "lottie"):
        try:
            text = subprocess.run(["git", "show", f"{BEFORE}:src/isotween/render/{name}.py"], cwd=HERE.parent,
                                  check=True, capture_output=True, text=True).stdout
        except (OSError, subprocess.CalledProcessError):
            return None
        # names that have moved since (the same functions): `_decimals` is `_view.decimals` now
        text = text.replace("from .html import _decimals", "from ._view import decimals as _decimals")
        folder = Path(tempfile.mkdtemp())
        (folder / f"{name}.py").write_text(text)
        spec = importlib.util.spec_from_file_location(f"isotween.render._before_{name}", folder / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = module
        spec.loader.exec_module(module)
        out.append(module)
    return out[1].lottie_data, out[0].write_svg_animation


OLD = old_writers()


def sizes(seq):
    """Bytes of each output, old and new (the default timing of rendered outputs)."""
    out = {}
    if OLD is not None:  # the writers of before, as they were
        lottie_old = OLD[0](seq, hold=HOLD, background="white")
    else:  # the closest option of today's writer
        lottie_old = lottie_data(seq, hold=HOLD, background="white", curves=False, reduce=False)
    lottie_new = lottie_data(seq, hold=HOLD, background="white")
    out["lottie_old"] = len(json.dumps(lottie_old, separators=(",", ":")))
    out["lottie_new"] = len(json.dumps(lottie_new, separators=(",", ":")))
    with tempfile.TemporaryDirectory() as folder:
        old, new = Path(folder) / "old.svg", Path(folder) / "new.svg"
        if OLD is not None:
            OLD[1](seq, old, hold=HOLD)
        else:
            write_svg_animation(seq, old, hold=HOLD, curves=False, reduce=False)
        write_svg_animation(seq, new, hold=HOLD)
        out["svg_old"], out["svg_new"] = old.stat().st_size, new.stat().st_size
    out["css"] = len(css_text(web_animation(seq, hold=HOLD)))
    return out, lottie_new


def pixels(page, seq, ticks=5):
    """Largest fraction of differing pixels over a few ticks: (lottie-web, SMIL) against our PNG render."""
    from browser import screenshot

    renderer = SequenceRenderer(seq, PIXEL_SIZE, background="white")
    order = playback_order(len(seq), FPS, HOLD)
    picks = np.unique(np.linspace(0, len(order) - 1, ticks).round().astype(int))
    data = lottie_data(seq, size=PIXEL_SIZE, hold=HOLD, background="white")
    page.set_viewport_size({"width": data["w"] + 20, "height": data["h"] + 20})
    page.set_content(f'<body style="margin:0;background:#fff"><div id="anim" '
                     f'style="width:{data["w"]}px;height:{data["h"]}px"></div></body>')
    page.add_script_tag(path=str(PLAYER))
    page.evaluate("text => { window.anim = lottie.loadAnimation({container: document.getElementById('anim'),"
                  " renderer: 'svg', loop: false, autoplay: false, animationData: JSON.parse(text)}); }",
                  json.dumps(data))

    def differ(selector, k):
        theirs = screenshot(page, selector).astype(int)
        ours = renderer.image(int(order[k])).astype(int)
        if theirs.shape != ours.shape:
            return 1.0
        return float((np.abs(theirs - ours).max(axis=2) > 60).mean())

    worst_lottie = 0.0
    for k in picks:
        page.evaluate(f"window.anim.goToAndStop({int(k)}, true)")
        worst_lottie = max(worst_lottie, differ("#anim", k))
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "a.svg"
        write_svg_animation(seq, path, hold=HOLD, size=PIXEL_SIZE, background="white")
        page.set_content(f'<body style="margin:0">{path.read_text().split("?>", 1)[1]}</body>')
    worst_svg = 0.0
    for k in picks:
        page.evaluate("t => { const s = document.querySelector('svg'); s.pauseAnimations(); s.setCurrentTime(t); }",
                      float(k) / FPS)
        worst_svg = max(worst_svg, differ("svg", k))
    return worst_lottie, worst_svg


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, default=20, help="corpus pairs [default: 20]")
    parser.add_argument("--no-pixels", action="store_true", help="sizes only (no Chromium)")
    parser.add_argument("--no-write", action="store_true", help="print, do not write RESULTS.md")
    args = parser.parse_args()
    started = time.perf_counter()
    cases = [("gallery", n, s) for n, s in gallery()] + [("corpus", n, s) for n, s in corpus_pairs(args.pairs)]
    browser = page = None
    if not args.no_pixels:
        from playwright.sync_api import sync_playwright

        from browser import ARGS, CHROMIUM

        play = sync_playwright().start()
        browser = play.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        page = browser.new_page()
    rows, ratios = [], {"lottie": [], "svg": []}
    worst = {"lottie": 0.0, "svg": 0.0}
    for kind, name, seq in cases:
        seq = timed(seq, DURATION, FPS)  # what `-o out.lottie.json` writes by default
        got, _ = sizes(seq)
        r_l, r_s = got["lottie_old"] / got["lottie_new"], got["svg_old"] / got["svg_new"]
        ratios["lottie"].append(r_l)
        ratios["svg"].append(r_s)
        px = ("", "")
        if page is not None:
            d_l, d_s = pixels(page, seq)
            worst["lottie"], worst["svg"] = max(worst["lottie"], d_l), max(worst["svg"], d_s)
            px = (f"{100 * d_l:.2f} %", f"{100 * d_s:.2f} %")
        rows.append([kind, name, seq.shape.n_vertices,
                     f"{got['lottie_old'] / 1e3:.1f}", f"{got['lottie_new'] / 1e3:.1f}", f"{r_l:.1f}x",
                     f"{got['svg_old'] / 1e3:.1f}", f"{got['svg_new'] / 1e3:.1f}", f"{r_s:.1f}x",
                     f"{got['css'] / 1e3:.1f}", *px])
        print(" | ".join(str(c) for c in rows[-1]), flush=True)
    if browser is not None:
        browser.close()
        play.stop()
    header = ["set", "case", "vertices", "Lottie before kB", "Lottie after kB", "smaller", "SVG before kB",
              "SVG after kB", "smaller", "CSS kB", "Lottie px differ", "SVG px differ"]
    if page is None:
        header, rows = header[:-2], [r[:-2] for r in rows]

    def geo(v):
        return float(np.exp(np.mean(np.log(v))))

    summary = (f"{len(rows)} cases, {DURATION:g} s of motion at {FPS} fps with {HOLD:g} s holds, {SIZE} px. "
               f"Lottie: {geo(ratios['lottie']):.1f}x smaller (geometric mean; least {min(ratios['lottie']):.1f}x), "
               f"animated SVG: {geo(ratios['svg']):.1f}x (least {min(ratios['svg']):.1f}x).")
    if page is not None:
        summary += (f" Pixels against our PNG render ({PIXEL_SIZE} px, 5 ticks a case): at most "
                    f"{100 * worst['lottie']:.2f} % (Lottie) and {100 * worst['svg']:.2f} % (SVG) differ by more "
                    f"than 60 levels; the bound of tests/test_lottie.py is {100 * BOUND:.0f} %.")
    before = (f"the Lottie and SVG writers of commit {BEFORE} (before issue 24), loaded from git" if OLD is not None
              else "`curves=False, reduce=False` (a polyline keyframe per tick)")
    body = (f"Before: {before}, on the same resampled sequence; after: the defaults (Bezier curves within 0.1 % "
            "of the diagonal, keys kept only where easing misses a tick by 0.25 % of it; the SVG in relative "
            "commands and whole numbers of a quarter of the curve tolerance, a mesh's edges in paths grouped by "
            "the keys they need). "
            f"{summary}\n\n" + _results.table(header, rows)
            + f"\n\nWall time: {time.perf_counter() - started:.0f} s.")
    print(summary)
    if not args.no_write:
        _results.write_section("Output sizes", body, "PYTHONPATH=src python benchmarks/outputs.py")


if __name__ == "__main__":
    main()
