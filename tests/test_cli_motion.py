"""`isotween transfer`, `edit` and `keyframes` from the command line."""

import numpy as np
from click.testing import CliRunner

from isotween import interpolate
from isotween.cli import main
from isotween.io import load, load_sequence, save
from shapes import bend, grid_mesh


def test_transfer_edit_keyframes_commands(tmp_path):
    src = grid_mesh(10, 3)
    bent = src.with_vertices(bend(src.vertices, np.pi))
    half = src.with_vertices(bend(src.vertices, np.pi / 2))
    for name, shape in (("a", src), ("b", bent), ("h", half)):
        save(shape, tmp_path / f"{name}.obj")
    a, b, h = (str(tmp_path / f"{n}.obj") for n in "abh")
    run = CliRunner().invoke

    r = run(main, ["transfer", a, b, a, "--frames", "7", "-o", str(tmp_path / "t.npz"), "-q"])
    assert r.exit_code == 0, r.output
    ref = interpolate(load(a), load(b), frames=7)
    np.testing.assert_allclose(load_sequence(tmp_path / "t.npz").frames, ref.frames, atol=1e-9)

    r = run(main, ["interpolate", a, b, "-o", str(tmp_path / "s.npz"), "-q"])
    assert r.exit_code == 0, r.output
    r = run(main, ["edit", str(tmp_path / "s.npz"), "--frame", "4", "--shape", h,
                   "-o", str(tmp_path / "e.npz")])
    assert r.exit_code == 0, r.output
    np.testing.assert_allclose(load_sequence(tmp_path / "e.npz").frames[4], half.vertices, atol=1e-9)

    r = run(main, ["keyframes", a, h, b, "--frames", "13", "-o", str(tmp_path / "k.npz"), "-q"])
    assert r.exit_code == 0, r.output
    k = load_sequence(tmp_path / "k.npz")
    np.testing.assert_allclose(k.frames[[0, 6, 12]], [src.vertices, half.vertices, bent.vertices], atol=1e-12)

    r = run(main, ["edit", str(tmp_path / "s.npz"), "--frame", "40", "--shape", h,
                   "-o", str(tmp_path / "bad.npz")])
    assert r.exit_code != 0 and "frame index 40 is out of range" in r.output
    assert not (tmp_path / "bad.npz").exists()
