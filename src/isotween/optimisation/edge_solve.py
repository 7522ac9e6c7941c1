"""Eq. (9): every edge's sequence of vectors, all edges in one tridiagonal solve.

For fixed rotation coefficients, the energy of one edge is a Hermitian
tridiagonal quadratic in its interior vectors e_1..e_{m-1}. We stack all edges
into one block-diagonal tridiagonal system of size E (m - 1) (the blocks do not
couple) and hand it to LAPACK's Hermitian positive-definite tridiagonal solver.
"""

import numpy as np
from scipy.linalg import get_lapack_funcs, solve_banded

__all__ = ["tridiagonal", "TridiagonalSolver", "solve_edges"]

# LAPACK's Hermitian positive-definite tridiagonal factorisation and solve
_PTTRF, _PTTRS = get_lapack_funcs(("pttrf", "pttrs"), dtype=np.complex128)


def tridiagonal(coeffs, h):
    """Normal equations of ``sum_k w |alpha_k x_{k+1} + beta_k x_k|^2 / h_k``.

    Parameters
    ----------
    coeffs : list of (alpha, beta, weight)
        As returned by :func:`isotween.optimisation.schemes.coefficients`;
        alpha, beta are (E, m) complex.
    h : (m,) float

    Returns
    -------
    diag : (E, m+1) float
        Diagonal for every node (ends included).
    lower : (E, m) complex
        Entry A[k+1, k] of every interval.
    """
    E, m = coeffs[0][0].shape
    diag = np.zeros((E, m + 1))
    lower = np.zeros((E, m), dtype=complex)
    for alpha, beta, weight in coeffs:
        s = weight / h
        diag[:, 1:] += s * (alpha.real**2 + alpha.imag**2)
        diag[:, :-1] += s * (beta.real**2 + beta.imag**2)
        lower += s * alpha.conj() * beta
    return diag, lower


class TridiagonalSolver:
    """Factorised block tridiagonal system over the interior nodes of every edge.

    Parameters
    ----------
    diag : (E, m+1) float
    lower : (E, m) complex
        From :func:`tridiagonal`; the end nodes 0 and m are eliminated.
    """

    def __init__(self, diag, lower):
        E, m = lower.shape
        self.shape = (E, m - 1)
        d = np.ascontiguousarray(diag[:, 1:-1]).ravel()
        # sub-diagonal per edge plus a zero that decouples consecutive edges
        sub = np.zeros((E, m - 1), dtype=complex)
        sub[:, :-1] = lower[:, 1:-1]
        sub = sub.ravel()[:-1]
        self.lower = lower
        if d.size:
            self._d, self._e, info = _PTTRF(d, sub)
            if info != 0:
                raise np.linalg.LinAlgError("Eq. (9) system is not positive definite")

    def solve(self, rhs):
        """(E, m-1) complex -> (E, m-1) complex."""
        if rhs.size == 0:
            return rhs.copy()
        x, info = _PTTRS(self._d, self._e, rhs.ravel(), lower=1)
        return x.reshape(self.shape)

    def boundary_rhs(self, first, last):
        """Right-hand side of fixed end vectors (E,) and (E,) -> (E, m-1)."""
        E, m = self.lower.shape
        rhs = np.zeros((E, m - 1), dtype=complex)
        if m >= 2:
            rhs[:, 0] -= self.lower[:, 0] * first
            rhs[:, -1] -= self.lower[:, -1].conj() * last
        return rhs


def solve_edges(e, diag, lower, fixed=None, couplings=()):
    """Eq. (9): minimise each edge's energy with some of its vectors fixed.

    Parameters
    ----------
    e : (E, m+1) complex
        Current edge vectors; only the fixed columns are used.
    diag, lower : (E, m+1) float and (E, m) complex
        Normal equations from :func:`tridiagonal` or
        :func:`isotween.optimisation.schemes.normal_equations`.
    fixed : (m+1,) bool array, optional
        Frames whose edge vectors are held (default: the two ends).
    couplings : list of (k, rho, weight)
        Extra terms ``weight |e_{k+1} - e_k - rho (e_k - e_{k-1})|^2`` at fixed
        interior frames k (rho: (E,) complex), which ask the velocity to turn
        smoothly through a keyframe.

    Returns
    -------
    (E, m+1) complex
        New edge vectors, equal to ``e`` on the fixed frames.
    """
    if fixed is not None and (fixed[1:-1].any() or couplings):
        return _solve_with_keyframes(e, diag, lower, fixed, couplings)
    solver = TridiagonalSolver(diag, lower)
    out = np.empty_like(e)
    out[:, 0], out[:, -1] = e[:, 0], e[:, -1]
    out[:, 1:-1] = solver.solve(solver.boundary_rhs(e[:, 0], e[:, -1]))
    return out



def _solve_with_keyframes(e, diag, lower, fixed, couplings):
    """Eq. (9) with interior frames held, as one banded system over all nodes."""
    E, F = e.shape
    diag, lower = diag.copy(), lower.copy()
    rhs = np.zeros((E, F), dtype=complex)
    fixed = np.asarray(fixed, dtype=bool)
    k = np.flatnonzero(fixed)
    # move the couplings to fixed nodes to the right-hand side, then decouple them
    nxt, prv = k[k < F - 1], k[k > 0]
    rhs[:, nxt + 1] -= lower[:, nxt] * e[:, nxt]
    rhs[:, prv - 1] -= lower[:, prv - 1].conj() * e[:, prv]
    lower[:, nxt] = 0.0
    lower[:, prv - 1] = 0.0
    diag[:, k] = 1.0
    rhs[:, k] = e[:, k]
    # banded storage, u = l = 2: ab[2 + i - j, j] = A[i, j]; no coupling across edges
    ab = np.zeros((5, E, F), dtype=complex)
    ab[2] = diag
    ab[1, :, 1:] = lower.conj()  # A[i, i+1]
    ab[3, :, :-1] = lower  # A[i+1, i]
    for j, rho, weight in couplings:
        if fixed[j - 1] or fixed[j + 1]:
            continue
        c = (1.0 + rho) * e[:, j]
        ab[2, :, j + 1] += weight
        ab[2, :, j - 1] += weight * np.abs(rho) ** 2
        ab[0, :, j + 1] += weight * rho.conj()  # A[j-1, j+1]
        ab[4, :, j - 1] += weight * rho  # A[j+1, j-1]
        rhs[:, j + 1] += weight * c
        rhs[:, j - 1] += weight * rho.conj() * c
    return solve_banded((2, 2), ab.reshape(5, -1), rhs.ravel(), check_finite=False).reshape(E, F)
