"""Paths that stay put, shrink or grow between the drawings are held on their straight way (`optimisation.hold`)."""

import numpy as np

import isotween
from isotween.geometry import ring_area
from isotween.optimisation.hold import HOLD, Hold, still_vertices
from shapes import grid_mesh

HEAD = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 16 16">'
#: a square outline (a hole inside) and the filled square: the outline is the same, the hole closes
OUTLINE = HEAD + '<path fill-rule="evenodd" d="M1 1h14v14H1zM3 3v10h10V3z"/></svg>'
FILLED = HEAD + '<path d="M1 1h14v14H1z"/></svg>'


def test_held_frames_are_the_least_squares_positions_with_the_held_vertices_fixed():
    # Eq. (10): the positions closest (in the solver's weights) to the frames' edge vectors, the held vertices
    # on their straight way
    mesh = grid_mesh(4, 3)
    n = mesh.n_vertices
    rng = np.random.default_rng(3)
    z = (mesh.vertices[:, 0] + 1j * mesh.vertices[:, 1])[:, None] + rng.normal(size=(n, 5)) * 0.1
    times = np.linspace(0.0, 1.0, 5)
    held = np.array([0, 1, 2, 7])
    out = Hold(mesh, z[:, 0], z[:, -1], held)(z, times)
    line = z[held, :1] + (z[held, -1:] - z[held, :1]) * times
    assert np.allclose(out[held], line)
    D = mesh.topology.D.toarray()
    w = np.sqrt(2 / (np.abs(D @ z[:, 0]) + np.abs(D @ z[:, -1])))[:, None]  # the local solver's weights
    free = np.setdiff1d(np.arange(n), held)
    for k in range(5):
        target = D @ z[:, k] - D[:, held] @ line[:, k]
        best = np.linalg.lstsq(w * D[:, free], w[:, 0] * target, rcond=None)[0]
        assert np.allclose(out[free, k], best)
    assert np.allclose(out[:, [0, -1]], z[:, [0, -1]])  # the ends stay


def test_paths_that_stay_put_are_held_and_scaled_copies_in_their_piece():
    grid = grid_mesh(3, 3)
    z0 = grid.vertices[:, 0] + 1j * grid.vertices[:, 1]
    low, high = np.argsort(z0.imag)[:3], np.argsort(z0.imag)[-3:]  # two rows of the same piece
    mesh = isotween.Shape(grid.vertices, faces=grid.faces, paths=[(low, False), (high, False)])
    z1 = z0.copy()
    assert np.array_equal(still_vertices(mesh, z0, z1, 1.0), np.sort(np.r_[low, high]))
    z1[high] = z0[high].mean() + 0.1 + 0.5 * (z0[high] - z0[high].mean())  # moved and shrunk
    assert np.array_equal(still_vertices(mesh, z0, z1, 1.0), np.sort(np.r_[low, high]))
    z1[high] = z0[high].mean() + 1j * (z0[high] - z0[high].mean())  # turned: not a copy
    assert np.array_equal(still_vertices(mesh, z0, z1, 1.0), np.sort(low))
    z1[high] = z0[high].mean() + 0.5 * (z0[high] - z0[high].mean())
    z1[low[0]] += 0.02  # one vertex of the other row moves 2 % of the diagonal: nothing stays put
    assert still_vertices(mesh, z0, z1, 1.0).size == 0
    z1[low[0]] -= 0.02 - 0.5 * HOLD  # half the tolerance: it stays
    assert np.array_equal(still_vertices(mesh, z0, z1, 1.0), np.sort(np.r_[low, high]))


def test_an_outline_whose_hole_closes_stays_put_and_the_hole_shrinks_as_a_copy(tmp_path):
    # the square outline into the filled square: the outline stays where it is in every frame while the
    # hole shrinks, a square in every frame; left free, the outline bulges out as the region grows into the
    # hole, and the hole's corners stand out
    a, b = tmp_path / "outline.svg", tmp_path / "filled.svg"
    a.write_text(OUTLINE)
    b.write_text(FILLED)
    seq = isotween.morph(a, b, frames=9)
    assert seq.method == "aiap" and not seq.info.get("fallback")
    z = seq.z
    rings = sorted(seq.shape.paths, key=lambda p: -np.ptp(z[0, p[0]].real))
    outer, hole = rings[0][0], rings[1][0]
    assert np.abs(z[:, outer] - z[0, outer]).max() < 1e-9
    areas = [abs(ring_area(z[k, hole])) for k in range(len(z))]
    assert np.all(np.diff(areas) < 0) and areas[-1] < 1e-9
    a = z[0, hole] - z[0, hole].mean()
    for k in range(len(z) - 1):  # a copy of the hole, shrunk
        b = z[k, hole] - z[k, hole].mean()
        s = np.vdot(a, b).real / np.vdot(a, a).real
        assert np.abs(b - s * a).max() < 1e-9
