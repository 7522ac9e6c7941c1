"""The CHOLMOD path of Eq. (10) writes the frames sparse LU computes, whatever the layout of its inputs."""

import numpy as np
import pytest

from isotween import Shape
from isotween.optimisation import assembly
from isotween.optimisation.assembly import FrameAssembler
from shapes import grid_mesh

pytest.importorskip("sksparse.cholmod")


@pytest.fixture(scope="module")
def pieces():
    """Three bars, vertices shuffled so that components and free vertices interleave."""
    parts = [grid_mesh(9, 3), grid_mesh(5, 4), grid_mesh(12, 2)]
    v, f, k = [], [], 0
    for i, p in enumerate(parts):
        v.append(p.vertices + [0.0, 3.0 * i])
        f.append(p.faces + k)
        k += p.n_vertices
    v, f = np.vstack(v), np.vstack(f)
    perm = np.random.default_rng(3).permutation(len(v))
    rank = np.argsort(perm)
    shape = Shape.from_mesh(v[perm], rank[f])
    assert shape.topology.n_components == 3
    return shape


def _problem(shape, frames, seed=0):
    rng = np.random.default_rng(seed)
    E, C = shape.n_edges, shape.topology.n_components
    w = rng.uniform(0.5, 2.0, E)
    edges = rng.standard_normal((E, frames)) + 1j * rng.standard_normal((E, frames))
    centroids = rng.standard_normal((C, frames)) + 1j * rng.standard_normal((C, frames))
    z = rng.standard_normal((shape.n_vertices, frames)) + 1j * rng.standard_normal((shape.n_vertices, frames))
    return w, edges, centroids, z


@pytest.mark.parametrize("block_bytes", [4 << 20, 16 * 7])
@pytest.mark.parametrize("frames", [slice(1, 10), np.array([1, 2, 5, 9])])
def test_cholmod_update_matches_splu(pieces, monkeypatch, block_bytes, frames):
    """Same frames and the same Eq. (11) move to 1e-10, in blocks of a few rows or one block.

    Columns as the local solver passes them: a slice of a C-ordered array (read in place), or
    keyframes picked out (a copy).
    """
    monkeypatch.setattr(FrameAssembler, "BLOCK_BYTES", block_bytes)
    w, edges, centroids, z = _problem(pieces, 11)
    fast = FrameAssembler(pieces, w, factorisation="cholmod")
    ref = FrameAssembler(pieces, w, factorisation="splu")
    assert (fast.method, ref.method) == ("cholmod", "splu")
    if block_bytes < 1 << 10:
        assert len(fast._row_blocks(2 * 9)) > 10
    z_fast, z_ref = z.copy(), z.copy()
    for it in range(2):  # a second iteration reuses the first one's arrays
        e = edges[:, frames] * (1.0 + 0.5j * it)
        move = fast.update(z_fast, frames, e, centroids[:, frames])
        move_ref = ref.update(z_ref, frames, e, centroids[:, frames])
        np.testing.assert_allclose(z_fast, z_ref, atol=1e-10)
        assert move == pytest.approx(move_ref, rel=1e-10) and move > 0
    # the frames left alone are untouched; each component's centroid is where it was asked to be
    rest = np.setdiff1d(np.arange(11), np.arange(11)[frames])
    np.testing.assert_array_equal(z_fast[:, rest], z[:, rest])
    np.testing.assert_allclose(pieces.topology.centroids(z_fast[:, frames]), centroids[:, frames], atol=1e-12)


def test_cholmod_positions_solve_eq10(pieces):
    """Positions satisfy the normal equations of Eq. (10): D^T W (D z - e) = 0 at every free vertex."""
    w, edges, centroids, _ = _problem(pieces, 6, seed=1)
    top = pieces.topology
    z = FrameAssembler(pieces, w, factorisation="cholmod").positions(edges, centroids)
    residual = top.D.T @ (w[:, None] * (top.D @ z - edges))
    np.testing.assert_allclose(residual[top.free], 0.0, atol=1e-10)


def _address(a):
    return a.__array_interface__["data"][0]


def test_parent_columns_reads_a_slice_in_place():
    """A column slice is read as columns of a C-ordered view of the memory it lies in; anything else is not."""
    flat = np.arange(60, dtype=complex)
    whole = flat.reshape(12, 5)
    for e in (whole[:, 1:4], whole[:, 1:4][:, 1:], whole[::2, 1:3], whole, flat.reshape(4, 15)[:, 6:9]):
        found, first = assembly._parent_columns(e)
        part = found[:, first : first + e.shape[1]]
        assert found.flags.c_contiguous and np.shares_memory(found, flat)
        assert _address(part) == _address(e) and part.strides == e.strides
        np.testing.assert_array_equal(part, e)
    for other in (whole[:, ::2], whole.T, whole.real.copy(), np.asfortranarray(whole)[:, 1:3]):
        assert assembly._parent_columns(other)[0] is None
