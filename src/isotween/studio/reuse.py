"""What the studio keeps between solves: the meshes of region pairs that a hint does not change.

`isotween.correspond` takes a mapping of region meshes (``meshes=``, keyed
by `isotween.correspondence.region_key`): a region pair whose rings come
again is not meshed again. A landmark changes the matched rings of one
outline only, so after a hint only that region is meshed. `MeshMemo` is
that mapping for one studio session: it forgets the oldest meshes beyond
`MEMO_SIZE` and learns how long meshing takes here, so the session can tell
whether a hint's meshes come within its live budget or an outline preview
should be shown first. (The factorisation of Eq. (10) that repeated edits of
one morph share is kept by the library itself: `isotween.edit` keeps it per
sequence.)
"""

from __future__ import annotations

import threading
from collections import OrderedDict
from collections.abc import MutableMapping
from typing import Any

__all__ = ["MeshMemo", "pending_vertices", "MEMO_SIZE"]

#: region meshes kept per session
MEMO_SIZE = 64


class MeshMemo(MutableMapping):
    """Compatible meshes of recent region pairs (a mapping for ``correspond(meshes=...)``), least recent forgotten.

    Attributes
    ----------
    rate : float or None
        Seconds per ring vertex that meshing took here lately (`learn`).
    hits, misses : int
    """

    def __init__(self, size: int = MEMO_SIZE):
        self.size = size
        self._items: OrderedDict = OrderedDict()
        self.rate: float | None = None
        self.hits = self.misses = 0
        self._lock = threading.Lock()

    def __getitem__(self, key: Any) -> Any:
        with self._lock:
            value = self._items[key]
            self._items.move_to_end(key)
            return value

    def __contains__(self, key: object) -> bool:
        with self._lock:
            found = key in self._items
            if found:
                self.hits += 1
            else:
                self.misses += 1
            return found

    def __setitem__(self, key: Any, value: Any) -> None:
        with self._lock:
            self._items[key] = value
            self._items.move_to_end(key)
            while len(self._items) > self.size:
                self._items.popitem(last=False)

    def __delitem__(self, key: Any) -> None:
        with self._lock:
            del self._items[key]

    def __iter__(self) -> Any:
        with self._lock:
            return iter(list(self._items))

    def __len__(self) -> int:
        return len(self._items)

    def has_rings(self, digest: str) -> bool:
        """Whether meshes of the rings with this digest (``region_key(...)[0]``, any mesh size) are kept."""
        with self._lock:
            return any(k[0] == digest for k in self._items)

    def learn(self, seconds: float, vertices: int) -> None:
        """Meshing ``vertices`` ring vertices took ``seconds``: update `rate` (a running mean)."""
        if vertices > 0:
            rate = seconds / vertices
            self.rate = rate if self.rate is None else 0.5 * (self.rate + rate)


def _region_rings(shape: Any, region: Any) -> list:
    return [shape.vertices[shape.paths[p][0]] for p in region]


def pending_vertices(outline: Any, memo: MeshMemo) -> int:
    """Ring vertices of the region pairs of an outline correspondence whose meshes are not in ``memo``."""
    from ..correspondence import region_key

    src, tgt = outline.source, outline.target
    total = 0
    for region in src.regions or []:
        rs, rt = _region_rings(src, region), _region_rings(tgt, region)
        if not memo.has_rings(region_key(rs, rt, None)[0]):
            total += sum(len(r) for r in rs)
    return total
