"""The numba kernels (isotween[fast]) give the numpy / scipy path's frames."""

import numpy as np
import pytest

from isotween import Shape, interpolate
from isotween.initialisation import edge_vector_init
from isotween.optimisation import accelerated, backend
from isotween.optimisation.assembly import FrameAssembler
from shapes import bend, chain, ellipse, grid_mesh, rotation

pytestmark = pytest.mark.skipif(backend.current().name != "numba", reason="numba missing or ISOTWEEN_NUMBA=0")


def two_bars():
    """Two separate triangulated bars (two components), the second one bent."""
    a = grid_mesh(12, 3)
    v = np.vstack([a.vertices, a.vertices + [0.0, 3.0]])
    src = Shape.from_mesh(v, np.vstack([a.faces, a.faces + a.n_vertices]))
    return src, src.with_vertices(np.vstack([bend(a.vertices, 2.0), a.vertices @ rotation(40).T]))


def pairs():
    bar = grid_mesh(30, 4)
    ring = ellipse(40)
    return {
        "bar": (bar, bar.with_vertices(bend(bar.vertices, 1.3 * np.pi) * [1.0, 1.2])),
        "two components": two_bars(),
        "ring": (ring, ring.with_vertices(ring.vertices @ rotation(150).T * [1.0, 0.6])),
        "chain": chain(25, 1.3),
    }


def run(pair, enabled, **kw):
    with backend.use("numba" if enabled else "numpy"):
        return interpolate(*pair, **kw)


@pytest.mark.parametrize("name", list(pairs()))
@pytest.mark.parametrize("frames", [3, 4, 17])
def test_kernels_give_the_numpy_frames(name, frames):
    pair = pairs()[name]
    moves = {True: [], False: []}
    seq = {}
    for enabled in (True, False):
        seq[enabled] = run(pair, enabled, frames=frames, tol=1e-12, max_iter=4,
                           callback=lambda it, energy, move, out=moves[enabled]: out.append(move))
    size = pair[0].bbox_diagonal()
    np.testing.assert_allclose(seq[True].frames, seq[False].frames, atol=1e-10 * size)
    assert seq[True].energy == pytest.approx(seq[False].energy, rel=1e-9)
    assert moves[True][1:] == pytest.approx(moves[False][1:], rel=1e-6)


def test_threaded_kernels_give_the_serial_frames(monkeypatch):
    pair = pairs()["two components"]
    serial = interpolate(*pair, frames=21, tol=1e-12, max_iter=3)
    monkeypatch.setattr(accelerated, "PARALLEL_SIZE", 0)
    threaded = interpolate(*pair, frames=21, tol=1e-12, max_iter=3)
    np.testing.assert_allclose(threaded.frames, serial.frames, atol=1e-12)
    assert threaded.energy == pytest.approx(serial.energy, rel=1e-12)


@pytest.mark.parametrize("threaded", [False, True])
@pytest.mark.parametrize("route", ["substitution", "blas"])
def test_banded_assembly_solves_eq10_and_reports_the_move(route, threaded, monkeypatch):
    """Both banded solves (substitution; BLAS on blocks of bandwidth rows), one thread or several."""
    monkeypatch.setattr(accelerated, "BLAS_BANDWIDTH", 0 if route == "blas" else 1 << 30)
    monkeypatch.setattr(accelerated, "BLAS_SIZE", 0)
    if threaded:
        monkeypatch.setattr(accelerated, "PARALLEL_SIZE", 0)
    src, tgt = two_bars()
    rng = np.random.default_rng(3)
    w = rng.uniform(0.5, 2.0, src.n_edges)
    e = rng.standard_normal((src.n_edges, 6)) + 1j * rng.standard_normal((src.n_edges, 6))
    centroids = rng.standard_normal((2, 6)) + 1j * rng.standard_normal((2, 6))
    banded = FrameAssembler(src, w)
    assert banded._band is not None
    nf, bw = banded._band[0].shape[0], banded._band[0].shape[1] - 1
    assert nf % bw and nf > 2 * bw  # BLAS: several blocks of rows, the last one partial
    with backend.use("numpy"):
        reference = FrameAssembler(src, w)
    want = reference.positions(e, centroids)
    np.testing.assert_allclose(banded.positions(e, centroids), want, atol=1e-10)
    # the normal equations of Eq. (10) hold and the centroids are where they were asked to be
    D, W = src.topology.D, np.diag(w)
    residual = (D.T @ W @ (D @ want - e))[reference.free]
    np.testing.assert_allclose(residual, 0.0, atol=1e-9)
    np.testing.assert_allclose(src.topology.avg @ want, centroids, atol=1e-12)
    z = rng.standard_normal((src.n_vertices, 8)) + 0j
    old = z.copy()
    move = banded.update(z, slice(1, 7), e, centroids)
    np.testing.assert_allclose(z[:, 1:7], want, atol=1e-10)
    np.testing.assert_array_equal(z[:, [0, 7]], old[:, [0, 7]])
    assert move == pytest.approx(np.abs(want - old[:, 1:7]).max(), rel=1e-9)


@pytest.mark.parametrize("threaded", [False, True])
@pytest.mark.parametrize("uniform", [True, False])
def test_edge_init_kernel_matches_numpy(uniform, threaded, monkeypatch):
    src, tgt = chain(40, 1.3)  # angles past pi: needs the propagation along the tree
    t = np.linspace(0, 1, 23) if uniform else np.sort(np.r_[0.0, np.random.default_rng(1).random(21), 1.0])
    if threaded:
        monkeypatch.setattr(accelerated, "PARALLEL_SIZE", 0)
    fast = edge_vector_init(src, src.edge_vectors(), tgt.edge_vectors(), t)
    with backend.use("numpy"):
        slow = edge_vector_init(src, src.edge_vectors(), tgt.edge_vectors(), t)
    np.testing.assert_allclose(fast, slow, atol=1e-12)
    np.testing.assert_allclose(fast[:, -1], tgt.edge_vectors(), atol=1e-12)


def test_band_cholesky_factorises_banded_matrices():
    rng = np.random.default_rng(5)
    n, bw = 30, 3
    A = np.zeros((n, n))
    for d in range(1, bw + 1):
        v = rng.uniform(-1, 1, n - d)
        A += np.diag(v, -d) + np.diag(v, d)
    A += np.diag(2 * bw + rng.uniform(0, 1, n))  # diagonally dominant: positive definite
    band = np.array([[A[j + d, j] if j + d < n else 0.0 for d in range(bw + 1)] for j in range(n)])
    assert accelerated.band_cholesky(band)
    L = np.zeros((n, n))
    for j in range(n):
        for d in range(min(bw, n - 1 - j) + 1):
            L[j + d, j] = band[j, d]
    np.testing.assert_allclose(L, np.linalg.cholesky(A), atol=1e-12)
    band = np.array([[1.0, 2.0], [1.0, 0.0]])  # [[1, 2], [2, 1]] is indefinite
    assert not accelerated.band_cholesky(band)


def test_fold_repair_derivatives_kernel_matches_numpy_and_the_energy():
    from isotween.optimisation.barrier import SymmetricDirichlet

    mesh = grid_mesh(9, 5)
    z0 = mesh.vertices[:, 0] + 1j * mesh.vertices[:, 1]
    z1 = z0 * np.exp(0.3j) + 0.05 * np.sin(3 * z0.real)  # bent a little: every face stays positive
    fixed = np.zeros(len(z0), dtype=bool)
    fixed[:3] = True
    energies = {}
    for name in ("numba", "numpy"):
        with backend.use(name):  # the energy keeps the backend in use when it is made
            energies[name] = SymmetricDirichlet(z0, z1, mesh.faces, fixed)
        energies[name].rest(0.4)
    energy = energies["numba"]
    fast, slow = energy.derivatives(z1), energies["numpy"].derivatives(z1)
    np.testing.assert_allclose(fast[0], slow[0], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(fast[1].toarray(), slow[1].toarray(), rtol=1e-12, atol=1e-9)
    # the gradient is the energy's: central differences along a random direction of the free coordinates
    d = np.random.default_rng(3).normal(size=2 * len(energy.free))
    step = np.zeros(len(z0), dtype=complex)
    step[energy.free] = d[: len(energy.free)] + 1j * d[len(energy.free):]
    h = 1e-6
    slope = (energy(z1 + h * step) - energy(z1 - h * step)) / (2 * h)
    assert slope == pytest.approx(fast[0] @ d, rel=1e-6)
    # a pull on some free vertices: its gradient joins, and 2 lam on their diagonal entries
    energy.pull_towards(np.arange(3, 20), z0[3:20], 0.7)
    g, A = energy.derivatives(z1)
    slope = (energy(z1 + h * step) - energy(z1 - h * step)) / (2 * h)
    assert slope == pytest.approx(g @ d, rel=1e-6)
    pulled = np.r_[np.arange(3, 20), np.arange(3, 20) + len(energy.free)] - 3  # free coordinates
    added = (A - fast[1]).toarray()
    np.testing.assert_allclose(np.diag(added)[pulled], 1.4, rtol=1e-12)
    added[pulled, pulled] = 0.0
    assert np.abs(added).max() < 1e-9


def test_small_problems_run_on_numpy_until_numba_is_loaded_unless_chosen(monkeypatch):
    monkeypatch.setattr(accelerated, "numba", None)  # as in a fresh process
    monkeypatch.setitem(backend._state, "long_lived", False)
    with backend.sized(backend.FIRST_NUMBA - 1):
        assert backend.current().name == "numpy"
    with backend.sized(backend.FIRST_NUMBA):
        assert backend.current().name == "numba"
    with backend.use("numba"), backend.sized(10):  # chosen: kept
        assert backend.current().name == "numba"
    backend.long_lived()
    with backend.sized(10):
        assert backend.current().name == "numba"


def test_newton_hessian_sums_every_face_block_in_its_place():
    # the sparse pattern (one sort of vertex pairs) against a dense sum of the faces' 6 x 6 blocks, with
    # fixed vertices, a free vertex in no face and a pull (added on the diagonal)
    from isotween.optimisation.barrier import SymmetricDirichlet

    mesh = grid_mesh(7, 6)
    z0 = mesh.vertices[:, 0] + 1j * mesh.vertices[:, 1]
    z1 = z0 * np.exp(0.2j) + 0.04 * np.cos(2 * z0.imag)
    for lonely in (False, True):
        a, b = (np.r_[z0, 9 + 9j], np.r_[z1, 9 + 9j]) if lonely else (z0, z1)
        fixed = np.zeros(len(a), dtype=bool)
        fixed[[0, 5, 17]] = True
        energy = SymmetricDirichlet(a, b, mesh.faces, fixed)
        energy.rest(0.5)
        energy.pull_towards(energy.free[::3], a[energy.free[::3]], 0.3)
        g, A = energy.derivatives(b)
        _, H6 = backend.current().face_derivatives(b, energy.faces, energy._G, energy._area)
        dense = np.zeros(A.shape)
        dof = energy._dof
        rows, cols = np.broadcast_to(dof[:, :, None], H6.shape), np.broadcast_to(dof[:, None, :], H6.shape)
        keep = (rows >= 0) & (cols >= 0)
        np.add.at(dense, (rows[keep], cols[keep]), H6[keep])
        m = len(energy.free)
        slots = np.searchsorted(energy.free, energy.free[::3])
        dense[np.r_[slots, slots + m], np.r_[slots, slots + m]] += 0.6
        np.testing.assert_allclose(A.toarray(), dense, rtol=1e-12, atol=1e-12)
