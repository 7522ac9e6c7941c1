"""Optimisation.

The solve core (`problem.Problem` in, `problem.Result` out, `solve.solve` between), the time schemes, Eq. (9) edge
solve, Eq. (10) frame assembly, the local solver (Algorithm 2), the global solver (Algorithm 1) and the compute
backends (`backend`: the numpy `reference` or the numba `accelerated` kernels).
"""
