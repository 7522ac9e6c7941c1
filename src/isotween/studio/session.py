"""The studio's session: inputs, options, hints and edits, solved into a morph, with undo and redo.

A *document* (a plain dict, JSON-able) says what the user asked for; the
session solves it through the library (two drawings as `isotween.morph` does:
`pipeline.prepare_pair`, `interpolate` with ``fold='fallback'``,
`pipeline.finish`; keyframes by `correspond_keys` and
`interpolate_keyframes`; then `edit` and `transfer`) and keeps the last good one.
What a change leaves alone is reused: loaded inputs, correspondences, morphs
and the meshes of region pairs a hint does not touch (`reuse.py`). A new
document is committed only when its solve succeeds and no newer request has
superseded it, so a bad file or a failed solve leaves the session as it was.
"""

from __future__ import annotations

import base64
import copy
import dataclasses
import hashlib
import json
import tempfile
import threading
import time
from collections import OrderedDict
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import FileFormatError, IsotweenError, ParameterError
from ..interpolate import fold_notes
from ..pipeline import STROKES, fitted, size_hint
from ..shape import Shape

__all__ = ["Session", "Superseded", "PROJECT_FORMAT", "DEFAULT_OPTIONS", "METHODS"]

#: the ``format`` field of a project file
PROJECT_FORMAT = "isotween-studio-project/1"
#: interpolation methods offered (``method=`` of `isotween.interpolate`)
METHODS = ("aiap", "linear", "intrinsic", "arap", "arap-baxter", "shapespace", "convex", "injective")
#: options of a new session
DEFAULT_OPTIONS: dict[str, Any] = {
    "frames": 13, "method": "aiap", "easing": [0.0, 0.0, 1.0, 1.0], "points": None, "rotation": False,
    "outline": False, "unmatched": "grow", "roi": 0.35, "strokes": "untangle", "fit": False,
}
#: input file endings the studio opens
SUFFIXES = (".svg", ".obj", ".off", ".json", ".npz")
_CACHE = 24
#: `isotween.correspond`'s defaults of the options the studio sets: only the others are passed on
CORRESPOND_DEFAULTS = {"points": None, "rotation": False, "outline": False, "unmatched": "grow", "fit": False}
#: seconds from a hint to its meshed morph, solved on the server, within which a quick hint is answered
#: with the meshes at once (else by an outline preview first)
LIVE_BUDGET = 0.06


class Superseded(Exception):
    """A newer request replaced this one; its result is dropped."""


@dataclass
class Blob:
    """One input drawing: an uploaded or command-line file, or a built-in example's side."""

    name: str
    data: bytes = b""
    example: str | None = None
    side: int = 0

    def to_json(self) -> dict:
        """The blob as a project-file entry."""
        if self.example is not None:
            return {"name": self.name, "example": self.example, "side": self.side}
        return {"name": self.name, "data": base64.b64encode(self.data).decode("ascii")}

    @classmethod
    def from_json(cls, entry: Any) -> Blob:
        """A blob from a project-file entry."""
        if not isinstance(entry, dict) or not isinstance(entry.get("name"), str):
            raise FileFormatError("project: every input needs a name")
        if entry.get("example") is not None:
            return cls(entry["name"], example=str(entry["example"]), side=int(entry.get("side", 0)))
        try:
            data = base64.b64decode(entry["data"], validate=True)
        except (KeyError, TypeError, ValueError):
            raise FileFormatError(f"project: input {entry['name']!r} has no base64 data") from None
        return cls(entry["name"], data)


def _compatible(a: Any, b: Any) -> bool:
    """Whether two shapes are compatible already (else correspondence runs, as `prepare_pair` decides)."""
    from ..correspondence import check_compatible

    try:
        check_compatible(a, b)
    except IsotweenError:
        return False
    return True


def _suffix(name: str) -> str:
    low = name.lower()
    suffix = next((s for s in SUFFIXES if low.endswith(s)), "")
    if not suffix:
        raise FileFormatError(f"{name}: the studio opens {', '.join(SUFFIXES)} files")
    return suffix


def _bezier(curve: Any) -> tuple[np.ndarray, np.ndarray]:
    """Points (x, y) of a CSS-style cubic-bezier(x1, y1, x2, y2), controls clipped to [0, 1]."""
    try:
        x1, y1, x2, y2 = (float(c) for c in curve)
    except (TypeError, ValueError):
        raise ParameterError("easing must be four numbers (cubic-bezier x1, y1, x2, y2) or one such list "
                             "per segment") from None
    if not np.all(np.isfinite([x1, y1, x2, y2])):
        raise ParameterError("easing must be four finite numbers")
    x1, y1, x2, y2 = (float(np.clip(c, 0.0, 1.0)) for c in (x1, y1, x2, y2))
    tau = np.linspace(0.0, 1.0, 4097)

    def cubic(a: float, b: float) -> np.ndarray:
        return 3 * (1 - tau) ** 2 * tau * a + 3 * (1 - tau) * tau ** 2 * b + tau ** 3

    return cubic(x1, x2), cubic(y1, y2)


def segment_curves(easing: Any, segments: int) -> list:
    """The easing of every segment: one curve for all, or one per segment (list of 4-lists)."""
    if isinstance(easing, (list, tuple)) and easing and all(isinstance(c, (list, tuple)) for c in easing):
        curves = [list(c) for c in easing]
        if len(curves) != segments:
            curves = (curves + [curves[-1]] * segments)[:segments]
    else:
        curves = [list(easing)] * segments if isinstance(easing, (list, tuple)) else [easing] * segments
    return curves


def eased(curves: list) -> Any:
    """The piecewise easing u: [0, 1] -> [0, 1] of the segments' cubic-bezier curves (a callable on arrays).

    Examples
    --------
    >>> import numpy as np
    >>> eased([[0, 0, 1, 1], [0, 0, 1, 1]])(np.array([0.0, 0.25, 0.5, 1.0])).tolist()
    [0.0, 0.25, 0.5, 1.0]
    """
    pieces = [_bezier(c) for c in curves]
    m = len(pieces)

    def u(s: np.ndarray) -> np.ndarray:
        s = np.asarray(s, dtype=float)
        seg = np.clip(np.floor(s * m).astype(int), 0, m - 1)
        local = s * m - seg
        out = np.empty_like(s)
        for j, (bx, by) in enumerate(pieces):
            pick = seg == j
            out[pick] = (j + np.interp(local[pick], bx, by)) / m
        return out

    return u


def bezier_times(frames: int, curve: Any) -> np.ndarray:
    """Frame times eased by a CSS-style cubic-bezier(x1, y1, x2, y2).

    Parameters
    ----------
    frames : int
    curve : sequence of 4 float
        Control points; x1 and x2 are clipped to [0, 1], y1 and y2 to [0, 1]
        (so that time increases).

    Returns
    -------
    (frames,) float array from 0 to 1.

    Examples
    --------
    >>> bezier_times(3, [0, 0, 1, 1]).tolist()
    [0.0, 0.5, 1.0]
    """
    t = eased(segment_curves(curve, 1))(np.linspace(0.0, 1.0, int(frames)))
    t[0], t[-1] = 0.0, 1.0
    if np.any(np.diff(t) <= 0):
        raise ParameterError("this easing curve holds still between frames; make it steeper or use fewer frames")
    return t


@dataclass
class Solved:
    """What one document solves to."""

    inputs: list  # loaded input shapes
    source: Any  # compatible shapes
    target: Any
    report: Any
    base: Any  # the morph before edits
    sequence: Any  # with edits
    transfer: Any = None
    notes: list = field(default_factory=list)
    keys: list = field(default_factory=list)  # the compatible inputs
    preview: bool = False  # outlines standing in for meshes not solved yet (see Session.refine)
    raw: Any = None  # ``sequence`` before vanishing items collapse at its ends (what edits and drags start from)

    def __post_init__(self) -> None:
        if self.raw is None:
            self.raw = self.sequence


class Session:
    """Inputs, options, hints and edits of one studio user, with undo and redo.

    Parameters
    ----------
    paths : list of path-like, optional
        Files given on the command line: the only paths the session reads
        (besides uploads); the first two are opened.
    """

    def __init__(self, paths: Any = ()):
        self.allowed = {str(Path(p).resolve()): Path(p).name for p in paths}
        self.blobs: dict[str, Blob] = {}
        self.doc: dict | None = None
        self.solved: Solved | None = None
        self.undo_stack: list[dict] = []
        self.redo_stack: list[dict] = []
        self.generation = 0
        self.progress: dict = {"generation": 0, "stage": "idle"}
        self.lock = threading.Lock()
        self._cache: OrderedDict = OrderedDict()
        self._deform_cache: tuple | None = None
        from .reuse import MeshMemo

        self.meshes = MeshMemo()  # region meshes kept between solves (see reuse.py)
        self.live_budget = LIVE_BUDGET
        self._morph_seconds = 0.0  # the last morph solve's time (for the estimate of `_in_time`)

    # ---------------------------------------------------------------- inputs
    def add_blob(self, name: str, data: bytes) -> str:
        """Store an uploaded file; its id (str). The file is checked by loading it."""
        name = Path(str(name)).name or "drawing"
        blob = Blob(name, bytes(data))
        self._load_blob(blob)  # raises on a bad file
        key = hashlib.sha256(name.encode() + b"\0" + blob.data).hexdigest()[:16]
        self.blobs[key] = blob
        return key

    def add_path(self, path: str) -> str:
        """Store a command-line file by its path; other paths are refused."""
        resolved = str(Path(path).resolve())
        if resolved not in self.allowed:
            raise ParameterError(f"{path}: the studio reads only uploads and the files named on its command line")
        return self.add_blob(self.allowed[resolved], Path(resolved).read_bytes())

    def add_example(self, name: str) -> list[str]:
        """Store both sides of a built-in example; their ids."""
        from ..examples import names

        if name not in names():
            raise ParameterError(f"unknown example '{name}'; available: {', '.join(names())}")
        keys = []
        for side in (0, 1):
            key = f"example-{name}-{side}"
            self.blobs[key] = Blob(f"{name} ({'source' if side == 0 else 'target'})", example=name, side=side)
            keys.append(key)
        return keys

    def _load_blob(self, blob: Blob) -> Any:
        if blob.example is not None:
            from ..examples import DATA, _entry, load_example
            from ..io import load as load_file

            entry = _entry(blob.example)
            if "correspond" in entry and not entry.get("resample"):  # the drawings as drawn: the studio corresponds
                return load_file(DATA / entry["source" if blob.side == 0 else "target"])
            return load_example(blob.example)[blob.side]
        from ..io import is_sequence_file, load, load_sequence

        suffix = _suffix(blob.name)
        with tempfile.TemporaryDirectory(prefix="isotween-studio-") as tmp:
            path = Path(tmp) / f"input{suffix}"
            path.write_bytes(blob.data)
            try:
                if suffix in (".npz", ".json") and is_sequence_file(path):  # a saved sequence
                    return load_sequence(path)
                return load(path)
            except IsotweenError as exc:
                raise type(exc)(str(exc).replace(str(path), blob.name)) from None

    def _shape(self, key: str) -> Any:
        if key not in self.blobs:
            raise ParameterError(f"no input {key!r} in this session; open the file again")
        return self._cached(("shape", key), lambda: self._load_blob(self.blobs[key]))

    def _cached(self, key: Any, make: Any) -> Any:
        """``make()``, or its value from a recent call with the same key (solves run in several threads)."""
        with self.lock:
            if key in self._cache:
                self._cache.move_to_end(key)
                return self._cache[key]
        value = make()
        with self.lock:
            self._cache[key] = value
            while len(self._cache) > _CACHE:
                self._cache.popitem(last=False)
        return value

    # ---------------------------------------------------------------- solving
    def new_document(self, inputs: list[str]) -> dict:
        """A document of two inputs with the current (or default) options."""
        options = dict(self.doc["options"]) if self.doc else dict(DEFAULT_OPTIONS)
        from ..sequence import Sequence

        loaded = [self._shape(key) for key in inputs]
        saved = [isinstance(x, Sequence) for x in loaded]
        if len(inputs) == 1 and saved[0]:  # a saved sequence: its own frames
            options["frames"] = len(loaded[0])
            options["easing"] = list(DEFAULT_OPTIONS["easing"])
        elif any(saved):
            name = self.blobs[inputs[saved.index(True)]].name
            raise ParameterError(f"{name} is a saved sequence: open it on its own")
        elif not 2 <= len(inputs) <= 12:
            raise ParameterError(f"open two drawings (source and target) or up to 12 keyframes, got {len(inputs)}")
        if all(self.blobs[k].example for k in inputs):  # an example's own frame count
            from ..examples import load_example

            options["frames"] = int(load_example(self.blobs[inputs[0]].example)[2].get("frames", options["frames"]))
        if isinstance(options["easing"][0], list) and len(options["easing"]) != max(len(inputs) - 1, 1):
            options["easing"] = segment_curves(options["easing"], max(len(inputs) - 1, 1))
        return {"inputs": list(inputs), "third": None, "options": options, "pairs": [], "landmarks": [],
                "edits": {}}

    def solve(self, doc: dict, generation: int | None = None, quick: bool = False) -> Solved:
        """Solve a document (raises on failure, `Superseded` when a newer request came in).

        With ``quick``, two drawings whose filled regions would be meshed
        afresh are solved as outlines first (``Solved.preview``); `refine`
        then solves the meshes.
        """
        from ..correspondence import correspond_keys
        from ..editing import edit
        from ..transfer import transfer
        started = time.perf_counter()
        check = (lambda: None) if generation is None else (lambda: self._check_generation(generation))
        options = {**DEFAULT_OPTIONS, **doc.get("options", {})}
        frames = options["frames"]
        if isinstance(frames, bool) or not isinstance(frames, int) or not 2 <= frames <= 1000:
            raise ParameterError(f"frames must be a whole number from 2 to 1000, got {frames!r}")
        if options["method"] not in METHODS:
            raise ParameterError(f"unknown method {options['method']!r}; choose one of {', '.join(METHODS)}")
        if options["strokes"] not in STROKES:
            raise ParameterError(f"unknown strokes {options['strokes']!r}; choose one of {', '.join(STROKES)}")
        inputs = [self._shape(k) for k in doc["inputs"]]
        notes: list[str] = []
        corr_kw: dict[str, Any] = {"points": options["points"], "rotation": bool(options["rotation"]),
                                   "outline": bool(options["outline"]), "unmatched": options["unmatched"],
                                   "fit": bool(options["fit"])}
        if doc.get("pairs"):
            corr_kw["pairs"] = [tuple(int(v) for v in p) for p in doc["pairs"]]
        if doc.get("landmarks"):  # checked by `correspond` (a point off the drawing: its one-line message)
            corr_kw["landmarks"] = doc["landmarks"]
        self._stage(generation, "preparing")

        def progress(iteration: int, energy: float, move: float) -> None:
            self._stage(generation, "morph", iteration=iteration, energy=float(energy))
            check()

        hooks = (progress, check, lambda stage: self._stage(generation, stage))
        curves = segment_curves(options["easing"], max(len(inputs) - 1, 1))
        if len(inputs) == 1:
            morph = self._solve_saved(doc, inputs[0], options, curves, notes)
        elif len(inputs) == 2:
            if all(isinstance(x, Shape) for x in inputs):
                if corr_kw["fit"]:  # fitted here, so that the correspondence panel and its hints see the same
                    inputs = [inputs[0], fitted(inputs[1], inputs[0])]  # (in ``corr_kw``: the caches kept apart)
                elif (hint := size_hint(inputs[0], inputs[1], switch="Fit")) is not None:
                    notes.append(hint)
            morph = self._solve_pair(doc, inputs, options, curves, corr_kw, quick, hooks, started)
        else:
            morph = self._solve_keys(doc, inputs, options, curves, notes, hooks)
        inputs, src, tgt, report, keys, base, times, preview = morph
        notes += [f"fold check: {note}" for note in fold_notes(base)]
        check()
        seq = base
        edits = {int(k): np.asarray(v, dtype=np.float64) for k, v in doc.get("edits", {}).items()}
        if edits:
            self._stage(generation, "edit")
            held = {int(k): base[int(k)] for k in base.info.get("keyframe_indices", [])}  # keyframes stay keys
            held.update({k: base.shape.with_vertices(v) for k, v in edits.items()})
            seq = edit(base, edits=held)  # the library keeps the factorisation of Eq. (10) per morph
            check()
        moved = None
        if doc.get("third"):
            self._stage(generation, "transfer")
            third = self._shape(doc["third"])
            if not isinstance(third, Shape):
                name = self.blobs[doc["third"]].name
                raise ParameterError(f"{name} is a saved sequence, not a drawing to transfer onto")
            tkey = ("transfer", tuple(doc["inputs"][:2]), doc["third"], frames, json.dumps(times.tolist()))

            def make_transfer() -> Any:
                shapes, _ = correspond_keys([inputs[0], inputs[1], third], points=options["points"],
                                            rotation=bool(options["rotation"]), unmatched=options["unmatched"])
                return transfer(shapes[0], shapes[1], shapes[2], len(times), times=times)

            moved = self._cached(tkey, make_transfer)
            check()
        shown = seq
        if len(doc["inputs"]) == 2 and report is not None and not report.unchanged:
            # as `isotween.morph`: an item one drawing lacks is one point in its end frame, no speck left, and
            # strokes that would pass through others are drawn off and on
            from ..pipeline import finish

            shown = dataclasses.replace(seq, frames=seq.frames.copy(), info=dict(seq.info))
            finish(shown, report, strokes=options["strokes"])
            if "strokes" in shown.info:
                notes.append(f"strokes: {shown.info['strokes']}")
        return Solved(inputs, src, tgt, report, base, shown, moved, notes, keys, preview, raw=seq)

    def _solve_saved(self, doc: dict, saved: Any, options: dict, curves: list, notes: list) -> tuple:
        """A saved sequence, resampled when the frame count or the easing asks."""
        from ..correspondence import CorrespondenceReport
        from ..sequence import Sequence

        if not isinstance(saved, Sequence):
            raise ParameterError("open two drawings (source and target), or one saved sequence")
        frames = options["frames"]
        times = bezier_times(frames, curves[0])
        same = len(saved) == frames and np.allclose(saved.times, times, rtol=0, atol=1e-12)
        base = saved if same else self._cached(("resampled", doc["inputs"][0], frames, json.dumps(curves)),
                                               lambda: saved.resample(times=times))
        src, tgt = base[0], base[-1]
        if options["method"] != "aiap" or doc.get("pairs") or doc.get("landmarks"):
            notes.append("a saved sequence: the method and correspondence hints do not apply")
        return [src, tgt], src, tgt, CorrespondenceReport(unchanged=True), [src, tgt], base, times, False

    def _solve_pair(self, doc: dict, inputs: list, options: dict, curves: list, corr_kw: dict, quick: bool,
                    hooks: tuple, started: float) -> tuple:
        """Two drawings through the library's pipeline, as `isotween.morph` runs them.

        `isotween.pipeline.prepare_pair` makes them compatible (its ``'auto'``
        policy: drawings and inputs given correspondence options or hints are
        corresponded, compatible inputs kept), `isotween.interpolate` solves
        (``fold='fallback'`` where meshes were built here, pieces with no
        partner staggered: `pipeline.unmatched_spans`), vanishing items
        collapse at their ends and crossing strokes are drawn off and on
        (`pipeline.finish`). The outline
        correspondence is kept and meshed separately (`pipeline.mesh_prepared`), so that
        the outline preview and the meshes share it and region pairs that a
        hint does not change keep their meshes.

        ``hooks``: (the solver's callback, the supersession check, the progress stage setter).
        """
        from ..interpolate import interpolate
        from ..pipeline import mesh_prepared, prepare_pair, unmatched_spans
        from .reuse import pending_vertices

        progress, check, stage = hooks
        a, b = inputs
        ids = tuple(doc["inputs"])
        names = [self.blobs[k].name for k in ids]
        kw = {k: v for k, v in corr_kw.items() if v != CORRESPOND_DEFAULTS.get(k)}
        tag = json.dumps(kw, sort_keys=True, default=list)
        preview = False
        if not (any(self._is_drawing(k) for k in ids) or kw or not _compatible(a, b)):
            which = "as-is"
            prepared = self._cached(("as-is", ids), lambda: prepare_pair(a, b, names=names))
        else:
            def correspond_outlines() -> Any:
                stage("correspondence")
                given = {k: v for k, v in kw.items() if k != "fit"}  # b is fitted already (`solve`)
                return prepare_pair(a, b, correspondence="always", names=names, **{**given, "outline": True})

            outline = self._cached(("outline", ids, tag), correspond_outlines)
            check()
            which, prepared = "outline", outline
            if not kw.get("outline") and outline.source.regions:  # filled regions to mesh
                mkey = ("meshed", ids, tag)
                if quick and not a.n_faces and not doc.get("edits") and not self._has(mkey) \
                        and not self._in_time(outline, started):
                    preview = True  # outlines now, the meshes in `refine`
                else:
                    which = "meshed"

                    def mesh() -> Any:
                        stage("meshing")
                        pending = pending_vertices(outline, self.meshes)
                        began = time.perf_counter()
                        done = mesh_prepared(outline, meshes=self.meshes)
                        self.meshes.learn(time.perf_counter() - began, pending)
                        return done

                    prepared = self._cached(mkey, mesh)
        check()
        frames = options["frames"]
        times = bezier_times(frames, curves[0])
        kwargs: dict[str, Any] = {"method": options["method"], "times": times}
        if prepared.built_meshes:  # meshes built here: as the command line does
            kwargs["fold"] = "fallback"
        spans = unmatched_spans(prepared.source, prepared.report, target=prepared.target)  # as morph staggers
        if spans is not None:
            kwargs["spans"] = spans
        bkey = ("base", which, ids, tag, frames, json.dumps(curves), options["method"])

        def solve() -> Any:
            stage("morph")
            started = time.perf_counter()
            seq = interpolate(prepared.source, prepared.target, frames, callback=progress, **kwargs)
            if which == "meshed":  # the morph of meshes (with its fold check), for `_in_time`'s estimate
                self._morph_seconds = time.perf_counter() - started
            return seq

        base = self._cached(bkey, solve)
        report = prepared.report
        if report is None:  # used as they were
            from ..correspondence import CorrespondenceReport

            report = CorrespondenceReport(unchanged=True, unmatched=options["unmatched"])
        return inputs, prepared.source, prepared.target, report, [prepared.source, prepared.target], base, times, \
            preview

    def _in_time(self, outline: Any, started: float) -> bool:
        """Whether the meshes of ``outline`` are expected within `live_budget` of the request (else: a preview)."""
        from .reuse import pending_vertices

        rate = self.meshes.rate
        if rate is None:  # nothing meshed yet in this session: no estimate
            return False
        estimate = rate * pending_vertices(outline, self.meshes) + self._morph_seconds
        return time.perf_counter() - started + estimate <= self.live_budget

    def _is_drawing(self, key: str) -> bool:
        """An SVG drawing (whose point order means nothing: always corresponded, as `prepare_pair` does)."""
        blob = self.blobs[key]  # an example's drawings are corresponded as `load_example` does: when needed
        if blob.example is not None:
            return False
        return blob.name.lower().endswith(".svg")

    def _solve_keys(self, doc: dict, inputs: list, options: dict, curves: list, notes: list, hooks: tuple) -> tuple:
        """Keyframes: made compatible together as outlines, one solve through all of them (``hooks`` as above)."""
        from ..correspondence import correspond_keys
        from ..keyframes import interpolate_keyframes

        progress, check, stage = hooks
        if doc.get("pairs") or doc.get("landmarks"):
            notes.append("region pairs and landmarks apply to two drawings; they are not used with keyframes")
        key = ("keys", tuple(doc["inputs"]), options["points"], bool(options["rotation"]), options["unmatched"])
        keys, report = self._cached(key, lambda: stage("correspondence") or correspond_keys(
            inputs, points=options["points"], rotation=bool(options["rotation"]), unmatched=options["unmatched"]))
        check()
        bkey = ("base", key, options["frames"], json.dumps(curves), options["method"])
        base = self._cached(bkey, lambda: stage("morph") or interpolate_keyframes(
            keys, frames=options["frames"], easing=eased(curves), method=options["method"], callback=progress))
        return inputs, keys[0], keys[1], report, keys, base, base.times, False


    def _check_generation(self, generation: int) -> None:
        if generation != self.generation:
            raise Superseded()

    def _stage(self, generation: int | None, stage: str, **extra: Any) -> None:
        if generation is not None and generation == self.generation:
            self.progress = {"generation": generation, "stage": stage, **extra}

    def apply(self, doc: dict, record: bool = True, quick: bool = False) -> Solved:
        """Solve ``doc`` and make it the session's document (undoable); raises and keeps the old one on failure.

        ``quick``: an outline preview when meshes would be built (see `solve`).
        """
        with self.lock:
            self.generation += 1
            generation = self.generation
        try:
            solved = self.solve(doc, generation, quick)
        finally:
            self._stage(generation, "idle")
        with self.lock:
            if generation != self.generation:
                raise Superseded()
            if record and self.doc is not None:
                self.undo_stack.append(self.doc)
                self.redo_stack.clear()
            self.doc, self.solved = doc, solved
        return solved

    def change(self, quick: bool = False, **parts: Any) -> Solved:
        """A new document: the current one with ``parts`` replaced, solved and committed."""
        if self.doc is None:
            raise ParameterError("open two drawings first")
        doc = copy.deepcopy(self.doc)
        doc.update(parts)
        return self.apply(doc, quick=quick)

    def set_hints(self, quick: bool = False, **hints: Any) -> Solved:
        """New region pairs and/or landmarks; edits are dropped (they belong to the old correspondence)."""
        unknown = sorted(set(hints) - {"pairs", "landmarks"})
        if unknown:
            raise ParameterError(f"unknown hint {unknown[0]!r}; give pairs and/or landmarks")
        return self.change(quick=quick, edits={}, **hints)

    def refine(self) -> Solved | None:
        """The meshes of an outline preview, solved and committed in its place (not a new undo step)."""
        if self.solved is None or not self.solved.preview or self.doc is None:
            return self.solved
        return self.apply(self.doc, record=False)

    def _has(self, key: Any) -> bool:
        with self.lock:
            return key in self._cache

    def set_options(self, options: dict) -> Solved:
        """New options; edits are dropped when the frame count or the correspondence changes."""
        if self.doc is None:
            raise ParameterError("open two drawings first")
        unknown = sorted(set(options) - set(DEFAULT_OPTIONS))
        if unknown:
            raise ParameterError(f"unknown option {unknown[0]!r}; use {', '.join(DEFAULT_OPTIONS)}")
        merged = {**self.doc["options"], **options}
        edits = self.doc["edits"]
        if any(merged[k] != self.doc["options"][k]
               for k in ("frames", "points", "rotation", "outline", "unmatched", "fit")):
            edits = {}
        return self.change(options=merged, edits=edits)

    def undo(self) -> Solved:
        """Back to the document before the last change."""
        return self._step(self.undo_stack, self.redo_stack, "undo")

    def redo(self) -> Solved:
        """The change undone last, again."""
        return self._step(self.redo_stack, self.undo_stack, "redo")

    def _step(self, take: list, give: list, what: str) -> Solved:
        if not take:
            raise ParameterError(f"nothing to {what}")
        previous = self.doc
        solved = self.apply(take[-1], record=False)
        take.pop()
        give.append(previous)
        return solved

    # ---------------------------------------------------------------- edits
    def deform(self, frame: int, handles: dict, anchor: int | None = None) -> np.ndarray:
        """Frame ``frame`` of the current morph deformed ARAP with the handles (nothing committed)."""
        from .deform import arap_deform

        if self.solved is None or self.doc is None:
            raise ParameterError("open two drawings first")
        if self.solved.preview:
            raise ParameterError("the morph is an outline preview while its meshes are solved; drag again in a moment")
        seq = self.solved.raw
        if isinstance(frame, bool) or not isinstance(frame, int) or not 0 <= frame < len(seq):
            raise ParameterError(f"frame {frame!r} is out of range (0..{len(seq) - 1})")
        radius = self.doc["options"].get("roi")
        diag = float(np.linalg.norm(np.ptp(seq.frames[frame], axis=0)))
        radius = None if not radius else float(radius) * diag
        key = (frame, tuple(sorted((int(k), tuple(map(float, v))) for k, v in handles.items())), anchor, radius)
        last = self._deform_cache  # a release sends the handles of the drag's last move: that answer again
        if last is not None and last[0] is seq and last[1] == key:
            return last[2].copy()
        moved = arap_deform(seq.shape, seq.frames[frame], handles, anchor=anchor, radius=radius)
        self._deform_cache = (seq, key, moved)
        return moved.copy()

    def edit_frame(self, frame: int, handles: dict, anchor: int | None = None) -> Solved:
        """The frame deformed by the handles becomes a key; the sequence re-solves around it (`isotween.edit`)."""
        shape = self.deform(frame, handles, anchor)
        assert self.doc is not None
        edits = dict(self.doc["edits"])
        edits[str(frame)] = shape.tolist()
        return self.change(edits=edits)

    # ---------------------------------------------------------------- project files
    def project(self) -> dict:
        """The whole session as one JSON-able dict (inputs, hints, edits, options)."""
        if self.doc is None:
            raise ParameterError("nothing to save: open two drawings first")
        used = list(self.doc["inputs"]) + ([self.doc["third"]] if self.doc.get("third") else [])
        return {"format": PROJECT_FORMAT, "document": self.doc,
                "inputs": {k: self.blobs[k].to_json() for k in used}}

    def open_project(self, project: Any) -> Solved:
        """Restore a session saved by `project` (undoable)."""
        if not isinstance(project, dict) or project.get("format") != PROJECT_FORMAT:
            raise FileFormatError(f"not an isotween studio project (its format must be {PROJECT_FORMAT!r})")
        doc, inputs = project.get("document"), project.get("inputs")
        if not isinstance(doc, dict) or not isinstance(inputs, dict) or not isinstance(doc.get("inputs"), list):
            raise FileFormatError("project: 'document' and 'inputs' are missing or malformed")
        blobs = {str(k): Blob.from_json(v) for k, v in inputs.items()}
        for blob in blobs.values():
            self._load_blob(blob)
        self.blobs.update(blobs)
        clean = {"inputs": [str(k) for k in doc["inputs"]], "third": doc.get("third"),
                 "options": {**DEFAULT_OPTIONS, **dict(doc.get("options") or {})},
                 "pairs": list(doc.get("pairs") or []), "landmarks": list(doc.get("landmarks") or []),
                 "edits": {str(k): v for k, v in dict(doc.get("edits") or {}).items()}}
        return self.apply(clean)
