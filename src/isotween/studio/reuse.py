"""What the studio reuses between solves: the meshes of region pairs that a hint does not change.

`isotween.correspond` is outline correspondence (regions paired, rings
matched) followed by meshing every pair of filled regions
(``correspond._solids``, one ``_mesh_region`` call per region pair). A
landmark changes the matched rings of one outline only, and the outline
preview has already done the outline part; so the studio

- makes the meshes of an outline correspondence it already has (`meshed`:
  ``_solids`` on a copy of the outline pair, exactly what `correspond` does
  after its outline stage), and
- keeps the meshes of recent region pairs (`MeshMemo`): while a studio solve
  meshes, ``_mesh_region`` is answered from the memo when the same rings and
  mesh size come again (the meshing is deterministic, so the answer is the
  one it would compute).

Sequence editing (Sec. 5.2) factorises the Eq. (10) Laplacian of the
sequence's shape with weights from the unedited morph (``problems.assemble``
in `isotween.edit`); the studio edits the same morph again and again, so
`FactorMemo` keeps that factorisation (banded Cholesky) for the next edit.

The memos stand in for hooks the library does not have yet (a mesh cache
argument of ``_solids``, an assembler or factorisation cache for
``assemble``); outside a studio solve (any other thread, any other caller)
the wrappers call the library's own code and keep nothing. Tests check the
results are bit for bit the library's (`isotween.correspond`, `isotween.edit`).
"""

from __future__ import annotations

import copy
import hashlib
import threading
import time
from collections import OrderedDict
from typing import Any

import numpy as np

__all__ = ["MeshMemo", "FactorMemo", "meshed", "pending_vertices", "reusing"]

#: region meshes kept per session
MEMO_SIZE = 64

_local = threading.local()
_install_lock = threading.Lock()


def _module() -> Any:
    import importlib

    return importlib.import_module("isotween.correspondence.correspond")


def _key(rings: Any) -> str:
    h = hashlib.blake2b(digest_size=16)
    for ring in rings:
        a = np.ascontiguousarray(ring, dtype=np.float64)
        h.update(str(a.shape).encode())
        h.update(a.tobytes())
    return h.hexdigest()


class MeshMemo:
    """Compatible meshes of recent region pairs, and how long meshing takes here (seconds per ring vertex)."""

    def __init__(self, size: int = MEMO_SIZE):
        self.size = size
        self.items: OrderedDict = OrderedDict()
        self.rate: float | None = None  # seconds per ring vertex of the last region pairs meshed
        self.hits = self.misses = 0
        self.lock = threading.Lock()

    def rings_key(self, source_rings: Any, target_rings: Any) -> tuple:
        """The key of a region pair's rings (digests of their coordinates)."""
        return (_key(source_rings), _key(target_rings))

    def has_rings(self, key: tuple) -> bool:
        """Whether meshes of these rings (any mesh size) are kept."""
        with self.lock:
            return any(k[:2] == key for k in self.items)

    def get(self, key: tuple) -> Any:
        """The kept ``_mesh_region`` answer of ``key`` (rings and mesh size), or None."""
        with self.lock:
            if key in self.items:
                self.items.move_to_end(key)
                self.hits += 1
                return self.items[key]
            self.misses += 1
            return None

    def put(self, key: tuple, value: Any, seconds: float, vertices: int) -> None:
        """Keep an answer that took ``seconds`` for ``vertices`` ring vertices (and update `rate`)."""
        with self.lock:
            self.items[key] = value
            while len(self.items) > self.size:
                self.items.popitem(last=False)
            rate = seconds / max(vertices, 1)
            self.rate = rate if self.rate is None else 0.5 * (self.rate + rate)

    def clear(self) -> None:
        """Forget every kept mesh (the rate stays)."""
        with self.lock:
            self.items.clear()


class FactorMemo:
    """Banded factorisations of Eq. (10) of recent (connectivity, weights), for `isotween.edit`."""

    def __init__(self, size: int = 2):
        self.size = size
        self.items: OrderedDict = OrderedDict()
        self.hits = self.misses = 0
        self.lock = threading.Lock()

    def get(self, shape: Any, weights: Any) -> tuple:
        """(key, the kept assembler of ``shape``'s connectivity with ``weights`` or None)."""
        key = (id(shape.topology), _key([weights]))
        with self.lock:
            found = self.items.get(key)
            if found is not None and found[0] is shape.topology:
                self.items.move_to_end(key)
                self.hits += 1
                return key, found[1]
            self.misses += 1
            return key, None

    def put(self, key: tuple, shape: Any, assembler: Any) -> None:
        """Keep an assembler under ``key`` (from `get`)."""
        with self.lock:
            self.items[key] = (shape.topology, assembler)
            while len(self.items) > self.size:
                self.items.popitem(last=False)


class reusing:  # noqa: N801 (a context manager, used as ``with reusing(...)``)
    """While the block runs in this thread, library calls are answered from these memos where they can be."""

    def __init__(self, meshes: MeshMemo | None = None, factors: FactorMemo | None = None):
        self.values = {"memo": meshes if meshes is not None and _install() else None,
                       "factors": factors if factors is not None and _install_assembler() else None}

    def __enter__(self) -> reusing:
        self.previous = {k: getattr(_local, k, None) for k in self.values}
        for k, v in self.values.items():
            setattr(_local, k, v)
        return self

    def __exit__(self, *exc: Any) -> None:
        for k, v in self.previous.items():
            setattr(_local, k, v)


def _install_assembler() -> bool:
    """Wrap ``problems.FrameAssembler`` once (a pass-through outside a studio edit); False if it is gone."""
    import importlib

    mod = importlib.import_module("isotween.problems")
    with _install_lock:
        current = getattr(mod, "FrameAssembler", None)
        if current is None:
            return False
        if getattr(current, "_studio_memo", False):
            return True
        original = current

        def frame_assembler(shape: Any, weights: Any = None, factorisation: str = "auto") -> Any:
            memo = getattr(_local, "factors", None)
            if memo is None or weights is None or factorisation != "auto":
                return original(shape, weights, factorisation)
            key, found = memo.get(shape, weights)
            if found is not None:
                return found
            assembler = original(shape, weights, factorisation)
            if assembler.method == "banded":  # its solves keep no state: safe to share between threads
                memo.put(key, shape, assembler)
            return assembler

        frame_assembler._studio_memo = True  # type: ignore[attr-defined]
        frame_assembler.__wrapped__ = original  # type: ignore[attr-defined]
        setattr(mod, "FrameAssembler", frame_assembler)  # noqa: B010 (a module attribute replaced)
        return True


def _install() -> bool:
    """Wrap ``correspond._mesh_region`` once (a pass-through outside a studio solve); False if it is gone."""
    mod = _module()
    with _install_lock:
        current = getattr(mod, "_mesh_region", None)
        if current is None:
            return False
        if getattr(current, "_studio_memo", False):
            return True
        original = current

        def mesh_region(source_rings: Any, target_rings: Any, mesh_size: Any) -> Any:
            memo = getattr(_local, "memo", None)
            if memo is None:
                return original(source_rings, target_rings, mesh_size)
            key = (*memo.rings_key(source_rings, target_rings), repr(mesh_size))
            found = memo.get(key)
            if found is not None:
                return found
            started = time.perf_counter()
            value = original(source_rings, target_rings, mesh_size)
            memo.put(key, value, time.perf_counter() - started, sum(len(r) for r in source_rings))
            return value

        mesh_region._studio_memo = True  # type: ignore[attr-defined]
        mesh_region.__wrapped__ = original  # type: ignore[attr-defined]
        mod._mesh_region = mesh_region
        return True


def _region_rings(shape: Any, region: Any) -> list:
    return [shape.vertices[shape.paths[p][0]] for p in region]


def pending_vertices(outline: Any, memo: MeshMemo) -> int:
    """Ring vertices of the region pairs of an outline correspondence whose meshes are not in ``memo``."""
    src, tgt = outline.source, outline.target
    total = 0
    for region in src.regions or []:
        rs, rt = _region_rings(src, region), _region_rings(tgt, region)
        if not memo.has_rings(memo.rings_key(rs, rt)):
            total += sum(len(r) for r in rs)
    return total


def meshed(outline: Any, source: Any, memo: MeshMemo | None = None, *, fallback: Any = None) -> Any:
    """The compatible meshes of an outline correspondence, as `correspond` (without ``outline``) makes them.

    Parameters
    ----------
    outline : isotween.pipeline.Prepared
        From ``prepare_pair(..., outline=True)``; not changed.
    source : Shape
        The source input (whether the meshes were built here: ``built_meshes``).
    memo : MeshMemo, optional
        Region meshes to reuse (and to keep).
    fallback : callable, optional
        ``fallback()`` gives the meshed `Prepared` the long way (``prepare_pair`` without
        ``outline``) when this library has no ``_solids`` stage to call.

    Returns
    -------
    isotween.pipeline.Prepared
    """
    from ..pipeline import Prepared

    mod = _module()
    solids = getattr(mod, "_solids", None)
    if solids is None:
        if fallback is None:
            raise RuntimeError("this isotween has no correspondence meshing stage to call")
        return fallback()
    report = copy.deepcopy(outline.report)  # _solids records the meshes in the report
    with reusing(meshes=memo):
        src, tgt = solids([outline.source, outline.target], report, None)
    return Prepared(src, tgt, report, built_meshes=not source.n_faces and src.n_faces > 0)
