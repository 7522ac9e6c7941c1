"""Which frame an animation shows at each tick: frames per second, holds at the ends, bounce.

Shared by every animated output (light: importing it loads no plotting library).
"""

import numpy as np

from ..errors import ParameterError
from .defaults import FPS

__all__ = ["MAX_HOLD", "check_fps", "playback_order"]

#: longest hold (seconds) at each end of an animation
MAX_HOLD = 3600


def check_fps(fps):
    """Raise `ParameterError` unless ``fps`` is in (0, 100]."""
    if isinstance(fps, bool) or not isinstance(fps, (int, float, np.number)) or not np.isfinite(fps) \
            or fps <= 0 or fps > 100:
        raise ParameterError(f"fps must be a number in (0, 100], got {fps!r}")


def playback_order(n, fps=FPS, hold=0.0, bounce=False):
    """Which frame is shown at each tick of ``1 / fps`` seconds.

    Parameters
    ----------
    n : int
        Frames in the sequence.
    fps : float
    hold : float
        Seconds the first and the last frame stay on screen (each end; with
        ``bounce`` the turning point holds too), on top of their own tick.
    bounce : bool
        Play forward then backward (``2 n - 2`` ticks before holds).

    Returns
    -------
    (P,) int array
        Frame index of every tick.
    """
    check_fps(fps)
    if isinstance(hold, bool) or not isinstance(hold, (int, float, np.number)) or not 0 <= hold <= MAX_HOLD:
        raise ParameterError(f"hold must be a number of seconds from 0 to {MAX_HOLD}, got {hold!r}")
    extra = int(round(hold * fps))
    forward = np.arange(n)
    ends = lambda k: np.full(extra, k, dtype=np.int64)  # noqa: E731
    parts = [ends(0), forward, ends(n - 1)]
    if bounce and n > 2:
        parts += [forward[-2:0:-1]]
    return np.concatenate(parts).astype(np.int64)
