"""`isotween transfer`, `edit` and `keyframes` from the command line."""

import numpy as np
import pytest
from click.testing import CliRunner

from isotween import interpolate
from isotween.cli import main
from isotween.io import load, load_sequence, save
from shapes import bend, grid_mesh


@pytest.fixture
def files(tmp_path):
    """A straight bar, bent by 180 and by 90 degrees: ``(src, bent, half)`` shapes and their .obj paths."""
    src = grid_mesh(10, 3)
    bent = src.with_vertices(bend(src.vertices, np.pi))
    half = src.with_vertices(bend(src.vertices, np.pi / 2))
    for name, shape in (("a", src), ("b", bent), ("h", half)):
        save(shape, tmp_path / f"{name}.obj")
    return (src, bent, half), tuple(str(tmp_path / f"{n}.obj") for n in "abh")


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args])


def test_transfer_command(files, tmp_path):
    _, (a, b, _) = files
    r = run("transfer", a, b, a, "--frames", "7", "-o", tmp_path / "t.npz", "-q")
    assert r.exit_code == 0, r.output
    ref = interpolate(load(a), load(b), frames=7)
    np.testing.assert_allclose(load_sequence(tmp_path / "t.npz").frames, ref.frames, atol=1e-9)


def test_edit_command(files, tmp_path):
    (_, _, half), (a, b, h) = files
    r = run("interpolate", a, b, "-o", tmp_path / "s.npz", "-q")
    assert r.exit_code == 0, r.output
    r = run("edit", tmp_path / "s.npz", "--frame", "4", "--shape", h, "-o", tmp_path / "e.npz")
    assert r.exit_code == 0, r.output
    np.testing.assert_allclose(load_sequence(tmp_path / "e.npz").frames[4], half.vertices, atol=1e-9)


def test_keyframes_command(files, tmp_path):
    (src, bent, half), (a, b, h) = files
    r = run("keyframes", a, h, b, "--frames", "13", "-o", tmp_path / "k.npz", "-q")
    assert r.exit_code == 0, r.output
    k = load_sequence(tmp_path / "k.npz")
    np.testing.assert_allclose(k.frames[[0, 6, 12]], [src.vertices, half.vertices, bent.vertices], atol=1e-12)


def test_edit_command_refuses_a_frame_out_of_range(files, tmp_path):
    _, (a, b, h) = files
    r = run("interpolate", a, b, "-o", tmp_path / "s.npz", "-q")
    assert r.exit_code == 0, r.output
    r = run("edit", tmp_path / "s.npz", "--frame", "40", "--shape", h, "-o", tmp_path / "bad.npz")
    assert r.exit_code != 0 and "frame index 40 is out of range" in r.output
    assert not (tmp_path / "bad.npz").exists()
