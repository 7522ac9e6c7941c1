"""Throughput of `isotween.batch`: glyph morphs, or (--set icons) icon pairs through correspondence.

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

Icon pairs (``--set icons``): the jobs are random pairs (fixed ``--seed``) of
Bootstrap Icons' filled icons (``*-fill.svg``, benchmarks/corpus.py), written to a
CSV manifest (source, target, output .npz, frames) with no other option, so every
job goes through the library's correspondence pipeline (``isotween.morph``) as
``isotween batch MANIFEST -o OUTDIR`` runs it: the manifest is checked, then read
lazily by `isotween.batch`. A job with no result within ``--timeout`` seconds
(an alarm in the worker, around `isotween.batch.run_job`) and a job that fails
count as failed, with their reasons. ``--budget`` seconds per run stops handing
out new jobs (those in flight finish), so a run fits a time slot; the jobs not
reached are counted, not hidden. Results go below the glyph table of the
section, which a glyph run keeps in turn.

Usage: python benchmarks/batch.py [--jobs 1000] [--runs 3] [--points 120] [--frames 21]
       python benchmarks/batch.py --set icons [--jobs 1000] [--runs 1] [--runners local,one]
              [--timeout 60] [--budget SECONDS] [--seed 20261124]
"""

import argparse
import collections
import csv
import itertools
import json
import os
import re
import resource
import shutil
import signal
import statistics
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


# ---------------------------------------------------------------- icon pairs with correspondence
ICONS_SECTION = "Batches: icon pairs"
TIMEOUT = [60.0]  # seconds per job (set by --timeout before the workers are forked)


class JobTimeout(Exception):
    """A job ran past the benchmark's bound (not an OSError, so no file-handling code takes it for one)."""


def _expire(signum, frame):
    signal.setitimer(signal.ITIMER_REAL, 1.0)  # again in 1 s, should anything swallow this one
    raise JobTimeout(f"no result within {TIMEOUT[0]:g} s")


def _bounded_run_job(job):
    """`isotween.batch.run_job` under an alarm of TIMEOUT seconds; a job past it is a failed record."""
    run_job = _ORIGINAL_RUN_JOB[0]
    start, cpu = time.perf_counter(), time.process_time()
    previous = signal.signal(signal.SIGALRM, _expire)
    signal.setitimer(signal.ITIMER_REAL, TIMEOUT[0])
    try:
        try:
            rec = run_job(job)  # records a JobTimeout raised inside as a failure, like any error
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
    except JobTimeout as exc:  # raised outside run_job's own try
        rec = {"output": job["output"], "key": job["key"], "line": job.get("line"), "status": "failed",
               "error": f"JobTimeout: {exc}", "seconds": round(time.perf_counter() - start, 6),
               "cpu_seconds": round(time.process_time() - cpu, 6)}
    finally:
        signal.signal(signal.SIGALRM, previous)
    rec["bounded"] = True
    return rec


_ORIGINAL_RUN_JOB: list = []


def bound_jobs(seconds):
    """Put every job of `isotween.batch` under an alarm of ``seconds``.

    `run_jobs` (in local workers) and `batch` (in this process) call the module's `run_job`,
    so replacing it here reaches workers forked from this process; the records carry
    ``bounded`` so that a worker which did not inherit it shows.
    """
    import isotween.batch as ib

    TIMEOUT[0] = float(seconds)
    if not _ORIGINAL_RUN_JOB:
        _ORIGINAL_RUN_JOB.append(ib.run_job)
        ib.run_job = _bounded_run_job


def icon_pairs(count, seed):
    """``count`` random ordered pairs (two different icons) of Bootstrap Icons' filled set, a fixed seed."""
    import numpy as np

    from corpus import icons

    pool = icons()[0]
    rng = np.random.default_rng(seed)
    return [tuple(pool[k] for k in rng.choice(len(pool), size=2, replace=False)) for _ in range(count)], len(pool)


def write_manifest(path, pairs, frames):
    """A CSV manifest: source, target (absolute paths), output (.npz), frames; no other option."""
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["source", "target", "output", "frames"])
        for k, (a, b) in enumerate(pairs):
            name = f"{k:04d}-{a.stem.removesuffix('-fill')}-{b.stem.removesuffix('-fill')}.npz"
            w.writerow([str(a), str(b), name, frames])
    return path


def run_manifest(manifest, workers=None, client=None, budget=None):
    """One run of a manifest as `isotween batch MANIFEST -o OUTDIR` runs it, into a fresh folder.

    Returns wall seconds, the report's records, the client's CPU seconds, the local workers' CPU
    seconds (0 with Dask or in one process), and the number of jobs not reached within ``budget``.
    """
    import isotween
    from isotween.batch import check_jobs, read_manifest

    out = Path(tempfile.mkdtemp(prefix="isotween-batch-icons-"))
    left = [0]

    def within(jobs, deadline):
        for job in jobs:
            if deadline is not None and time.perf_counter() > deadline:
                left[0] += 1
                continue
            yield job

    try:
        c0, w0, t0 = time.process_time(), _children_cpu(), time.perf_counter()
        total = sum(1 for _ in read_manifest(manifest))
        check_jobs(read_manifest(manifest), out)
        isotween.batch(within(read_manifest(manifest), None if budget is None else t0 + budget), outdir=out,
                       workers=workers, client=client, resume=False, total=total)
        wall, client_cpu, workers_cpu = time.perf_counter() - t0, time.process_time() - c0, _children_cpu() - w0
        recs = [json.loads(line) for line in open(out / "batch-report.jsonl", encoding="utf-8")]
    finally:
        shutil.rmtree(out, ignore_errors=True)
    return wall, recs, client_cpu, workers_cpu, left[0]


def _reason(error):
    """A failure's reason without the pair's numbers and names: its type and the start of its message."""
    text = error.split("\n")[0]
    if not text.startswith("JobTimeout"):
        text = re.sub(r"\d+(\.\d+)?", "N", text)
    return text[:110] + ("..." if len(text) > 110 else "")


def _pct(values, q):
    values = sorted(values)
    return values[min(len(values) - 1, int(round(q * (len(values) - 1))))]


def icons_main(args, ap):
    """Icon pairs through the correspondence pipeline: jobs per second per runner."""
    from _results import machine, table

    cores = os.cpu_count()
    load0 = os.getloadavg()[0]
    runners = [r.strip() for r in args.runners.split(",") if r.strip()]
    unknown = [r for r in runners if r not in ("local", "dask", "one")]
    if unknown:
        ap.error(f"unknown runner(s) {', '.join(unknown)}; choose from local, dask, one")
    if args.replay:  # the runs of an earlier invocation, reported again
        saved = json.loads(Path(args.replay).read_text())
        results = {k: (w, [tuple(r) for r in runs]) for k, (w, runs) in saved["results"].items()}
        load0, load1, pool = saved["load0"], saved["load1"], saved["pool"]
    else:
        results = {}

        def save():  # after every runner: the records survive a failure of the report below
            Path(args.save).write_text(json.dumps({"results": results, "load0": load0, "load1": os.getloadavg()[0],
                                                   "pool": pool}))

        bound_jobs(args.timeout)
        pairs, pool = icon_pairs(args.jobs, args.seed)
        folder = Path(tempfile.mkdtemp(prefix="isotween-icons-"))
        try:
            manifest = write_manifest(folder / "jobs.csv", pairs, args.frames)
            warm = write_manifest(folder / "warm.csv", pairs[:2], args.frames)
            import isotween.batch as ib

            for name in runners:
                if name == "local":
                    # forked from this process (no job has run here yet), as the command line starts them;
                    # a fork server would not carry the job bound
                    if ib._start_method().get_start_method() != "fork":
                        raise SystemExit("local workers would start from a fork server; run 'local' first")
                    if args.warmup:
                        run_manifest(warm, workers=cores)  # numba's on-disk cache
                    runs = [run_manifest(manifest, workers=cores, budget=args.budget) for _ in range(args.runs)]
                    results[f"local processes (all {cores} cores)"] = (cores, runs)
                elif name == "dask":
                    from distributed import Client, LocalCluster

                    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                      dashboard_address=None) as cluster, Client(cluster) as client:
                        client.run(bound_jobs, args.timeout)  # the same bound in the Dask workers
                        if args.warmup:
                            run_manifest(warm, client=client)
                        runs = [run_manifest(manifest, client=client, budget=args.budget) for _ in range(args.runs)]
                    results["Dask LocalCluster (2 workers x 1 thread)"] = (2, runs)
                else:
                    from isotween.batch import single_threaded

                    single_threaded()  # one thread, as every worker runs
                    if args.warmup:
                        run_manifest(warm, workers=1)
                    runs = [run_manifest(manifest, workers=1, budget=args.budget) for _ in range(args.runs)]
                    results["1 process"] = (1, runs)
                save()
        finally:
            shutil.rmtree(folder, ignore_errors=True)

        load1 = os.getloadavg()[0]
    rows, failures, notes = [], {}, []
    one_rate = None
    if "1 process" in results:
        _, runs = results["1 process"]
        one_rate = statistics.median(len(r[1]) / r[0] for r in runs)
    for name, (w, runs) in results.items():
        runs = sorted(runs, key=lambda r: len(r[1]) / r[0])
        wall, recs, client_cpu, workers_cpu, left = runs[len(runs) // 2]
        rates = [len(r[1]) / r[0] for r in runs]
        done = [r for r in recs if r["status"] == "done"]
        failed = [r for r in recs if r["status"] == "failed"]
        unbounded = sum(1 for r in recs if not r.get("bounded"))
        if unbounded:
            notes.append(f"{name}: {unbounded} job(s) ran without the {args.timeout:g} s bound")
        secs = [r["seconds"] for r in recs]
        in_jobs_cpu = sum(r.get("cpu_seconds", 0.0) for r in recs)
        rate = len(recs) / wall
        rows.append([name, w, f"{len(recs)} of {args.jobs}" + (f" ({left} not reached)" if left else ""),
                     len(done), len(failed), f"{wall:.0f}",
                     f"{rate:.3f}" + (f" ({min(rates):.3f}-{max(rates):.3f})" if len(runs) > 1 else ""),
                     f"{len(done) / wall:.3f}", f"{statistics.median(secs):.2f}",
                     f"{statistics.median([r['seconds'] for r in done]):.2f}" if done else "-",
                     f"{_pct(secs, 0.95):.1f} / {max(secs):.1f}",
                     f"{sum(secs) / len(recs):.2f}",
                     f"{in_jobs_cpu / len(recs):.2f}",
                     f"{100 * rate / (w * one_rate):.0f} %" if one_rate else "-",
                     f"{1e3 * (client_cpu - (in_jobs_cpu if w == 1 else 0.0)) / len(recs):.1f}"])
        print(rows[-1], flush=True)
        counts = collections.Counter(_reason(r["error"]) for r in failed)
        failures[name] = [(n, why, next(Path(r["output"]).stem for r in failed if _reason(r["error"]) == why))
                          for why, n in counts.most_common()]

    cmd = "python benchmarks/batch.py --set icons" + "".join(
        f" --{k.replace('_', '-')} {v}" for k, v in vars(args).items()
        if k not in ("set", "points", "warmup", "save", "replay") and v != ap.get_default(k))
    lines = [f"{args.jobs} jobs: random ordered pairs of two different icons among Bootstrap Icons' {pool} "
             f"filled icons (`*-fill.svg`, bootstrap-icons 1.13.2; seed {args.seed}), in a CSV manifest "
             f"(source, target, output .npz, frames {args.frames}; no other option), so that every job runs "
             "the library's correspondence pipeline (`isotween.morph`: read, correspond, mesh, AIAP with the "
             "fold fallback, write) as `isotween batch jobs.csv -o OUTDIR` runs it; "
             f"{args.runs} run(s) per runner into a fresh folder"
             + (" (median by jobs / s; min-max in brackets)" if args.runs > 1 else "")
             + f". A job with no result within {args.timeout:g} s counts as failed (an alarm in the worker "
             "around `isotween.batch.run_job`; a long compiled kernel finishes before it can act)"
             + (f"; each run hands out no new job after {args.budget:g} s (those in flight finish), and "
                "the jobs not reached are counted" if args.budget else "") + ".",
             "",
             table(["runner", "workers", "jobs run", "done", "failed", "wall s", "jobs / s", "done / s",
                    "s per job (median)", "s per job, done (median)", "s per job p95 / max",
                    "s in a job (mean)", "CPU s in a job (mean)", "parallel efficiency",
                    "client CPU ms / job"], rows),
             "",
             "Jobs / s: jobs finished (done or failed) / wall time of the run, from reading the manifest to the "
             "last record; s per job: a job's own wall time in its worker (from reading both files to the "
             "written .npz, or to its failure). Parallel efficiency: jobs / s / (workers x jobs / s of 1 "
             "process), where the 1-process baseline ran. Every worker runs numba, the BLAS and OpenMP on one "
             "thread, as `isotween batch` runs them."]
    if "1 process" not in results:
        lines += ["", "The 1-process baseline did not run (`--runners` left it out: the shared machine had no time "
                  "left for it), so there is no parallel efficiency; 1 / (CPU s in a job) is a stand-in for its "
                  "jobs / s, not a measurement."]
    for name, items in failures.items():
        lines += ["", f"Failures ({name}): " + ("none." if not items else f"{sum(n for n, _, _ in items)}, by reason "
                                                "(job number-source-target of one):\n")]
        lines += [f"- {n} x {why} (e.g. {example})" for n, why, example in items]
    lines += [""] + [f"Note: {n}." for n in notes]
    lines += ["", f"Load average (1 min) at the start and the end: {load0:.1f}, {load1:.1f} on "
              f"{cores} cores (the machine is shared; timings under load)."]
    body = "\n".join(lines).replace("\n\n\n", "\n\n")
    print(body)
    if args.write:
        write_icons_section(body, cmd, machine())


def _sub_block(body, command, machine_line):
    return (f"<!-- begin {ICONS_SECTION} -->\n### Icon pairs with correspondence\n\nCommand: `{command}`  \n"
            f"Machine: {machine_line}  \nDate: {time.strftime('%Y-%m-%d')}\n\n{body.strip()}\n"
            f"<!-- end {ICONS_SECTION} -->")


_SUB = re.compile(rf"<!-- begin {re.escape(ICONS_SECTION)} -->.*?<!-- end {re.escape(ICONS_SECTION)} -->", re.S)


def kept_icons_block():
    """The icon-pair block of the Batches section in RESULTS.md ('' if none), for a glyph run to keep."""
    from _results import RESULTS

    found = _SUB.search(RESULTS.read_text()) if RESULTS.exists() else None
    return found.group(0) if found else ""


def write_icons_section(body, command, machine_line):
    """Replace the icon-pair block, or put it at the end of the Batches section (below the glyph table)."""
    from _results import RESULTS

    text = RESULTS.read_text()
    block = _sub_block(body, command, machine_line)
    if _SUB.search(text):
        text = _SUB.sub(lambda _: block, text)
    else:
        end = "<!-- end Batches -->"
        if end not in text:
            raise SystemExit(f"{RESULTS}: no Batches section to add the icon pairs to (run the glyphs first)")
        text = text.replace(end, "\n" + block + "\n" + end, 1)
    RESULTS.write_text(text)


def main():
    from _results import table, write_section

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    ap.add_argument("--set", choices=("glyphs", "icons"), default="glyphs",
                    help="glyphs: resampled single-outline glyphs; icons: pairs of filled icons through correspondence")
    ap.add_argument("--jobs", type=int, default=1000)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--points", type=int, default=120, help="glyphs: vertices of each resampled outline")
    ap.add_argument("--frames", type=int, default=21)
    ap.add_argument("--runners", default="local,one", help="icons: local, dask, one (1 process), in this order")
    ap.add_argument("--timeout", type=float, default=60.0, help="icons: seconds per job before it counts as failed")
    ap.add_argument("--budget", type=float, default=None,
                    help="icons: seconds per run after which no new job is handed out")
    ap.add_argument("--seed", type=int, default=20261124, help="icons: seed of the random pairs")
    ap.add_argument("--warmup", type=int, default=1, help="icons: 1 runs 2 jobs first, untimed (numba's cache)")
    ap.add_argument("--save", default=os.path.join(tempfile.gettempdir(), "isotween-batch-icons.json"),
                    help="icons: the runs' records are saved here after every runner")
    ap.add_argument("--replay", default=None, metavar="FILE", help="icons: report the runs saved in FILE again")
    ap.add_argument("--no-write", dest="write", action="store_false", help="print only; RESULTS.md untouched")
    args = ap.parse_args()
    if args.set == "icons":
        return icons_main(args, ap)
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
            client.run(lambda: callable(__import__("isotween").interpolate))  # workers import isotween (a bool back)
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
    if args.write:  # the icon-pair block below the glyph table stays
        write_section("Batches", body + ("\n\n" + kept_icons_block()).rstrip(), "python benchmarks/batch.py" + "".join(
            f" --{k} {v}" for k, v in vars(args).items() if v != ap.get_default(k)))


if __name__ == "__main__":
    main()
