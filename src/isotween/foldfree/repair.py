"""Folds of an interpolated sequence repaired frame by frame, as close to its own frames as no flip allows.

Where AIAP's least-squares frames (Eq. 10) fold a few triangles, the rest of
the frame is still what the method asks for. Every folding frame is
replaced by the minimum of

    E(x) = sum_f A_f (|J_f|^2 + |J_f^-1|^2) + mu sum_v |x_v - a_v|^2,

where ``a`` is the folding frame, ``J_f`` the Jacobian of face f's map from
its rest triangle (the triangle of ``a`` with the same side lengths, so a
folded face rests as its unfolded mirror image), and ``mu`` pulls every
vertex to its place in ``a`` (`PULL`, in units of the least energy per
vertex and squared edge). The symmetric Dirichlet term is infinite on a
degenerate triangle, and the projected Newton of
`isotween.optimisation.barrier` keeps every iterate flip-free, so the start
must be: it is the repaired frame before, moved along the frame-to-frame
motion of the sequence as far as no triangle degenerates. Frames from the
first folding one to the last folding one are repaired (so the motion has no
jump inside that range); the others are kept bit for bit.
"""

import numpy as np

from ..errors import MethodError
from ..geometry import triangle_areas
from ..optimisation.barrier import SymmetricDirichlet, max_step, minimise

__all__ = ["repair_folds", "PULL", "MAX_ITER", "TOL", "WORK"]

PULL = 1.0  # weight of the pull to the folding frame, in units of the least energy per vertex and squared edge
MAX_ITER = 30  # Newton iterations per frame at most
TOL = 1e-3  # stop when an iteration lowers the energy above its least value by less than this fraction
WORK = 2_000_000  # Newton iterations x vertices for the whole repair; beyond it the repair gives up


def repair_folds(frames, faces, accept=None):
    """Frames with no flipped triangle, each as close to the given frame as that allows.

    Parameters
    ----------
    frames : (T, N) complex
        Vertex positions per frame; frame 0 (the source) has no degenerate
        face, and its orientation of every face is the one kept.
    faces : (F, 3) int
    accept : callable, optional
        ``accept(k, x)`` with a repaired frame ``x`` (N,) complex: False
        stops the repair (`MethodError`), e.g. when the frame's outline
        crosses itself, which no repair of flips mends.

    Returns
    -------
    frames : (T, N) complex
        The repaired frames (a new array; frames outside the repaired range
        are copies).
    info : dict
        ``frames`` (indices repaired), ``iterations`` (Newton iterations in
        all), ``deviation`` (largest distance of a repaired vertex from its
        place in the given frame).

    Raises
    ------
    MethodError
        Frame 0 has a degenerate face, the last frame a flipped or degenerate
        one, a Newton system cannot be solved, ``accept`` refused a frame, or
        the repair needs more than `WORK` (Newton iterations times vertices).
    """
    frames = np.asarray(frames, dtype=complex)
    f = np.asarray(faces, dtype=np.int64)
    area0 = triangle_areas(frames[0], f)
    if np.any(area0 == 0):
        raise MethodError("the first frame has a degenerate triangle; its folds cannot be told")
    f = np.where((area0 < 0)[:, None], f[:, ::-1], f)  # every face positive in frame 0
    if np.any(triangle_areas(frames[-1], f) <= 0):
        raise MethodError("the last frame itself has flipped triangles: no fold-free way leads to it")
    folded = [k for k in range(1, len(frames) - 1) if np.any(triangle_areas(frames[k], f) <= 0)]
    out = frames.copy()
    info = {"frames": [], "iterations": 0, "deviation": 0.0}
    if not folded:
        return out, info
    energy = SymmetricDirichlet(frames[0], frames[0], f, np.zeros(frames.shape[1], dtype=bool))
    everyone = np.arange(frames.shape[1])
    for k in range(folded[0], folded[-1] + 1):
        a = frames[k]
        sides = a[np.roll(f, -1, axis=1)] - a[f]
        energy.rest_lengths(np.abs(sides))
        h2 = float(np.mean(np.abs(sides) ** 2))
        energy.pull_towards(everyone, a, PULL * energy.least / (len(a) * h2))
        step = a - frames[k - 1]
        x = out[k - 1] + min(1.0, 0.9 * max_step(out[k - 1], step, f)) * step
        x, used = minimise(energy, x, MAX_ITER, tol=TOL)
        out[k] = x
        info["iterations"] += used
        if info["iterations"] * len(a) > WORK:
            raise MethodError(f"repairing the folds needs more than {WORK} Newton iterations x vertices")
        if accept is not None and not accept(k, x):
            raise MethodError(f"repaired frame {k} is not accepted")
        info["deviation"] = max(info["deviation"], float(np.abs(x - a).max()))
    info["frames"] = list(range(folded[0], folded[-1] + 1))
    return out, info
