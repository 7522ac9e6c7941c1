"""One solve core (Problem -> solve -> Result) and one place that picks the compute backend."""

import ast
import dataclasses
import pathlib
import subprocess
import sys
import types

import numpy as np
import pytest

import isotween
from isotween import baselines, edit, interpolate, interpolate_keyframes, problems, relative_velocity_field, transfer
from isotween.errors import MissingDependencyError, ParameterError
from isotween.optimisation import backend
from isotween.optimisation.problem import Problem, Result, pack
from isotween.optimisation.solve import solve
from isotween.problems import assemble, held_problem, keyed_problem
from shapes import bend, ellipse, grid_mesh

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
    code = (f"import importlib, sys; importlib.import_module({module!r}); import isotween.interpolate; "
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


# ---------------------------------------------------------------- every entry point builds through held_problem

@pytest.fixture
def built(monkeypatch):
    """Snapshots of every Problem made while the test runs, and the count of all Problems constructed.

    ``problems.held_problem`` is wrapped wherever it is bound, and ``Problem.__init__``
    is counted, so a Problem made around the builder shows up as a mismatch.
    """
    original, init = problems.held_problem, Problem.__init__
    made, count = [], [0]

    def recording(*args, **kwargs):
        p = original(*args, **kwargs)
        snapshot = {f.name: getattr(p, f.name) for f in dataclasses.fields(p)}  # as built, before any solve
        snapshot.update(z=p.z.copy(), centroids=p.centroids.copy(), edges=None if p.edges is None else p.edges.copy())
        made.append(types.SimpleNamespace(**snapshot))
        return p

    def counting(self, *args, **kwargs):
        count[0] += 1
        init(self, *args, **kwargs)

    for name, module in list(sys.modules.items()):
        if name.startswith("isotween") and getattr(module, "held_problem", None) is original:
            monkeypatch.setattr(module, "held_problem", recording)
    monkeypatch.setattr(Problem, "__init__", counting)
    return made, count


def _held(problem):
    """Indices of the held frames of a snapshot."""
    return np.flatnonzero(problem.held).tolist()


def test_interpolate_and_keyframes_build_through_the_builder(bar, built):
    made, count = built
    a, b = bar
    seq = interpolate(a, b, frames=7)
    keys = interpolate_keyframes([a, b, a], frames=9)
    assert count[0] == len(made) == 2
    two, three = made
    assert _held(two) == [0, 6] and _held(three) == [0, 4, 8]
    np.testing.assert_array_equal(two.z[:, [0, 6]], np.c_[a.z, b.z])
    np.testing.assert_array_equal(three.z[:, [0, 4, 8]], np.c_[a.z, b.z, a.z])
    np.testing.assert_array_equal(two.times, seq.times)
    np.testing.assert_array_equal(three.times, keys.times)
    assert two.edges is not None and three.edges is not None


def test_transfer_builds_its_target_problem_through_the_builder(bar, built):
    """Two problems: the source pair held at both ends, the target held at its first frame only."""
    made, count = built
    a, b = bar
    target = a.with_vertices(a.vertices * [1.0, 1.5] + [0.2, -0.1])
    seq = transfer(a, b, target, frames=7)
    assert count[0] == len(made) == 2
    source, tgt = made
    assert _held(source) == [0, 6] and _held(tgt) == [0]
    np.testing.assert_array_equal(tgt.z[:, 0], target.z)
    np.testing.assert_array_equal(tgt.times, seq.times)
    np.testing.assert_array_equal(tgt.edges[:, 0], target.edge_vectors())  # exact on the held frame
    np.testing.assert_allclose(tgt.centroids[:, 0], target.topology.centroids(target.z), rtol=0, atol=1e-12)
    np.testing.assert_array_equal(seq.frames[0], target.vertices)


@pytest.mark.parametrize("keep_ends, held", [(True, [0, 3, 6]), (False, [3])])
def test_edit_builds_its_problem_through_the_builder(bar, built, keep_ends, held):
    made, count = built
    seq = interpolate(*bar, frames=7)
    bent = seq[3].with_vertices(seq[3].vertices + 0.1 * np.sin(seq[3].vertices[:, ::-1]))
    edited = edit(seq, frame=3, shape=bent, keep_ends=keep_ends)
    assert count[0] == len(made) == 2  # the interpolation, then the edit
    problem = made[1]
    assert _held(problem) == held and problem.edges is not None
    np.testing.assert_array_equal(problem.z[:, 3], bent.z)
    np.testing.assert_array_equal(edited.frames[3], bent.vertices)  # held frames kept bit for bit


#: the methods whose modules live in isotween/baselines under their own name
BASELINES = ("linear", "intrinsic", "arap", "arap-baxter", "shapespace", "convex", "injective")


def _pair(method, bar):
    """A pair of shapes the method takes: a polygon for 'intrinsic', the triangulated bar else."""
    if method == "intrinsic":
        src = ellipse(20)
        return src, src.with_vertices(src.vertices @ [[0.3, 1.2], [-0.9, 0.4]] + [1.0, 2.0])
    return bar


@pytest.mark.parametrize("method", BASELINES)
def test_baselines_run_builds_one_problem_and_equals_the_method_on_it(bar, built, method):
    """run() builds one Problem (both inputs held, no initial edges) and returns what the method gives on it."""
    made, count = built
    src, tgt = _pair(method, bar)
    t = np.array([0.0, 0.1, 0.35, 0.5, 0.8, 1.0])
    seq = baselines.run(method, src, tgt, 6, times=t, tol=1e-4, max_iter=30)
    assert count[0] == len(made) == 1
    problem = made[0]
    assert _held(problem) == [0, 5] and problem.edges is None
    np.testing.assert_array_equal(problem.z[:, [0, 5]], np.c_[src.z, tgt.z])
    np.testing.assert_array_equal(problem.times, t)
    np.testing.assert_array_equal(seq.times, t)
    module = baselines.method_module(method)
    again = keyed_problem([src, tgt], t, np.array([0, 5]), init=None, scheme="midpoint", tol=1e-4, max_iter=30)
    direct = module.solve(again).z
    size = src.bbox_diagonal()
    np.testing.assert_allclose(seq.z, direct.T, rtol=0, atol=1e-12 * size)


@pytest.mark.parametrize("method", BASELINES)
def test_baselines_refuse_a_problem_with_a_held_interior_frame(bar, method):
    src, tgt = _pair(method, bar)
    problem = keyed_problem([src, tgt, src], np.linspace(0, 1, 5), np.array([0, 2, 4]), init=None,
                            scheme="midpoint", tol=1e-4, max_iter=5)
    module = baselines.method_module(method)
    with pytest.raises(ParameterError, match="holds only the first and the last frame"):
        module.solve(problem)


def test_solvers_refuse_a_problem_without_initial_edges(bar):
    problem = keyed_problem(list(bar), np.linspace(0, 1, 5), np.array([0, 4]), init=None, scheme="midpoint",
                            tol=1e-4, max_iter=5)
    with pytest.raises(ParameterError, match="initial edges"):
        solve(problem)
    with pytest.raises(ParameterError, match="edges"):
        assemble(problem, np.ones(bar[0].n_edges))


def test_assemble_recovers_a_rigid_motion_from_its_exact_edges(bar):
    """Exact edges and centroids of a turn about the centroid: assemble() gives the turned frames, held ones intact."""
    src = bar[0]
    t = np.linspace(0.0, 1.0, 6)
    c = src.topology.centroids(src.z)
    turn = np.exp(1j * 1.7 * t)
    want = (src.z - c)[:, None] * turn + c + (0.5 - 2j) * t
    edges = src.edge_vectors()[:, None] * turn
    centroids = (c + (0.5 - 2j) * t)[None, :]
    problem = held_problem(src, t, np.array([0, 3]), want[:, [0, 3]], centroids=centroids, edges=edges)
    result = assemble(problem, np.ones(src.n_edges))
    np.testing.assert_allclose(result.z, want, rtol=0, atol=1e-12 * src.bbox_diagonal())
    np.testing.assert_array_equal(result.z[:, [0, 3]], want[:, [0, 3]])
