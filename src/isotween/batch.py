"""`batch`: many interpolations at once, in local processes or on a Dask cluster.

A job is a source file, a target file, an output path and options (those of
`isotween.interpolate`, plus ``resample`` and ``mesh`` to make the pair
compatible and ``format`` for a folder of frames). Each job runs in a worker
that reads its own files, writes its output atomically and returns a small
record; the client only keeps the jobs in flight (a bounded window), so
thousands of jobs do not grow its memory.

Every record goes to a JSON Lines report as soon as the job ends. A re-run
skips a job whose output exists and whose key (a hash of both input files'
contents, the options and the isotween version) matches the last successful
record of that output in the report (resume). A failed job is recorded with
its error and does not stop the others.
"""

import csv
import hashlib
import json
import os
import time
from pathlib import Path

from ._callable import make_callable
from .errors import FileFormatError, ParameterError

__all__ = ["batch", "read_manifest", "run_job", "run_jobs", "run_jobs_one_thread", "single_threaded",
           "threads_in_use", "JOB_OPTIONS"]

#: per-job options and how a text value (a CSV cell) becomes one
JOB_OPTIONS = {
    "frames": int,
    "solver": str,
    "init": str,
    "scheme": str,
    "tol": float,
    "max_iter": int,
    "method": str,
    "resample": int,
    "mesh": lambda v: v if v == "auto" else float(v),
    "format": str,
}
_FIELDS = ("source", "target", "output")
_SHAPE_EXTS = (".obj", ".off", ".svg", ".json", ".npz")
REPORT = "batch-report.jsonl"


def read_manifest(path, defaults=None):
    """Jobs from a CSV or JSON Lines manifest, or from a folder of pairs.

    Parameters
    ----------
    path : path-like
        - ``.csv``: a header with ``source``, ``target``, ``output`` and any of
          `JOB_OPTIONS` as columns (an empty cell takes the default);
        - ``.jsonl``: one object per line with the same keys (options also
          under ``"options"``);
        - a folder: every sub-folder holding ``source.EXT`` and ``target.EXT``
          (as ``isotween prepare`` writes them), and every ``NAME.source.EXT``
          beside a ``NAME.target.EXT``; the output is ``NAME.npz``.

        Relative input paths are relative to the manifest's folder.
    defaults : dict, optional
        Options for jobs that do not set them.

    Yields
    ------
    dict
        source, target (paths), output (as written), options (dict), line.

    Raises
    ------
    FileFormatError
        Unreadable manifest, missing column, bad JSON or bad option value
        (naming the file and line).
    """
    path = Path(path)
    defaults = dict(defaults or {})
    _check_options(defaults, f"{path}")
    if path.is_dir():
        yield from _folder_jobs(path, defaults)
        return
    if not path.is_file():
        raise FileFormatError(f"{path}: no such manifest")
    ext = path.suffix.lower()
    if ext not in (".csv", ".jsonl", ".ndjson"):
        raise FileFormatError(f"{path}: a manifest is a .csv or .jsonl file or a folder of pairs")
    base = path.parent
    with open(path, newline="", encoding="utf-8") as f:
        if ext == ".csv":
            rows = csv.DictReader(f)
            missing = [c for c in _FIELDS if c not in (rows.fieldnames or [])]
            if missing:
                raise FileFormatError(f"{path}: line 1: missing column(s) {', '.join(missing)}")
            unknown = [c for c in rows.fieldnames if c not in _FIELDS and c not in JOB_OPTIONS]
            if unknown:
                raise FileFormatError(f"{path}: line 1: unknown column(s) {', '.join(unknown)}; "
                                      f"options are {', '.join(JOB_OPTIONS)}")
            for row in rows:
                line = rows.line_num
                options = {k: _convert(k, v, path, line) for k, v in row.items()
                           if k in JOB_OPTIONS and v not in (None, "")}
                yield _job(row, options, defaults, base, path, line)
        else:
            for line, text in enumerate(f, 1):
                if not text.strip():
                    continue
                try:
                    row = json.loads(text)
                except json.JSONDecodeError as exc:
                    raise FileFormatError(f"{path}: line {line}: not JSON ({exc.msg})") from None
                if not isinstance(row, dict):
                    raise FileFormatError(f"{path}: line {line}: expected a JSON object")
                options = dict(row.get("options") or {})
                options.update({k: v for k, v in row.items() if k not in _FIELDS and k != "options"})
                _check_options(options, f"{path}: line {line}")
                yield _job(row, options, defaults, base, path, line)


def _convert(key, value, path, line):
    try:
        return JOB_OPTIONS[key](value)
    except ValueError:
        raise FileFormatError(f"{path}: line {line}: bad value {value!r} for option {key}") from None


def _check_options(options, where):
    unknown = [k for k in options if k not in JOB_OPTIONS]
    if unknown:
        raise FileFormatError(f"{where}: unknown option(s) {', '.join(map(str, unknown))}; "
                              f"options are {', '.join(JOB_OPTIONS)}")


def _job(row, options, defaults, base, path, line):
    for key in _FIELDS:
        if not isinstance(row.get(key), str) or not row[key].strip():
            raise FileFormatError(f"{path}: line {line}: missing {key}")
    return {"source": str(base / row["source"]), "target": str(base / row["target"]),
            "output": row["output"], "options": {**defaults, **options}, "line": line}


def _folder_jobs(folder, defaults):
    pairs = []
    for sub in sorted(p for p in folder.iterdir() if p.is_dir()):
        src = [p for p in sorted(sub.glob("source.*")) if p.suffix.lower() in _SHAPE_EXTS]
        tgt = [p for p in sorted(sub.glob("target.*")) if p.suffix.lower() in _SHAPE_EXTS]
        if src and tgt:
            pairs.append((sub.name, src[0], tgt[0]))
    for src in sorted(folder.glob("*.source.*")):
        if src.suffix.lower() in _SHAPE_EXTS:
            name = src.name[: -len(".source" + src.suffix)]
            tgt = src.with_name(f"{name}.target{src.suffix}")
            if tgt.is_file():
                pairs.append((name, src, tgt))
    if not pairs:
        raise FileFormatError(f"{folder}: no pairs found (sub-folders with source.EXT and target.EXT, "
                              "or NAME.source.EXT beside NAME.target.EXT)")
    for i, (name, src, tgt) in enumerate(pairs, 1):
        yield {"source": str(src), "target": str(tgt), "output": f"{name}.npz",
               "options": dict(defaults), "line": i}


def _digest(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def job_key(job):
    """Hash of both input files' contents, the options and the isotween version (hex str).

    Raises
    ------
    OSError
        An input file cannot be read.
    """
    from . import __version__

    h = hashlib.sha256()
    h.update(_digest(job["source"]).encode())
    h.update(_digest(job["target"]).encode())
    h.update(json.dumps(job["options"], sort_keys=True).encode())
    h.update(__version__.encode())
    return h.hexdigest()[:32]


def run_job(job):
    """Run one job in this process; never raises.

    Parameters
    ----------
    job : dict
        source, target, output (absolute path), options, key.

    Returns
    -------
    dict
        output, key, status ('done' or 'failed'), seconds (wall clock),
        cpu_seconds (CPU time of this process during the job, all its
        threads), and iterations, energy, vertices (done) or error (failed).
    """
    start, cpu = time.perf_counter(), time.process_time()
    record = {"output": job["output"], "key": job["key"], "line": job.get("line")}
    try:
        import warnings

        from . import interpolate
        from .correspondence import check_compatible, mesh_pair, resample
        from .io import load
        from .outputs import write_output

        opts = dict(job["options"])
        points, area, fmt = opts.pop("resample", None), opts.pop("mesh", None), opts.pop("format", None)
        src, tgt = load(job["source"]), load(job["target"])
        if points is not None:
            src, tgt = resample(src, tgt, points=points)
        if area is not None:
            check_compatible(src, tgt)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                src, tgt, _ = mesh_pair(src, tgt, max_area=None if area == "auto" else area)
        seq = interpolate(src, tgt, **opts)
        write_output(seq, job["output"], format=fmt, quiet=True)
        record.update(status="done", iterations=int(seq.iterations),
                      energy=float(seq.energy[-1]) if len(seq.energy) else None,
                      vertices=int(src.n_vertices))
    except Exception as exc:  # noqa: BLE001 - one job's failure is recorded, the others go on
        record.update(status="failed", error=f"{type(exc).__name__}: {exc}")
    record["seconds"] = round(time.perf_counter() - start, 6)
    record["cpu_seconds"] = round(time.process_time() - cpu, 6)
    return record


def run_jobs(jobs):
    """`run_job` on each of a list of jobs (one task of several small jobs): list of records."""
    return [run_job(job) for job in jobs]


def run_jobs_one_thread(jobs):
    """`run_jobs` in a worker that shares the cores with other workers: `single_threaded` first."""
    single_threaded()
    return run_jobs(jobs)


_LIMITS: list = []  # threadpoolctl's limits, held for the life of the worker process


def single_threaded():
    """Run this thread's numba kernels, and this process's BLAS and OpenMP pools, on one thread.

    Every batch worker is one of several processes sharing the cores, so
    threads inside a worker would only compete with the other workers.
    numba's setting is per thread (applied on every call); the BLAS and
    OpenMP limits (threadpoolctl, with the 'fast' extra) once per process.

    Returns
    -------
    dict
        Threads now in use, as `threads_in_use` gives them.
    """
    try:
        import numba
    except ImportError:
        pass
    else:
        numba.set_num_threads(1)
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        pass
    else:
        if not _LIMITS:
            _LIMITS.append(threadpool_limits(1))
    return threads_in_use()


def threads_in_use():
    """Threads this thread's numba kernels and this process's BLAS would use.

    Returns
    -------
    dict
        ``numba`` (None without numba) and ``blas`` (the largest BLAS pool;
        None without threadpoolctl or without a BLAS loaded).
    """
    threads = {"numba": None, "blas": None}
    try:
        import numba
    except ImportError:
        pass
    else:
        threads["numba"] = numba.get_num_threads()
    try:
        from threadpoolctl import threadpool_info
    except ImportError:
        return threads
    threads["blas"] = max((p["num_threads"] for p in threadpool_info() if p["user_api"] == "blas"), default=None)
    return threads


def _start_method():
    """How local workers start: forked from this process unless that is unsafe here.

    Forking shares the imports already made (workers start at once), but GNU
    OpenMP, which numba's default threading layer uses, does not survive a
    fork once its pool runs in the parent (the child is terminated): then a
    fork server, a fresh process that imports isotween once, forks the workers.
    """
    import multiprocessing as mp
    import sys

    if "fork" not in mp.get_all_start_methods() or sys.platform == "darwin":
        return mp.get_context()
    numba = sys.modules.get("numba")
    if numba is not None:
        try:
            numba.threading_layer()
        except ValueError:  # no thread pool started in this process
            pass
        else:
            ctx = mp.get_context("forkserver")
            ctx.set_forkserver_preload(["isotween.batch", "isotween.interpolate", "isotween.correspondence",
                                        "isotween.io", "isotween.outputs"])
            return ctx
    return mp.get_context("fork")


def _finished(report):
    """Map each output to the key of its last successful record in an existing report."""
    done = {}
    if report.is_file():
        with open(report, encoding="utf-8") as f:
            for text in f:
                try:
                    rec = json.loads(text)
                except json.JSONDecodeError:
                    continue  # a line cut short by an interrupted run
                if rec.get("status") in ("done", "skipped"):
                    done[rec["output"]] = rec["key"]
                elif "output" in rec:
                    done.pop(rec["output"], None)
    return done


class _Local:
    """A ProcessPoolExecutor behind the submit / wait interface `batch` uses."""

    def __init__(self, workers):
        from concurrent.futures import ProcessPoolExecutor

        self.pool = ProcessPoolExecutor(workers, mp_context=_start_method(), initializer=single_threaded)

    def submit(self, jobs):
        return self.pool.submit(run_jobs, jobs)

    def wait(self, futures):
        from concurrent.futures import FIRST_COMPLETED, wait

        return wait(futures, return_when=FIRST_COMPLETED)[0]

    def close(self):
        self.pool.shutdown()


class _Dask:
    """A dask.distributed Client behind the same interface."""

    def __init__(self, client):
        from distributed import wait

        self.client, self._wait = client, wait

    def submit(self, jobs):
        return self.client.submit(run_jobs_one_thread, jobs, pure=False)

    def wait(self, futures):
        return self._wait(list(futures), return_when="FIRST_COMPLETED").done

    def close(self):
        pass


def batch(jobs, outdir=".", workers=None, client=None, scheduler=None, report=None, resume=True,
          window=None, progress=False, total=None, chunk=None):
    """Run many interpolations; outputs written atomically, results in a JSON Lines report.

    Parameters
    ----------
    jobs : iterable of dict, or path-like
        Dicts with ``source``, ``target``, ``output`` and optionally
        ``options`` (see `JOB_OPTIONS`), or a manifest / folder for
        `read_manifest`. Consumed lazily.
    outdir : path-like
        Relative outputs go here (created if missing).
    workers : int, optional
        Local worker processes (default: all cores), each on one thread
        (`single_threaded`). 1 runs in this process. Workers are forked from
        this process, or from a fork server once this process has started
        numba's OpenMP pool (by running jobs itself); a script that then
        calls `batch` needs the ``if __name__ == "__main__":`` guard.
    client : distributed.Client, optional
        Run on this Dask cluster instead of local processes.
    scheduler : str, optional
        Address of a Dask scheduler to connect to (``tcp://host:8786``).
    report : path-like, optional
        JSON Lines report; default ``OUTDIR/batch-report.jsonl``. Appended to.
    resume : bool
        Skip jobs whose output exists with the same key in the report.
    window : int, optional
        Most tasks in flight at once (default 4 per worker).
    chunk : int, optional
        Jobs per task (default 1 in local processes, 8 on Dask, whose
        scheduler costs a few milliseconds per task).
    progress : bool
        A tqdm progress bar on stderr.
    total : int, optional
        Job count for the progress bar (default ``len(jobs)`` where defined).

    Returns
    -------
    dict
        done, skipped, failed (counts), seconds (wall clock), failures (their records),
        report (path).

    Raises
    ------
    FileFormatError
        Unreadable manifest or unwritable output folder or report.
    ParameterError
        Bad ``workers`` or ``window``, or both ``client`` and ``scheduler``.
    """
    start = time.perf_counter()
    outdir = Path(outdir)
    if isinstance(jobs, (str, os.PathLike)):
        if total is None and Path(jobs).suffix.lower() in (".csv", ".jsonl", ".ndjson"):
            total = sum(1 for _ in read_manifest(jobs))
        jobs = read_manifest(jobs)
    elif total is None and hasattr(jobs, "__len__"):
        total = len(jobs)
    if client is not None and scheduler is not None:
        raise ParameterError("give a Dask client or a scheduler address, not both")
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise ParameterError(f"workers must be an integer >= 1, got {workers!r}")
    try:
        outdir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FileFormatError(f"cannot create folder {outdir}: {exc.strerror or exc}") from exc
    report = Path(report) if report is not None else outdir / REPORT
    finished = _finished(report) if resume else {}
    own_client = None
    if scheduler is not None:
        from .errors import require

        require("distributed", "dask")
        from distributed import Client

        try:
            client = own_client = Client(scheduler, timeout="20s")
        except OSError as exc:
            raise ParameterError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from None
    if client is not None:
        runner = _Dask(client)
        slots = sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values()) or 1
    else:
        workers = workers or os.cpu_count() or 1
        runner, slots = (_Local(workers) if workers > 1 else None), workers
    window = window or 4 * slots
    chunk = chunk or (8 if client is not None else 1)
    for name, value in (("window", window), ("chunk", chunk)):
        if not isinstance(value, int) or value < 1:
            raise ParameterError(f"{name} must be an integer >= 1, got {value!r}")
    counts = {"done": 0, "skipped": 0, "failed": 0}
    failures = []
    bar = None
    if progress:
        import sys

        from tqdm import tqdm

        bar = tqdm(total=total, desc="jobs", unit="job", file=sys.stderr)
    try:
        with open(report, "a", encoding="utf-8") as log:
            def record(rec):
                counts[rec["status"]] += 1
                if rec["status"] == "failed":
                    failures.append(rec)
                log.write(json.dumps(rec) + "\n")
                log.flush()
                if bar is not None:
                    bar.update(1)
                    bar.set_postfix(failed=counts["failed"], refresh=False)

            pending, ready = set(), []

            def collect(at_most):
                while len(pending) > at_most:
                    for fut in runner.wait(pending):
                        pending.discard(fut)
                        for rec in fut.result():
                            record(rec)

            for job in jobs:
                prepared = _prepare(job, outdir)
                if "status" in prepared:  # unreadable input: failed before it ran
                    record(prepared)
                    continue
                if (resume and finished.get(prepared["output"]) == prepared["key"]
                        and Path(prepared["output"]).exists()):
                    record({"output": prepared["output"], "key": prepared["key"],
                            "line": prepared.get("line"), "status": "skipped", "seconds": 0.0})
                    continue
                if runner is None:
                    record(run_job(prepared))
                    continue
                ready.append(prepared)
                if len(ready) == chunk:
                    pending.add(runner.submit(ready))
                    ready = []
                    collect(window - 1)
            if ready:
                pending.add(runner.submit(ready))
            collect(0)
    except OSError as exc:
        raise FileFormatError(f"cannot write the report {report}: {exc.strerror or exc}") from exc
    finally:
        if bar is not None:
            bar.close()
        if runner is not None:
            runner.close()
        if own_client is not None:
            own_client.close()
    return {**counts, "seconds": time.perf_counter() - start, "failures": failures, "report": str(report)}


def _prepare(job, outdir):
    """The job with an absolute output path and its key, or a failed record."""
    if not isinstance(job, dict) or any(k not in job for k in _FIELDS):
        raise ParameterError(f"a job is a dict with {', '.join(_FIELDS)}; got {job!r}")
    options = dict(job.get("options") or {})
    out = Path(job["output"])
    out = out if out.is_absolute() else outdir / out
    prepared = {"source": str(job["source"]), "target": str(job["target"]),
                "output": str(out.resolve()), "options": options, "line": job.get("line")}
    failed = {"output": prepared["output"], "key": None, "line": job.get("line"), "status": "failed",
              "seconds": 0.0}
    try:
        _check_options(options, f"job {job['output']}")
        prepared["key"] = job_key(prepared)
    except FileFormatError as exc:
        return {**failed, "error": f"FileFormatError: {exc}"}
    except OSError as exc:
        return {**failed, "error": f"FileFormatError: {exc.filename}: {exc.strerror or exc}"}
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return {**failed, "key": prepared["key"],
                "error": f"FileFormatError: cannot create {out.parent}: {exc.strerror or exc}"}
    return prepared


# `isotween.batch(...)` calls `batch`; `import isotween.batch` still gives this module
make_callable(__name__)
