"""Time discretisations of the isometric energy, Eq. (6).

Every residual of a time interval k (between frames k and k+1) has the form

    r_k = alpha_k * e_{k+1} + beta_k * e_k          (complex, one per edge)

with ``alpha, beta`` depending on the angular speed c fitted by the corrected
Eq. (8). The energy is ``sum_k |r_k|^2 / h_k`` (h times |r/h|^2). We carry the
per-step angle ``omega = h c`` so that h cancels out of every coefficient.

Schemes
-------
'midpoint'
    (1 - i omega/2) e_{k+1} - (1 + i omega/2) e_k, omega fitted at the midpoint
    (e_k + e_{k+1}) / 2 (docs/how-it-works.md). Time-symmetric; exact for constant-speed turning.
'paper'
    Forward differences e_{k+1} - (1 + i omega_k) e_k with omega fitted at e_k,
    plus the reverse sampling of Sec. 3.2, e_k - (1 + i omega'_{k+1}) e_{k+1},
    each with weight 1/2.
"""

import numpy as np

from ..errors import ParameterError

__all__ = ["SCHEMES", "step_angle", "midpoint_angle", "coefficients", "energy_terms", "isometric_energy",
           "normal_equations"]

SCHEMES = ("midpoint", "paper")


def _ratio(num, den):
    """The quotient num / den, and 0 where den vanishes (a degenerate edge has no rotation)."""
    tiny = 1e-24 * float(np.mean(den)) if den.size else 0.0
    ok = den > tiny
    return np.divide(num, den, out=np.zeros_like(num), where=ok)


def step_angle(e, de):
    """Corrected Eq. (8) times h: omega = Im(conj(e) de) / |e|^2.

    Zero where e has (numerically) zero length, e.g. an edge that a linear
    initialisation collapses halfway through a half turn.

    Parameters
    ----------
    e : complex array
        Edge vectors the rotation is fitted at.
    de : complex array, same shape
        Edge vector change over the step.
    """
    return _ratio((e.conj() * de).imag, e.real**2 + e.imag**2)


def midpoint_angle(e0, e1):
    """Corrected Eq. (8) times h, fitted at the midpoint (e0 + e1) / 2.

    omega = Im(conj(s) d) / (|s|^2 / 2) with s = e0 + e1, d = e1 - e0; zero
    where s vanishes. The numba twin is in
    :mod:`isotween.optimisation.accelerated` (``_edge_solve``).

    Parameters
    ----------
    e0, e1 : (E, m) complex
        Edge vectors at the start and the end of every interval.

    Returns
    -------
    omega : (E, m) float
    p_imag : (E, m) float
        Im(conj(s) d), which the energy needs as well.
    d : (E, m) complex
        e1 - e0.
    """
    s, d = e0 + e1, e1 - e0
    p_imag = (s.conj() * d).imag
    return 2.0 * _ratio(p_imag, s.real**2 + s.imag**2), p_imag, d


def coefficients(e, scheme):
    """Residual coefficients of every edge and interval.

    Parameters
    ----------
    e : (E, m+1) complex array
        Edge vectors of every frame.
    scheme : {'midpoint', 'paper'}

    Returns
    -------
    list of (alpha, beta, weight)
        alpha, beta : (E, m) complex arrays; weight : float. One entry for the
        midpoint scheme, two (forward, reverse) for the paper scheme.
    """
    e0, e1 = e[:, :-1], e[:, 1:]
    if scheme == "midpoint":
        w = 0.5j * midpoint_angle(e0, e1)[0]  # i omega / 2, omega at the midpoint
        return [(1.0 - w, -(1.0 + w), 1.0)]
    de = e1 - e0
    if scheme == "paper":
        fwd = 1j * step_angle(e0, de)  # Eq. (7)-(8): forward difference at t_k
        rev = 1j * step_angle(e1, -de)  # Sec. 3.2 reverse sampling at t_{k+1}
        return [(np.ones_like(fwd), -(1.0 + fwd), 0.5), (-(1.0 + rev), np.ones_like(rev), 0.5)]
    raise ParameterError(f"unknown scheme {scheme!r}; choose one of {', '.join(SCHEMES)}")


def energy_terms(e, h, scheme):
    """(E, m) float: each edge's and interval's share of Eq. (6), c optimal."""
    out = 0.0
    for alpha, beta, weight in coefficients(e, scheme):
        r = alpha * e[:, 1:] + beta * e[:, :-1]
        out = out + weight * (r.real**2 + r.imag**2)
    return out / h


def isometric_energy(e, h, scheme):
    """Dimensionless isometric energy (docs/how-it-works.md): Eq. (6) over sum |e(0)|^2.

    Parameters
    ----------
    e : (E, m+1) complex array
    h : (m,) float array
        Interval lengths t_{k+1} - t_k.
    scheme : str
    """
    if e.shape[1] < 2 or e.shape[0] == 0:
        return 0.0
    return float(energy_terms(e, h, scheme).sum() / np.sum(np.abs(e[:, 0]) ** 2))


def normal_equations(e, h, scheme):
    """Fused Eq. (8) + the tridiagonal normal equations of Eq. (9) + the energy.

    Equal to :func:`isotween.optimisation.edge_solve.tridiagonal` of
    :func:`coefficients` and to :func:`energy_terms`, but in real arithmetic on
    a few (E, m) arrays: this is the hot loop of the local solver.

    Parameters
    ----------
    e : (E, m+1) complex
    h : (m,) float
    scheme : {'midpoint', 'paper'}

    Returns
    -------
    diag : (E, m+1) float
    lower : (E, m) complex
    energy : float
        Eq. (6), not yet divided by sum |e(0)|^2.
    """
    e0, e1 = e[:, :-1], e[:, 1:]
    inv_h = 1.0 / h
    diag = np.zeros(e.shape)
    if scheme == "midpoint":
        # alpha = 1 - i w/2, beta = -(1 + i w/2): |alpha|^2 = |beta|^2 = 1 + w^2/4,
        # conj(alpha) beta = -(1 - w^2/4 + i w)
        w, p_imag, d = midpoint_angle(e0, e1)  # Eq. (8)
        q = 0.25 * w * w
        a2 = (1.0 + q) * inv_h
        diag[:, 1:] += a2
        diag[:, :-1] += a2
        lower = np.empty(w.shape, dtype=complex)
        lower.real = -(1.0 - q) * inv_h
        lower.imag = -w * inv_h
        # |r|^2 = |d|^2 - (Im p)^2 / |s|^2 = (Re p)^2 / |s|^2, also where s = 0 (p = conj(s) d)
        d2 = d.real**2 + d.imag**2
        energy = float(np.sum((d2 - 0.5 * w * p_imag) @ inv_h))
        return diag, lower, energy
    if scheme == "paper":
        d = e1 - e0
        pf = e0.conj() * d  # forward: omega_f = Im(pf) / |e0|^2
        pr = e1.conj() * d  # reverse: omega_r = -Im(pr) / |e1|^2
        n0 = e0.real**2 + e0.imag**2
        n1 = e1.real**2 + e1.imag**2
        wf = _ratio(pf.imag, n0)
        wr = -_ratio(pr.imag, n1)
        half = 0.5 * inv_h
        # forward (1, -(1 + i wf)) and reverse (-(1 + i wr), 1), weight 1/2 each
        diag[:, 1:] += half * (2.0 + wr * wr)
        diag[:, :-1] += half * (2.0 + wf * wf)
        lower = np.empty(wf.shape, dtype=complex)
        lower.real = -2.0 * half
        lower.imag = half * (wr - wf)
        d2 = d.real**2 + d.imag**2
        energy = float(np.sum((2.0 * d2 - wf * pf.imag + wr * pr.imag) @ half))
        return diag, lower, energy
    raise ParameterError(f"unknown scheme {scheme!r}; choose one of {', '.join(SCHEMES)}")
