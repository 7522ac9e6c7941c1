"""Opt-in: keep freed memory in the heap between solver iterations.

The solvers allocate many short-lived arrays of a few MB. glibc returns such
memory to the kernel when it is freed, and touching it again costs page faults;
on virtual machines that fault slowly this was measured to make the local
solver's hot loop 4-5x slower (benchmarks/RESULTS.md). Raising glibc's trim
and mmap thresholds keeps that memory for reuse.

The setting is process-wide, so the library never applies it on its own: the
``isotween`` command line and the benchmarks call :func:`keep_heap`, and a
program that embeds isotween may call it too (or set ``ISOTWEEN_KEEP_HEAP=1``,
which the solvers' entry points honour through :func:`keep_heap_if_asked`).
It is applied once, is a no-op off glibc, and ``ISOTWEEN_KEEP_HEAP=0``
disables it everywhere.
"""

from __future__ import annotations

import ctypes
import os

__all__ = ["keep_heap", "keep_heap_if_asked"]

_M_TRIM_THRESHOLD, _M_TOP_PAD, _M_MMAP_THRESHOLD = -1, -2, -3
_done = False


def keep_heap(trim: int = 1 << 30, pad: int = 64 << 20, mmap: int = 32 << 20) -> bool:
    """Apply the thresholds to this process once (bytes); returns True when all were set.

    glibc caps the mmap threshold at 32 MiB; arrays above it are still mapped
    afresh, which is why the solvers work on blocks of edges below that size.

    Parameters
    ----------
    trim : int
        ``M_TRIM_THRESHOLD``: free memory at the top of the heap kept before trimming.
    pad : int
        ``M_TOP_PAD``: extra memory requested from the kernel with every heap growth.
    mmap : int
        ``M_MMAP_THRESHOLD``: allocations from this size up are mapped separately.

    Returns
    -------
    bool
        False when already applied, disabled by ``ISOTWEEN_KEEP_HEAP=0``, or
        not on glibc.
    """
    global _done
    if _done or os.environ.get("ISOTWEEN_KEEP_HEAP", "") == "0":
        return False
    _done = True
    try:
        mallopt = _libc().mallopt
    except (OSError, AttributeError):
        return False
    results = [mallopt(k, v) for k, v in
               ((_M_MMAP_THRESHOLD, mmap), (_M_TRIM_THRESHOLD, trim), (_M_TOP_PAD, pad))]
    return all(r == 1 for r in results)


def _libc() -> ctypes.CDLL:
    """The C library: glibc's by its soname, else the one `ctypes.util.find_library` finds.

    The soname first: ``find_library`` runs ``ldconfig -p`` in a subprocess (2-5 ms at every
    command's start), and on glibc it answers that name anyway.
    """
    try:
        return ctypes.CDLL("libc.so.6")
    except OSError:
        from ctypes.util import find_library

        return ctypes.CDLL(find_library("c") or "libc.so.6")


def keep_heap_if_asked() -> bool:
    """:func:`keep_heap` when the environment sets ``ISOTWEEN_KEEP_HEAP=1``; else nothing.

    Returns
    -------
    bool
        Whether the thresholds were set by this call.
    """
    if os.environ.get("ISOTWEEN_KEEP_HEAP", "") != "1":
        return False
    return keep_heap()
