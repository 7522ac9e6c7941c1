"""One solve core (Problem -> solve -> Result) and one place that picks the compute backend."""

import ast
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import isotween
from isotween import baselines, edit, interpolate, interpolate_keyframes, relative_velocity_field, transfer
from isotween.errors import MissingDependencyError, ParameterError
from isotween.optimisation import backend
from isotween.optimisation.problem import Result, pack
from isotween.optimisation.solve import solve
from isotween.problems import keyed_problem
from shapes import bend, grid_mesh

SRC = pathlib.Path(isotween.__file__).parent


@pytest.fixture(scope="module")
def bar():
    src = grid_mesh(12, 3)
    return src, src.with_vertices(bend(src.vertices, 0.9 * np.pi) * [1.0, 1.1])


@pytest.mark.parametrize("scheme", ["midpoint", "paper"])
@pytest.mark.parametrize("init", ["edge", "linear"])
def test_interpolate_is_the_two_key_case_of_keyframes(bar, scheme, init):
    """Same frames (to 1e-12 of the shape's size), energies and iteration count, uniform and eased times."""
    for easing in ("linear", "ease-in-out"):
        keys = interpolate_keyframes(list(bar), frames=9, easing=easing, scheme=scheme, init=init, tol=1e-6)
        two = interpolate(*bar, frames=9, times=keys.times, scheme=scheme, init=init, tol=1e-6)
        size = bar[0].bbox_diagonal()
        np.testing.assert_allclose(keys.frames, two.frames, rtol=0, atol=1e-12 * size)
        assert keys.iterations == two.iterations
        np.testing.assert_allclose(keys.energy, two.energy, rtol=1e-12)


def test_a_rigid_motion_is_recovered_through_problem_and_solve(bar):
    """The problem path alone (no public function) turns a bar rigidly, with both solvers."""
    src = bar[0]
    angle = 2.0
    tgt = src.rotate(angle).translate([3.0, -1.0])
    t = np.linspace(0.0, 1.0, 7)
    c0, c1 = src.z.mean(), tgt.z.mean()
    for solver in ("local", "global"):
        problem = keyed_problem([src, tgt], t, np.array([0, 6]), init="edge", scheme="midpoint", tol=1e-9,
                                max_iter=20, diagonal=src.bbox_diagonal())
        result = solve(problem, solver=solver)
        assert isinstance(result, Result) and result.converged
        for k, tk in enumerate(t):
            want = (src.z - c0) * np.exp(1j * angle * tk) + c0 + tk * (c1 - c0)
            np.testing.assert_allclose(result.z[:, k], want, atol=1e-9)


def test_global_solver_refuses_held_interior_frames(bar):
    keys = [bar[0], bar[1], bar[0]]
    t = np.linspace(0.0, 1.0, 9)
    problem = keyed_problem(keys, t, np.array([0, 4, 8]), init="edge", scheme="midpoint", tol=1e-6,
                            max_iter=5, diagonal=1.0)
    with pytest.raises(ParameterError, match="global solver holds only the first and the last frame"):
        solve(problem, solver="global")


def test_result_packs_frames_and_round_trips_through_a_sequence(bar):
    rng = np.random.default_rng(2)
    z = rng.standard_normal((bar[0].n_vertices, 4)) + 1j * rng.standard_normal((bar[0].n_vertices, 4))
    xy = pack(z)
    assert xy.shape == (4, bar[0].n_vertices, 2)
    np.testing.assert_array_equal(xy[..., 0], z.real.T)
    np.testing.assert_array_equal(xy[..., 1], z.imag.T)
    seq = Result(z, iterations=3, converged=False, info={"a": 1}).sequence(
        bar[0], np.linspace(0, 1, 4), method="m", info={"b": 2})
    np.testing.assert_array_equal(seq.z.T, z)
    assert (seq.iterations, seq.converged, seq.method, seq.info) == (3, False, "m", {"a": 1, "b": 2})


@pytest.mark.parametrize("call", [
    lambda a, b, seq: interpolate(a, b, 5, "global"),
    lambda a, b, seq: interpolate_keyframes([a, b], [0.0, 1.0]),
    lambda a, b, seq: transfer(a, b, a, 5, "local"),
    lambda a, b, seq: edit(seq, 2, seq[2]),
    lambda a, b, seq: relative_velocity_field(seq, "paper"),
    lambda a, b, seq: baselines.run("linear", a, b, 3, [0.0, 0.5, 1.0]),
])
def test_public_functions_take_options_by_keyword_only(bar, call):
    seq = interpolate(*bar, frames=5)
    with pytest.raises(TypeError, match="positional argument"):
        call(*bar, seq)


def _reads(tree, name):
    """Whether a module's syntax tree mentions ``name`` as a string or an attribute."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and node.value == name:
            return True
        if isinstance(node, ast.Attribute) and node.attr == name:
            return True
    return False


def test_only_the_backend_module_reads_the_switch_and_reaches_the_kernels():
    """ISOTWEEN_NUMBA is read in optimisation/backend.py alone; only it imports the numba kernels."""
    readers, importers = [], []
    for path in SRC.rglob("*.py"):
        tree = ast.parse(path.read_text())
        name = path.relative_to(SRC).as_posix()
        if _reads(tree, "ISOTWEEN_NUMBA") or _reads(tree, "ENABLED"):
            readers.append(name)
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and any(a.name == "accelerated" for a in node.names):
                importers.append(name)
            if isinstance(node, ast.ImportFrom) and (node.module or "").endswith("accelerated"):
                importers.append(name)
    assert readers == ["optimisation/backend.py"]
    assert importers == ["optimisation/backend.py"]


def test_the_environment_picks_the_backend_in_a_fresh_interpreter():
    code = "from isotween.optimisation import backend; print(backend.current().name)"
    env = {"PYTHONPATH": str(SRC.parent), "ISOTWEEN_NUMBA": "0", "PATH": ""}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "numpy"


def test_use_switches_the_backend_and_back():
    before = backend.current().name
    with backend.use("numpy"):
        assert backend.current().name == "numpy" and not backend.current().banded
    assert backend.current().name == before
    with pytest.raises(ParameterError, match="unknown backend 'cuda'"):
        backend.use("cuda")
    if "numba" not in backend.available():
        with pytest.raises(MissingDependencyError, match="numba"):
            backend.use("numba")


@pytest.mark.parametrize("module", ["isotween.baselines", "isotween.interpolate", "isotween.keyframes",
                                    "isotween.transfer", "isotween.optimisation.solve"])
def test_no_import_cycle(module):
    """Each module imports first in a fresh interpreter, and interpolate reaches baselines at module level."""
    code = (f"import importlib, sys; importlib.import_module({module!r}); "
            "m = sys.modules['isotween.interpolate']; import isotween.baselines as b; assert m.baselines is b")
    subprocess.run([sys.executable, "-c", code], env={"PYTHONPATH": str(SRC.parent), "PATH": ""}, check=True)


@pytest.mark.parametrize("times, message", [
    ("soon", "times must give one number per frame"),
    ([0.0, 1.0], r"one value per frame \(3\)"),
    ([0.0, 0.7, 0.5], "frame times must increase strictly from 0 to 1"),
])
def test_frame_times_are_checked_in_one_place(bar, times, message):
    """Bad times: `interpolate` and `interpolate_keyframes` refuse them with one check, naming frames or keyframes."""
    with pytest.raises(ParameterError, match=message):
        interpolate(*bar, frames=3, times=times)
    with pytest.raises(ParameterError, match=message.replace("frame", "keyframe")):
        interpolate_keyframes([bar[0], bar[1], bar[0]], times=times, frames=9)
