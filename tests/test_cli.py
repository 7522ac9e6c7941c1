"""The command line: results, summary line, and one-line errors without partial output."""

import os

import numpy as np
import pytest
from click.testing import CliRunner

from isotween import Shape, io
from isotween.cli import main
from isotween.correspondence.correspond import MIN_POINTS
from isotween.render.defaults import DURATION, FPS


def run(*args):
    result = CliRunner().invoke(main, [str(a) for a in args])
    return result


def assert_one_line_error(result, *needles):
    assert result.exit_code != 0
    assert result.exception is None or isinstance(result.exception, SystemExit)
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: "), result.stderr
    assert "Traceback" not in result.output
    for needle in needles:
        assert needle in lines[0]


def chain(n=12):
    t = np.linspace(0.0, 1.0, n)
    return Shape.from_polyline(np.column_stack([t, 0.3 * t**2]))


def rotated(shape, angle, shift=0.0):
    z = shape.z * np.exp(1j * angle) + shift
    return shape.with_vertices(np.column_stack([z.real, z.imag]))


@pytest.fixture
def pair(tmp_path):
    """An open chain and the same chain turned by 120 degrees and moved."""
    src = chain()
    io.save(src, tmp_path / "a.obj")
    io.save(rotated(src, 2 * np.pi / 3, 2 + 1j), tmp_path / "b.off")
    return tmp_path / "a.obj", tmp_path / "b.off"


def test_interpolate_recovers_a_rigid_motion(tmp_path, pair):
    result = run("interpolate", *pair, "--frames", 7, "-o", tmp_path / "out.npz", "--quiet")
    assert result.exit_code == 0, result.output
    seq = io.load_sequence(tmp_path / "out.npz")
    src, tgt = io.load(pair[0]), io.load(pair[1])
    assert len(seq) == 7
    np.testing.assert_allclose(seq.frames[0], src.vertices, atol=1e-9)
    np.testing.assert_allclose(seq.frames[-1], tgt.vertices, atol=1e-9)
    # every in-between of a rigid motion keeps every edge length
    lengths = np.abs(seq.edge_vectors())
    np.testing.assert_allclose(lengths, np.abs(src.edge_vectors())[None, :].repeat(7, axis=0), rtol=1e-6)
    line = result.stdout.strip()
    assert line.startswith(f"frames=7 vertices={src.n_vertices} edges={src.n_edges} iterations=")
    assert "converged=yes" in line and "energy=" in line and "seconds=" in line and "out.npz" in line
    assert result.stderr == ""  # --quiet: no progress bar


def test_interpolate_frame_folder_matches_sequence_file(tmp_path, pair):
    assert run("interpolate", *pair, "-n", 5, "-o", tmp_path / "s.json", "-q").exit_code == 0
    result = run("interpolate", *pair, "-n", 5, "-o", tmp_path / "frames", "--format", "obj", "-q")
    assert result.exit_code == 0, result.output
    assert sorted(os.listdir(tmp_path / "frames")) == [f"frame_{k:04d}.obj" for k in range(5)]
    a = io.load_sequence(tmp_path / "s.json")
    b = io.load_sequence(tmp_path / "frames")
    np.testing.assert_array_equal(a.frames, b.frames)


def test_interpolate_options_reach_the_solver(tmp_path, pair):
    out = tmp_path / "g.npz"
    result = run("interpolate", *pair, "-n", 4, "--solver", "global", "--scheme", "paper",
                 "--init", "linear", "--max-iter", 1, "-o", out, "-q")
    assert result.exit_code == 0, result.output
    seq = io.load_sequence(out)
    assert (seq.scheme, seq.iterations, len(seq)) == ("paper", 1, 4)


def test_info_prints_counts_and_box(tmp_path):
    shape = Shape.from_polygon([[[0, 0], [4, 0], [4, 3]], [[10, -1], [11, -1], [11, 2], [10, 2]]])
    io.save(shape, tmp_path / "s.off")
    result = run("info", tmp_path / "s.off")
    assert result.exit_code == 0, result.output
    lines = result.stdout.splitlines()
    assert lines[:4] == ["vertices: 7", "edges: 7", "faces: 0", "components: 2"]
    assert lines[4].startswith("bounding box: x 0 .. 11, y -1 .. 3")


def test_info_on_a_sequence(tmp_path, pair):
    run("interpolate", *pair, "-n", 6, "-o", tmp_path / "s.npz", "-q")
    result = run("info", tmp_path / "s.npz")
    assert result.exit_code == 0
    assert result.stdout.splitlines()[0] == "frames: 6"
    assert "vertices: 12" in result.stdout


# ---------------------------------------------------------------- errors
def test_missing_file(tmp_path, pair):
    result = run("interpolate", pair[0], tmp_path / "nope.obj", "-o", tmp_path / "o.npz")
    assert_one_line_error(result, "nope.obj", "no such file")
    assert not (tmp_path / "o.npz").exists()


def test_unknown_extensions(tmp_path, pair):
    (tmp_path / "s.ply").write_text("ply\n")
    assert_one_line_error(run("interpolate", tmp_path / "s.ply", pair[1], "-o", tmp_path / "o.npz"), "s.ply", "'.ply'")
    assert_one_line_error(run("interpolate", *pair, "-o", tmp_path / "o.xyz"), "o.xyz", "unknown output kind")
    assert_one_line_error(run("info", tmp_path / "s.ply"), "s.ply")


@pytest.mark.parametrize(
    "name, text, needles",
    [
        ("bad.obj", "v 0 0\nv 1 0\nv 2 zz\n", ["bad.obj", "line 3", "'zz' is not a number"]),
        ("flat.obj", "v 0 0 0\nv 1 0 0.25\nl 1 2\n", ["flat.obj", "line 2", "z = 0.25"]),
        ("bad.svg", '<svg xmlns="http://www.w3.org/2000/svg"><path id="p7" d="M 0 0 L x"/></svg>',
         ["bad.svg", '<path id="p7">', "malformed path data"]),
        ("bad.json", '{"vertices": [\n[0, 0],\n[0, "y"]]}', ["bad.json", "line 3", "vertices[1]"]),
    ],
)
def test_malformed_inputs(tmp_path, pair, name, text, needles):
    (tmp_path / name).write_text(text)
    out = tmp_path / "o.gif"
    result = run("interpolate", tmp_path / name, pair[1], "-o", out)
    assert_one_line_error(result, *needles)
    assert not out.exists()


def test_different_vertex_counts_are_put_in_correspondence(tmp_path, pair):
    io.save(chain(7), tmp_path / "short.json")
    result = run("interpolate", pair[0], tmp_path / "short.json", "-n", 5, "-o", tmp_path / "o.npz")
    assert result.exit_code == 0, result.output
    lines = result.stdout.strip().splitlines()
    # at least the larger input's 12 points (every input vertex kept), and at least MIN_POINTS
    assert len(lines) == 2 and lines[0].startswith("correspondence: polylines 1 paired; ")
    assert int(lines[0].split("; ")[1].split()[0]) >= max(12, MIN_POINTS)
    seq = io.load_sequence(tmp_path / "o.npz")
    # both ends lie on their chains (y = 0.3 x^2), end points kept
    for frame in (seq.frames[0], seq.frames[-1]):
        np.testing.assert_allclose(frame[:, 1], 0.3 * frame[:, 0] ** 2, atol=0.01)
        np.testing.assert_allclose(frame[[0, -1]], [[0, 0], [1, 0.3]], atol=1e-12)


def test_shapes_without_paths_name_the_file(tmp_path, pair):
    io.save(Shape(np.eye(3)[:, :2] + [[0, 0], [0, 0], [1, 1]], [[0, 1], [1, 2], [2, 0], [0, 2]][:3]),
            tmp_path / "soup.npz")
    soup = io.load(tmp_path / "soup.npz")
    assert not soup.paths
    result = run("interpolate", pair[0], tmp_path / "soup.npz", "-o", tmp_path / "o.npz")
    assert_one_line_error(result, "soup.npz (target)", "the target has no paths")
    assert not (tmp_path / "o.npz").exists()


def test_unwritable_output(tmp_path, pair):
    (tmp_path / "plain").write_text("x")
    result = run("interpolate", *pair, "-o", tmp_path / "plain" / "o.npz")
    assert_one_line_error(result, "o.npz", "not a folder")
    result = run("interpolate", *pair, "-o", tmp_path / "plain", "--format", "obj")
    assert_one_line_error(result, "plain", "not a folder")
    assert sorted(os.listdir(tmp_path)) == ["a.obj", "b.off", "plain"]


def test_missing_texture(tmp_path, pair):
    result = run("interpolate", *pair, "-o", tmp_path / "o.npz", "--texture", tmp_path / "t.png")
    assert_one_line_error(result, "t.png")
    assert not (tmp_path / "o.npz").exists()


# ---------------------------------------------------------------- rendering and demo (merged later)
def test_gif_and_energy_plot(tmp_path, pair):
    pytest.importorskip("isotween.render")
    from PIL import Image

    result = run("interpolate", *pair, "-n", 5, "-o", tmp_path / "a.gif", "--plot", tmp_path / "e.png", "-q")
    assert result.exit_code == 0, result.output
    with Image.open(tmp_path / "a.gif") as im:  # 1 s of motion at 24 fps by default: 25 frames from the 5
        assert im.n_frames == round(DURATION * FPS) + 1
    with Image.open(tmp_path / "e.png") as im:
        assert im.format == "PNG"


def test_demo(tmp_path):
    examples = pytest.importorskip("isotween.examples")
    pytest.importorskip("isotween.render")
    listed = run("demo", "--list")
    assert listed.exit_code == 0
    assert [line.split()[0] for line in listed.stdout.splitlines()] == list(examples.names())
    name = examples.names()[0]
    result = run("demo", name, "-o", tmp_path / "d", "-q")
    assert result.exit_code == 0, result.output
    assert sorted(os.listdir(tmp_path / "d")) == sorted([f"{name}.gif", f"{name}.html"])
    assert_one_line_error(run("demo", "no-such-example", "-o", tmp_path / "e"), "no-such-example")
    assert not (tmp_path / "e").exists()
