"""Any two drawings: isotween and flubber on the same pairs of filled icons, glyphs and stroked icons.

Usage: python benchmarks/correspondence.py [--icons 500] [--glyphs 200] [--strokes 100] [--frames 21]
[--workers 2] [--timeout 120]

Every pair (the classic morphs, random pairs within Bootstrap Icons' filled set and
within Font Awesome's solid set, random pairs of DejaVu glyphs, random pairs within
Lucide's stroked line icons; benchmarks/corpus.py) goes through

- isotween with no options, as ``isotween interpolate A.svg B.svg -o out.npz`` runs it:
  ``isotween.morph(a, b, out.npz, frames=F)`` (load, correspond, interpolate with the
  fold fallback, ends of vanishing rings collapsed, write), in one worker process per
  pair, timed from reading the files to the written file, and per stage (read,
  correspondence, meshing, solve, fallback, write) by timers wrapped around the
  functions ``morph`` calls;
- flubber 0.4 (Node.js, benchmarks/flubber_run.js) on the same rings (the SVG
  subpaths as isotween reads them), each subpath a ring, with maxSegmentLength set
  to 1 % of the drawing's bounding-box diagonal.

Per pair it records: success (frames made for the whole drawing, every ring of both
ends included), flipped triangles in the generated meshes and in the in-between
frames, outline crossings in every in-between frame, over the whole drawing (any two
outline edges) and within each filled region (outer ring and holes), the exact ends
(Hausdorff distance of frame 0 and the last frame to the input drawings), specks at
the ends, whether stroked paths morphed as strokes, the method (AIAP or a fallback),
and the edge-length deviation of the outline edges (SPEC.md's definition: the largest
| |e(t)| / ((1-t)|e(0)| + t|e(1)|) - 1 |).
"""

import argparse
import json
import multiprocessing as mp
import os
import signal
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
import corpus  # noqa: E402
from _results import table, write_section  # noqa: E402

TIMEOUT = 120  # seconds per pair before it counts as a failure


# ---------------------------------------------------------------- measures
def outline_measures(seq, regions=None):
    """Crossings per in-between frame and edge-length deviation of the outline edges.

    The outline is every path of the sequence's shape (closed rings and open strokes);
    crossings are counted within each filled region (outer ring and holes: ``regions``,
    default the shape's) and within each path outside the regions, as
    `isotween.metrics.outline_crossings` with ``scope="region"`` does, leaving out paths drawn
    with opacity 0 in a frame (``visible=True``).
    """
    import isotween

    shape = seq.shape
    drawn = [k for k, (p, _) in enumerate(shape.paths) if len(p) > 1]
    paths = [shape.paths[k] for k in drawn]
    renumber = {k: i for i, k in enumerate(drawn)}
    regions = shape.regions if regions is None else regions
    regions = [[renumber[k] for k in r if k in renumber] for r in (regions or [])]
    edges = np.vstack([np.c_[p, np.roll(p, -1)] if closed else np.c_[p[:-1], p[1:]] for p, closed in paths])
    outline = isotween.Shape(shape.vertices, edges, paths=paths, regions=[r for r in regions if r] or None)
    paint = (seq.info or {}).get("paint")
    info = {}
    if paint and all(len(key) == len(shape.paths) for key in paint["keys"]):  # the drawn paths' paint
        info["paint"] = {**paint, "keys": [[key[k] for k in drawn] for key in paint["keys"]],
                         "regions": outline.regions}
    oseq = isotween.Sequence(frames=seq.frames, shape=outline, times=seq.times, info=info)
    crossings = isotween.metrics.outline_crossings(oseq, scope="region", visible=True)[1:-1]
    return [int(c) for c in crossings], isotween.metrics.edge_length_deviation(oseq)


# ---------------------------------------------------------------- ends
#: straight pieces per curve of the reference drawings (a quarter circle: within 0.008 % of its radius)
REFERENCE_SEGMENTS = 64


def reference(path):
    """The drawing the ends are measured against: its curves nearly exact, not isotween's sampling of them."""
    import isotween

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return isotween.io.load(path, curve_segments=REFERENCE_SEGMENTS)


def _dense(polylines, step):
    """Points along polylines ((k, 2) arrays, closed ones with their first point repeated), ``step`` apart.

    Returns the points (m, 2) and a (m,) mask of those on a seam: a stretch of the outline
    that another stretch runs back over (points within ``step`` of each other, heading
    opposite ways: samples are at most a step apart, so a vertex where seams meet counts too).
    A seam has no width, so a fill draws nothing there: a slit that opened a hole into a notch,
    closed again at its end (`isotween.correspondence.notches.close_slits`), runs from the outer
    ring to the hole and back; the parts of a region cut where the other drawing parts it
    (`isotween.correspondence.splits`) meet along their cuts. (The tip of a drawing's own cusp
    is one too.)
    """
    out, heading = [], []
    for p in polylines:
        if len(p) == 1:
            out.append(p)
            heading.append(np.zeros((1, 2)))
            continue
        seg = np.diff(p, axis=0)
        length = np.hypot(seg[:, 0], seg[:, 1])
        n = np.maximum(1, np.ceil(length / step).astype(int))
        s = np.concatenate([np.arange(m) / m for m in n])
        out.append(np.repeat(p[:-1], n, axis=0) + s[:, None] * np.repeat(seg, n, axis=0))
        heading.append(np.repeat(seg / np.maximum(length, 1e-300)[:, None], n, axis=0))
    points, heading = np.vstack(out), np.vstack(heading)
    from scipy.spatial import cKDTree

    near = cKDTree(points).query_pairs(step, output_type="ndarray")
    back = near[np.einsum("ij,ij->i", heading[near[:, 0]], heading[near[:, 1]]) < -0.9]
    seam = np.zeros(len(points), bool)
    seam[back.ravel()] = True
    return points, seam


def _covered(z, paths, keep, regions, fills, points, tol):
    """(m,) bool: which of ``points`` (m, 2), on a frame's outline, lie more than ``tol`` inside a visible region.

    Only regions sharing their fill with another count: a point of one's outline lies outside itself.
    """
    import shapely

    inside = np.zeros(len(points), np.int64)
    if not regions or fills is None:
        return inside > 0
    by_fill = {}
    for rs in regions:
        if keep is None or keep[rs[0]]:
            ring = z[paths[rs[0]][0]]
            poly = shapely.Polygon(ring, [z[paths[h][0]] for h in rs[1:]]).buffer(-tol)
            by_fill.setdefault(repr(fills[rs[0]]), []).append(poly)
    for polys in by_fill.values():
        if len(polys) > 1:
            for poly in polys:
                inside += shapely.contains_xy(poly, points[:, 0], points[:, 1])
    return inside > 0


def _polylines(vertices, paths, keep=None):
    """Visible paths as point arrays (closed ones closed); rings collapsed to a point and hidden paths left out."""
    out = []
    for k, (p, closed) in enumerate(paths):
        if keep is not None and not keep[k]:
            continue
        q = vertices[np.r_[p, p[:1]] if closed else p]
        if len(q) > 1 and np.ptp(q, axis=0).max() > 0:
            out.append(q)
    return out


def _area(ring):
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _centroid(ring):
    """The centroid of the area a ring encloses (not of its vertices, which bunch where curves are)."""
    x, y = ring[:, 0], ring[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    a = 3 * cross.sum()
    return np.array([((x + xn) * cross).sum() / a, ((y + yn) * cross).sum() / a]) if a else ring.mean(axis=0)


def end_measures(seq, drawings):
    """Hausdorff distance (% of the input's diagonal) and specks at frame 0 and the last frame.

    The input outline is every path of the drawing with its curves nearly exact (`reference`); the frame's
    is every path of the sequence that is visible at that end (opacity above zero; a ring
    collapsed to a point draws nothing). Both are sampled every 0.02 % of the diagonal. A speck
    is a closed ring of the frame with an area above zero and below 0.5 % of the input's
    bounding-box area, where the input has no closed ring of an area within a factor 2 whose
    centroid lies within 1 % of the diagonal.
    """
    keys = (seq.info.get("paint") or {}).get("keys")
    hd, specks = [], 0
    for frame, drawing in zip((0, -1), drawings, strict=True):
        keep = fills = None
        key = keys[frame] if keys else None  # the paint of the first (last) key time
        if key and len(key) == len(seq.shape.paths):
            keep = [k.get("opacity", 1.0) > 0 for k in key]
            fills = [k.get("fill") for k in key]
        d, n = end_error(seq.frames[frame], seq.shape.paths, drawing, keep, seq.shape.regions, fills)
        hd.append(d)
        specks += n
    return hd, specks


def end_error(z, paths, drawing, keep=None, regions=None, fills=None):
    """(Hausdorff distance in % of the diagonal, specks) of one end frame against its input drawing.

    Frame outline that lies inside another region of the same fill (``regions``, ``fills`` per path) draws
    nothing either: an X taken as its two crossed bars (`isotween.correspondence.splits`), each running
    through the other where they cross.
    """
    from scipy.spatial import cKDTree

    diag = drawing.bbox_diagonal()
    mine = _polylines(z, paths, keep)
    theirs = _polylines(drawing.vertices, drawing.paths)
    if not mine or not theirs:
        return float("inf"), 0
    (a, seam), (b, _) = _dense(mine, 2e-4 * diag), _dense(theirs, 2e-4 * diag)
    # the frame's seams (closed slits) draw nothing, so they need not lie on the input's outline;
    # every point of the input's outline, seams included, must lie on the frame's
    seam |= _covered(z, paths, keep, regions, fills, a, 2e-4 * diag)
    drawn = a[~seam] if (~seam).any() else a
    hd = 100 * float(max(cKDTree(b).query(drawn)[0].max(), cKDTree(a).query(b)[0].max())) / diag
    box = np.ptp(drawing.vertices, axis=0).prod()
    given = [(abs(_area(drawing.vertices[q])), _centroid(drawing.vertices[q]))
             for q, closed in drawing.paths if closed and len(q) > 2]
    specks = 0
    for k, (q, closed) in enumerate(paths):
        if not closed or (keep is not None and not keep[k]) or len(q) < 3:
            continue
        ring = z[q]
        area = abs(_area(ring))
        if not (area > 1e-12 * box and area < 5e-3 * box):
            continue
        c = _centroid(ring)
        if not any(0.5 * area <= a_in <= 2 * area and np.hypot(*(c - c_in)) <= 0.01 * diag for a_in, c_in in given):
            specks += 1
    return hd, specks


def stroke_measures(seq, drawings):
    """Whether the stroked paths of the inputs morphed as strokes, and how many paths fade in or out.

    As strokes: every path of the result that is stroked and not filled (at either end) is a
    polyline or ring with no triangle on its vertices, and it keeps a stroke of positive width
    at both ends. A path whose opacity is 0 at one end grows or shrinks there (fades).
    """
    stroked_in = sum(1 for d in drawings for p in (d.paint or []) if p.fill is None and p.stroke is not None)
    keys = (seq.info.get("paint") or {}).get("keys")
    if not stroked_in:
        return None
    if not keys or len(keys[0]) != len(seq.shape.paths):
        return {"strokes": False, "stroked_paths": 0, "fades": 0, "why": "no paint per path"}
    faced = np.zeros(seq.shape.n_vertices, bool)
    if seq.shape.n_faces:
        faced[np.asarray(seq.shape.faces).ravel()] = True
    ok, n, fades, why = True, 0, 0, ""
    for k, (p, _closed) in enumerate(seq.shape.paths):
        ends = [keys[0][k], keys[-1][k]]
        if not any(e["fill"] is None and e["stroke"] is not None for e in ends):
            continue
        n += 1
        if faced[p].any():
            ok, why = False, "faces on a stroked path"
        if any(e["stroke"] is None or not e["stroke_width"] > 0 for e in ends):
            ok, why = False, "stroke lost at an end"
        if min(e["opacity"] for e in ends) == 0 < max(e["opacity"] for e in ends):
            fades += 1
    return {"strokes": ok and n > 0, "stroked_paths": n, "fades": fades, "why": why, "on_view": on_view(seq)}


def on_view(seq):
    """The least stroke length on view in an in-between (length times opacity, all paths), over the smaller end's."""
    from isotween.paint import sequence_paint

    _, paints = sequence_paint(seq)
    z = seq.z
    ink = np.zeros(len(z))
    for k, (p, closed) in enumerate(seq.shape.paths):
        w = z[:, np.r_[p, p[:1]]] if closed else z[:, p]
        ink += np.abs(np.diff(w, axis=1)).sum(axis=1) * np.array([f[k].opacity for f in paints])
    return float(ink[1:-1].min() / max(min(ink[0], ink[-1]), 1e-300))


# ---------------------------------------------------------------- isotween
STAGES = ("read", "correspondence", "meshing", "solve", "fallback", "write")
_CLOCK = {}
_PREPARED = []


def _timed(fn, key):
    """``fn`` timed into ``_CLOCK[key]``, a call within a call of the same key counted once (in the outer one).

    The fold check runs the fold check of another timing inside itself.
    """
    depth = [0]

    def wrapper(*args, **kwargs):
        t0 = time.perf_counter()
        depth[0] += 1
        try:
            return fn(*args, **kwargs)
        finally:
            depth[0] -= 1
            if not depth[0]:
                _CLOCK[key] = _CLOCK.get(key, 0.0) + time.perf_counter() - t0

    wrapper.__wrapped__ = fn
    return wrapper


def _instrument():
    """Wrap the stages that `isotween.morph` calls with timers (once per worker process).

    read: `isotween.io.load`; correspondence: `isotween.correspond` less meshing
    (``correspond._solids``); solve: `interpolate` less the fold fallback
    (``interpolate._fallback``, counted as fallback only where it replaced or flagged the
    result; its fold check alone stays in solve); write: `isotween.write_output` (.npz).
    """
    import isotween
    import isotween.correspondence
    import isotween.io
    import isotween.outputs

    if getattr(isotween.io.load, "__wrapped__", None):
        return
    corr = sys.modules["isotween.correspondence.correspond"]
    interp = sys.modules["isotween.interpolate"]
    isotween.io.load = _timed(isotween.io.load, "read")
    isotween.correspondence.correspond = _timed(isotween.correspondence.correspond, "correspond")
    corr._solids = _timed(corr._solids, "meshing")
    interp.interpolate = _timed(interp.interpolate, "interpolate")
    interp._fallback = _timed(interp._fallback, "fallback")
    pipeline = sys.modules["isotween.pipeline"]
    prepare = pipeline.prepare_pair

    def keep(*args, **kwargs):  # the compatible shapes, for the mesh check
        _PREPARED[:] = [prepare(*args, **kwargs)]
        return _PREPARED[0]

    pipeline.prepare_pair = keep
    isotween.outputs.write_output = _timed(isotween.outputs.write_output, "write")


def _stages(seq):
    c = dict(_CLOCK)
    fallback = c.get("fallback", 0.0) if seq.info.get("fallback") else 0.0
    return {
        "read": c.get("read", 0.0),
        "correspondence": c.get("correspond", 0.0) - c.get("meshing", 0.0),
        "meshing": c.get("meshing", 0.0),
        "solve": c.get("interpolate", 0.0) - fallback,
        "fallback": fallback,
        "write": c.get("write", 0.0),
    }


def frame_flips(seq, source):
    """Triangles of every in-between frame whose orientation differs from the generated source mesh's.

    The sequence's own triangles (where AIAP folded a few faces, the fold fallback may have
    flipped edges of the generated mesh: `isotween.foldfree.unfold`), oriented as at the
    generated source mesh's positions, not as in frame 0 of the sequence: a ring that
    vanishes at the start is collapsed to a point in frame 0 (`pipeline.collapse_vanishing`),
    which would flip its triangles there. A triangle of zero area in between counts as flipped.
    """
    if not source.n_faces:
        return [0] * (len(seq.frames) - 2)
    from isotween.geometry import triangle_areas

    f = np.asarray(source.faces if seq.shape.faces is None else seq.shape.faces)
    ref = np.sign(triangle_areas(source.vertices, f))
    area = triangle_areas(seq.frames[1:-1], f)
    return [int(c) for c in np.count_nonzero((np.sign(area) * ref <= 0) & (ref != 0), axis=1)]


def _warm(job):
    """Load isotween and numba's kernels in a new worker by one untimed morph (of the first pair)."""
    import isotween
    from isotween.batch import single_threaded
    from isotween.optimisation import backend

    single_threaded()  # as `isotween batch` runs its workers: the workers share the cores
    backend.long_lived()  # as a batch worker or the studio: numba's kernels for every pair

    _, a_file, b_file, n_frames = job
    with warnings.catch_warnings(), tempfile.TemporaryDirectory() as tmp:
        warnings.simplefilter("ignore")
        isotween.morph(a_file, b_file, Path(tmp) / "warm.npz", frames=n_frames)


def _alarm(signum, frame):
    raise TimeoutError(f"no result within {TIMEOUT} s")


def run_isotween(job):
    """One pair through ``isotween.morph`` with no options but the frame count (in a worker process)."""
    import isotween
    from isotween.batch import single_threaded

    _instrument()
    single_threaded()
    k, a_file, b_file, n_frames = job
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(TIMEOUT)
    out = {"id": k}
    _CLOCK.clear()
    try:
        with warnings.catch_warnings(), tempfile.TemporaryDirectory() as tmp:
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            seq = isotween.morph(a_file, b_file, Path(tmp) / "out.npz", frames=n_frames)
            out["seconds"] = time.perf_counter() - t0
            out["stages"] = _stages(seq)
        signal.alarm(0)
        drawings = (reference(a_file), reference(b_file))
        shape = seq.shape
        out["ok"] = True
        out["report"] = seq.info.get("correspondence", "")
        out["fallback"] = seq.info.get("fallback", "")
        out["method"] = seq.method
        out["stopped"] = seq.info.get("stopped")  # AIAP's iterations stopped before the first that folds
        out["vertices"] = shape.n_vertices
        out["faces"] = shape.n_faces
        # meshes: every face of the source with one orientation, the target's the same
        src, tgt = _PREPARED[0].source, _PREPARED[0].target
        if src.n_faces:
            s = np.sign(src.face_areas())
            t = np.sign(tgt.face_areas())
            major = 1.0 if np.count_nonzero(s > 0) >= np.count_nonzero(s < 0) else -1.0
            out["mesh_flips"] = int(np.count_nonzero(s != major) + np.count_nonzero(t != major))
        else:
            out["mesh_flips"] = 0
        out["frame_flips"] = frame_flips(seq, src)
        crossings = isotween.metrics.outline_crossings(seq, visible=True)
        out["all_crossings"] = [int(c) for c in crossings[1:-1]]
        out["end_crossings"] = [int(crossings[0]), int(crossings[-1])]  # the inputs' own, e.g. an 'x' stroke
        out["new_crossings"] = [int(c) for c in isotween.metrics.new_crossings(seq)[1:-1]]  # less those
        out["crossings"], out["edge_deviation"] = outline_measures(seq)
        out["ends"], out["specks"] = end_measures(seq, drawings)
        out["stroke"] = stroke_measures(seq, drawings)
        out["untangled"] = seq.info.get("strokes", "")  # strokes drawn off and on instead of crossing
    except Exception as exc:  # noqa: BLE001 - every failure is a measured outcome
        out["ok"] = False
        out["error"] = f"{type(exc).__name__}: {exc}"
    finally:
        signal.alarm(0)
    return out


# ---------------------------------------------------------------- flubber
def flubber_inputs(jobs):
    """Rings of both drawings of every pair (as isotween reads them) for flubber."""
    import isotween

    items, groups = [], {}
    for k, a_file, b_file, _ in jobs:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                a, b = isotween.io.load(a_file), isotween.io.load(b_file)
        except Exception:  # noqa: BLE001 - a drawing isotween cannot read is skipped for both
            continue
        ra = [a.vertices[p].tolist() for p, _ in a.paths]
        rb = [b.vertices[p].tolist() for p, _ in b.paths]
        diag = max(a.bbox_diagonal(), b.bbox_diagonal())
        items.append({"id": k, "a": ra, "b": rb, "seg": 0.01 * diag})
        groups[k] = (a.regions, (reference(a_file), reference(b_file)))
    return items, groups


def run_flubber(jobs, n_frames):
    """The outcome of flubber for every pair (one Node.js process)."""
    items, groups = flubber_inputs(jobs)
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
        json.dump(items, fh)
    try:
        proc = subprocess.run(["node", str(HERE / "flubber_run.js"), fh.name, str(n_frames)],
                              capture_output=True, text=True, check=True)
    finally:
        os.unlink(fh.name)

    times = np.linspace(0, 1, n_frames)
    out = {}
    for line in proc.stdout.splitlines():
        r = json.loads(line)
        res = {"id": r["id"], "ok": r["ok"], "mode": r["mode"], "seconds": r["seconds"]}
        if not r["ok"]:
            res["error"] = r["error"]
        else:
            try:
                _flubber_measures(res, r, groups, times, n_frames)
            except Exception as exc:  # noqa: BLE001 - a result that cannot be measured counts as failed
                res.update(ok=False, error=f"measures failed: {type(exc).__name__}: {exc}")
        out[r["id"]] = res
    return out, groups


def _flubber_measures(res, r, groups, times, n_frames):
    """Measures of one flubber result, into ``res``."""
    import isotween

    frames = np.array([np.vstack(f) for f in r["frames"]], dtype=float)
    shape = isotween.Shape.from_paths([np.asarray(ring, float) for ring in r["frames"][0]])
    seq = isotween.Sequence(frames=frames, shape=shape, times=times)
    # interpolateAll morphs ring k of the source into ring k of the target: ring k keeps the
    # source's region; separate / combine make pieces, each its own region
    regions = groups[r["id"]][0] if r["mode"] == "interpolateAll" else []
    res["crossings"], res["edge_deviation"] = outline_measures(seq, regions)
    res["all_crossings"] = [int(c) for c in isotween.metrics.outline_crossings(seq)[1:-1]]
    res["frame_flips"] = [0] * (n_frames - 2)
    res["ends"], res["specks"] = end_measures(seq, groups[r["id"]][1])


# ---------------------------------------------------------------- GSAP
def _bezier(p, s):
    """Points of one cubic Bezier (4 control points) at parameters ``s``."""
    s = s[:, None]
    return ((1 - s) ** 3 * p[0] + 3 * (1 - s) ** 2 * s * p[1] + 3 * (1 - s) * s ** 2 * p[2] + s ** 3 * p[3])


def _gsap_frame(frame, diag):
    """([points], [closed]) of one GSAP frame, every cubic sampled at 8 points."""
    rings, closed = [], []
    for seg in frame:
        pts = np.asarray(seg["points"], float).reshape(-1, 2)
        n = (len(pts) - 1) // 3
        if n < 1:
            continue
        curve = np.vstack([_bezier(pts[3 * i:3 * i + 4], np.arange(8) / 8) for i in range(n)] + [pts[-1:]])
        c = bool(seg["closed"] or np.hypot(*(pts[-1] - pts[0])) < 1e-6 * diag)
        rings.append(curve[:-1] if c else curve)
        closed.append(c)
    return rings, closed


def run_gsap(jobs, n_frames, groups):
    """The outcome of GSAP's MorphSVGPlugin for every pair (one Node.js process), or {} without GSAP."""
    if not (HERE / ".corpus" / "node_modules" / "gsap").exists():
        return {}
    items = []
    for k in groups:
        a, b = groups[k][1]
        d = [" ".join("M " + " L ".join(f"{x:.6g} {y:.6g}" for x, y in s.vertices[p]) + (" Z" if c else "")
                      for p, c in s.paths) for s in (a, b)]
        items.append({"id": k, "a": d[0], "b": d[1]})
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as fh:
        json.dump(items, fh)
    try:
        proc = subprocess.run(["node", str(HERE / "gsap_drawings.js"), fh.name, str(n_frames)],
                              capture_output=True, text=True, check=True)
    finally:
        os.unlink(fh.name)
    times = np.linspace(0, 1, n_frames)
    out = {}
    for line in proc.stdout.splitlines():
        r = json.loads(line)
        res = {"id": r["id"], "ok": r["ok"], "seconds": r["seconds"]}
        if not r["ok"]:
            res["error"] = r["error"]
            out[r["id"]] = res
            continue
        try:
            _gsap_measures(res, r, groups, times, n_frames)
        except Exception as exc:  # noqa: BLE001 - a result that cannot be measured counts as failed
            res.update(ok=False, error=f"measures failed: {type(exc).__name__}: {exc}")
        out[r["id"]] = res
    return out


def _gsap_measures(res, r, groups, times, n_frames):
    """Measures of one GSAP result, into ``res``."""
    import isotween

    drawings = groups[r["id"]][1]
    diag = max(d.bbox_diagonal() for d in drawings)
    frames = [_gsap_frame(f, diag) for f in r["frames"]]
    # GSAP writes the given path data at progress 0 and 1, and its own normalised subpaths in between
    inner = frames[1:-1]
    sizes = [[len(q) for q in f[0]] for f in inner]
    if any(sz != sizes[0] for sz in sizes) or any(f[1] != inner[0][1] for f in inner):
        res.update(ok=False, error="the in-between frames do not share one structure")
        return
    shape = isotween.Shape.from_paths(inner[0][0], inner[0][1])
    z = np.array([np.vstack(f[0]) for f in inner])
    seq = isotween.Sequence(frames=np.concatenate([z[:1], z, z[-1:]]), shape=shape, times=times)
    # GSAP pairs subpaths by its own rules: every subpath its own region
    res["crossings"], _ = outline_measures(seq, [])
    res["edge_deviation"] = float("nan")  # the ends are other polylines than the in-betweens
    res["all_crossings"] = [int(c) for c in isotween.metrics.outline_crossings(seq)[1:-1]]
    res["frame_flips"] = [0] * (n_frames - 2)
    res["ends"], res["specks"] = [], 0
    for f, drawing in zip((frames[0], frames[-1]), drawings, strict=True):
        end = isotween.Shape.from_paths(f[0], f[1])
        d, n = end_error(end.vertices, end.paths, drawing)
        res["ends"].append(d)
        res["specks"] += n


# ---------------------------------------------------------------- summary
END_TARGET = 0.1  # % of the diagonal


def _clean(r):
    return not any(r["all_crossings"]) and not any(r["frame_flips"])


def _exact(r):
    return max(r["ends"]) <= END_TARGET


def _pct(a, b):
    return f"{100 * a / b:.1f} %" if b else "-"


def summarise(results, ids):
    """One table row: pairs, morphed, clean, exact ends, specks, per-region crossings, deviation, times."""
    rs = [results.get(k, {"ok": False}) for k in ids]
    ok = [r for r in rs if r["ok"]]
    clean = [r for r in ok if _clean(r)]
    region_clean = [r for r in ok if not any(r["crossings"]) and not any(r["frame_flips"])]
    exact = [r for r in ok if _exact(r)]
    speck = [r for r in ok if r["specks"]]
    ends = [max(r["ends"]) for r in ok]
    dev = [r["edge_deviation"] for r in ok]
    secs = [r["seconds"] for r in ok]
    n = len(rs)
    return [
        n, f"{len(ok)} ({_pct(len(ok), n)})", f"{len(clean)} ({_pct(len(clean), n)})",
        f"{len(region_clean)} ({_pct(len(region_clean), n)})",
        f"{len(exact)} ({_pct(len(exact), n)})", f"{np.median(ends):.3f} / {np.max(ends):.2f}" if ends else "-",
        f"{len(speck)} ({sum(r['specks'] for r in speck)})",
        f"{np.nanmedian(dev):.3f}" + (f" ({np.isnan(dev).sum()} undef.)" if np.isnan(dev).any() else "")
        if dev and not np.isnan(dev).all() else "-",
        f"{1e3 * np.median(secs):.0f} / {1e3 * np.percentile(secs, 95):.0f} / {1e3 * np.max(secs):.0f}"
        if secs else "-",
    ]


def _name(pairs, k):
    kind, a, b = pairs[k]
    return f"{Path(a).stem} -> {Path(b).stem} ({kind})"


def main():
    global TIMEOUT
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--icons", type=int, default=500)
    parser.add_argument("--glyphs", type=int, default=200)
    parser.add_argument("--strokes", type=int, default=100, help="random pairs of Lucide's stroked icons")
    parser.add_argument("--frames", type=int, default=21)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--timeout", type=int, default=TIMEOUT, help="seconds per pair before it counts as failed")
    parser.add_argument("--budget", type=float, default=None,
                        help="wall seconds for isotween's pairs: pairs not finished by then are left out and counted")
    parser.add_argument("--no-write", action="store_true", help="print only; leave RESULTS.md alone")
    args = parser.parse_args()
    TIMEOUT = args.timeout

    pairs = corpus.pairs(args.icons, args.glyphs, n_strokes=args.strokes)
    jobs = [(k, str(a), str(b), args.frames) for k, (_, a, b) in enumerate(pairs)]
    order = np.random.default_rng(7).permutation(len(jobs))  # a time budget then cuts a random subset
    t0 = time.perf_counter()
    ours = {}
    log = HERE / ".corpus" / "correspondence-progress.jsonl"  # one line per finished pair, as it finishes
    with mp.get_context("fork").Pool(args.workers, initializer=_warm, initargs=(jobs[0],),
                                                  maxtasksperchild=50) as pool, log.open("w") as fh:
        for r in pool.imap_unordered(run_isotween, [jobs[i] for i in order], chunksize=1):
            ours[r["id"]] = r
            fh.write(json.dumps(r) + "\n")
            fh.flush()
            if args.budget and time.perf_counter() - t0 > args.budget:
                pool.terminate()
                break
    wall = time.perf_counter() - t0
    cut = len(jobs) - len(ours)
    jobs = [j for j in jobs if j[0] in ours]
    theirs, groups = run_flubber(jobs, args.frames)
    gsap = run_gsap(jobs, args.frames, groups)
    gsap_tool = f"GSAP {corpus.PACKAGES['gsap']}"

    header = ["tool", "set", "pairs", "morphed", "clean: no crossing in the drawing, no flip",
              "no crossing within a region, no flip", f"exact ends (<= {END_TARGET} %)",
              "end error median / max (% diag.)", "pairs with specks (specks)", "median edge-length dev.",
              "time median / p95 / max (ms)"]
    rows = []
    kinds = {"all": sorted(ours)}
    for kind in ("classic", "icon", "glyph", "stroke"):
        kinds[kind] = [k for k in sorted(ours) if pairs[k][0] == kind]
    for kind, ids in kinds.items():
        if not ids:
            continue
        rows.append(["isotween", kind, *summarise(ours, ids)])
        rows.append(["flubber 0.4", kind, *summarise(theirs, ids)])
        if gsap:
            rows.append([gsap_tool, kind, *summarise(gsap, ids)])
    good = [r for r in ours.values() if r["ok"]]
    mesh_flips = sum(r.get("mesh_flips", 0) for r in good)
    meshed = [r for r in good if r.get("faces")]
    aiap = [r for r in meshed if r["method"] == "aiap"]
    repaired = [r for r in aiap if "repaired" in r["fallback"]]
    kept_folding = [r for r in aiap if r["fallback"] and r not in repaired]
    plain = [r for r in aiap if not r["fallback"]]
    stopped = [r for r in plain if r.get("stopped")]
    methods = {}
    for r in meshed:
        method = "aiap, folds repaired" if r in repaired else r["method"]
        methods[method] = methods.get(method, 0) + 1

    # per-stage times, medians over the pairs that morphed
    stage_rows = []
    for kind, ids in kinds.items():
        rs = [ours[k] for k in ids if ours.get(k, {}).get("ok")]
        if not rs:
            continue
        med = [f"{1e3 * np.median([r['stages'][st] for r in rs]):.1f}" for st in STAGES]
        tot = [r["seconds"] for r in rs]
        stage_rows.append([kind, len(rs), *med, f"{1e3 * np.median(tot):.0f}", f"{1e3 * np.percentile(tot, 95):.0f}",
                           sum(1 for x in tot if x > 2.0)])
    fell = [r for r in good if r["stages"]["fallback"] > 0]
    fb_med = f"{1e3 * np.median([r['stages']['fallback'] for r in fell]):.0f} ms" if fell else "-"

    secs = np.array([r["seconds"] for r in good])
    both = [r for r in good if theirs.get(r["id"], {}).get("ok")]
    ratio = (f"{np.median([r['seconds'] for r in both]) / np.median([theirs[r['id']]['seconds'] for r in both]):.0f} "
             f"times flubber's median time on the {len(both)} pairs both morph" if both else "-")
    both = [r for r in good if gsap.get(r["id"], {}).get("ok")]
    if both:
        g = np.median([r["seconds"] for r in both]) / np.median([gsap[r["id"]]["seconds"] for r in both])
        ratio += f" and {g:.0f} times GSAP's on the {len(both)} pairs both morph"

    strokes = [ours[k] for k in kinds["stroke"] if ours.get(k, {}).get("ok")]
    as_strokes = [r for r in strokes if r["stroke"] and r["stroke"]["strokes"]]
    fading = [r for r in strokes if r["stroke"] and r["stroke"]["fades"]]
    not_strokes = {}
    for r in strokes:
        if not (r["stroke"] and r["stroke"]["strokes"]):
            why = (r["stroke"] or {}).get("why") or "no stroked path"
            not_strokes[why] = not_strokes.get(why, 0) + 1

    failures = {}
    for k in sorted(ours):
        r = ours[k]
        if not r["ok"]:
            failures.setdefault(r["error"].split(":")[0], []).append(k)
    flub_fail = {}
    for r in theirs.values():
        if not r["ok"]:
            key = "several rings into a different number" if r["error"].startswith("no flubber call") else r["error"]
            flub_fail[key] = flub_fail.get(key, 0) + 1

    n_meshed = len(meshed)
    n_clean = sum(1 for r in good if _clean(r))
    n_exact = sum(1 for r in good if _exact(r))
    n_speck = sum(1 for r in good if r["specks"])
    crossed_ends = [r for r in good if not _clean(r) and any(r["end_crossings"])]
    new_clean = [r for r in good if not any(r["new_crossings"]) and not any(r["frame_flips"])]
    n_new_clean = len(new_clean)
    n_new_stroke = sum(1 for r in new_clean if pairs[r["id"]][0] == "stroke")
    body = [
        f"{len(ours)} pairs ({len(kinds['classic'])} classic morphs, {len(kinds['icon'])} random icon pairs, "
        f"{len(kinds['glyph'])} random glyph pairs, {len(kinds['stroke'])} random pairs of Lucide's stroked icons "
        f"(lucide-static {corpus.PACKAGES['lucide-static']}); seed 20261123), {args.frames} frames each, no options: "
        f"`isotween.morph(a, b, out.npz, frames={args.frames})` as the command line runs it, one worker process per "
        f"pair ({args.workers} workers, {wall:.0f} s wall in all, {TIMEOUT} s bound per pair). Times are per pair in "
        "process, from reading both files to the written .npz (imports and numba kernels are loaded in every new "
        "worker by an untimed morph of the first pair; numba and BLAS on one thread per worker, as `isotween batch` "
        "runs them)" + (f"; {cut} more pairs of the draw were not reached within the {args.budget:.0f} s budget "
                       "(pairs run in a random order, so those left out are a random subset)" if cut else "")
        + ". flubber: its own call per "
        "ring count on the same rings, each subpath a ring (open strokes are closed), time of its interpolators only. "
        "GSAP's MorphSVGPlugin (headless, its defaults, one Node.js process for all pairs; "
        "benchmarks/gsap_drawings.js) "
        "on the path data of the same subpaths, time of the tween and its frames; its cubic Beziers are sampled at 8 "
        "points each for the measures. "
        "**Clean**: no two outline edges of the whole drawing cross (different regions included; "
        "`metrics.outline_crossings` with its default scope and ``visible=True``: a path drawn with opacity 0 in a "
        "frame, a piece with no partner before or after its span, is left out there) and no triangle flips, in "
        "any in-between frame; the "
        "older per-region measure counts only crossings within one region. **Exact ends**: the symmetric Hausdorff "
        "distance between frame 0 and the source drawing's outline (every path, curves in 64 pieces each), and "
        "between the last frame and the target's, both sampled every 0.02 % of the diagonal, at most "
        f"{END_TARGET} % of that drawing's diagonal; paths invisible at an end (opacity 0, or a ring collapsed to a "
        "point) are left out, and so are seams, stretches of an outline that another stretch runs back over "
        "(no width, so a fill draws nothing there: a slit that opened a hole into a notch, closed again at its "
        "end, or the cuts between the parts of a region that the other drawing shows in pieces; regions with a "
        "stroke keep their holes and stay whole), and outline inside another region of the same fill, which "
        "draws over it (an X taken as its two crossed bars, each running through the other). **Speck**: a closed "
        "ring of an end frame with an area "
        "above 0 and below 0.5 % of the "
        "drawing's bounding-box area where the input has no ring of about that area and place.",
        "",
        table(header, rows),
        "",
        f"Against the targets: clean {n_clean} of {len(ours)} ({_pct(n_clean, len(ours))}; issue 20: 97 %); "
        f"exact ends {n_exact} ({_pct(n_exact, len(ours))}; issue 20: every pair), {n_speck} pairs with specks "
        f"(issue 20: none); AIAP without fallback on {len(aiap) - len(kept_folding) - len(repaired)} of {n_meshed} "
        f"meshed pairs ({_pct(len(aiap) - len(kept_folding) - len(repaired), n_meshed)}; issue 20: 90 %), and with "
        f"its folding frames repaired on {len(repaired)} more ({_pct(len(repaired), n_meshed)}); morphed "
        f"{_pct(len(good), len(ours))} (issue 11: 99 %); {mesh_flips} flipped triangles in all generated meshes "
        f"(issue 11: 0); time per pair {1e3 * np.median(secs):.0f} ms median, {1e3 * np.percentile(secs, 95):.0f} ms "
        f"p95, {int(np.count_nonzero(secs > 2))} pairs over 2 s (issue 21: 50 ms, 300 ms, none); isotween takes "
        f"{ratio}.",
        "",
        f"Of the {len(good) - n_clean} pairs that are not clean, {len(crossed_ends)} have crossing outline edges at "
        f"an end already ({sum(1 for r in crossed_ends if pairs[r['id']][0] == 'stroke')} of them stroked pairs: "
        "strokes that cross in the drawing itself, as in an 'x'); the measure counts those in every in-between. "
        f"Leaving out crossings between two paths that cross in an input drawing already "
        f"(`metrics.new_crossings`): {n_new_clean} of {len(ours)} pairs clean "
        f"({_pct(n_new_clean, len(ours))}; of the stroked pairs {n_new_stroke} of {len(kinds['stroke'])}).",
        "",
        f"Methods of the {n_meshed} meshed pairs: " + ", ".join(f"{m} {c}" for m, c in sorted(methods.items()))
        + f" ('aiap' kept with a fold where no fold-free morph could be built: {len(kept_folding)}). "
        f"Of the {len(plain)} AIAP results with no fallback, {len(stopped)} stopped before the first iteration "
        "that folds a triangle or lets outlines cross (`interpolate`'s fold check; "
        + (f"at iteration {np.median([r['stopped']['iteration'] for r in stopped]):.0f} of "
           f"{np.median([r['stopped']['of'] for r in stopped]):.0f} begun, medians; "
           f"{sum(1 for r in stopped if r['stopped']['iteration'] == 1)} at iteration 1, the assembled "
           "edge-vector initialisation of Eqs. (12)-(13) and (10)" if stopped else "-")
        + f"), {len(plain) - len(stopped)} ran until Eq. (11) holds.",
        "",
        "Per-stage time, medians over the pairs that morphed (ms): read = `io.load` of both files; correspondence = "
        "`correspond` less meshing (`correspond._solids`); solve = `interpolate` less the fallback (the fold check "
        "stays in solve); fallback = `interpolate._fallback` where it repaired or replaced the result; "
        "write = the .npz. "
        f"The fallback ran on {len(fell)} pairs, {fb_med} median there.",
        "",
        table(["set", "pairs", *STAGES, "total median", "total p95", "pairs over 2 s"], stage_rows),
    ]
    if kinds["stroke"]:
        body += ["", f"Strokes: {len(as_strokes)} of {len(kinds['stroke'])} Lucide pairs morphed as strokes (every "
                 "stroked path a polyline or ring with no triangles, its stroke kept at both ends; issue 20: every "
                 f"pair); {len(fading)} of them have a path that grows from or shrinks to nothing with opacity 0 at "
                 "its end (a piece with no partner)."
                 + ("" if not not_strokes else " Not as strokes: " + ", ".join(f"{v} x {k}" for k, v in
                                                                                 not_strokes.items()) + ".")]
        changed = [r for r in strokes if r.get("untangled")]
        n_changed = sum(int(r["untangled"].split()[0]) for r in changed)
        n_all = sum(r["stroke"]["stroked_paths"] for r in strokes if r["stroke"])
        seen = [r["stroke"]["on_view"] for r in strokes if r["stroke"] and "on_view" in r["stroke"]]
        body += ["", f"Strokes drawn off and on instead of passing through other paths (`isotween.strokes.untangle`): "
                 f"{n_changed} of the {n_all} stroked paths, in {len(changed)} of the {len(strokes)} stroked pairs; "
                 "the others morph."
                 + (f" The least stroke length on view in an in-between (length times opacity), as a share of the "
                    f"smaller end's: median {np.median(seen):.2f}, lowest {min(seen):.2f} (0: the drawing empties)."
                    if seen else "")]
    by_time = sorted(good, key=lambda r: -r["seconds"])[:10]
    by_end = sorted(good, key=lambda r: -max(r["ends"]))[:10]
    body += ["", "Slowest pairs: " + "; ".join(
        f"{_name(pairs, r['id'])} {r['seconds']:.2f} s ("
        + ", ".join(f"{st} {r['stages'][st]:.2f}" for st in STAGES if r["stages"][st] >= 0.01) + ")" for r in by_time),
        "", "Largest end errors (% of the diagonal, source / target end): " + "; ".join(
        f"{_name(pairs, r['id'])} {r['ends'][0]:.2f} / {r['ends'][1]:.2f}" for r in by_end)]
    if failures:
        body += ["", "isotween failures:", ""]
        for _key, ks in sorted(failures.items(), key=lambda kv: -len(kv[1])):
            first = ours.get(ks[0], {"error": "no result"})
            body.append(f"- {len(ks)} x {first['error'][:160]} (" + ", ".join(_name(pairs, k) for k in ks[:5])
                        + (", ..." if len(ks) > 5 else "") + ")")
    if flub_fail:
        body += ["", "flubber failures: " + ", ".join(f"{v} x {k}" for k, v in flub_fail.items())]
    gsap_fail = {}
    for r in gsap.values():
        if not r["ok"]:
            gsap_fail[r["error"][:100]] = gsap_fail.get(r["error"][:100], 0) + 1
    if gsap_fail:
        body += ["", "GSAP failures: " + ", ".join(f"{v} x {k}" for k, v in gsap_fail.items())]
    text = "\n".join(body)
    print(text)
    details = HERE / ".corpus" / "drawings.json"
    details.write_text(json.dumps({"pairs": [[p[0], str(p[1]), str(p[2])] for p in pairs],
                                   "isotween": ours, "flubber": theirs, "gsap": gsap}))
    print(f"per-pair details: {details}")
    if not args.no_write:
        write_section("Any two drawings", text, " ".join(["python benchmarks/correspondence.py", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
