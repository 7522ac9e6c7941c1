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
  a banded Cholesky factor (reverse Cuthill-McKee order); no BLAS (whose threads
  fight numba's on a busy machine), no sparse matrices.
- :func:`edge_init`: Eqs. (12)-(13): angles along the edge tree, then every
  edge's frames (threaded over edges for large inputs).

The numpy twins are in :mod:`isotween.optimisation.reference`;
:mod:`isotween.optimisation.backend` chooses between the two (the tests
compare them).
"""

import numpy as np

__all__ = ["PARALLEL_SIZE", "midpoint_edge_pass", "band_cholesky", "banded_positions",
           "edge_init"]

#: below this many edge-frames one thread does the pass (thread start-up costs more)
PARALLEL_SIZE = 4_000_000
#: edges solved side by side by one thread
EDGE_BLOCK = 16

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


def _laplace_block(e, indptr, indices, data, band, rows, anchors, comp, inv_count, centroids, z):
    """Eq. (10) for a block of frames, placed on the centroids, written into ``z``.

    Real arithmetic on interleaved (re, im) columns: e (E, 2B), centroids
    (C, 2B), z (n, 2B) float views of the block. ``indptr, indices, data``: the
    rows of D^T W in banded order (CSR); ``band``: the lower band of its
    Cholesky factor (band[j, i - j] = L[i, j], from :func:`band_cholesky`); ``rows``:
    the vertex of every banded row; ``comp``, ``inv_count``: component of every
    vertex and 1 / its size. Returns the largest squared move of a vertex.
    """
    nf, B = len(rows), z.shape[1]
    bw = band.shape[1] - 1
    y = np.zeros((nf, B))
    for p in range(nf):  # y = D^T W e
        for q in range(indptr[p], indptr[p + 1]):
            c, edge = data[q], indices[q]
            for f in range(B):
                y[p, f] += c * e[edge, f]
    for j in range(nf):  # L y' = y
        d = 1.0 / band[j, 0]
        for f in range(B):
            y[j, f] *= d
        for i in range(j + 1, min(j + bw, nf - 1) + 1):
            lij = band[j, i - j]
            if lij != 0.0:
                for f in range(B):
                    y[i, f] -= lij * y[j, f]
    shift = np.zeros((len(inv_count), B))
    for j in range(nf - 1, -1, -1):  # L^T x = y'
        for i in range(j + 1, min(j + bw, nf - 1) + 1):
            lij = band[j, i - j]
            if lij != 0.0:
                for f in range(B):
                    y[j, f] -= lij * y[i, f]
        d = 1.0 / band[j, 0]
        for f in range(B):
            y[j, f] *= d
            shift[comp[rows[j]], f] -= y[j, f]
    for c in range(len(inv_count)):  # centroid of the solution (anchors at 0) -> the target
        for f in range(B):
            shift[c, f] = centroids[c, f] + shift[c, f] * inv_count[c]
    move = 0.0
    for p in range(nf + len(anchors)):
        v = rows[p] if p < nf else anchors[p - nf]
        for f in range(0, B, 2):
            re = (y[p, f] if p < nf else 0.0) + shift[comp[v], f]
            im = (y[p, f + 1] if p < nf else 0.0) + shift[comp[v], f + 1]
            move = max(move, (re - z[v, f]) ** 2 + (im - z[v, f + 1]) ** 2)
            z[v, f], z[v, f + 1] = re, im
    return move


def _band_cholesky(band):
    """In place: band[j, i - j] = A[i, j] (i >= j) -> L[i, j], A = L L^T; False unless A > 0."""
    nf, bw = band.shape[0], band.shape[1] - 1
    for j in range(nf):
        if band[j, 0] <= 0.0:
            return False
        d = np.sqrt(band[j, 0])
        band[j, 0] = d
        last = min(bw, nf - 1 - j)
        for p in range(1, last + 1):
            band[j, p] /= d
        for p in range(1, last + 1):  # A[j+q, j+p] -= L[j+q, j] L[j+p, j], q >= p
            ljp = band[j, p]
            if ljp != 0.0:
                for q in range(p, last + 1):
                    band[j + p, q - p] -= band[j, q] * ljp
    return True


def _laplace_parallel(e, indptr, indices, data, band, rows, anchors, comp, inv_count, centroids,
                      z, block):
    n_blocks = (z.shape[1] + block - 1) // block
    moves = np.zeros(n_blocks)
    for b in numba.prange(n_blocks):
        c0 = b * block
        c1 = c0 + block
        moves[b] = _laplace_block(e[:, c0:c1], indptr, indices, data, band, rows, anchors, comp,
                                  inv_count, centroids[:, c0:c1], z[:, c0:c1])
    return moves.max()


def _laplace_serial(e, indptr, indices, data, band, rows, anchors, comp, inv_count, centroids,
                    z, block):
    move = 0.0
    for c0 in range(0, z.shape[1], block):
        c1 = c0 + block
        move = max(move, _laplace_block(e[:, c0:c1], indptr, indices, data, band, rows, anchors,
                                        comp, inv_count, centroids[:, c0:c1], z[:, c0:c1]))
    return move


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


def _compile():
    """Import numba and compile the kernels (loaded from numba's cache after the first time)."""
    global numba, _band_cholesky, _edge_angles, _laplace_block, _laplace_parallel, _laplace_serial
    global _edge_frames_serial, _edge_frames_parallel
    global _edge_vectors, _edge_solve, _scratch, _pass_parallel, _pass_serial
    if numba is not None:
        return
    import numba as nb

    jit, parallel = nb.njit(cache=True), nb.njit(parallel=True, cache=True)
    _band_cholesky, _edge_angles, _laplace_block = jit(_band_cholesky), jit(_edge_angles), jit(_laplace_block)
    _edge_frames_serial, _edge_frames_parallel = jit(_edge_frames), parallel(_edge_frames)
    _laplace_parallel, _laplace_serial = parallel(_laplace_parallel), jit(_laplace_serial)
    _edge_vectors, _edge_solve, _scratch = jit(_edge_vectors), jit(_edge_solve), jit(_scratch)
    _pass_parallel, _pass_serial = parallel(_pass_parallel), jit(_pass_serial)
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
    F = e.shape[1]
    e, centroids = (a if a.strides[1] == a.itemsize else np.ascontiguousarray(a) for a in (e, centroids))
    args = (e.view(np.float64), indptr, indices, data, band, rows, anchors, comp, inv_count,
            centroids.view(np.float64), z.view(np.float64))
    if e.size * band.shape[1] >= PARALLEL_SIZE:
        return float(np.sqrt(_laplace_parallel(*args, 2 * max(1, -(-F // 8)))))
    return float(np.sqrt(_laplace_serial(*args, 2 * max(1, min(F, (1 << 19) // (16 * len(rows) + 1))))))


def band_cholesky(band):
    """Cholesky factor of a banded symmetric matrix, in place (no BLAS threads).

    Parameters
    ----------
    band : (n, bw + 1) float, C-ordered
        band[j, i - j] = A[i, j] for j <= i <= j + bw; overwritten with L.

    Returns
    -------
    bool
        False when A is not positive definite.
    """
    _compile()
    return _band_cholesky(band)


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
