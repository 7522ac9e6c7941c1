"""Optional numba kernels of the local solver's hot loops (``pip install isotween[fast]``).

- :func:`midpoint_edge_pass`: one pass over every edge: its vectors
  e(t_k) = z_j - z_i from the assembled frames, the midpoint fit of the angular
  speed (Eq. 8), its share of the energy (Eq. 6) and, unless the solver has
  converged, the Hermitian tridiagonal solve of Eq. (9) with the end vectors
  held (Thomas algorithm; the system is positive definite). The same arithmetic
  as :func:`isotween.optimisation.schemes.normal_equations` followed by
  :func:`isotween.optimisation.edge_solve.solve_edges`, fused so that the
  (E, m+1) arrays are read once instead of some thirty times.
- :func:`band_cholesky`, :func:`banded_positions`: Eq. (10) for all frames with
  a banded Cholesky factor (reverse Cuthill-McKee order; LAPACK's blocked
  dpbtrf). The solves work on blocks of columns, one per thread: from
  bandwidth `BLAS_BANDWIDTH` on, on blocks of bandwidth rows with BLAS
  (trsm and gemm called from the kernel, each on one thread), below it by
  substitution; no sparse matrices.
- :func:`edge_init`: Eqs. (12)-(13): angles along the edge tree, then every
  edge's frames (threaded over edges for large inputs).
- :func:`face_derivatives`: the fold repair's per-face gradient and projected
  Hessian of the symmetric Dirichlet energy, one face at a time.

The numpy twins are in :mod:`isotween.optimisation.reference`;
:mod:`isotween.optimisation.backend` chooses between the two (the tests
compare them).
"""

import contextlib

import numpy as np
from scipy.linalg.lapack import dpbtrf

__all__ = ["PARALLEL_SIZE", "midpoint_edge_pass", "band_cholesky", "banded_positions",
           "edge_frames", "edge_init", "face_derivatives"]

#: below this many edge-frames one thread does the pass (thread start-up costs more)
PARALLEL_SIZE = 4_000_000
#: edges solved side by side by one thread
EDGE_BLOCK = 16
#: Eq. (10) by blocks of bandwidth rows with BLAS from this bandwidth and this many free
#: vertex-frames on, by substitution below (faster there: 100 vertices, 9 frames, 0.06 ms
#: against 0.13 ms; 24k vertices, bandwidth 4, 51 frames, 39 ms against 45 ms)
BLAS_BANDWIDTH = 16
BLAS_SIZE = 10_000
#: frames solved together by substitution (their window of rows stays in the L1 cache)
SUBSTITUTION_FRAMES = 16
_CHARS = np.frombuffer(b"RULNT", dtype=np.uint8).copy()  # BLAS's side, uplo, trans arguments
_ONE = np.array([1.0, -1.0])
_CONTROLLER = None  # threadpoolctl's, made on first use

#: numba, imported (a third of a second) and the kernels loaded from its cache on the first
#: call of a kernel, not with isotween
numba = None


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


def _edge_solve(r0, r1, out, inv_h, tiny, solve, energy, diag, lower, c, x):
    """Eqs. (8), (6) and (if ``solve``) (9) for the vectors of edges r0..r1-1.

    Frames are the outer loop and edges the inner one, so that the recurrences
    of several edges are in flight at once. ``diag`` (m+1, B) float and
    ``lower, c, x`` (m, B) complex are scratch space, B >= r1 - r0.
    """
    R, m = r1 - r0, out.shape[1] - 1
    diag[:, :R] = 0.0
    energy[r0:r1] = 0.0
    for k in range(m):
        for a in range(R):
            e0, e1 = out[r0 + a, k], out[r0 + a, k + 1]
            s, d = e0 + e1, e1 - e0
            s2 = s.real * s.real + s.imag * s.imag
            p_im = s.real * d.imag - s.imag * d.real  # Im(conj(s) d)
            w = 2.0 * p_im / s2 if s2 > tiny else 0.0  # omega = h c, Eq. (8) at the midpoint
            q = 0.25 * w * w
            a2 = (1.0 + q) * inv_h[k]
            diag[k, a] += a2
            diag[k + 1, a] += a2
            lower[k, a] = complex(-(1.0 - q) * inv_h[k], -w * inv_h[k])
            energy[r0 + a] += (d.real * d.real + d.imag * d.imag - 0.5 * w * p_im) * inv_h[k]  # Eq. (6)
    if not solve or m < 2:
        return
    # Eq. (9) over nodes 1..m-1 with A[k, k] = diag[k], A[k+1, k] = lower[k]:
    # forward elimination (the pivots are real and positive), then back substitution
    for a in range(R):  # the held end vectors
        x[0, a] = -lower[0, a] * out[r0 + a, 0]
        lower[0, a] = c[0, a] = 0.0
    for k in range(1, m):
        for a in range(R):
            b = x[k - 1, a] if k == 1 else 0.0j
            if k == m - 1:
                b -= lower[m - 1, a].conjugate() * out[r0 + a, m]
            sub = lower[k - 1, a]
            inv = 1.0 / (diag[k, a] - (sub * c[k - 1, a]).real)
            c[k, a] = lower[k, a].conjugate() * inv
            x[k, a] = (b - sub * x[k - 1, a]) * inv
    for a in range(R):
        out[r0 + a, m - 1] = x[m - 1, a]
    for k in range(m - 2, 0, -1):
        for a in range(R):
            x[k, a] -= c[k, a] * x[k + 1, a]
            out[r0 + a, k] = x[k, a]


def _scratch(m, B):
    return (np.empty((m + 1, B)), np.empty((m, B), dtype=np.complex128),
            np.empty((m, B), dtype=np.complex128), np.empty((m, B), dtype=np.complex128))


def _pass_parallel(z, first, second, inv_h, solve, out):
    E, m = len(first), out.shape[1] - 1
    energy = np.empty(E)
    sums = np.empty(E)
    for r in numba.prange(E):
        sums[r] = _edge_vectors(r, z, first, second, out)
    tiny = 1e-24 * sums.sum() / max(E * m, 1)  # as in schemes._ratio
    for b in numba.prange((E + EDGE_BLOCK - 1) // EDGE_BLOCK):
        diag, lower, c, x = _scratch(m, EDGE_BLOCK)
        _edge_solve(b * EDGE_BLOCK, min(E, (b + 1) * EDGE_BLOCK), out, inv_h, tiny, solve, energy,
                    diag, lower, c, x)
    return energy.sum()


def _pass_serial(z, first, second, inv_h, solve, out):
    E, m = len(first), out.shape[1] - 1
    energy = np.empty(E)
    total = 0.0
    for r in range(E):
        total += _edge_vectors(r, z, first, second, out)
    tiny = 1e-24 * total / max(E * m, 1)
    diag, lower, c, x = _scratch(m, EDGE_BLOCK)
    for r0 in range(0, E, EDGE_BLOCK):
        _edge_solve(r0, min(E, r0 + EDGE_BLOCK), out, inv_h, tiny, solve, energy, diag, lower, c, x)
    return energy.sum()


def _rhs(e, indptr, indices, data, y):
    """Right-hand sides of Eq. (10), y = D^T W e, in blocks of W columns.

    e (E, B) float: the frames' real and imaginary parts interleaved; y (nb, n_free, W)
    with nb W >= B: y[b, p, g] = (D^T W e)[p, b W + g], the padding columns 0.
    ``indptr, indices, data``: the rows of D^T W in banded order (CSR).
    """
    nb, nf, W = y.shape
    B = e.shape[1]
    for p in numba.prange(nf):
        y[:, p, :] = 0.0
        for q in range(indptr[p], indptr[p + 1]):
            c, edge = data[q], indices[q]
            for b in range(nb):
                f0 = b * W
                for g in range(min(W, B - f0)):
                    y[b, p, g] += c * e[edge, f0 + g]


def _substitute(band, y):
    """L L^T x = y in place by forward and back substitution; y (n_free, W), band[j, i - j] = L[i, j]."""
    nf, bw, W = band.shape[0], band.shape[1] - 1, y.shape[1]
    for j in range(nf):  # L y' = y
        d = 1.0 / band[j, 0]
        for f in range(W):
            y[j, f] *= d
        for i in range(j + 1, min(j + bw, nf - 1) + 1):
            lij = band[j, i - j]
            if lij != 0.0:
                for f in range(W):
                    y[i, f] -= lij * y[j, f]
    for j in range(nf - 1, -1, -1):  # L^T x = y'
        for i in range(j + 1, min(j + bw, nf - 1) + 1):
            lij = band[j, i - j]
            if lij != 0.0:
                for f in range(W):
                    y[j, f] -= lij * y[i, f]
        d = 1.0 / band[j, 0]
        for f in range(W):
            y[j, f] *= d


def _blocked(band, y, c, dims, chars, ones):
    """L L^T x = y in place, in blocks of s = bw rows with BLAS (level 3).

    The C-ordered band holds L[i, j] at flat index j bw + i: read as a
    column-major matrix with leading dimension bw, it is L itself (LAPACK's
    band storage trick), so every diagonal block D_k of L is a BLAS matrix in
    place. The block C_k left of it is upper triangular (s = bw); it is copied
    into ``c`` (s, s) for a general product. y (n_free, W) row-major is Y^T
    column-major. Forward: Y_k^T = (Y_k^T - Y_{k-1}^T C_k^T) D_k^{-T}; back:
    X_k^T = (Y_k^T - X_{k+1}^T C_{k+1}) D_k^{-1}. ``dims`` (3,) int32
    scratch; ``chars`` b"RULNT"; ``ones`` [1.0, -1.0].
    """
    nf, s, W = band.shape[0], band.shape[1] - 1, y.shape[1]
    Lp, Yp, Cp = band.ctypes.data, y.ctypes.data, c.ctypes.data
    right, lower, no, tr = chars.ctypes.data, chars.ctypes.data + 2, chars.ctypes.data + 3, chars.ctypes.data + 4
    m, n, rk = dims.ctypes.data, dims.ctypes.data + 4, dims.ctypes.data + 8
    one, minus = ones.ctypes.data, ones.ctypes.data + 8
    dims[0], dims[1] = W, s
    blocks = (nf + s - 1) // s
    c[:, :] = 0.0
    for k in range(blocks):
        dims[2] = min(s, nf - k * s)
        if k:  # c[b, a] = C_k[a, b] = L[ks + a, (k-1)s + b] = band[(k-1)s + b, s + a - b], a <= b
            for b in range(s):
                for a in range(b + 1):
                    c[b, a] = band[(k - 1) * s + b, s + a - b]
            _dgemm(no, tr, m, rk, n, minus, Yp + 8 * (k - 1) * s * W, m, Cp, n, one, Yp + 8 * k * s * W, m)
        _dtrsm(right, lower, tr, no, m, rk, one, Lp + 8 * k * s * (s + 1), n, Yp + 8 * k * s * W, m)
    for k in range(blocks - 1, -1, -1):
        if k + 1 < blocks:
            dims[2] = min(s, nf - (k + 1) * s)
            for b in range(s):
                for a in range(b + 1):
                    c[b, a] = band[k * s + b, s + a - b]
            # Y_k^T (W x s) -= X_{k+1}^T (W x r) C_{k+1} (r x s): c's first r rows, column-major
            _dgemm(no, no, m, n, rk, minus, Yp + 8 * (k + 1) * s * W, m, Cp, n, one, Yp + 8 * k * s * W, m)
        dims[2] = min(s, nf - k * s)
        _dtrsm(right, lower, no, no, m, rk, one, Lp + 8 * k * s * (s + 1), n, Yp + 8 * k * s * W, m)


def _solve_columns(band, y, blas, chars, one):
    """L L^T x = y for every block of columns y[b] (threaded over blocks when compiled parallel)."""
    s = band.shape[1] - 1
    for b in numba.prange(y.shape[0]):
        if blas:
            _blocked(band, y[b], np.empty((s, s)), np.empty(3, np.int32), chars, one)
        else:
            _substitute(band, y[b])


def _place(y, rows, anchors, comp, inv_count, centroids, z):
    """Move each component of the solution (anchors at 0) onto its centroid and write it into z.

    y (nb, n_free, W) from :func:`_solve_columns`; centroids (C, B), z (n, B)
    float views (B even, W even). Returns the largest squared move of a vertex.
    """
    nb, nf, W = y.shape
    B, C = z.shape[1], len(inv_count)
    shift = np.zeros((C, nb * W))
    for b in numba.prange(nb):  # minus the sum over each component, then the target centroid
        for p in range(nf):
            c = comp[rows[p]]
            for g in range(W):
                shift[c, b * W + g] -= y[b, p, g]
    for c in range(C):
        for f in range(B):
            shift[c, f] = centroids[c, f] + shift[c, f] * inv_count[c]
    n = nf + len(anchors)
    moves = np.empty(n)
    for p in numba.prange(n):
        v = rows[p] if p < nf else anchors[p - nf]
        c = comp[v]
        move = 0.0
        for b in range(nb):
            for g in range(0, min(W, B - b * W), 2):
                f = b * W + g
                re = (y[b, p, g] if p < nf else 0.0) + shift[c, f]
                im = (y[b, p, g + 1] if p < nf else 0.0) + shift[c, f + 1]
                move = max(move, (re - z[v, f]) ** 2 + (im - z[v, f + 1]) ** 2)
                z[v, f], z[v, f + 1] = re, im
        moves[p] = move
    return moves.max() if n else 0.0


def edge_frames(e0, s, theta, t):
    """Eq. (13) from given scales ``s`` and angles ``theta`` (E,): (E, F) complex, as `reference.edge_frames`."""
    _compile()
    t = np.asarray(t, dtype=float)
    out = np.empty((len(e0), len(t)), dtype=complex)
    kernel = _edge_frames_parallel if out.size >= PARALLEL_SIZE else _edge_frames_serial
    kernel(np.asarray(e0, dtype=complex), np.asarray(theta, dtype=float), np.asarray(s, dtype=float), t, out)
    return out


def _edge_angles(e0, e1, parent, order):
    """Eq. (12): (E,) turning angle (whole turns propagated along the edge tree) and scale."""
    E = len(e0)
    theta = np.empty(E)
    turns = np.zeros(E)
    scale = np.empty(E)
    for r in range(E):
        ratio = e1[r] / e0[r]
        theta[r] = np.arctan2(ratio.imag, ratio.real)
        scale[r] = abs(e1[r]) / abs(e0[r])
    for r in order:  # parents first: whole turns accumulated from the root (Sec. 4.3)
        p = parent[r]
        if p != r:
            turns[r] = turns[p] + np.rint((theta[p] - theta[r]) / (2 * np.pi))
    return theta + 2 * np.pi * turns, scale


def _edge_frames(e0, angle, scale, t, out):
    """Eq. (13) for every edge and frame (``numba.prange``: threaded when compiled parallel)."""
    E, F = out.shape
    h = t[1:] - t[:-1]
    uniform = F > 1 and h.max() - h.min() <= 1e-12 * h[0]
    for r in numba.prange(E):
        if uniform:
            step = np.exp(1j * (t[1] - t[0]) * angle[r])
            rot = 1.0 + 0.0j
            for k in range(F):
                out[r, k] = (1 - t[k] + t[k] * scale[r]) * rot * e0[r]
                rot *= step
        else:
            for k in range(F):
                out[r, k] = (1 - t[k] + t[k] * scale[r]) * np.exp(1j * t[k] * angle[r]) * e0[r]


def face_derivatives(z, faces, G, w):
    """As `reference.face_derivatives`: (K, 6) gradient and (K, 6, 6) projected Hessian of every face."""
    _compile()
    K = len(w)
    g6, H6 = np.empty((K, 6)), np.empty((K, 6, 6))
    z = np.asarray(z, dtype=complex)
    _face_derivatives(z.real.copy(), z.imag.copy(), np.asarray(faces, dtype=np.int64),
                      np.ascontiguousarray(G, dtype=float), np.asarray(w, dtype=float), g6, H6)
    return g6, H6


def _face_derivatives(x, y, faces, G, w, g6, H6):
    """`reference.face_derivatives`, face by face with 4 x 4 scratch: no (K, 4, 6) temporaries."""
    J, gd, grad, H, vec = np.empty(4), np.empty(4), np.empty(4), np.empty((4, 4)), np.empty(4)
    HD = np.empty((4, 6))
    hdet = np.array([[0.0, 0.0, 0.0, 1.0], [0.0, 0.0, -1.0, 0.0], [0.0, -1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0]])
    for k in range(len(w)):
        a, b, c = faces[k, 0], faces[k, 1], faces[k, 2]
        for i in range(2):  # rows of J = G (x0, x1, x2), then G (y0, y1, y2)
            J[i] = G[k, i, 0] * x[a] + G[k, i, 1] * x[b] + G[k, i, 2] * x[c]
            J[2 + i] = G[k, i, 0] * y[a] + G[k, i, 1] * y[b] + G[k, i, 2] * y[c]
        det = J[0] * J[3] - J[1] * J[2]
        norm = J[0] * J[0] + J[1] * J[1] + J[2] * J[2] + J[3] * J[3]
        gd[0], gd[1], gd[2], gd[3] = J[3], -J[2], -J[1], J[0]
        inv2 = 1.0 / (det * det)
        inv3 = inv2 / det
        cr, ci = 0.5 * (J[0] + J[3]), 0.5 * (J[2] - J[1])  # the twist's projection: see the reference
        ar, ai = 0.5 * (J[0] - J[3]), 0.5 * (J[2] + J[1])
        mc, ma = np.sqrt(cr * cr + ci * ci), np.sqrt(ar * ar + ai * ai)
        s1, s2 = mc + ma, mc - ma
        lam = max(0.0, -(2.0 - 2.0 * (s1 * s1 - s1 * s2 + s2 * s2) / (s1 * s2) ** 3))
        rr, ri = -ci / mc, cr / mc
        r2 = np.sqrt(0.5)
        vec[0], vec[1], vec[2], vec[3] = rr * r2, -ri * r2, ri * r2, rr * r2
        for i in range(4):
            grad[i] = w[k] * (2.0 * J[i] * (1.0 + inv2) - 2.0 * norm * inv3 * gd[i])
            for j in range(4):
                h = -4.0 * inv3 * (J[i] * gd[j] + gd[i] * J[j]) + 6.0 * norm * inv2 * inv2 * gd[i] * gd[j]
                h += -2.0 * norm * inv3 * hdet[i, j] + lam * vec[i] * vec[j]
                if i == j:
                    h += 2.0 * (1.0 + inv2)
                H[i, j] = w[k] * h
        # D = blockdiag(G, G): coordinates x0 x1 x2 y0 y1 y2
        for i in range(4):
            for m in range(3):
                HD[i, m] = H[i, 0] * G[k, 0, m] + H[i, 1] * G[k, 1, m]
                HD[i, 3 + m] = H[i, 2] * G[k, 0, m] + H[i, 3] * G[k, 1, m]
        for m in range(3):
            g6[k, m] = G[k, 0, m] * grad[0] + G[k, 1, m] * grad[1]
            g6[k, 3 + m] = G[k, 0, m] * grad[2] + G[k, 1, m] * grad[3]
            for n in range(6):
                H6[k, m, n] = G[k, 0, m] * HD[0, n] + G[k, 1, m] * HD[1, n]
                H6[k, 3 + m, n] = G[k, 0, m] * HD[2, n] + G[k, 1, m] * HD[3, n]


def _compile():
    """Import numba and compile the kernels (loaded from numba's cache after the first time)."""
    global numba, _edge_angles, _edge_frames_serial, _edge_frames_parallel
    global _edge_vectors, _edge_solve, _scratch, _pass_parallel, _pass_serial
    global _dgemm, _dtrsm, _substitute, _blocked, _rhs_serial, _rhs_parallel
    global _solve_serial, _solve_parallel, _place_serial, _place_parallel, _face_derivatives
    if numba is not None:
        return
    import llvmlite.binding
    import numba as nb
    from numba.core import types
    from numba.extending import get_cython_function_address

    # scipy's BLAS, called from the kernels by symbol (so that numba can cache them)
    for name in ("dgemm", "dtrsm"):
        llvmlite.binding.add_symbol(f"isotween_{name}", get_cython_function_address("scipy.linalg.cython_blas", name))
    # Fortran BLAS: every argument by address
    _dgemm = types.ExternalFunction("isotween_dgemm", types.void(*[types.intp] * 13))
    _dtrsm = types.ExternalFunction("isotween_dtrsm", types.void(*[types.intp] * 11))
    jit, parallel = nb.njit(cache=True), nb.njit(parallel=True, cache=True)
    _edge_angles = jit(_edge_angles)
    _edge_frames_serial, _edge_frames_parallel = jit(_edge_frames), parallel(_edge_frames)
    _substitute, _blocked = jit(_substitute), jit(_blocked)
    _rhs_serial, _rhs_parallel = jit(_rhs), parallel(_rhs)
    _solve_serial, _solve_parallel = jit(_solve_columns), parallel(_solve_columns)
    _place_serial, _place_parallel = jit(_place), parallel(_place)
    _edge_vectors, _edge_solve, _scratch = jit(_edge_vectors), jit(_edge_solve), jit(_scratch)
    _pass_parallel, _pass_serial = parallel(_pass_parallel), jit(_pass_serial)
    _face_derivatives = jit(_face_derivatives)
    numba = nb  # the kernels' numba.prange resolves through this global


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
    _compile()
    kernel = _pass_parallel if out.size >= PARALLEL_SIZE else _pass_serial
    return kernel(z, first, second, inv_h, solve, out)


def banded_positions(z, e, centroids, band, indptr, indices, data, rows, anchors, comp, inv_count):
    """Eq. (10) with a banded Cholesky factor, written into the frames ``z``.

    Parameters
    ----------
    z : (n, F) complex
        Frames to overwrite; the last axis contiguous (a column slice of a
        C-ordered array is fine).
    e : (E, F) complex
        Edge vectors of the same frames.
    centroids : (C, F) complex
        Where every component's centroid goes.
    band : (n_free, bw + 1) float
        The Cholesky factor of the Laplacian in banded order, from
        :func:`band_cholesky`.
    indptr, indices, data : arrays
        D^T W, (n_free, E) CSR, rows in banded order.
    rows : (n_free,) int
        Vertex of every row of the banded order.
    anchors : (C,) int
        The vertex pinned in every component.
    comp : (n,) int
        Component of every vertex.
    inv_count : (C,) float
        1 / vertex count of every component.

    Returns
    -------
    float
        The largest distance a vertex moved (Eq. 11).
    """
    _compile()
    F, (nf, bw) = e.shape[1], (band.shape[0], band.shape[1] - 1)
    e, centroids = (a if a.strides[1] == a.itemsize else np.ascontiguousarray(a) for a in (e, centroids))
    threaded = e.size * (bw + 1) >= PARALLEL_SIZE
    blas = bw >= BLAS_BANDWIDTH and nf > bw and nf * F >= BLAS_SIZE
    # blocks of columns: one per thread with BLAS; for substitution, narrow enough to stay in cache
    blocks = numba.get_num_threads() if threaded else 1
    if not blas:
        blocks = max(blocks, -(-F // SUBSTITUTION_FRAMES))
    width = 2 * -(-F // blocks)  # real and imaginary parts of a frame stay in one block
    y = np.empty((-(-2 * F // width), nf, width))
    rhs, solve, place = ((_rhs_parallel, _solve_parallel, _place_parallel) if threaded
                         else (_rhs_serial, _solve_serial, _place_serial))
    rhs(e.view(np.float64), indptr, indices, data, y)
    with _one_blas_thread() if blas else contextlib.nullcontext():
        solve(band, y, blas, _CHARS, _ONE)
    return float(np.sqrt(place(y, rows, anchors, comp, inv_count, centroids.view(np.float64), z.view(np.float64))))


def _one_blas_thread():
    """BLAS on one thread while the kernels call it (they are threaded over blocks of columns)."""
    global _CONTROLLER
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:
        return contextlib.nullcontext()
    if _CONTROLLER is None:  # after _compile: scipy's BLAS is loaded
        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER.limit(limits=1, user_api="blas")


def band_cholesky(band):
    """Cholesky factor of a banded symmetric matrix, in place (LAPACK's blocked dpbtrf).

    Parameters
    ----------
    band : (n, bw + 1) float, C-ordered
        band[j, i - j] = A[i, j] for j <= i <= j + bw; overwritten with L.
        Its transpose is LAPACK's lower band storage.

    Returns
    -------
    bool
        False when A is not positive definite.
    """
    if band.size == 0:
        return True
    factor, info = dpbtrf(band.T, lower=1, overwrite_ab=1)
    if not np.shares_memory(factor, band):
        band[...] = factor.T
    return info == 0


def edge_init(top, e0, e1, t):
    """Eqs. (12)-(13) with angles propagated along the edge tree: (E, F) complex.

    The same as :func:`isotween.optimisation.reference.edge_angles` followed by
    :func:`~isotween.optimisation.reference.edge_frames`.
    """
    _compile()
    t = np.asarray(t, dtype=float)
    out = np.empty((len(e0), len(t)), dtype=complex)
    angle, scale = _edge_angles(e0, e1, top.parent, top.tree_order)
    kernel = _edge_frames_parallel if out.size >= PARALLEL_SIZE else _edge_frames_serial
    kernel(e0, angle, scale, t, out)
    return out
