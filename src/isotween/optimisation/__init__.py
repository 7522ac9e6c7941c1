"""Optimisation.

The time schemes, Eq. (9) edge solve, Eq. (10) frame assembly, the local solver (Algorithm 2) and the global solver
(Algorithm 1).
"""
