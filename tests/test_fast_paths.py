"""Every shortcut of the solvers gives the straightforward solver's frames."""

import numpy as np
import pytest

from isotween import interpolate, metrics
from isotween.initialisation import edge_vector_init
from isotween.optimisation import backend, reference
from isotween.optimisation.assembly import FrameAssembler
from shapes import bend, chain, grid_mesh


@pytest.fixture(scope="module")
def bar():
    src = grid_mesh(30, 4)
    tgt = src.with_vertices(bend(src.vertices, 1.3 * np.pi) * [1.0, 1.2])
    return src, tgt


def test_edge_blocks_on_threads_match_one_block(bar, monkeypatch):
    ref = interpolate(*bar, frames=33, tol=1e-7)
    monkeypatch.setattr(reference.EdgeBlocks, "BYTES", 16 * 33 * 7)  # 7 edges a block
    fast = interpolate(*bar, frames=33, tol=1e-7)
    np.testing.assert_allclose(fast.frames, ref.frames, atol=1e-12)
    assert fast.energy == pytest.approx(ref.energy, rel=1e-12)


def test_uniform_time_init_equals_closed_form():
    src, tgt = chain(40, 1.3)
    t = np.linspace(0, 1, 23)
    fast = edge_vector_init(src, src.edge_vectors(), tgt.edge_vectors(), t)
    t_nonuniform = t.copy()
    t_nonuniform[5] += 1e-13  # forces the closed-form branch
    slow = edge_vector_init(src, src.edge_vectors(), tgt.edge_vectors(), t_nonuniform)
    np.testing.assert_allclose(fast, slow, atol=1e-11)


@pytest.mark.parametrize("scheme", ["midpoint", "paper"])
def test_frozen_weights_keep_quality_of_per_frame_weights(bar, scheme):
    """Rules of the performance issue: energy within 1 %, deviation within 0.1 pp."""
    fast = interpolate(*bar, frames=21, scheme=scheme)
    ref = interpolate(*bar, frames=21, scheme=scheme, assembly="per-frame")
    e_fast, e_ref = metrics.isometric_energy(fast), metrics.isometric_energy(ref)
    assert abs(e_fast - e_ref) <= 0.01 * e_ref
    assert abs(metrics.edge_length_deviation(fast) - metrics.edge_length_deviation(ref)) <= 1e-3


@pytest.mark.parametrize("numba", [False, True])
@pytest.mark.parametrize("assembly", ["shared", "relative", "per-frame"])
def test_eq11_compares_successive_iterations(bar, numba, assembly):
    """Eq. (11) measures how far the frames moved between two iterations.

    Positive and, with a tolerance below it, no early stop (a solver that compared the frames with themselves stopped at
    iteration 2).
    """
    if numba and "numba" not in backend.available():
        pytest.skip("numba missing")
    moves = []
    with backend.use("numba" if numba else "numpy"):
        seq = interpolate(*bar, frames=9, tol=1e-12, max_iter=5, assembly=assembly,
                          callback=lambda it, energy, move: moves.append(move))
        diag = np.hypot(*np.ptp(np.vstack([bar[0].vertices, bar[1].vertices]), axis=0))
        loose = interpolate(*bar, frames=9, tol=1.01 * moves[2] / diag, max_iter=5, assembly=assembly)
    assert seq.iterations == 5 and not seq.converged
    assert all(m > 0 for m in moves[1:])
    assert loose.iterations == 3


def _local(pair, frames, factorisation, tol=1e-7, max_iter=100):
    """`interpolate`'s local solve with a chosen factorisation of Eq. (10): (z (n, F), Result)."""
    from isotween.optimisation.solve import solve
    from isotween.problems import keyed_problem

    src, tgt = pair
    t = np.linspace(0.0, 1.0, frames)
    problem = keyed_problem([src, tgt], t, np.array([0, frames - 1]), init="edge", scheme="midpoint",
                            tol=tol, max_iter=max_iter, diagonal=1.0)
    result = solve(problem, factorisation=factorisation)
    return result.z, result


def _methods():
    from isotween.optimisation.assembly import HAVE_CHOLMOD

    return ["splu"] + (["banded"] if backend.current().banded else []) + (["cholmod"] if HAVE_CHOLMOD else [])


@pytest.mark.parametrize("method", ["banded", "cholmod"])
def test_factorisations_give_the_same_frames(bar, method):
    """Every factorisation of Eq. (10) gives sparse LU's frames to 1e-10 of the shape's size.

    The bar is 4 long; the iteration count is the same too.
    """
    if method not in _methods():
        pytest.skip(f"{method} not available (numba / scikit-sparse)")
    rng = np.random.default_rng(7)
    w = rng.uniform(0.5, 2.0, bar[0].n_edges)
    e = rng.standard_normal((bar[0].n_edges, 5)) + 1j * rng.standard_normal((bar[0].n_edges, 5))
    c = rng.standard_normal((1, 5)) + 1j * rng.standard_normal((1, 5))
    fast, ref = FrameAssembler(bar[0], w, factorisation=method), FrameAssembler(bar[0], w, factorisation="splu")
    assert (fast.method, ref.method) == (method, "splu")
    np.testing.assert_allclose(fast.positions(e, c), ref.positions(e, c), atol=1e-10)
    z_ref, info_ref = _local(bar, 17, "splu")
    z, info = _local(bar, 17, method)
    assert info.iterations == info_ref.iterations
    np.testing.assert_allclose(z, z_ref, atol=1e-10)
    assert info.energy == pytest.approx(info_ref.energy, rel=1e-9)


def test_cholmod_factorises_once_per_solve_and_analyses_once_per_connectivity(bar, monkeypatch):
    """Eq. (10) is factorised once for all iterations of a solve.

    The fill-reducing ordering (symbolic analysis) once for every shape with the same connectivity.
    """
    cholmod = pytest.importorskip("sksparse.cholmod")
    from isotween.optimisation import assembly

    calls = {"analyze": 0, "factor": 0}
    analyze = cholmod.analyze

    def counting_analyze(*args, **kwargs):
        calls["analyze"] += 1
        symbolic = analyze(*args, **kwargs)

        class Counting:
            def cholesky(self, L):
                calls["factor"] += 1
                return symbolic.cholesky(L)

        return Counting()

    monkeypatch.setattr(cholmod, "analyze", counting_analyze)
    monkeypatch.setattr(assembly, "_ANALYSIS", type(assembly._ANALYSIS)())
    src, tgt = bar
    _, info = _local((src, tgt), 9, "cholmod", tol=1e-12, max_iter=4)
    assert info.iterations == 4 and calls == {"analyze": 1, "factor": 1}
    other = tgt.with_vertices(tgt.vertices * [1.0, 0.8])  # new weights, same connectivity
    _local((src, other), 9, "cholmod", tol=1e-12, max_iter=3)
    assert calls == {"analyze": 1, "factor": 2}


def test_unknown_factorisation_is_a_parameter_error(bar):
    from isotween.errors import ParameterError

    with pytest.raises(ParameterError, match="unknown factorisation 'qr'"):
        FrameAssembler(bar[0], factorisation="qr")
