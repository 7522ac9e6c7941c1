"""Method 'injective': the convex morph refined towards isometry, never folding.

Every in-between frame is an embedding of the completed disc (no flipped
triangle, no crossing of a region's outline), the ends are the inputs, the
outline's edge lengths follow their linear blend far better than the convex
morph's, and the line search never leaves the embeddings.
"""

import sys
import time

import numpy as np
import pytest

import isotween
from isotween.foldfree import injective
from isotween.geometry import triangle_areas
from isotween.metrics import edge_length_deviation, flipped_faces, outline_crossings
from isotween.optimisation import barrier
from test_convex import pair


def outline_deviation(seq):
    """SPEC.md's edge-length deviation of the closed paths' edges only (the drawn outline)."""
    shape = seq.shape
    rings = [p for p, closed in shape.paths if closed]
    outline = isotween.Shape(shape.vertices, np.vstack([np.c_[p, np.roll(p, -1)] for p in rings]))
    return edge_length_deviation(isotween.Sequence(frames=seq.frames, shape=outline, times=seq.times))


@pytest.mark.parametrize("name", ["W->T", "square->U", "B->D"])
def test_never_folds_ends_exact_and_far_more_isometric_than_convex(name):
    src, tgt = pair(name)
    seq = isotween.interpolate(src, tgt, frames=9, method="injective")
    assert seq.method == "injective"
    assert flipped_faces(seq, None).tolist() == [0] * 9
    assert outline_crossings(seq, scope="region").tolist() == [0] * 9
    assert np.array_equal(seq.frames[0], src.vertices)  # bit for bit
    assert np.array_equal(seq.frames[-1], tgt.vertices)
    base = isotween.interpolate(src, tgt, frames=9, method="convex")
    # measured (outline edge-length deviation, injective / convex) on pairs corresponded with every
    # input vertex kept (short edges where the drawings' vertices interleave): W->T 0.48 / 0.78,
    # square->U 0.27 / 0.46, B->D 0.82 / 1.22
    assert outline_deviation(seq) <= 0.7 * outline_deviation(base)


def test_rigid_pair_is_recovered():
    src, _ = pair("square->U")
    tgt = src.rotate(2.0, origin=(1.0, 2.0)).translate([5.0, -3.0])
    seq = isotween.interpolate(src, tgt, frames=7, method="injective")
    # the energy's minimum is the identity in the aligned placement: every frame is the
    # rotation by t * 2 rad about the centroid, the centroid moving on a straight line
    cs, ct = src.z.mean(), tgt.z.mean()
    t = seq.times[:, None]
    expected = (src.z - cs) * np.exp(2j * t) + cs + t * (ct - cs)
    assert np.abs(seq.z - expected).max() < 1e-6 * src.bbox_diagonal()


def test_max_step_is_the_first_time_a_triangle_degenerates():
    z = np.array([0, 1, 0.5 + 1j, 0.5 - 1j])
    faces = np.array([[0, 1, 2], [1, 0, 3]])  # both counter-clockwise
    d = np.array([0, 0, -3j, 0])  # vertex 2 pushed down through the edge 0-1 (at s = 1/3)
    s = injective.max_step(z, d, faces)
    assert s == pytest.approx(1 / 3, rel=1e-12)
    areas = [triangle_areas(z + k * d, faces) for k in (0.99 * s, s, 1.0)]
    assert np.all(areas[0] > 0) and abs(areas[1][0]) < 1e-12 and areas[2][0] < 0  # a full step flips
    # a quadratic case: vertex 2 moves right while 1 moves left; they cross edge 0-1's line later
    d2 = np.array([0, -2, 1.5 - 0.5j, 0])
    s2 = injective.max_step(z, d2, faces)
    a = triangle_areas(z + s2 * d2, faces)
    assert np.min(np.abs(a)) < 1e-12 and np.all(triangle_areas(z + 0.999 * s2 * d2, faces) > 0)
    assert injective.max_step(z, np.zeros(4, complex), faces) == np.inf  # standing still never flips
    assert injective.max_step(z, 2 * z, faces) == np.inf  # a scaling never flips


def test_every_newton_iterate_is_an_embedding(monkeypatch):
    src, tgt = pair("W->T")
    seen = []
    original = barrier.SymmetricDirichlet.derivatives

    def record(self, z):
        seen.append(triangle_areas(z, self.faces).min())
        return original(self, z)

    monkeypatch.setattr(barrier.SymmetricDirichlet, "derivatives", record)
    isotween.interpolate(src, tgt, frames=5, method="injective")
    assert len(seen) >= 3 and min(seen) > 0


def test_fallback_says_what_it_did(monkeypatch, shared_only):
    from isotween.foldfree import repair

    monkeypatch.setattr(repair, "WORK", 0)  # the repair gives up: the injective morph replaces AIAP
    src, tgt = pair("W->T")
    seq = isotween.interpolate(src, tgt, frames=9, fold="fallback")
    assert seq.method == "injective"
    assert "replaced by the fold-free injective morph" in seq.info["fallback"]
    assert seq.info["components"][0]["iterations"] > 0


def test_superlu_and_cholmod_give_the_same_frames(monkeypatch):
    src, tgt = pair("square->U")
    monkeypatch.setattr(barrier, "HAVE_CHOLMOD", False)  # SuperLU, as where scikit-sparse is missing
    lu = isotween.interpolate(src, tgt, frames=5, method="injective")
    assert flipped_faces(lu) == 0
    monkeypatch.undo()
    if not barrier.HAVE_CHOLMOD:
        pytest.skip("scikit-sparse is not installed")
    chol = isotween.interpolate(src, tgt, frames=5, method="injective")
    assert lu.iterations == chol.iterations
    assert np.abs(lu.z - chol.z).max() < 1e-9 * src.bbox_diagonal()


def test_a_singular_newton_system_is_a_method_error_and_the_fallback_is_convex(monkeypatch):
    src, tgt = pair("square->U")
    monkeypatch.setattr(barrier, "HAVE_CHOLMOD", False)
    monkeypatch.setattr(barrier.SymmetricDirichlet, "derivatives", lambda self, z: (
        np.ones(self._size), barrier.csc_matrix((self._size, self._size))))  # all zeros: singular
    with pytest.raises(isotween.errors.MethodError, match="method 'injective', component 0.*cannot be solved"):
        isotween.interpolate(src, tgt, frames=5, method="injective")
    # a folding AIAP result then falls back to the plain convex morph, and says why (its iterations run to the
    # end: stopped before the first fold, at 5 frames W->T does not fold at all)
    monkeypatch.setattr(sys.modules["isotween.interpolate"], "_flips", lambda shape: lambda z: 1)
    src, tgt = pair("W->T")
    seq = isotween.interpolate(src, tgt, frames=5, fold="fallback")
    assert seq.method == "convex" and "injective failed" in seq.info["fallback"]
    assert flipped_faces(seq) == 0 and np.array_equal(seq.frames[-1], tgt.vertices)


def test_the_budget_counts_iterations_so_results_do_not_depend_on_speed(monkeypatch):
    """A component past its budget gets WORK // N Newton iterations, however slow the machine."""
    src, tgt = pair("W->T")
    free = isotween.interpolate(src, tgt, frames=7, method="injective")
    n = free.info["components"][0]["vertices"]
    assert free.iterations > 5 + 3  # unconstrained it needs more than the small budget below
    monkeypatch.setattr(injective, "WORK", 8 * n)  # 8 iterations for the 5 in-between frames
    capped = isotween.interpolate(src, tgt, frames=7, method="injective")
    assert capped.iterations == 8
    original = barrier.SymmetricDirichlet.derivatives

    def slow(self, z):  # a machine ten times slower would once have cut this short
        time.sleep(0.01)
        return original(self, z)

    monkeypatch.setattr(barrier.SymmetricDirichlet, "derivatives", slow)
    again = isotween.interpolate(src, tgt, frames=7, method="injective")
    assert again.iterations == 8 and np.array_equal(again.z, capped.z)
    assert flipped_faces(capped, None).tolist() == [0] * 7


def test_superlu_orders_once_and_solves_every_later_newton_system(monkeypatch):
    # without CHOLMOD, the first system's fill-reducing order is kept for the later ones of its pattern
    monkeypatch.setattr(barrier, "HAVE_CHOLMOD", False)
    src, _ = pair("W->T")
    specs = []
    splu = barrier.splu
    monkeypatch.setattr(barrier, "splu",
                        lambda A, permc_spec, **kw: specs.append(permc_spec) or splu(A, permc_spec, **kw))
    z = src.z
    energy = barrier.SymmetricDirichlet(z, z, src.faces, np.zeros(len(z), dtype=bool))
    energy.rest(0.0)
    energy.pull_towards(np.arange(len(z)), z, 1.0)  # every vertex free: the pull makes the Hessian definite
    rng = np.random.default_rng(1)
    for _ in range(4):
        x = z + 1e-3 * src.bbox_diagonal() * (rng.standard_normal(len(z)) + 1j * rng.standard_normal(len(z)))
        g, H = energy.derivatives(x)
        assert np.linalg.norm(H @ energy.solve(H, -g) + g) <= 1e-9 * np.linalg.norm(g)  # the residual
    assert specs == ["MMD_AT_PLUS_A"] + ["NATURAL"] * 3
