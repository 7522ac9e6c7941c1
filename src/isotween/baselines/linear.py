"""Linear blending of vertex positions: z(t) = (1 - t) z(0) + t z(1)."""

import numpy as np

__all__ = ["interpolate"]


def interpolate(source, target, t):
    """Frames of the linear blend.

    Parameters
    ----------
    source, target : Shape
    t : (F,) float

    Returns
    -------
    frames : (F, n) complex
    info : dict
    """
    t = np.asarray(t)[:, None]
    return (1 - t) * source.z[None] + t * target.z[None], {}
