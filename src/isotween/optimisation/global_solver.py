"""Algorithm 1: the global solver.

Each iteration fits the angular speeds to the current frames (Eq. 8) and then
solves Eq. (6) for the vertices of all intermediate frames at once: one sparse
Hermitian positive-definite system of (m - 1) n complex unknowns.

Two linear solvers:
'cg'
    Preconditioned conjugate gradients, warm-started from the current frames.
    The preconditioner is L^-1 D^H T^-1 D L^-1 (L: the graph Laplacian,
    factorised once; T: the per-edge tridiagonal time operator of Eq. 9), which
    is the exact inverse when every edge shares one time operator.
'direct'
    Sparse LU of the assembled normal equations (reference; memory grows fast).
"""

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import LinearOperator, cg, spsolve

from ..errors import ParameterError
from .assembly import FrameAssembler
from .edge_solve import TridiagonalSolver, tridiagonal
from .problem import Result
from .schemes import coefficients, isometric_energy

__all__ = ["LINEAR_SOLVERS", "global_solve"]

LINEAR_SOLVERS = ("cg", "direct")


def global_solve(problem, *, linear_solver="cg", cg_rtol=1e-9, callback=None):
    """Run Algorithm 1.

    Parameters
    ----------
    problem : Problem
        Only the first and the last frame held; ``problem.z`` holds the
        initial frames (:class:`~isotween.optimisation.problem.Problem`).
    linear_solver : {'cg', 'direct'}
    cg_rtol : float
        Relative residual at which conjugate gradients stop.
    callback : callable(iteration, energy, max_move), optional

    Returns
    -------
    Result
        ``z`` (n, m+1) complex; ``info['cg_iterations']`` per iteration.
    """
    if linear_solver not in LINEAR_SOLVERS:
        raise ParameterError(f"unknown linear solver {linear_solver!r}; choose one of {', '.join(LINEAR_SOLVERS)}")
    shape, t, scheme, tol, max_iter = problem.shape, problem.times, problem.scheme, problem.tol, problem.max_iter
    z0 = problem.z[:, 0]
    h = np.diff(t)
    m = len(h)
    asm = FrameAssembler(shape)
    D, nf = asm.D_free, asm.free.size
    centroids = problem.centroids[:, 1:-1]
    Dfull = shape.topology.D
    z = problem.z.copy()
    e = Dfull @ z
    energies = [isometric_energy(e, h, scheme)]
    converged, move, cg_iters = False, np.inf, []
    # selects the interior node after / before every interval
    after = sp.eye(m, m - 1, k=0, format="csr")
    before = sp.eye(m, m - 1, k=-1, format="csr")
    DA, DB = sp.kron(after, D, format="csr"), sp.kron(before, D, format="csr")
    it = 0
    for it in range(1, max_iter + 1):
        coeffs = coefficients(e, scheme)  # Eq. (8) on the current frames
        A = 0
        b = 0
        for alpha, beta, weight in coeffs:
            s = np.repeat(weight / h, shape.n_edges)
            # residual rows (interval-major): alpha e_{k+1} + beta e_k
            R = sp.diags(alpha.T.ravel()) @ DA + sp.diags(beta.T.ravel()) @ DB
            known = np.zeros((m, shape.n_edges), dtype=complex)
            known[0] += beta[:, 0] * e[:, 0]
            known[-1] += alpha[:, -1] * e[:, -1]
            RhS = R.conj().T @ sp.diags(s)
            A = A + RhS @ R
            b = b - RhS @ known.ravel()
        x0 = asm.gauge(z[:, 1:-1]).T
        if linear_solver == "direct":
            x = spsolve(A.tocsc(), b)
        else:
            tri = TridiagonalSolver(*tridiagonal(coeffs, h))
            M = LinearOperator(A.shape, matvec=lambda g, tri=tri: _precondition(g, asm, tri, m, nf), dtype=complex)
            count = [0]
            x, _ = cg(A, b, x0=x0.ravel(), rtol=cg_rtol, maxiter=10 * nf + 100, M=M,
                      callback=lambda _x, count=count: count.__setitem__(0, count[0] + 1))
            cg_iters.append(count[0])
        new = np.zeros((len(z0), m - 1), dtype=complex)
        new[asm.free] = x.reshape(m - 1, nf).T
        new = asm.place(new, centroids)
        move = float(np.max(np.abs(new - z[:, 1:-1]), initial=0.0))  # Eq. (11)
        z[:, 1:-1] = new
        e = Dfull @ z
        energies.append(isometric_energy(e, h, scheme))
        if callback is not None:
            callback(it, energies[-1], move)
        if move < tol:
            converged = True
            break
    return Result(z, energies, it, converged, move, info={"cg_iterations": cg_iters})


def _precondition(g, asm, tri, m, nf):
    """L^-1 D^H T^-1 D L^-1 applied to a (m-1) n_free vector."""
    y = asm.solve_laplacian(g.reshape(m - 1, nf).T)  # (nf, m-1)
    y = tri.solve(asm.D_free @ y)  # (E, m-1)
    return asm.solve_laplacian(asm.D_free.T @ y).T.ravel()
