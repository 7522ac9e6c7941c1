"""Numerical defaults shared by the library and the command line (imports nothing, so `isotween render` stays light)."""

DEFAULT_TOL = 5e-4
"""Default stopping tolerance of the AIAP solvers: no vertex moves more than tol x the bbox diagonal (Eq. 11)."""
