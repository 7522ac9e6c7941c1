"""Any two drawings: isotween and flubber on the same pairs of filled icons and glyphs.

Usage: python benchmarks/correspondence.py [--icons 500] [--glyphs 200] [--frames 9] [--workers 2]

Every pair (the classic morphs, random pairs within Bootstrap Icons' filled set and
within Font Awesome's solid set, random pairs of DejaVu glyphs; benchmarks/corpus.py)
goes through

- isotween with no options, as ``isotween interpolate A.svg B.svg`` runs it: ``load``
  both SVG files, ``correspond`` (solid meshes of the filled regions), ``interpolate``
  with ``fold="fallback"`` (a folding AIAP result is replaced by the fold-free
  injective morph); in one worker process per pair, timed from reading the files to the last
  frame;
- flubber 0.4 (Node.js, benchmarks/flubber_run.js) on the same rings (the SVG
  subpaths as isotween reads them), each subpath a ring, with maxSegmentLength set
  to 1 % of the drawing's bounding-box diagonal.

Per pair it records: success (frames made for the whole drawing, every ring of both
ends included), flipped triangles in the generated meshes and in the in-between
frames, outline crossings in every in-between frame (two edges of one filled region,
outer ring or hole, that cross), and the edge-length deviation of the outline edges
(SPEC.md's definition: the largest | |e(t)| / ((1-t)|e(0)| + t|e(1)|) - 1 |).
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

    The outline is every closed path of the sequence's shape; crossings are counted
    within each filled region (outer ring and holes: ``regions``, default the
    shape's), as `isotween.metrics.outline_crossings` with ``scope="region"`` does.
    """
    import isotween

    shape = seq.shape
    closed = [k for k, (_, c) in enumerate(shape.paths) if c]
    rings = [shape.paths[k][0] for k in closed]
    renumber = {k: i for i, k in enumerate(closed)}
    regions = shape.regions if regions is None else regions
    regions = [[renumber[k] for k in r if k in renumber] for r in (regions or [])]
    outline = isotween.Shape(shape.vertices, np.vstack([np.c_[p, np.roll(p, -1)] for p in rings]),
                             paths=[(p, True) for p in rings], regions=[r for r in regions if r] or None)
    oseq = isotween.Sequence(frames=seq.frames, shape=outline, times=seq.times)
    crossings = isotween.metrics.outline_crossings(oseq, scope="region")[1:-1]
    return [int(c) for c in crossings], isotween.metrics.edge_length_deviation(oseq)


# ---------------------------------------------------------------- isotween
def _alarm(signum, frame):
    raise TimeoutError(f"no result within {TIMEOUT} s")


def run_isotween(job):
    """One pair through isotween with no options (in a worker process)."""
    import isotween

    k, a_file, b_file, n_frames = job
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(TIMEOUT)
    out = {"id": k}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            t0 = time.perf_counter()
            a, b = isotween.io.load(a_file), isotween.io.load(b_file)
            src, tgt, report = isotween.correspond(a, b)
            # as `isotween interpolate A.svg B.svg` does for meshes it built: a folding AIAP result
            # is replaced by the fold-free injective morph
            seq = isotween.interpolate(src, tgt, frames=n_frames, fold="fallback" if src.n_faces else "allow")
            out["seconds"] = time.perf_counter() - t0
        out["ok"] = True
        out["report"] = report.summary()
        out["method"] = seq.method
        out["vertices"] = src.n_vertices
        out["faces"] = src.n_faces
        # meshes: every face of the source with one orientation, the target's the same
        if src.n_faces:
            s = np.sign(src.face_areas())
            t = np.sign(tgt.face_areas())
            major = 1.0 if np.count_nonzero(s > 0) >= np.count_nonzero(s < 0) else -1.0
            out["mesh_flips"] = int(np.count_nonzero(s != major) + np.count_nonzero(t != major))
        else:
            out["mesh_flips"] = 0
        out["frame_flips"] = [int(c) for c in isotween.metrics.flipped_faces(seq, None)[1:-1]]
        out["crossings"], out["edge_deviation"] = outline_measures(seq)
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
        groups[k] = a.regions
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
    import isotween

    times = np.linspace(0, 1, n_frames)
    out = {}
    for line in proc.stdout.splitlines():
        r = json.loads(line)
        res = {"id": r["id"], "ok": r["ok"], "mode": r["mode"], "seconds": r["seconds"]}
        if not r["ok"]:
            res["error"] = r["error"]
        else:
            frames = np.array([np.vstack(f) for f in r["frames"]], dtype=float)
            shape = isotween.Shape.from_paths([np.asarray(ring, float) for ring in r["frames"][0]])
            seq = isotween.Sequence(frames=frames, shape=shape, times=times)
            # interpolateAll morphs ring k of the source into ring k of the target: ring k keeps the
            # source's region; separate / combine make pieces, each its own region
            regions = groups[r["id"]] if r["mode"] == "interpolateAll" else []
            res["crossings"], res["edge_deviation"] = outline_measures(seq, regions)
            res["frame_flips"] = [0] * (n_frames - 2)
        out[r["id"]] = res
    return out


# ---------------------------------------------------------------- summary
def summarise(results, ids):
    """One table row: pairs, morphed, clean, frames with crossings, edge deviation, times."""
    rs = [results.get(k, {"ok": False}) for k in ids]
    ok = [r for r in rs if r["ok"]]
    clean = [r for r in ok if not any(r["crossings"]) and not any(r["frame_flips"])]
    bad_frames = sum(int(np.count_nonzero(np.array(r["crossings"]) > 0)) for r in ok)
    dev = [r["edge_deviation"] for r in ok]
    secs = [r["seconds"] for r in ok]

    def pct(a, b):
        return f"{100 * a / b:.1f} %" if b else "-"

    return [
        len(rs), f"{len(ok)} ({pct(len(ok), len(rs))})", f"{len(clean)} ({pct(len(clean), len(rs))})",
        bad_frames,
        f"{np.nanmedian(dev):.3f}" + (f" ({np.isnan(dev).sum()} undefined)" if np.isnan(dev).any() else "")
        if dev and not np.isnan(dev).all() else "-",
        f"{1e3 * np.median(secs):.0f} / {1e3 * np.percentile(secs, 95):.0f}" if secs else "-",
    ]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--icons", type=int, default=500)
    parser.add_argument("--glyphs", type=int, default=200)
    parser.add_argument("--frames", type=int, default=9)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--no-write", action="store_true", help="print only; leave RESULTS.md alone")
    args = parser.parse_args()

    pairs = corpus.pairs(args.icons, args.glyphs)
    jobs = [(k, str(a), str(b), args.frames) for k, (_, a, b) in enumerate(pairs)]
    t0 = time.perf_counter()
    ours = {}
    log = HERE / ".corpus" / "correspondence-progress.jsonl"  # one line per finished pair, as it finishes
    with mp.get_context("fork").Pool(args.workers, maxtasksperchild=50) as pool, log.open("w") as fh:
        for r in pool.imap_unordered(run_isotween, jobs, chunksize=1):
            ours[r["id"]] = r
            fh.write(json.dumps(r) + "\n")
            fh.flush()
    wall = time.perf_counter() - t0
    theirs = run_flubber(jobs, args.frames)

    header = ["tool", "set", "pairs", "morphed", "no crossing, no flip", "frames with crossings",
              "median edge-length dev.", "time median / p95 (ms)"]
    rows = []
    kinds = {"all": [k for k in range(len(pairs))]}
    for kind in ("classic", "icon", "glyph"):
        kinds[kind] = [k for k, p in enumerate(pairs) if p[0] == kind]
    for kind, ids in kinds.items():
        rows.append(["isotween", kind, *summarise(ours, ids)])
        rows.append(["flubber 0.4", kind, *summarise(theirs, ids)])
    mesh_flips = sum(r.get("mesh_flips", 0) for r in ours.values() if r["ok"])
    injective = sum(1 for r in ours.values() if r["ok"] and r.get("method") == "injective")
    convex = sum(1 for r in ours.values() if r["ok"] and r.get("method") == "convex")
    meshes = sum(1 for r in ours.values() if r["ok"] and r.get("faces"))
    failures = {}
    for r in ours.values():
        if not r["ok"]:
            key = r["error"].split(":")[0]
            failures.setdefault(key, []).append(r)
    flub_fail = {}
    for r in theirs.values():
        if not r["ok"]:
            key = "several rings into a different number" if r["error"].startswith("no flubber call") else r["error"]
            flub_fail[key] = flub_fail.get(key, 0) + 1

    body = [
        f"{len(pairs)} pairs ({len(kinds['classic'])} classic morphs, {len(kinds['icon'])} random icon "
        f"pairs, {len(kinds['glyph'])} random glyph pairs; seed 20261123), {args.frames} frames each, "
        f"no options. isotween: {args.workers} worker processes, {wall:.0f} s wall in all; times are "
        "per pair in process (reading both files, correspondence, meshing, interpolation). flubber: "
        "its own call per ring count, time of its interpolators only. An edge-length deviation is "
        "undefined where an edge has zero length at both ends (flubber repeats points); the median "
        "is over the other pairs.",
        "",
        table(header, rows),
        "",
        f"Meshes: {meshes} pairs meshed, {mesh_flips} flipped triangles in all generated meshes. "
        f"AIAP folded and the fold-free morph was used instead on {injective + convex} pairs "
        f"(method 'injective' on {injective}, 'convex' where that could not be built on {convex}).",
    ]
    if failures:
        body += ["", "isotween failures:", ""]
        for _key, rs in sorted(failures.items(), key=lambda kv: -len(kv[1])):
            first = rs[0]
            body.append(f"- {len(rs)} x {first['error'][:160]} (pair {first['id']}: "
                        f"{Path(pairs[first['id']][1]).name} -> {Path(pairs[first['id']][2]).name})")
    if flub_fail:
        body += ["", "flubber failures: " + ", ".join(f"{v} x {k}" for k, v in flub_fail.items())]
    text = "\n".join(body)
    print(text)
    details = HERE / ".corpus" / "drawings.json"
    details.write_text(json.dumps({"pairs": [[p[0], str(p[1]), str(p[2])] for p in pairs],
                                   "isotween": ours, "flubber": theirs}))
    print(f"per-pair details: {details}")
    if not args.no_write:
        write_section("Any two drawings", text, " ".join(["python benchmarks/correspondence.py", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
