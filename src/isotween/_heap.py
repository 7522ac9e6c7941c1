"""Keep freed memory in the heap between solver iterations.

The solvers allocate many short-lived arrays of a few MB. glibc returns such
memory to the kernel when it is freed, and touching it again costs page faults;
on virtual machines that fault slowly this was measured to make the local
solver's hot loop 4-5x slower (benchmarks/RESULTS.md). Raising glibc's trim
and mmap thresholds keeps that memory for reuse. It is process-wide, applied
once, a no-op off glibc, and skipped when ISOTWEEN_KEEP_HEAP=0.
"""

import ctypes
import ctypes.util
import os

_M_TRIM_THRESHOLD, _M_TOP_PAD, _M_MMAP_THRESHOLD = -1, -2, -3
_done = False


def keep_heap(trim=1 << 30, pad=64 << 20, mmap=256 << 20):
    """Apply the thresholds once (bytes); returns True when they were set."""
    global _done
    if _done or os.environ.get("ISOTWEEN_KEEP_HEAP", "1") == "0":
        return False
    _done = True
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    return all(mallopt(k, v) == 1 for k, v in
               ((_M_MMAP_THRESHOLD, mmap), (_M_TRIM_THRESHOLD, trim), (_M_TOP_PAD, pad)))
