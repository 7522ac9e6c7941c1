"""Size and speed of the HTML viewer (`isotween.render.write_html`) in headless Chromium.

For each case: page size, time from navigation to the first frame drawn
(wall time from page.goto until the page reports it has inflated its data
and drawn; polled every 20 ms, so an upper bound), the time to show one
frame (setFrame until two animation frames later, so the canvas has been
rasterised; median over all frames, so at least one display interval), and
the playback rate (frames drawn per second while playing, requestAnimationFrame
paced). Medians of --runs page loads. Frames are made directly (a grid mesh
turning and stretching), not solved.

Usage: python benchmarks/page.py [--runs 5] [--no-write]
"""

import argparse
import shutil
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

CASES = [("43k vertices, 30 frames", 208, 30), ("10k vertices, 30 frames", 100, 30)]
ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--disable-component-update",
        "--disable-sync"]


def sequence(n_side, frames):
    from isotween import Sequence
    from shapes import grid_mesh

    mesh = grid_mesh(n_side, n_side, length=1.0, width=1.0)
    z = mesh.z
    t = np.linspace(0, 1, frames)[:, None]
    zt = (z - 0.5 - 0.5j) * np.exp(1j * np.pi * t) * (1 + 0.3 * t * z.real) + 2 * t
    return Sequence(np.stack([zt.real, zt.imag], axis=-1), mesh)


def wait_ready(page, timeout=60.0):
    """Wait until the page has inflated its data and drawn its first frame (polled from here)."""
    deadline = time.monotonic() + timeout
    while page.evaluate("document.body.dataset.ready") != "1":
        if time.monotonic() > deadline:
            raise TimeoutError("the page never drew its first frame")
        time.sleep(0.02)


def measure(page, path, mode):
    t0 = time.perf_counter()
    page.goto(path.as_uri(), wait_until="commit")
    wait_ready(page)
    first = 1000 * (time.perf_counter() - t0)  # navigation to first frame, polled every 20 ms
    if mode != page.eval_on_selector("#mode", "s => s.value"):
        page.select_option("#mode", mode)
    draw_ms = page.evaluate("""async () => {
        const n = window.isotween.nFrames, times = [];
        const painted = () => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)));
        await painted();
        for (let k = 0; k < n; k++) {
            const t0 = performance.now(); window.isotween.setFrame(k); await painted();
            times.push(performance.now() - t0);
        }
        times.sort((a, b) => a - b); return times[Math.floor(times.length / 2)]; }""")
    page.select_option("#speed", "4")
    page.click("#play")
    start = page.evaluate("window.isotween.drawn()")
    t0 = time.perf_counter()
    time.sleep(3.0)
    fps = (page.evaluate("window.isotween.drawn()") - start) / (time.perf_counter() - t0)
    page.click("#play")
    return first, draw_ms, fps


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--runs", type=int, default=5)
    parser.add_argument("--no-write", action="store_true")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    from isotween import render

    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    rows = []
    with tempfile.TemporaryDirectory() as folder, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=chromium, args=ARGS)
        page = browser.new_page(viewport={"width": 900, "height": 640})
        for name, n_side, frames in CASES:
            seq = sequence(n_side, frames)
            path = Path(folder) / f"{n_side}.html"
            t0 = time.perf_counter()
            render.write_html(seq, path)
            write_s = time.perf_counter() - t0
            mb = path.stat().st_size / 2**20
            print(f"{name}: page {mb:.2f} MB written in {write_s:.1f} s", flush=True)
            for mode in ("fill", "wire"):
                runs = [measure(page, path, mode) for _ in range(args.runs)]
                first, draw_ms, fps = (statistics.median(r[i] for r in runs) for i in range(3))
                rows.append([name, mode, f"{mb:.2f}", f"{write_s:.1f}", f"{first:.0f}", f"{draw_ms:.1f}", f"{fps:.0f}"])
                print(" | ".join(rows[-1]), flush=True)
        browser.close()
    body = table(["case", "view", "page MB", "write s", "first frame ms", "show ms/frame", "playback fps"], rows)
    body += ("\n\nMedians of the page loads; 'first frame' runs from navigation to the first drawn frame "
             "(data inflated in the browser), 'show' is setFrame until two animation frames later "
             "(rasterised; median over the frames, at least one display interval), "
             "'playback' counts frames drawn per second while playing at 4x (requestAnimationFrame paced, "
             "so at most the display rate). Headless Chromium with --disable-gpu (software canvas). "
             "Measured on a shared machine under load from other jobs.")
    print(body)
    if not args.no_write:
        write_section("HTML viewer", body, "python benchmarks/page.py")


if __name__ == "__main__":
    main()
