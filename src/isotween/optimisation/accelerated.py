"""Optional numba kernel for the hot loop of the local solver (``pip install isotween[fast]``).

One pass over every edge, each edge independent (parallel over edges): its
vectors e(t_k) = z_j - z_i from the assembled frames, the midpoint fit of the
angular speed (Eq. 8), its share of the energy (Eq. 6) and, unless the solver
has converged, the Hermitian tridiagonal solve of Eq. (9) with the end vectors
held (Thomas algorithm; the system is positive definite). This is the same
arithmetic as :func:`isotween.optimisation.schemes.normal_equations` followed by
:func:`isotween.optimisation.edge_solve.solve_edges`, fused so that the (E, m+1)
arrays are read once instead of some thirty times.

``ENABLED`` is False when numba is missing or the environment sets
``ISOTWEEN_NUMBA=0``; the numpy path is then used (and is the reference the
tests compare this kernel with).
"""

import os

import numpy as np

__all__ = ["ENABLED", "PARALLEL_SIZE", "midpoint_edge_pass"]

#: below this many edge-frames one thread does the pass (thread start-up costs more)
PARALLEL_SIZE = 1_000_000

try:
    import numba
except ImportError:  # the optional extra is not installed
    numba = None

ENABLED = numba is not None and os.environ.get("ISOTWEEN_NUMBA", "1") != "0"


def _edge_vectors(r, z, first, second, out):
    """Row r of ``out`` = z[second[r]] - z[first[r]]; returns sum |e_k + e_{k+1}|^2."""
    i, j = first[r], second[r]
    F = out.shape[1]
    for k in range(F):
        out[r, k] = z[j, k] - z[i, k]
    acc = 0.0
    for k in range(F - 1):
        s = out[r, k] + out[r, k + 1]
        acc += s.real * s.real + s.imag * s.imag
    return acc


def _edge_solve(r, out, inv_h, tiny, solve):
    """Eqs. (8), (6) and (if ``solve``) (9) for the vectors of edge r; returns its energy."""
    m = out.shape[1] - 1
    diag = np.zeros(m + 1)
    lower = np.empty(m, dtype=np.complex128)
    energy = 0.0
    for k in range(m):
        e0, e1 = out[r, k], out[r, k + 1]
        s, d = e0 + e1, e1 - e0
        s2 = s.real * s.real + s.imag * s.imag
        p_im = s.real * d.imag - s.imag * d.real  # Im(conj(s) d)
        w = 2.0 * p_im / s2 if s2 > tiny else 0.0  # omega = h c, Eq. (8) at the midpoint
        q = 0.25 * w * w
        a2 = (1.0 + q) * inv_h[k]
        diag[k] += a2
        diag[k + 1] += a2
        lower[k] = complex(-(1.0 - q) * inv_h[k], -w * inv_h[k])
        energy += (d.real * d.real + d.imag * d.imag - 0.5 * w * p_im) * inv_h[k]  # Eq. (6)
    if not solve or m < 2:
        return energy
    # Eq. (9) over nodes 1..m-1 with A[k, k] = diag[k], A[k+1, k] = lower[k]:
    # forward elimination (the pivots are real and positive), then back substitution
    cp = np.empty(m, dtype=np.complex128)
    xp = np.empty(m, dtype=np.complex128)
    c, x = 0.0j, 0.0j
    for k in range(1, m):
        b = -lower[0] * out[r, 0] if k == 1 else 0.0j  # the held end vectors
        if k == m - 1:
            b -= lower[m - 1].conjugate() * out[r, m]
        sub = lower[k - 1] if k > 1 else 0.0j
        pivot = diag[k] - (sub * c).real
        c = lower[k].conjugate() / pivot
        x = (b - sub * x) / pivot
        cp[k], xp[k] = c, x
    out[r, m - 1] = x
    for k in range(m - 2, 0, -1):
        x = xp[k] - cp[k] * x
        out[r, k] = x
    return energy


def _pass_parallel(z, first, second, inv_h, solve, out, energy):
    E, m = len(first), out.shape[1] - 1
    sums = np.empty(E)
    for r in numba.prange(E):
        sums[r] = _edge_vectors(r, z, first, second, out)
    tiny = 1e-24 * sums.sum() / max(E * m, 1)  # as in schemes._ratio
    for r in numba.prange(E):
        energy[r] = _edge_solve(r, out, inv_h, tiny, solve)


def _pass_serial(z, first, second, inv_h, solve, out, energy):
    E, m = len(first), out.shape[1] - 1
    total = 0.0
    for r in range(E):
        total += _edge_vectors(r, z, first, second, out)
    tiny = 1e-24 * total / max(E * m, 1)
    for r in range(E):
        energy[r] = _edge_solve(r, out, inv_h, tiny, solve)


if ENABLED:
    _edge_vectors = numba.njit(cache=True)(_edge_vectors)
    _edge_solve = numba.njit(cache=True)(_edge_solve)
    _pass_parallel = numba.njit(parallel=True, cache=True)(_pass_parallel)
    _pass_serial = numba.njit(cache=True)(_pass_serial)


def midpoint_edge_pass(z, first, second, inv_h, solve, out):
    """Edge vectors, Eq. (8), Eq. (6) and (if ``solve``) Eq. (9) in one pass.

    Parameters
    ----------
    z : (n, m+1) complex, C-contiguous
        Assembled frames.
    first, second : (E,) int64
        Edge end points (e = z[second] - z[first]).
    inv_h : (m,) float
        1 / (t_{k+1} - t_k).
    solve : bool
        False: only the energy (the solver has converged).
    out : (E, m+1) complex, C-contiguous
        Overwritten with the edge vectors of ``z``, or with the new ones of
        Eq. (9) (ends unchanged) when ``solve``.

    Returns
    -------
    float
        Eq. (6) of the edge vectors of ``z``, not yet divided by sum |e(0)|^2.
    """
    energy = np.empty(len(first))
    kernel = _pass_parallel if out.size >= PARALLEL_SIZE else _pass_serial
    kernel(z, first, second, inv_h, solve, out, energy)
    return float(energy.sum())
