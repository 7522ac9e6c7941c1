"""Every per-frame format of ``isotween render`` loads back as it was written (issue 22 item 6).

A frame written by ``render --format FMT`` and loaded again is the frame: the
same vertices (to 1e-9), edges and orientation (``y_down``); and ``edit``
with that unchanged frame leaves the sequence as it was. Formats that are
y-up by convention (OBJ, OFF) or y-down (SVG) write the other orientation
with y negated, so that other programs show the shape upright, and mark the
file so that isotween negates it back.
"""

import numpy as np
import pytest
from click.testing import CliRunner

from isotween import Shape, interpolate
from isotween.cli import main
from isotween.io import FRAME_FORMATS, load, load_sequence, save_sequence
from shapes import bend, grid_mesh

FRAME = 4


def _ring_sequence(y_down):
    t = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    ring = np.c_[2 * np.cos(t), np.sin(t) + 0.3 * np.cos(3 * t)]
    source = Shape.from_paths([ring], [True], y_down=y_down)
    return interpolate(source, source.rotate(1.2), frames=9)


def _mesh_sequence(y_down):
    bar = grid_mesh(8, 3)
    source = Shape(bar.vertices, faces=bar.faces, y_down=y_down)
    return interpolate(source, source.with_vertices(bend(source.vertices, np.pi / 2)), frames=9)


CASES = [(fmt, kind, y_down) for fmt in FRAME_FORMATS for kind in ("outline", "mesh") for y_down in (False, True)
         if not (fmt == "svg" and kind == "mesh")]  # SVG stores outlines, not triangles


@pytest.fixture(scope="module")
def sequences():
    return {(kind, y_down): (_ring_sequence if kind == "outline" else _mesh_sequence)(y_down)
            for kind in ("outline", "mesh") for y_down in (False, True)}


def _run(*args):
    result = CliRunner().invoke(main, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return result


def test_every_frame_format_is_covered():
    assert set(FRAME_FORMATS) == {fmt for fmt, _, _ in CASES}


@pytest.mark.parametrize("fmt, kind, y_down", CASES)
def test_a_rendered_frame_loads_back_as_it_was_written(sequences, tmp_path, fmt, kind, y_down):
    seq = sequences[kind, y_down]
    save_sequence(seq, tmp_path / "seq.npz")
    _run("render", tmp_path / "seq.npz", "--format", fmt, "-o", tmp_path / "frames")
    frame = load(tmp_path / "frames" / f"frame_{FRAME:04d}.{fmt}")
    assert frame.y_down == y_down
    np.testing.assert_allclose(frame.vertices, seq.frames[FRAME], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(frame.edges, seq.shape.edges)
    if kind == "mesh":
        np.testing.assert_array_equal(frame.faces, seq.shape.faces)


@pytest.mark.parametrize("fmt, kind, y_down", CASES)
def test_edit_with_an_unchanged_rendered_frame_changes_nothing(sequences, tmp_path, fmt, kind, y_down):
    seq = sequences[kind, y_down]
    save_sequence(seq, tmp_path / "seq.npz")
    _run("render", tmp_path / "seq.npz", "--format", fmt, "-o", tmp_path / "frames")
    _run("edit", tmp_path / "seq.npz", "--frame", FRAME, "--shape", tmp_path / "frames" / f"frame_{FRAME:04d}.{fmt}",
         "-o", tmp_path / "edited.npz")
    edited = load_sequence(tmp_path / "edited.npz")
    assert edited.shape.y_down == y_down
    np.testing.assert_allclose(edited.frames, seq.frames, rtol=0, atol=1e-9)
