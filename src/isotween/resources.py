"""Memory guards: estimate what a run needs and refuse it before allocating.

The limit is the memory available now (``MemAvailable`` in /proc/meminfo, or
the physical memory where that file does not exist), unless a caller gives
``max_memory`` (bytes) or runs inside :func:`memory_limit` (the command
line's ``--max-memory``).
"""

import contextlib
import contextvars
import os

from .errors import ParameterError, ResourceError

__all__ = ["available_memory", "memory_limit", "check_memory", "solve_bytes", "parse_size", "format_size"]

_LIMIT = contextvars.ContextVar("isotween_memory_limit", default=None)
_UNITS = {"": 1, "b": 1, "k": 1 << 10, "kb": 1 << 10, "m": 1 << 20, "mb": 1 << 20,
          "g": 1 << 30, "gb": 1 << 30, "t": 1 << 40, "tb": 1 << 40}


def available_memory():
    """Bytes of memory available to a new allocation (int).

    ``MemAvailable`` from /proc/meminfo (Linux); elsewhere the physical
    memory (``os.sysconf``); 8 GiB when neither can be read. A limit on the
    address space (``ulimit -v``, ``RLIMIT_AS``) lowers it to what is left
    of that limit.
    """
    free = _meminfo("/proc/meminfo", "MemAvailable:")
    if free is None:
        try:
            free = int(os.sysconf("SC_PAGE_SIZE")) * int(os.sysconf("SC_PHYS_PAGES"))
        except (AttributeError, ValueError, OSError):
            free = 8 << 30
    try:
        import resource

        soft = resource.getrlimit(resource.RLIMIT_AS)[0]
    except (ImportError, OSError, ValueError):
        soft = -1
    if soft not in (-1, getattr(resource, "RLIM_INFINITY", -1)):
        used = _meminfo("/proc/self/status", "VmSize:") or 0
        free = min(free, max(soft - used, 0))
    return free


def _meminfo(path, key):
    """Bytes of the ``key`` line (in kB) of a /proc file, or None."""
    try:
        with open(path, encoding="ascii") as fh:
            for line in fh:
                if line.startswith(key):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def parse_size(text):
    """Bytes of a size such as ``512M``, ``4G``, ``2.5GB`` or ``1000000`` (int).

    Raises
    ------
    ParameterError
        Not a positive size.
    """
    s = str(text).strip().lower().replace(" ", "")
    num = s.rstrip("kmgtb")
    unit = s[len(num):]
    try:
        value = float(num) * _UNITS[unit]
    except (ValueError, KeyError):
        raise ParameterError(f"--max-memory takes a size such as 512M, 4G or 2.5GB, got {text!r}") from None
    if not value > 0 or value != value or value == float("inf"):
        raise ParameterError(f"--max-memory must be a positive size, got {text!r}")
    return int(value)


def format_size(nbytes):
    """``nbytes`` in the largest fitting binary unit, e.g. ``'15.7 GiB'``."""
    value = float(nbytes)
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if value < 1024 or unit == "PiB":
            return f"{value:.0f} {unit}" if unit == "B" else f"{value:.1f} {unit}"
        value /= 1024
    return f"{value:.1f} PiB"  # pragma: no cover


@contextlib.contextmanager
def memory_limit(nbytes):
    """Within the block, `check_memory` uses ``nbytes`` as the limit (None: available memory)."""
    token = _LIMIT.set(nbytes)
    try:
        yield
    finally:
        _LIMIT.reset(token)


def check_memory(nbytes, what, max_memory=None, advice="use fewer frames or vertices"):
    """Raise `ResourceError` when ``nbytes`` exceed the memory limit.

    Parameters
    ----------
    nbytes : int or float
        Estimated peak bytes of the step.
    what : str
        The step, as the message names it (e.g. ``"interpolating 1000000000 frames of 4 vertices"``).
    max_memory : int, optional
        Limit in bytes; default the :func:`memory_limit` in force, else
        :func:`available_memory`.
    advice : str
        What to change, as the message suggests it.
    """
    if max_memory is not None and (isinstance(max_memory, bool) or not max_memory > 0):
        raise ParameterError(f"max_memory must be a positive number of bytes, got {max_memory!r}")
    limit = max_memory if max_memory is not None else _LIMIT.get()
    source = "the limit" if limit is not None else "the available memory"
    if limit is None:
        limit = available_memory()
    if nbytes > limit:
        raise ResourceError(
            f"{what} needs about {format_size(nbytes)}, more than {source} ({format_size(limit)}); "
            f"{advice}, or raise the limit with --max-memory (max_memory=)"
        )


def solve_bytes(frames, n_vertices, n_edges):
    """Estimated peak bytes of an interpolation (float).

    Per frame: the vertex positions (complex, current and previous), the
    output frames, and about five complex arrays over the edges (current,
    next, fitted speeds, normal equations). Measured peaks (numpy path, a
    ring, 2,000-20,000 frames) were 131-134 bytes per frame and vertex
    against 144 estimated here; the numba path needs less (69-84).
    """
    return float(frames) * (64.0 * n_vertices + 80.0 * n_edges)
