"""Throughput of `isotween.batch` on glyph morphs: 1 process, all local cores, Dask.

Jobs: ordered pairs of single-outline DejaVu Sans Bold glyphs (matplotlib's
bundled font, outlines as in scripts/build_examples.py), written as .json
shape files; every job resamples both outlines to --points vertices
(`isotween.resample`) and interpolates --frames frames into an .npz file.
Every configuration runs the same jobs into a fresh folder (no resume), --runs
times; the table gives the median wall time.

- parallel efficiency = (1-process time) / (workers x time with that many workers);
- per-task overhead = (workers x wall time - sum of the time spent inside the
  jobs) / jobs: what a job costs beyond its own work (scheduling, transfer,
  waiting), seen from the workers.

Usage: python benchmarks/batch.py [--jobs 1000] [--runs 3] [--points 120] [--frames 21]
"""

import argparse
import itertools
import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent / "scripts"))

# glyphs with one outline (no holes) in DejaVu Sans Bold
CHARS = "CEFGHIJKLMNSTUVWXYZ12357cfhijklmnrstuvwxyz"


def make_jobs(folder, count, points, frames):
    """Write the glyph outlines and return `count` job dicts."""
    from build_examples import glyph
    from isotween import Shape, io

    files = {}
    for c in CHARS:
        rings = glyph(c)
        if len(rings) == 1:
            files[c] = folder / f"glyph_{ord(c)}.json"
            io.save(Shape.from_polygon(rings), files[c])
    pairs = itertools.islice(itertools.cycle(itertools.permutations(files, 2)), count)
    return [{"source": files[a], "target": files[b], "output": f"{ord(a)}_{ord(b)}_{i}.npz",
             "options": {"resample": points, "frames": frames}} for i, (a, b) in enumerate(pairs)]


def run(jobs, workers=None, client=None, runs=3):
    """Median wall time, sum of in-job seconds (of the median run) and the counts."""
    import isotween

    results = []
    for _ in range(runs):
        out = Path(tempfile.mkdtemp(prefix="isotween-batch-"))
        try:
            t0 = time.perf_counter()
            res = isotween.batch(jobs, outdir=out, workers=workers, client=client, resume=False)
            wall = time.perf_counter() - t0
            busy = sum(json.loads(line)["seconds"] for line in open(res["report"], encoding="utf-8"))
        finally:
            shutil.rmtree(out, ignore_errors=True)
        assert res["done"] == len(jobs), res["failures"][:3]
        results.append((wall, busy))
    results.sort()
    return results[len(results) // 2], [w for w, _ in results]


def main():
    from _results import table, write_section

    ap = argparse.ArgumentParser()
    ap.add_argument("--jobs", type=int, default=1000)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--points", type=int, default=120)
    ap.add_argument("--frames", type=int, default=21)
    args = ap.parse_args()
    cores = os.cpu_count()
    load0 = os.getloadavg()[0]
    folder = Path(tempfile.mkdtemp(prefix="isotween-glyphs-"))
    try:
        jobs = make_jobs(folder, args.jobs, args.points, args.frames)
        run(jobs[:20], workers=1, runs=1)  # warm-up: imports, numba cache
        rows = []
        (one, busy1), all1 = run(jobs, workers=1, runs=args.runs)
        rows.append(["1 process", 1, one, busy1, all1])
        (loc, busyl), alll = run(jobs, workers=cores, runs=args.runs)
        rows.append([f"local processes (all {cores} cores)", cores, loc, busyl, alll])
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            client.run(lambda: __import__("isotween").interpolate)  # workers import isotween first
            run(jobs[:20], client=client, runs=1)
            (dsk, busyd), alld = run(jobs, client=client, runs=args.runs)
        rows.append(["Dask LocalCluster (2 workers x 1 thread)", 2, dsk, busyd, alld])
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    out = []
    for name, w, wall, busy, walls in rows:
        out.append([name, w, f"{wall:.2f} ({min(walls):.2f}-{max(walls):.2f})", f"{args.jobs / wall:.1f}",
                    f"{1e3 * busy / args.jobs:.1f}", f"{100 * one / (w * wall):.0f} %",
                    f"{1e3 * (w * wall - busy) / args.jobs:.1f}"])
        print(out[-1], flush=True)
    body = (f"{args.jobs} glyph morphs (DejaVu Sans Bold outlines, pairs of {len(CHARS)} single-outline "
            f"characters, each resampled to {args.points} vertices in the job, {args.frames} frames, "
            "written as .npz), run by `isotween.batch`; median (min-max) of "
            f"{args.runs} runs into a fresh folder.\n\n"
            + table(["runner", "workers", "wall s", "jobs / s", "ms in a job (mean)", "parallel efficiency",
                     "overhead ms / job"], out)
            + "\n\nParallel efficiency: 1-process wall time / (workers x wall time). Overhead per job: "
            "(workers x wall time - time spent inside the jobs) / jobs, i.e. what a job costs the "
            "workers beyond its own work (process start-up, scheduling, transfer of the job and its "
            "record, the client's hashing of the input files).\n\n"
            f"Parallel efficiency on {cores} cores: {100 * one / (cores * loc):.0f} % with local processes, "
            f"{100 * one / (2 * dsk):.0f} % with Dask (target 80 %: "
            f"{'met' if one / (cores * loc) >= 0.8 else 'NOT met'} locally).\n\n"
            f"Load average (1 min) at the start and the end: {load0:.1f}, {os.getloadavg()[0]:.1f} on "
            f"{cores} cores (the machine is shared; timings under load).")
    print(body)
    write_section("Batches", body, "python benchmarks/batch.py" + "".join(
        f" --{k} {v}" for k, v in vars(args).items() if v != ap.get_default(k)))


if __name__ == "__main__":
    main()
