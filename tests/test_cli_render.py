"""Rendering controls on the command line: `isotween render`, playback options, colours, summary."""

import json
import re

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from isotween import Sequence, Shape, io, metrics
from isotween.cli import main
from isotween.paint import Paint
from test_colour import MID  # Oklab midpoint of red and blue, from published Oklab values

SQUARE = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


@pytest.fixture
def saved(tmp_path):
    """A 5-frame sequence file of a square that slides and turns."""
    shape = Shape.from_polygon(SQUARE)
    z = shape.z
    frames = [z * np.exp(1j * a) + 2 * a for a in np.linspace(0, 1, 5)]
    seq = Sequence(np.stack([np.column_stack([f.real, f.imag]) for f in frames]), shape)
    io.save_sequence(seq, tmp_path / "q.npz")
    return tmp_path / "q.npz"


def gif_timing(path):
    with Image.open(path) as im:
        durations = []
        for k in range(im.n_frames):
            im.seek(k)
            durations.append(im.info["duration"])
        return im.size, durations, im.info.get("loop")


def test_help_short_option_and_method_choices():
    result = run("-h")
    assert result.exit_code == 0 and "render" in result.output and "interpolate" in result.output
    result = run("interpolate", "-h")
    assert result.exit_code == 0
    choices = "[aiap|linear|intrinsic|arap|arap-baxter|shapespace|convex|injective]"
    assert choices in result.output.replace("\n", "").replace(" ", "")
    for name in ("--fps", "--size", "--hold", "--bounce", "--loop", "--title", "--background", "--fill"):
        assert name in result.output
    result = run("interpolate", "a.obj", "b.obj", "--method", "magic", "-o", "x.npz")
    assert result.exit_code == 2 and "'magic' is not one of" in result.output


def test_render_applies_fps_size_hold_bounce_loop(tmp_path, saved):
    out = tmp_path / "a.gif"
    result = run("render", saved, "-o", out, "--fps", 10, "--size", "64x48", "--hold", 0.5, "--bounce",
                 "--no-loop", "--duration", 0, "-q")  # duration 0: the 5 frames, one per tick
    assert result.exit_code == 0, result.output
    size, durations, loop = gif_timing(out)
    assert size == (64, 48) and loop is None
    # 5 ticks of hold on each end (merged into one long GIF frame), then back: 0.1 s per tick
    assert sum(durations) == 100 * (5 + 5 + 5 + 3)
    assert durations[0] == 600 and durations[4] == 600
    result = run("render", saved, "-o", tmp_path / "b.gif", "-q")
    _, durations, loop = gif_timing(tmp_path / "b.gif")
    # the defaults: 24 fps (4 centiseconds a tick), 1 s of motion (25 frames resampled from 5),
    # held 0.25 s (6 ticks) on the first and the last frame, looping
    # (Pillow merges the 7 equal ticks of 42 ms: 294 ms, stored in centiseconds)
    assert loop == 0 and durations == [290] + [40] * 23 + [290]


@pytest.mark.parametrize("name", ["a.webp", "a.apng", "a.svg", "a.html", "a.lottie.json", "a.png", "back.json"])
def test_render_writes_every_kind(tmp_path, saved, name):
    result = run("render", saved, "-o", tmp_path / name, "--fps", 12, "-q")
    assert result.exit_code == 0, result.output
    assert result.output.strip().endswith(str(tmp_path / name))
    if name.endswith(".lottie.json"):
        data = json.loads((tmp_path / name).read_text())
        # 12 fps: 1 s of motion is 13 ticks, plus 3 ticks of hold at each end; title: the input file
        assert data["fr"] == 12 and data["op"] == 13 + 2 * 3 and data["nm"] == "q.npz"
        assert data["layers"][-1]["ty"] == 1 and data["layers"][-1]["sc"] == "#ffffff"  # the white background
    elif name == "back.json":
        np.testing.assert_allclose(io.load_sequence(tmp_path / name).frames, io.load_sequence(saved).frames)
    elif name.endswith(".html"):
        assert "<title>q.npz</title>" in (tmp_path / name).read_text()


def test_format_lottie_and_refusals(tmp_path, saved):
    result = run("render", saved, "-o", tmp_path / "anim.json", "--format", "lottie", "-q")
    assert result.exit_code == 0, result.output
    assert json.loads((tmp_path / "anim.json").read_text())["layers"]
    for args, needle in ((["--size", "3x3"], "is not a size"), (["--fill", "reddish"], "is not a colour"),
                         (["--background", "red:blue"], "give one colour"),
                         (["--fps", "0"], "--fps")):
        result = run("render", saved, "-o", tmp_path / "x.gif", *args)
        assert result.exit_code == 2 and needle in result.output
    assert not (tmp_path / "x.gif").exists()


def test_fill_option_blends_in_oklab(tmp_path, saved):
    result = run("render", saved, "-o", tmp_path / "c.svg", "--fill", "red:blue", "--stroke", "black",
                 "--duration", 0, "--hold", 0, "-q")  # the 5 frames, one per tick: frame 2 is the midpoint
    assert result.exit_code == 0, result.output
    text = (tmp_path / "c.svg").read_text()
    fills = re.search(r'attributeName="fill" values="([^"]*)"', text).group(1).split(";")
    assert fills[0] == "#ff0000" and fills[-1] == "#0000ff"
    mid = [int(fills[2][i:i + 2], 16) for i in (1, 3, 5)]
    assert np.abs(np.array(mid) - MID).max() <= 1  # the Oklab midpoint of red and blue
    assert 'stroke="#000000"' in text


def test_keyframes_and_transfer_take_solver_options(tmp_path):
    shape = Shape.from_polyline(np.column_stack([np.linspace(0, 1, 8), np.zeros(8)]))
    bent = shape.with_vertices(np.column_stack([np.sin(np.linspace(0, 1, 8)), 1 - np.cos(np.linspace(0, 1, 8))]))
    io.save(shape, tmp_path / "a.json")
    io.save(bent, tmp_path / "b.json")
    io.save(shape.with_vertices(shape.vertices * 2), tmp_path / "c.json")
    result = run("transfer", tmp_path / "a.json", tmp_path / "b.json", tmp_path / "c.json", "-n", 5,
                 "--solver", "global", "--init", "linear", "--easing", "ease-in", "-o", tmp_path / "t.npz", "-q")
    assert result.exit_code == 0, result.output
    seq = io.load_sequence(tmp_path / "t.npz")
    np.testing.assert_allclose(seq.times, np.linspace(0, 1, 5) ** 2)  # ease-in reached the solver
    line = result.output.strip()
    # the summary measures the written (transferred) sequence itself
    energy = float(re.search(r"energy=(\S+)", line).group(1))
    assert energy == pytest.approx(metrics.isometric_energy(seq), rel=1e-3)
    assert "nan" not in line and "seconds=" in line
    result = run("keyframes", tmp_path / "a.json", tmp_path / "b.json", tmp_path / "a.json", "--init", "linear",
                 "--scheme", "paper", "-o", tmp_path / "k.npz", "-q")
    assert result.exit_code == 0, result.output
    assert io.load_sequence(tmp_path / "k.npz").scheme == "paper"


def test_paint_of_the_inputs_reaches_the_rendered_sequence(tmp_path):
    base = Shape.from_polygon(SQUARE)
    a = Shape(base.vertices, base.edges, paths=base.paths, paint=[Paint(fill=(1, 0, 0, 1))])
    b = Shape(base.vertices + 2, base.edges, paths=base.paths, paint=[Paint(fill=(0, 0, 1, 1))])
    from isotween import interpolate

    io.save_sequence(interpolate(a, b, frames=5), tmp_path / "p.npz")
    result = run("render", tmp_path / "p.npz", "-o", tmp_path / "p.svg", "-q")
    assert result.exit_code == 0, result.output
    assert 'values="#ff0000;' in (tmp_path / "p.svg").read_text()


def test_demo_example_in_colour(tmp_path):
    result = run("demo", "holes", "-o", tmp_path / "d", "-q", "--size", 120)
    assert result.exit_code == 0, result.output
    with Image.open(tmp_path / "d" / "holes.gif") as im:
        first = np.asarray(im.convert("RGB")).reshape(-1, 3).astype(int)
        im.seek(im.n_frames - 1)
        last = np.asarray(im.convert("RGB")).reshape(-1, 3).astype(int)
    # the example's paint: dark red at the start, blue at the end
    assert (np.abs(first - [0xC0, 0x39, 0x2B]).max(axis=1) <= 6).sum() > 500
    assert (np.abs(last - [0x1F, 0x5F, 0xA8]).max(axis=1) <= 6).sum() > 500
    assert "isotween demo: holes" in (tmp_path / "d" / "holes.html").read_text()


def test_info_reports_the_paint(tmp_path):
    base = Shape.from_polygon(SQUARE)
    a = Shape(base.vertices, base.edges, paths=base.paths, paint=[Paint(fill=(1, 0, 0, 1))])
    b = Shape(base.vertices + 2, base.edges, paths=base.paths, paint=[Paint(fill=(0, 0, 1, 1))])
    from isotween import interpolate

    io.save_sequence(interpolate(a, b, frames=3), tmp_path / "p.npz")
    result = run("info", tmp_path / "p.npz")
    assert result.exit_code == 0 and "paint: fills #ff0000 -> #0000ff (Oklab blend)" in result.output


@pytest.mark.parametrize("name", ["s.svg", "s.css", "s.lottie.json"])
def test_summary_gives_the_size_of_what_was_written(tmp_path, saved, name):
    result = run("render", saved, "-o", tmp_path / name, "-q")
    assert result.exit_code == 0, result.output
    written = result.output.strip().split(" -> ")[1].split(", ")
    total = sum((tmp_path / w).stat().st_size for w in written)
    size = re.search(r"size=(\S+)", result.output).group(1)
    value, unit = float(re.match(r"[\d.]+", size).group()), re.sub(r"[\d.]+", "", size)
    assert value * {"B": 1, "kB": 1e3, "MB": 1e6}[unit] == pytest.approx(total, rel=0.06, abs=1)
