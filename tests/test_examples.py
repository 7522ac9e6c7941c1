"""The example gallery: every example runs under `isotween demo`, and covers what it claims."""

import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import isotween
from isotween import examples, io
from isotween.cli import main
from isotween.errors import ParameterError
from isotween.render.defaults import DURATION, FPS, HOLD

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("name", examples.names())
def test_every_example_runs_under_demo(tmp_path, name):
    pytest.importorskip("isotween.render")
    from PIL import Image

    result = CliRunner().invoke(main, ["demo", name, "-o", str(tmp_path), "-q"])
    assert result.exit_code == 0, result.output
    src, tgt, options = examples.load_example(name)
    with Image.open(tmp_path / f"{name}.gif") as im:  # 1 s of motion at 24 fps by default, resampled
        durations = []
        for k in range(im.n_frames):
            im.seek(k)
            durations.append(im.info["duration"])
    # Pillow merges equal frames in a row (a plus whose arms are gone by half way), adding their durations
    assert len(durations) <= round(DURATION * FPS) + 1
    assert sum(durations) == pytest.approx(1000 * (DURATION + 2 * HOLD), abs=10 * len(durations))
    assert f"frames={options['frames']} vertices={src.n_vertices} edges={src.n_edges} " in result.stdout
    assert (tmp_path / f"{name}.html").stat().st_size > 0


def test_gallery_covers_the_issue():
    MplPath = pytest.importorskip("matplotlib.path").Path
    loaded = {name: examples.load_example(name) for name in examples.names()}
    assert len(loaded) >= 6
    for src, tgt, _ in loaded.values():
        isotween.check_compatible(src, tgt)
    # a polygon with holes: closed rings inside the outer ring
    src = loaded["holes"][0]
    assert len(src.paths) == 3 and all(c for _, c in src.paths)
    outer = MplPath(src.vertices[src.paths[0][0]])
    assert all(outer.contains_points(src.vertices[p]).all() for p, _ in src.paths[1:])
    # open polylines
    assert all(not c for _, c in loaded["curls"][0].paths)
    # a textured mesh
    src, _, options = loaded["hopper"]
    assert src.n_faces > 0 and src.uv is not None and Path(options["texture"]).is_file()
    # glyphs with different point counts before resampling
    raw = [io.load(examples.DATA / f"glyphs-{side}.npz") for side in ("source", "target")]
    assert raw[0].n_vertices != raw[1].n_vertices
    # an edge soup: several components, and a vertex where three or more edges meet
    soup = loaded["soup"][0]
    assert soup.n_components >= 3 and np.bincount(soup.edges.ravel()).max() >= 3


def test_worm_turns_its_head_by_more_than_half_a_turn():
    src, tgt, options = examples.load_example("worm")
    seq = isotween.interpolate(src, tgt, **options)
    ends = [np.argmin(src.vertices[:, 0]), np.argmax(src.vertices[:, 0])]  # tail and head tips
    tail, head = (int(np.flatnonzero(np.any(src.edges == v, axis=1))[0]) for v in ends)
    e = seq.edge_vectors()
    turn = np.unwrap(np.angle(e[:, head] / e[:, tail]))  # head against tail, frame by frame
    assert abs(turn[-1] - turn[0]) > np.pi
    assert np.all(np.abs(np.diff(turn)) < np.pi / 4)  # in small steps, not a jump


def test_glyph_outlines_interpolate_from_the_command_line(tmp_path):
    """Two glyph outlines with different point counts, end to end through SVG files."""
    pytest.importorskip("svgelements")
    raw = [io.load(examples.DATA / f"glyphs-{side}.npz") for side in ("source", "target")]
    io.save(raw[0], tmp_path / "S.svg")
    io.save(raw[1], tmp_path / "5.svg")
    result = CliRunner().invoke(main, ["interpolate", str(tmp_path / "S.svg"), str(tmp_path / "5.svg"),
                                       "--resample", "150", "-n", "6", "-o", str(tmp_path / "out.npz"), "-q"])
    assert result.exit_code == 0, result.output
    seq = io.load_sequence(tmp_path / "out.npz")
    assert seq.frames.shape == (6, 150, 2) and seq.shape.n_edges == 150
    # every ring stays closed: closed paths, each vertex on exactly two edges
    # (the glyphs' orientation travels through the SVG files isotween wrote)
    assert all(closed for _, closed in seq.shape.paths) and seq.shape.y_down == raw[0].y_down
    assert np.all(np.bincount(seq.shape.edges.ravel(), minlength=150) == 2)
    # and the ends are the resampled inputs
    src, tgt = isotween.resample(io.load(tmp_path / "S.svg"), io.load(tmp_path / "5.svg"), points=150)
    np.testing.assert_allclose(seq.frames[0], src.vertices, atol=1e-12)
    np.testing.assert_allclose(seq.frames[-1], tgt.vertices, atol=1e-12)


def test_readme_shows_every_gallery_strip_and_the_demo():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    linked = set(re.findall(r"docs/gallery/([\w-]+)\.png", readme)) - {"studio"}  # the studio's screenshot
    assert linked == set(examples.names())
    assert "docs/gallery/demo.gif" in readme
    for name in linked | {"demo"}:
        path = ROOT / "docs" / "gallery" / (f"{name}.gif" if name == "demo" else f"{name}.png")
        assert path.is_file() and path.stat().st_size < 150 * 1024


def test_unknown_example():
    with pytest.raises(ParameterError, match="unknown example 'nope'; available: worm"):
        examples.load_example("nope")
