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
import resource
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


def _children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(jobs, workers=None, client=None, runs=3):
    """Wall, in-job seconds, in-job CPU, client CPU and worker CPU seconds of the median run; all walls.

    Worker CPU: of the worker processes that ended during the run and are this process's children
    (local workers forked from here); 0 otherwise.
    """
    import isotween

    results = []
    for _ in range(runs):
        out = Path(tempfile.mkdtemp(prefix="isotween-batch-"))
        try:
            c0, w0, t0 = time.process_time(), _children_cpu(), time.perf_counter()
            res = isotween.batch(jobs, outdir=out, workers=workers, client=client, resume=False)
            wall, client_cpu, workers_cpu = time.perf_counter() - t0, time.process_time() - c0, _children_cpu() - w0
            recs = [json.loads(line) for line in open(res["report"], encoding="utf-8")]
        finally:
            shutil.rmtree(out, ignore_errors=True)
        assert res["done"] == len(jobs), res["failures"][:3]
        results.append((wall, sum(r["seconds"] for r in recs), sum(r["cpu_seconds"] for r in recs), client_cpu,
                        workers_cpu))
    results.sort()
    return results[len(results) // 2], [r[0] for r in results]


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
        from isotween.batch import single_threaded

        # local processes first: this process has run no job yet, so the workers are forked from it
        # (as `isotween batch` starts them); a batch after jobs ran here starts them from a fork server
        run(jobs[:20], workers=cores, runs=1)  # warm-up: numba's on-disk cache
        (loc, *restl), alll = run(jobs, workers=cores, runs=args.runs)
        from distributed import Client, LocalCluster

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            client.run(lambda: __import__("isotween").interpolate)  # workers import isotween first
            run(jobs[:20], client=client, runs=1)
            (dsk, *restd), alld = run(jobs, client=client, runs=args.runs)
        threads = single_threaded()  # the 1-process baseline runs on one thread, as every worker does
        run(jobs[:20], workers=1, runs=1)
        (one, *rest1), all1 = run(jobs, workers=1, runs=args.runs)
        rows = [["1 process", 1, one, *rest1, all1],
                [f"local processes (all {cores} cores)", cores, loc, *restl, alll],
                ["Dask LocalCluster (2 workers x 1 thread)", 2, dsk, *restd, alld]]
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    cpu_one = rest1[2]  # the whole process's CPU time: jobs and bookkeeping
    cpu_all = (restl[3] if restl[3] > 0 else restl[1]) + restl[2]  # workers (whole, or in jobs) + client
    out = []
    for name, w, wall, busy, cpu, client_cpu, workers_cpu, walls in rows:
        out.append([name, w, f"{wall:.2f} ({min(walls):.2f}-{max(walls):.2f})", f"{args.jobs / wall:.1f}",
                    f"{1e3 * busy / args.jobs:.1f}", f"{1e3 * cpu / args.jobs:.1f}",
                    f"{100 * one / (w * wall):.0f} %", f"{1e3 * (w * wall - busy) / args.jobs:.1f}",
                    f"{1e3 * (client_cpu - (cpu if w == 1 else 0.0)) / args.jobs:.2f}",
                    f"{1e3 * (workers_cpu - cpu) / args.jobs:.2f}" if workers_cpu > 0 else "n/a"])
        print(out[-1], flush=True)
    body = (f"{args.jobs} glyph morphs (DejaVu Sans Bold outlines, pairs of {len(CHARS)} single-outline "
            f"characters, each resampled to {args.points} vertices in the job, {args.frames} frames, "
            "written as .npz), run by `isotween.batch`; median (min-max) of "
            f"{args.runs} runs into a fresh folder.\n\n"
            + table(["runner", "workers", "wall s", "jobs / s", "ms in a job (mean)", "CPU ms in a job (mean)",
                     "parallel efficiency", "overhead ms / job", "client CPU ms / job",
                     "worker CPU ms / job outside jobs"], out)
            + "\n\nParallel efficiency: 1-process wall time / (workers x wall time). Overhead per job: "
            "(workers x wall time - time spent inside the jobs) / jobs, i.e. what a job costs the "
            "workers beyond its own work (process start-up, scheduling, transfer of the job and its "
            "record, the client's hashing of the input files). CPU in a job: the worker process's CPU "
            "time during the job (all its threads); above the wall time in a job when threads run side "
            "by side, below it when the job waits for a core. Client CPU per job: CPU time of the "
            "process that calls `isotween.batch` outside the jobs (hashing the inputs, submitting, "
            "waiting, writing the report), which competes with the workers for the cores. Worker CPU outside "
            "jobs: the local workers' whole CPU time (start-up, imports, loading numba's kernels, "
            "receiving jobs, sending records) less their CPU inside jobs, per job (n/a for Dask, whose "
            "workers are not measured).\n\n"
            f"Threads: every worker runs numba, the BLAS and OpenMP on one thread "
            f"(`isotween.batch.single_threaded`, applied by the local workers and Dask tasks), and so does "
            f"the 1-process baseline here (threads in use: {threads}). Order: local processes, Dask, "
            "then 1 process, so that the local workers are forked from a process that has run no job, "
            "as the command line starts them.\n\n"
            f"CPU time per job with {cores} local processes, everything included (in jobs, workers outside "
            f"jobs, client): {1e3 * cpu_all / args.jobs:.1f} ms against {1e3 * cpu_one / args.jobs:.1f} ms in "
            f"1 process, i.e. {100 * cpu_one / cpu_all:.0f} % CPU efficiency, the parallel efficiency an "
            "otherwise idle machine would give if no worker ever waited.\n\n"
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
