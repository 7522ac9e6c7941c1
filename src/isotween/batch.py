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
from ._validate import check_int, is_int
from .errors import FileFormatError, IsotweenError, ParameterError

__all__ = ["batch", "read_manifest", "check_jobs", "output_path", "run_job", "run_jobs", "run_jobs_one_thread",
           "single_threaded", "threads_in_use", "JOB_OPTIONS"]


def _flag(value):
    """A yes/no option from a CSV cell ('true', '1', 'yes' or 'false', '0', 'no') or a JSON boolean."""
    if isinstance(value, bool):
        return value
    text = str(value).strip().lower()
    if text in ("true", "1", "yes"):
        return True
    if text in ("false", "0", "no"):
        return False
    raise ValueError(value)


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
    "correspondence": str,
    "stagger": float,
    "strokes": str,
    "fit": _flag,
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
    from .io._files import check_readable

    path = Path(path)
    defaults = dict(defaults or {})
    _check_options(defaults, f"{path}")
    if path.is_dir():
        yield from _folder_jobs(path, defaults)
        return
    try:
        check_readable(path)
    except FileFormatError as exc:
        raise FileFormatError(f"{exc} (the manifest)") from None
    ext = path.suffix.lower()
    if ext not in (".csv", ".jsonl", ".ndjson"):
        raise FileFormatError(f"{path}: a manifest is a .csv or .jsonl file or a folder of pairs")
    base = path.parent
    # utf-8-sig: spreadsheet programs start their CSV files with a byte-order mark
    with open(path, newline="", encoding="utf-8-sig") as f:
        try:
            if ext == ".csv":
                yield from _csv_jobs(f, defaults, base, path)
            else:
                yield from _jsonl_jobs(f, defaults, base, path)
        except UnicodeDecodeError as exc:
            raise FileFormatError(f"{path}: not a UTF-8 text file (byte {exc.start} of a block)") from None
        except csv.Error as exc:
            raise FileFormatError(f"{path}: malformed CSV ({exc})") from None


def _csv_jobs(f, defaults, base, path):
    rows = csv.DictReader(f)
    missing = [c for c in _FIELDS if c not in (rows.fieldnames or [])]
    if missing:
        raise FileFormatError(f"{path}: line 1: missing column(s) {', '.join(missing)}")
    unknown = [c for c in rows.fieldnames or [] if c not in _FIELDS and c not in JOB_OPTIONS]
    if unknown:
        raise FileFormatError(f"{path}: line 1: unknown column(s) {', '.join(map(str, unknown))}; "
                              f"options are {', '.join(JOB_OPTIONS)}")
    for row in rows:
        line = rows.line_num
        try:
            if None in row:  # more cells than columns
                raise FileFormatError(f"{path}: line {line}: more cells than the header's columns")
            options = {k: _convert(k, v, path, line) for k, v in row.items()
                       if k in JOB_OPTIONS and v not in (None, "")}
            yield _job(row, options, defaults, base, path, line)
        except FileFormatError as exc:  # this row fails alone; the others run
            yield _bad_row(row, line, exc)


def _jsonl_jobs(f, defaults, base, path):
    for line, text in enumerate(f, 1):
        if not text.strip():
            continue
        row = None
        try:
            try:
                row = json.loads(text)
            except json.JSONDecodeError as exc:
                raise FileFormatError(f"{path}: line {line}: not JSON ({exc.msg})") from None
            except (RecursionError, ValueError):
                raise FileFormatError(f"{path}: line {line}: not JSON (nested too deeply or too large)") from None
            if not isinstance(row, dict):
                raise FileFormatError(f"{path}: line {line}: expected a JSON object")
            given = row.get("options")
            if given is not None and not isinstance(given, dict):
                raise FileFormatError(f"{path}: line {line}: options must be a JSON object, "
                                      f"got {type(given).__name__}")
            options = dict(given or {})
            options.update({k: v for k, v in row.items() if k not in _FIELDS and k != "options"})
            _check_options(options, f"{path}: line {line}")
            yield _job(row, options, defaults, base, path, line)
        except FileFormatError as exc:  # this line fails alone; the others run
            yield _bad_row(row, line, exc)


def _bad_row(row, line, exc):
    """A job that fails before it runs, with the manifest's message (`batch` records it)."""
    output = row.get("output") if isinstance(row, dict) else None
    return {"source": None, "target": None, "output": output if isinstance(output, str) else f"line {line}",
            "options": {}, "line": line, "error": f"FileFormatError: {exc}"}


def _convert(key, value, path, line):
    try:
        return JOB_OPTIONS[key](value)
    except (ValueError, OverflowError):
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
        if "\0" in row[key]:
            raise FileFormatError(f"{path}: line {line}: {key} holds a NUL byte")
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

    The process runs a batch's jobs, so each of them runs on numba's kernels,
    loaded by the first (`isotween.optimisation.backend.long_lived`): a job
    gives the same frames in every runner.

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
        from .optimisation import backend
        from .outputs import write_output
        from .pipeline import morph

        backend.long_lived()
        opts = dict(job["options"])
        points, area, fmt = opts.pop("resample", None), opts.pop("mesh", None), opts.pop("format", None)
        if points is None and area is None:  # the library's pipeline: any two inputs, as `isotween interpolate`
            correspondence = opts.pop("correspondence", "auto")
            seq = morph(job["source"], job["target"], correspondence=correspondence, **opts)
        else:  # the older explicit steps (no correspondence: nothing to stagger or untangle)
            if opts.pop("fit", False):
                raise ParameterError("fit goes with correspondence, not with resample or mesh")
            for key in ("correspondence", "stagger", "strokes"):
                opts.pop(key, None)
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
                      vertices=int(seq.shape.n_vertices))
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


def _worker_start():
    """Initializer of local workers: one thread, Ctrl-C left to the parent, and an end when the parent ends.

    Ctrl-C reaches every process of the terminal's group; workers ignore it
    and the parent ends them (no "Exception ignored" from each). SIGTERM
    raises `SystemExit`, so a job's temporary file is removed. A daemon
    thread checks every half second that the parent still lives: when it
    has died (even by SIGKILL), the worker sends itself SIGTERM, and exits
    outright 3 s later if a long kernel keeps it busy.
    """
    import signal
    import threading

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, _exit_on_sigterm)
    if hasattr(signal, "pthread_sigmask"):  # blocked by `_Local.submit` while the workers were forked
        signal.pthread_sigmask(signal.SIG_UNBLOCK, _BLOCKED)
    single_threaded()
    parent = os.getppid()

    def watch():
        while os.getppid() == parent:
            time.sleep(0.5)
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(3.0)
        os._exit(1)

    threading.Thread(target=watch, name="isotween-parent-watch", daemon=True).start()


#: signals held while local workers are forked (see `_Local.submit`)
_BLOCKED = {2, 15}  # SIGINT, SIGTERM


def _exit_on_sigterm(signum, frame):
    """SIGTERM in a worker: end quietly (the parent ended it on purpose), removing a temporary file on the way."""
    try:
        os.dup2(os.open(os.devnull, os.O_WRONLY), 2)  # no traceback from wherever the exception lands
    except OSError:
        pass
    raise SystemExit(128 + signum)


class _Local:
    """A ProcessPoolExecutor behind the submit / wait interface `batch` uses."""

    def __init__(self, workers):
        from concurrent.futures import ProcessPoolExecutor

        self.pool = ProcessPoolExecutor(workers, mp_context=_start_method(), initializer=_worker_start)
        self.started = False

    def submit(self, jobs):
        """Submit a task; the first call forks the workers with Ctrl-C and SIGTERM blocked.

        A worker inherits the block and unblocks once it ignores Ctrl-C
        (`_worker_start`), so a Ctrl-C while it starts cannot print a
        traceback from it; the parent receives a signal held meanwhile when
        the block ends.
        """
        import signal

        if self.started or not hasattr(signal, "pthread_sigmask"):
            return self.pool.submit(run_jobs, jobs)
        self.started = True
        previous = signal.pthread_sigmask(signal.SIG_BLOCK, _BLOCKED)
        try:
            return self.pool.submit(run_jobs, jobs)
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, previous)

    def wait(self, futures):
        from concurrent.futures import FIRST_COMPLETED, wait

        return wait(futures, return_when=FIRST_COMPLETED)[0]

    def close(self, cancel=False):
        """Shut the pool down; with ``cancel``, drop queued jobs and end the running ones (SIGTERM)."""
        if not cancel:
            self.pool.shutdown()
            return
        processes = list((getattr(self.pool, "_processes", None) or {}).values())
        self.pool.shutdown(wait=False, cancel_futures=True)
        for proc in processes:
            if proc.is_alive():
                proc.terminate()
        deadline = time.monotonic() + 3.0  # a long numba kernel runs no Python signal handler: then SIGKILL
        for proc in processes:
            proc.join(timeout=max(deadline - time.monotonic(), 0.0))
        for proc in processes:
            if proc.is_alive():
                proc.kill()
                proc.join(timeout=5)


class _Dask:
    """A dask.distributed Client behind the same interface."""

    def __init__(self, client):
        from distributed import wait

        self.client, self._wait = client, wait

    def submit(self, jobs):
        return self.client.submit(run_jobs_one_thread, jobs, pure=False)

    def wait(self, futures):
        return self._wait(list(futures), return_when="FIRST_COMPLETED").done

    def close(self, cancel=False):
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
        check_jobs(read_manifest(jobs), outdir)  # reads the whole manifest first: colliding outputs refused
        if total is None and Path(jobs).suffix.lower() in (".csv", ".jsonl", ".ndjson"):
            total = sum(1 for _ in read_manifest(jobs))
        jobs = read_manifest(jobs)
    elif isinstance(jobs, list | tuple):
        check_jobs(jobs, outdir)
        total = len(jobs) if total is None else total
    elif total is None and hasattr(jobs, "__len__"):
        total = len(jobs)
    if client is not None and scheduler is not None:
        raise ParameterError("give a Dask client or a scheduler address, not both")
    if workers is not None:
        check_int("workers", workers, 1)
    try:
        outdir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise FileFormatError(f"cannot create folder {outdir}: {exc.strerror or exc}") from exc
    outdir = outdir.resolve()
    seen = {}  # outputs taken in this run -> their job
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
        check_int(name, value, 1)
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
                prepared = _prepare(job, outdir, seen)
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
    except BaseException:  # Ctrl-C, SIGTERM, an error here: queued jobs are dropped, running ones ended
        if runner is not None:
            runner.close(cancel=True)
            runner = None
        raise
    finally:
        if bar is not None:
            bar.close()
        if runner is not None:
            runner.close()
        if own_client is not None:
            own_client.close()
    return {**counts, "seconds": time.perf_counter() - start, "failures": failures, "report": str(report)}


def _option_types(options, where):
    """Raise `ParameterError` for an option whose value has the wrong type (before its job runs)."""
    for key, value in options.items():
        kind = JOB_OPTIONS.get(key)
        if kind is int:
            ok = is_int(value)
        elif kind is float:
            ok = isinstance(value, int | float) and not isinstance(value, bool)
        elif kind is str:
            ok = isinstance(value, str)
        elif kind is _flag:
            ok = isinstance(value, bool)
        else:  # mesh: 'auto' or a number
            ok = value == "auto" or isinstance(value, int | float) and not isinstance(value, bool)
        if not ok:
            raise ParameterError(f"{where}: option {key} has the wrong type ({type(value).__name__}: "
                                 f"{str(value)[:40]!r})")


def output_path(outdir, output):
    """Where a job's output goes: inside ``outdir``, through no symbolic link.

    Parameters
    ----------
    outdir : Path
        The batch's output folder, resolved (``Path.resolve``).
    output : str or path-like
        The job's output, relative to ``outdir``.

    Returns
    -------
    Path
        Absolute path below ``outdir``. Nothing is created.

    Raises
    ------
    FileFormatError
        An absolute path, a ``..`` component, a NUL byte, a folder of the
        path (or the output itself) that is a symbolic link, or a folder
        of the path that is a file.
    """
    from .io._files import check_path_text

    rel = check_path_text(output)
    if not str(rel).strip() or str(rel) in (".", "-"):
        raise FileFormatError(f"output {str(output)!r}: not a file name")
    if rel.is_absolute():
        raise FileFormatError(f"output {rel}: an absolute path; outputs are relative to the output folder")
    if ".." in rel.parts:
        raise FileFormatError(f"output {rel}: '..' would leave the output folder")
    path = outdir
    for i, part in enumerate(rel.parts):
        path = path / part
        if os.path.islink(path):
            what = "is" if i == len(rel.parts) - 1 else "goes through"
            raise FileFormatError(f"output {rel} {what} the symbolic link {path}; links are not followed "
                                  "for writing")
        if i < len(rel.parts) - 1 and os.path.exists(path) and not os.path.isdir(path):
            raise FileFormatError(f"output {rel}: {path} is a file, not a folder")
    return path


def _make_parents(outdir, path):
    """Create the folders between ``outdir`` and ``path`` one by one, refusing any that is a link."""
    folder = outdir
    for part in path.relative_to(outdir).parts[:-1]:
        folder = folder / part
        try:
            os.mkdir(folder)
        except FileExistsError:
            pass
        if os.path.islink(folder) or not os.path.isdir(folder):
            raise FileFormatError(f"cannot create {folder}: a link or a file is in the way")


def check_jobs(jobs, outdir="."):
    """Refuse, before anything runs, jobs whose outputs collide or overwrite an input.

    Parameters
    ----------
    jobs : iterable of dict
        As `batch` takes them (or `read_manifest` yields them).
    outdir : path-like

    Raises
    ------
    FileFormatError
        Naming both jobs (manifest line or output) of the first output that
        two jobs write, or of the first output that is any job's input.
        Jobs that cannot be placed at all (bad fields, outputs outside the
        folder) are left to `batch`, which records them as failed.
    """
    outdir = Path(outdir).resolve()
    outputs, inputs = {}, {}

    def name(job):
        return f"line {job['line']}" if job.get("line") is not None else f"job {str(job.get('output'))!r}"

    def key(path):
        try:
            st = os.stat(path)
        except (OSError, ValueError):
            return ("path", os.path.abspath(path))
        return ("inode", st.st_dev, st.st_ino)

    for job in jobs:
        if not isinstance(job, dict) or "error" in job:
            continue
        try:
            out = output_path(outdir, job.get("output"))
        except IsotweenError:
            continue
        for field in ("source", "target"):
            value = job.get(field)
            if isinstance(value, str | os.PathLike):
                inputs.setdefault(key(os.path.abspath(value)), job)
                inputs.setdefault(("path", os.path.abspath(value)), job)
        mine = key(out)
        other = outputs.get(mine) or outputs.get(("path", str(out)))
        if other is not None:
            raise FileFormatError(f"{name(job)} and {name(other)} both write {out}; one would replace the other "
                                  "(give each job its own output)")
        outputs[mine] = outputs[("path", str(out))] = job
    for mine, job in outputs.items():
        source = inputs.get(mine)
        if source is not None:
            raise FileFormatError(f"{name(job)}: output {job['output']} is an input of {name(source)}; it "
                                  "would be overwritten (choose another output)")


def _prepare(job, outdir, seen=None):
    """The job with an absolute output path and its key, or a failed record.

    ``seen`` maps outputs already taken in this run to their job's line
    (jobs from an iterator are checked as they come).
    """
    from .io._files import check_readable

    if not isinstance(job, dict) or any(k not in job for k in _FIELDS):
        raise ParameterError(f"a job is a dict with {', '.join(_FIELDS)}; got {str(job)[:200]}")
    failed = {"output": str(job.get("output")), "key": None, "line": job.get("line"), "status": "failed",
              "seconds": 0.0}
    if "error" in job:  # a manifest row that could not be read
        return {**failed, "error": job["error"]}
    where = f"line {job['line']}" if job.get("line") is not None else f"job {str(job['output'])[:80]!r}"
    try:
        options = job.get("options") or {}
        if not isinstance(options, dict):
            raise ParameterError(f"{where}: options must be a dict, got {type(options).__name__}")
        options = dict(options)
        _check_options(options, where)
        _option_types(options, where)
        for field in ("source", "target"):
            if not isinstance(job[field], str | os.PathLike):
                raise ParameterError(f"{where}: {field} must be a path, got {type(job[field]).__name__}")
            check_readable(job[field])
        if not isinstance(job["output"], str | os.PathLike):
            raise ParameterError(f"{where}: output must be a path, got {type(job['output']).__name__}")
        out = output_path(outdir, job["output"])
        failed["output"] = str(out)
        if seen is not None:
            if str(out) in seen:
                raise FileFormatError(f"{where}: output {out} is also the output of {seen[str(out)]}")
            seen[str(out)] = where
        prepared = {"source": str(job["source"]), "target": str(job["target"]), "output": str(out),
                    "options": options, "line": job.get("line")}
        for field in ("source", "target"):
            if os.path.exists(out) and os.path.samefile(out, prepared[field]):
                raise FileFormatError(f"{where}: output {out} is its own {field}; it would be overwritten")
        prepared["key"] = job_key(prepared)
    except IsotweenError as exc:
        text = str(exc) if str(exc).startswith(where) or where in str(exc) else f"{where}: {exc}"
        return {**failed, "error": f"{type(exc).__name__}: {text}"}
    except OSError as exc:
        return {**failed, "error": f"FileFormatError: {where}: {exc.filename}: {exc.strerror or exc}"}
    try:
        _make_parents(outdir, out)
    except FileFormatError as exc:
        return {**failed, "key": prepared["key"], "error": f"FileFormatError: {exc}"}
    except OSError as exc:
        return {**failed, "key": prepared["key"],
                "error": f"FileFormatError: cannot create {out.parent}: {exc.strerror or exc}"}
    return prepared


# `isotween.batch(...)` calls `batch`; `import isotween.batch` still gives this module
make_callable(__name__)
