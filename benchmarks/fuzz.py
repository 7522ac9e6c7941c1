"""Fuzzing the shape, sequence and manifest loaders with mutated valid files.

Every loader (OBJ, OFF, JSON, SVG, NPZ shapes; NPZ and JSON sequences; CSV
and JSON Lines batch manifests) reads files made from valid seeds by byte
flips, splices, truncation, swaps of numbers for huge, NaN, negative or
malformed ones, repeated or dropped lines and deep nesting; sequence files
also get hostile ``info`` (keyframe indices, paint, energy, times), manifests
hostile cells (NUL bytes, ``..``, absolute paths, options of the wrong type),
and SVG files random ``<use>`` graphs (copies of copies, cycles, missing
targets). A sequence that loads is also turned into the viewer page's data
(every JSON writer's check). The only allowed outcomes are a Shape (or
Sequence, or a list of jobs) or an `IsotweenError`, within a time bound (a watchdog alarm per input) and a memory
bound (``RLIMIT_AS`` in each worker). Any other outcome is a bug; the first
input of each kind is kept under ``--keep`` for reproduction.

Usage::

    python3 benchmarks/fuzz.py --inputs 100000 --workers 2           # prints the table
    python3 benchmarks/fuzz.py --inputs 100000 --workers 2 --write   # and RESULTS.md, Reliability

``--write`` also times the command lines the resource guards refuse (peak
memory by ``/usr/bin/time``) and counts the cases of tests/test_hostile.py.

Not part of the test suite; ``tests/test_hostile.py`` runs 300 inputs of it.
"""

import argparse
import io as _io
import os
import random
import re
import signal
import sys
import tempfile
import time
import zipfile
from collections import Counter
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # small address space per worker
os.environ.setdefault("OMP_NUM_THREADS", "1")

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "src"))

from isotween import Shape, io  # noqa: E402
from isotween.errors import IsotweenError  # noqa: E402
from isotween.sequence import Sequence  # noqa: E402

#: per-input limits: seconds, plus seconds per MB of input (mutations that repeat lines make
#: valid files of several MB, which the text parsers read at about 1 MB/s alone and slower on
#: a machine shared with other jobs)
TIME_LIMIT = 5.0
TIME_PER_MB = 5.0
MEMORY_LIMIT = 2 << 30  # bytes of address space per worker

NUMBERS = ["1e400", "-1e400", "nan", "NaN", "inf", "-inf", "1e200", "-1e308", "99999999999999999999999",
           "-99999999999999999999999", "0", "-0", "-1", "-2", "4294967296", "9223372036854775808", "1.5",
           "1e-320", "0x10", "", "--1", "1e", ".", "3e3e3", "1" * 400]
NUMBER = re.compile(rb"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


# ------------------------------------------------------------------ seeds
def _seed_shapes():
    t = np.linspace(0, 2 * np.pi, 12, endpoint=False)
    ring = Shape.from_polygon([np.c_[np.cos(t), np.sin(t)], 0.3 * np.c_[np.cos(t[:6]), np.sin(t[:6])][::-1]])
    chain = Shape.from_polyline(np.c_[np.linspace(0, 1, 7), np.linspace(0, 1, 7) ** 2])
    x, y = np.meshgrid(np.arange(4.0), np.arange(3.0), indexing="ij")
    v = np.c_[x.ravel(), y.ravel()]
    idx = np.arange(12).reshape(4, 3)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    mesh = Shape(v, faces=np.vstack([np.c_[a, b, c], np.c_[a, c, d]]), uv=v / v.max(axis=0))
    return [ring, chain, mesh]


SVG_SEEDS = [
    b'<?xml version="1.0"?>\n<svg xmlns="http://www.w3.org/2000/svg" '
    b'xmlns:xlink="http://www.w3.org/1999/xlink" viewBox="0 0 100 100">\n'
    b'<g transform="translate(10,5) rotate(30)">\n'
    b'<path id="a" d="M 0 0 L 10 0 Q 15 5 10 10 C 8 12 2 12 0 10 A 5 5 0 0 1 0 0 Z M 20 20 l 5 0 l 0 5 z"/>\n'
    b'<polygon points="30,30 40,30 40,40 30,40"/>\n<polyline points="0,50 10,55 20,50"/>\n</g>\n'
    b'<rect x="50" y="50" width="20" height="10" rx="2"/>\n<circle cx="80" cy="20" r="8"/>\n'
    b'<ellipse cx="20" cy="80" rx="8" ry="4"/>\n<line x1="0" y1="0" x2="5" y2="9"/>\n'
    b'<defs><polygon id="p" points="0,0 3,0 3,3"/></defs><use xlink:href="#p" x="60" y="60"/>\n</svg>\n',
    b'<svg xmlns="http://www.w3.org/2000/svg"><path d="m 1,1 h 10 v 10 h -10 z m 2,2 h 3 v 3 h -3 z"/>'
    b'<path d="M 0 0 S 5 5 10 0 T 20 0"/></svg>',
]


MANIFEST_SEEDS = [
    (".csv", b"source,target,output,frames,tol\na.json,b.json,out/a.npz,5,\nsub/c.svg,d.obj,b.gif,,1e-4\n"),
    (".jsonl", b'{"source": "a.json", "target": "b.json", "output": "a.npz", "options": {"frames": 5}}\n'
               b'{"source": "c.svg", "target": "d.obj", "output": "f/b.npz", "resample": 40, "mesh": "auto"}\n'),
]
#: hostile manifest cells
CELLS = ["", "\0", "a\0.json", "../../x.npz", "/etc/passwd", "-", ".", "a.json", "b.json", "x" * 300,
         "\ufeffsource", "\x1b[2J", "out/../../y.npz", "nan", "1e999", "[1]", '"fast"', "{}", "null", "true"]


def _manifest_cells(rng, data):
    """Replace a cell (CSV) or a value (JSON Lines) of a manifest with a hostile one."""
    import json

    text = data.decode("utf-8", "surrogateescape")
    if text.lstrip().startswith("{"):
        lines = text.splitlines()
        k = rng.randrange(len(lines)) if lines else 0
        try:
            row = json.loads(lines[k])
            key = rng.choice(sorted(row) + ["options", "frames", "output"])
            value = rng.choice(CELLS)
            row[key] = json.loads(value) if value in ("[1]", '"fast"', "{}", "null", "true", "1e999") else value
            lines[k] = json.dumps(row)
        except (ValueError, IndexError, TypeError, AttributeError, RecursionError):
            return _flip(rng, data)
        return "\n".join(lines).encode("utf-8", "surrogateescape") + b"\n"
    rows = [line.split(",") for line in text.splitlines()]
    if len(rows) > 1:
        r = rng.randrange(1, len(rows))
        rows[r][rng.randrange(len(rows[r]))] = rng.choice(CELLS)
    return "\n".join(",".join(r) for r in rows).encode("utf-8", "surrogateescape") + b"\n"


def _use_graph(rng):
    """An SVG of random ``<use>`` links: copies of copies, links to themselves or ancestors, missing targets.

    Most graphs expand to a few thousand elements at most (read within the time limit); one in five
    is a bomb (ten copies over every level), which the reader must refuse before expanding it.
    """
    bomb = rng.random() < 0.2
    n = rng.randint(7, 12) if bomb else rng.randint(2, 12)  # a bomb: at least 10^6 elements
    count = [1]  # elements each id expands to
    parts = ['<svg xmlns="http://www.w3.org/2000/svg"><defs><rect id="e0" width="1" height="1"/>']
    for k in range(1, n):
        refs, total = [], 1
        for i in range(10 if bomb else rng.choice([1, 2, 3])):
            t = k - 1 if bomb else rng.randrange(k + (2 if rng.random() < 0.1 else 0))  # k, k+1: a cycle, ahead
            if not bomb and t < k and total + count[t] > 600:
                continue
            refs.append(f'<use href="#e{t}" x="{i}"/>')
            total += 1 + (count[t] if t < k else 0)
        count.append(total)
        parts.append(f'<g id="e{k}">{"".join(refs)}</g>' if rng.random() < 0.8
                     else f'<g id="e{k}"><g>{"".join(refs)}</g></g>')
    parts.append(f'</defs><use href="#e{n - 1 if bomb else rng.randrange(n)}"/><use href="#missing"/></svg>')
    return "".join(parts).encode()


def _sequence_info(rng, data, ext):
    """Rewrite a sequence file's info, energy or times with values that disagree with its frames."""
    import json

    values = [["x"], [99], [-1], [True], "abc", {"a": 1}, [0.5], None, [[0]], 1e400]
    info = rng.choice([
        {"keyframe_indices": rng.choice(values)},
        {"paint": rng.choice([{"times": [0, 1], "keys": [[{}], [{}]], "regions": rng.choice(values)},
                              {"times": rng.choice(values), "keys": rng.choice(values)}, "red", [1, 2]])},
        rng.choice(values),
    ])
    try:
        if ext == ".npz":
            with np.load(_io.BytesIO(data), allow_pickle=False) as z:
                arrays = {k: z[k] for k in z.files}
            field = rng.choice(["info", "energy", "times"])
            if field == "info":
                arrays["info"] = np.array(json.dumps(info, allow_nan=True))
            else:
                a = np.array(arrays.get(field, np.zeros(3)), dtype=float)
                if a.size:
                    a.flat[rng.randrange(a.size)] = rng.choice([np.nan, np.inf, -5.0, 1e308])
                arrays[field] = a
            buf = _io.BytesIO()
            np.savez(buf, **arrays)
            return buf.getvalue()
        doc = json.loads(data)
        field = rng.choice(["info", "energy", "times"])
        doc[field] = info if field == "info" else [rng.choice([float("nan"), 1e308, -1.0, "x"])] * 4
        return json.dumps(doc, allow_nan=True).encode()
    except Exception:  # noqa: BLE001 - an earlier mutation broke the file: mutate it otherwise
        return _flip(rng, data)


def seeds():
    """(extension, kind, bytes) of every valid seed file; kind is 'shape', 'sequence' or 'manifest'."""
    out = []
    shapes = _seed_shapes()
    with tempfile.TemporaryDirectory() as tmp:
        for k, shape in enumerate(shapes):
            for ext in (".obj", ".off", ".json", ".npz", ".svg"):
                if ext == ".svg" and shape.faces is not None:
                    continue
                path = Path(tmp) / f"s{k}{ext}"
                io.save(shape, path)
                out.append((ext, "shape", path.read_bytes()))
        from isotween import interpolate

        seq = interpolate(shapes[0], shapes[0].with_vertices(shapes[0].vertices * [1.5, 0.7]), frames=4)
        for ext in (".npz", ".json"):
            path = Path(tmp) / f"seq{ext}"
            io.save_sequence(seq, path)
            out.append((ext, "sequence", path.read_bytes()))
    out += [(".svg", "shape", s) for s in SVG_SEEDS]
    out += [(ext, "manifest", s) for ext, s in MANIFEST_SEEDS]
    return out


# ------------------------------------------------------------------ mutations
def _flip(rng, data):
    b = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        if b:
            b[rng.randrange(len(b))] = rng.randrange(256)
    return bytes(b)


def _bit(rng, data):
    b = bytearray(data)
    if b:
        i = rng.randrange(len(b))
        b[i] ^= 1 << rng.randrange(8)
    return bytes(b)


def _truncate(rng, data):
    return data[: rng.randrange(len(data) + 1)]


def _splice(rng, data, other):
    i, j = sorted(rng.randrange(len(data) + 1) for _ in range(2))
    k, m = sorted(rng.randrange(len(other) + 1) for _ in range(2))
    return data[:i] + other[k:m] + data[j:]


def _number(rng, data):
    found = list(NUMBER.finditer(data))
    if not found:
        return _flip(rng, data)
    for _ in range(rng.randint(1, 3)):
        m = rng.choice(found)
        new = rng.choice(NUMBERS).encode()
        data = data[: m.start()] + new + data[m.end():]
        found = list(NUMBER.finditer(data))
        if not found:
            break
    return data


def _lines(rng, data):
    lines = data.split(b"\n")
    i = rng.randrange(len(lines))
    op = rng.randrange(3)
    if op == 0:
        del lines[i]
    elif op == 1:
        lines.insert(i, lines[rng.randrange(len(lines))] * rng.randint(1, 3))
    else:
        lines[i:i] = [lines[i]] * rng.randint(2, 50)
    return b"\n".join(lines)


def _nest(rng, data, ext):
    depth = rng.choice([10, 100, 1000, 100000])
    if ext == ".json":
        i = data.find(b"[")
        if i < 0:
            return b"[" * depth + data + b"]" * depth
        return data[:i] + b"[" * depth + data[i:i + 1] + b"]" * depth + data[i + 1:]
    if ext == ".svg":
        i = data.find(b">", data.find(b"<svg")) + 1
        return data[:i] + b"<g>" * depth + b"</g>" * depth + data[i:]
    return data * min(depth, 50)


def _npz_arrays(rng, data):
    """Rewrite one array of a .npz with hostile values, dtype or shape."""
    import warnings

    with np.errstate(all="ignore"), warnings.catch_warnings():  # lossy casts are what this is for
        warnings.simplefilter("ignore")
        return _npz_rewrite(rng, data)


def _npz_rewrite(rng, data):
    try:
        with np.load(_io.BytesIO(data), allow_pickle=False) as z:
            arrays = {k: z[k] for k in z.files}
    except Exception:
        return _flip(rng, data)
    name = rng.choice(sorted(arrays))
    a = arrays[name]
    choice = rng.randrange(8)
    if choice == 0 and a.size and a.dtype.kind == "f":
        a = a.copy()
        a.flat[rng.randrange(a.size)] = rng.choice([np.nan, np.inf, -np.inf, 1e200, -1e308])
    elif choice == 1 and a.size and a.dtype.kind in "iu":
        a = a.astype(np.int64)
        a.flat[rng.randrange(a.size)] = rng.choice([-1, 2**62, -(2**63), 10**9, a.max() + 1 if a.size else 0])
    elif choice == 2:
        try:
            a = a.astype(rng.choice(["<U3", "bool", "complex128", "float16", "uint8", "int8"]))
        except (ValueError, TypeError, OverflowError):
            a = np.array(["text"])
    elif choice == 3:
        a = a.reshape(-1) if a.ndim else np.zeros((2, 2, 2))
    elif choice == 4:
        a = a[: rng.randrange(max(len(a), 1) + 1)] if a.ndim else a
    elif choice == 5:
        del arrays[name]
        buf = _io.BytesIO()
        np.savez(buf, **arrays)
        return buf.getvalue()
    elif choice == 6:
        a = np.zeros(0) if rng.random() < 0.5 else np.array(3.0)
    else:  # a header that claims a huge shape
        buf = _io.BytesIO()
        np.savez(buf, **arrays)
        raw = buf.getvalue()
        return re.sub(rb"\((\d+),", lambda m: b"(" + str(int(m.group(1)) * 10**9).encode() + b",", raw, count=1)
    arrays[name] = a
    buf = _io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def mutate(rng, ext, data, pool, kind="shape"):
    """One hostile variant of ``data`` (a valid ``ext`` file of ``kind``)."""
    ops = ["flip", "bit", "truncate", "splice", "number", "number", "lines", "nest"]
    if ext == ".npz":
        ops += ["npz", "npz", "npz"]
    if kind == "sequence":
        ops += ["info"] * 6
    if kind == "manifest":
        ops += ["cells"] * 8
    if ext == ".svg" and rng.random() < 0.2:
        return _use_graph(rng)
    out = data
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        op = rng.choice(ops)
        if op == "flip":
            out = _flip(rng, out)
        elif op == "bit":
            out = _bit(rng, out)
        elif op == "truncate":
            out = _truncate(rng, out)
        elif op == "splice":
            out = _splice(rng, out, rng.choice(pool))
        elif op == "number":
            out = _number(rng, out)
        elif op == "lines":
            out = _lines(rng, out)
        elif op == "nest":
            out = _nest(rng, out, ext)
        elif op == "info":
            out = _sequence_info(rng, out, ext)
        elif op == "cells":
            out = _manifest_cells(rng, out)
        else:
            out = _npz_arrays(rng, out)
    return out


# ------------------------------------------------------------------ workers
class _Timeout(BaseException):
    """Raised by the watchdog alarm; not an Exception, so loaders cannot swallow it."""


def _alarm(signum, frame):
    raise _Timeout()


_STATE = {}


def _init(limit_bytes):
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (limit_bytes, limit_bytes))
    signal.signal(signal.SIGALRM, _alarm)
    _STATE["dir"] = tempfile.mkdtemp(prefix="isotween-fuzz-")
    _STATE["seeds"] = seeds()


def _one(index, base_seed):
    """Load the ``index``-th mutated file; (outcome, seconds, ext, size, data or None)."""
    rng = random.Random(base_seed * 1_000_003 + index)
    ext, kind, data = rng.choice(_STATE["seeds"])
    pool = [s for e, _, s in _STATE["seeds"] if e == ext]
    data = mutate(rng, ext, data, pool, kind)
    path = Path(_STATE["dir"]) / f"input{ext}"
    path.write_bytes(data)
    loader = {"sequence": _load_and_page, "manifest": _load_manifest}.get(kind, io.load)
    t0 = time.perf_counter()
    signal.setitimer(signal.ITIMER_REAL, TIME_LIMIT + TIME_PER_MB * len(data) / 1e6)
    try:
        result = loader(path)
        signal.setitimer(signal.ITIMER_REAL, 0)
        ok = isinstance(result, {"sequence": Sequence, "manifest": list}.get(kind, Shape))
        outcome = kind if ok else f"BUG wrong type {type(result).__name__}"
    except _Timeout:
        outcome = "BUG timeout"
    except IsotweenError as exc:
        signal.setitimer(signal.ITIMER_REAL, 0)
        outcome = f"error {type(exc).__name__}"
    except MemoryError:
        signal.setitimer(signal.ITIMER_REAL, 0)
        outcome = "BUG MemoryError"
    except BaseException as exc:  # noqa: BLE001 - any other outcome is what we look for
        signal.setitimer(signal.ITIMER_REAL, 0)
        outcome = f"BUG {type(exc).__name__}: {str(exc)[:80]}"
    seconds = time.perf_counter() - t0
    return outcome, seconds, ext, len(data), (data if outcome.startswith("BUG") else None)


def _load_and_page(path):
    """`load_sequence`, then the viewer page's data as JSON: what loads must also be writable."""
    from isotween.io._json import dumps_finite
    from isotween.render.html import page_data

    seq = io.load_sequence(path)
    dumps_finite(page_data(seq, downloads={}), path)
    return seq


def _load_manifest(path):
    """Every job of a manifest, and the check of their outputs (`batch`'s first steps; nothing runs)."""
    from isotween.batch import check_jobs, read_manifest

    jobs = list(read_manifest(path))
    check_jobs(jobs, path.parent / "out")
    return jobs


def _batch(args):
    start, stop, base_seed = args
    return [_one(i, base_seed) for i in range(start, stop)]


def run(inputs, workers=2, seed=1, batch=200, progress=False):
    """Fuzz ``inputs`` files.

    Returns
    -------
    counts : Counter
        Inputs per (extension, outcome).
    seconds : float
    bugs : dict {(extension, outcome): bytes}
        One input of every outcome that is not allowed.
    slowest : (float, int)
        Seconds and bytes of the slowest input.

    With ``workers=1`` it runs in this process (the memory limit is then not set).
    """
    tasks = [(i, min(i + batch, inputs), seed) for i in range(0, inputs, batch)]
    counts, bugs, slowest = Counter(), {}, (0.0, 0)
    t0 = time.perf_counter()
    previous = None
    if workers == 1:
        _STATE.setdefault("seeds", seeds())
        _STATE.setdefault("dir", tempfile.mkdtemp(prefix="isotween-fuzz-"))
        previous = signal.signal(signal.SIGALRM, _alarm)
        results = map(_batch, tasks)
    else:
        import multiprocessing

        pool = multiprocessing.get_context("fork").Pool(workers, _init, (MEMORY_LIMIT,))
        results = pool.imap_unordered(_batch, tasks)
    done = 0
    for rows in results:
        for outcome, seconds, ext, size, data in rows:
            counts[(ext, outcome)] += 1
            slowest = max(slowest, (seconds, size))
            if data is not None and (ext, outcome) not in bugs:
                bugs[(ext, outcome)] = data
        done += len(rows)
        if progress and done % 10000 < batch:
            n_bug = sum(v for (e, o), v in counts.items() if o.startswith('BUG'))
            print(f"{done} inputs, {time.perf_counter() - t0:.0f} s, bugs: {n_bug}", file=sys.stderr)
    if workers != 1:
        pool.close()
        pool.join()
    else:
        signal.signal(signal.SIGALRM, previous)
    return counts, time.perf_counter() - t0, bugs, slowest


def report(counts):
    """Markdown table: inputs per format and outcome."""
    from _results import table

    formats = sorted({e for e, _ in counts})
    outcomes = sorted({o for _, o in counts}, key=lambda o: (o.startswith("BUG"), o))
    rows = [[o] + [counts.get((e, o), 0) for e in formats] + [sum(counts.get((e, o), 0) for e in formats)]
            for o in outcomes]
    rows.append(["**all**"] + [sum(v for (e, _), v in counts.items() if e == f) for f in formats]
                + [sum(counts.values())])
    return table(["outcome"] + formats + ["total"], rows)


#: command lines refused by the resource guards, with what they cost before the guards
GUARDED = [
    (["interpolate", "{a}", "{b}", "--frames", "1000000000", "-o", "{out}/o.npz"],
     "39 s and 15.7 GB, then a MemoryError traceback"),
    (["interpolate", "{a}", "{b}", "--frames", "100000", "-o", "{out}/o.gif"],
     "a GIF of 100,000 frames drawn in memory (about 75 GB)"),
    (["interpolate", "{e1}", "{e2}", "--resample", "40", "--mesh", "1e-9", "-o", "{out}/o.gif"],
     "grew to 24 GB and was killed by the kernel"),
    (["interpolate", "{lie}", "{a}", "-o", "{out}/o.gif"], "MemoryError traceback"),
    (["info", "{squares}"], "15,000 small squares (230 KB): over 5 GB in 12 s (a dense winding-number matrix)"),
    (["info", "{bomb}"], "`<use>` bomb (8 levels x 10 copies): SystemError after 160 s at 3.7 GB"),
    (["interpolate", "{e1}", "{e2}", "--points", "10000000", "--max-memory", "4G", "-o", "{out}/o.npz"],
     "a segfault in shapely under a memory cap"),
    (["interpolate", "{a}", "{b}", "--frames", "300", "--size", "4000", "-o", "{out}/o.gif"], "over 5 GB"),
    (["interpolate", "{a}", "{b}", "--frames", "300", "--size", "2000", "-o", "{out}/o.mp4"],
     "every frame drawn in memory first (3000 frames: over 5 GB)"),
    (["interpolate", "{a}", "{b}", "--fps", "1e-300", "-o", "{out}/o.gif"], "OverflowError traceback (Pillow)"),
    (["info", "{fifo}"], "hangs (reads a FIFO)"),
]


def guards():
    """Peak memory and time of the guarded command lines (``/usr/bin/time``); a Markdown table."""
    import shutil
    import subprocess

    from _results import table

    timer = shutil.which("time") or "/usr/bin/time"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        t = np.linspace(0, 2 * np.pi, 40, endpoint=False)
        io.save(Shape.from_polygon([[0, 0], [1, 0], [1, 1], [0, 1]]), tmp / "a.json")  # two squares
        io.save(Shape.from_polygon([[0, 0], [2, 0], [2, 1], [0, 1]]), tmp / "b.json")
        io.save(Shape.from_polygon(np.c_[2 * np.cos(t), np.sin(t)]), tmp / "e1.svg")
        io.save(Shape.from_polygon(np.c_[np.cos(t), 2 * np.sin(t)]), tmp / "e2.svg")
        buf = _io.BytesIO()
        np.save(buf, np.zeros((1, 2)))
        with zipfile.ZipFile(tmp / "lie.npz", "w") as z:
            z.writestr("vertices.npy", buf.getvalue().replace(b"(1, 2)", b"(1000000000000, 2)"))
        squares = " ".join(f"M{2 * (i % 125)} {2 * (i // 125)}h1v1h-1z" for i in range(15000))
        (tmp / "squares.svg").write_text(f'<svg xmlns="http://www.w3.org/2000/svg"><path d="{squares}"/></svg>')
        bomb = '<defs><rect id="l0" width="1" height="1"/>' + "".join(
            f'<g id="l{k}">' + "".join(f'<use href="#l{k - 1}" x="{i}"/>' for i in range(10)) + "</g>"
            for k in range(1, 9))
        (tmp / "bomb.svg").write_text(f'<svg xmlns="http://www.w3.org/2000/svg">{bomb}</defs><use href="#l8"/></svg>')
        os.mkfifo(tmp / "fifo.svg")
        names = {k: tmp / f for k, f in (("a", "a.json"), ("b", "b.json"), ("e1", "e1.svg"), ("e2", "e2.svg"),
                                          ("lie", "lie.npz"), ("squares", "squares.svg"), ("bomb", "bomb.svg"),
                                          ("fifo", "fifo.svg"))}
        env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
        for args, before in GUARDED:
            argv = [a.format(out=tmp, **names) for a in args]
            proc = subprocess.run([timer, "-f", "%M %e", sys.executable, "-m", "isotween", *argv],
                                  capture_output=True, text=True, env=env)
            lines = proc.stderr.strip().splitlines()
            rss, seconds = lines[-1].split()
            message = next((ln for ln in lines if ln.startswith("error:")),
                           "(no error line)" if proc.returncode else "written" if "-o" in argv else "printed")
            message = message.replace(f"{tmp}/", "")
            shown = " ".join(Path(a).name for a in argv)
            rows.append([f"`isotween {shown}`", before, f"exit {proc.returncode}: `{message}`",
                         f"{int(rss) / 1024:.0f} MB", f"{float(seconds):.2f} s"])
    return table(["command", "reported before the guards", "now", "peak RSS", "time"], rows)


def hostile_cases():
    """Number of test cases in tests/test_hostile.py (pytest's collection)."""
    import subprocess

    proc = subprocess.run([sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider",
                           str(ROOT / "tests" / "test_hostile.py")], capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=str(ROOT / "src")), cwd=ROOT)
    return sum(1 for line in proc.stdout.splitlines() if "::" in line)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--inputs", type=int, default=100_000)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--keep", default=None, help="folder for one input of every bug outcome")
    parser.add_argument("--write", action="store_true", help="write the Reliability section of RESULTS.md")
    args = parser.parse_args()
    sys.path.insert(0, str(Path(__file__).parent))
    counts, seconds, bugs, slowest = run(args.inputs, args.workers, args.seed, progress=True)
    text = report(counts)
    print(text)
    n_bugs = sum(v for (_, o), v in counts.items() if o.startswith("BUG"))
    summary = (f"{sum(counts.values())} inputs in {seconds:.0f} s with {args.workers} workers "
               f"(limits per input: {TIME_LIMIT:g} s + {TIME_PER_MB:g} s per MB, {MEMORY_LIMIT >> 30} GiB address "
               f"space per worker); "
               f"slowest input {slowest[0]:.2f} s ({slowest[1] / 1e6:.2f} MB); "
               f"{n_bugs} inputs with an outcome other than a shape, "
               "a sequence, a list of jobs or an IsotweenError.")
    print(summary)
    if args.keep and bugs:
        keep = Path(args.keep)
        keep.mkdir(parents=True, exist_ok=True)
        for k, ((ext, outcome), data) in enumerate(bugs.items()):
            (keep / f"bug{k}{ext}").write_bytes(data)
            print(f"bug{k}{ext}: {outcome}")
    if args.write:
        from _results import write_section

        guarded = guards()
        print(guarded)
        cases = hostile_cases()
        body = (f"### Hostile inputs\n\n`tests/test_hostile.py` tries {cases} hostile inputs (library values, "
                "every loader, every command and option, SIGINT and SIGTERM during the solve and the rendering); "
                "each must give its exact error class, or exit code 2 and one `error:` line with no traceback, "
                "and leave no file behind. Round 3 (issue 25) added: batch outputs outside the output folder "
                "(`..`, absolute, through a symbolic link, a link to a file), two jobs with one output, an output "
                "that is an input, malformed manifest rows (NUL bytes, options of the wrong type, extra cells, "
                "bad JSON, FIFOs) failing alone, non-UTF-8 and byte-order-marked manifests; Ctrl-C and kill -9 "
                "of a batch (its workers end within 3 s); a full disk under MP4 (ffmpeg's status) and GIF; "
                "`-o x.svg --plot x.svg`, `-o -`, 250- and 300-byte names; titles with `<!--<script>`, control "
                "characters and undecodable bytes; newlines and escape sequences in file names and SVG ids "
                "(escaped in the one `error:` line), warnings before an error; GIF and APNG delays beyond "
                "their 16 bits; non-finite values in Lottie and the page; sequence files whose info, energy or "
                "times disagree with their frames (refused at load, and by `save_sequence` and every writer); "
                "FIFOs, `/dev/zero` and folders as inputs; `<use>` bombs and cycles; 15,000 rings in the "
                "winding test; pixels x frames of every raster and video output, Lottie and SVG ticks, points "
                "per shape, `Sequence.at(10**400)`, `resample(frames=10**8)`, `metrics.report` of no frame.\n\n"
                f"### Resource guards\n\nMemory is estimated before allocating and compared with MemAvailable "
                f"(or `--max-memory`); peak RSS by `/usr/bin/time` (the interpreter with isotween imported is "
                f"about 90 MB):\n\n{guarded}\n\n"
                f"### Loader fuzzing\n\nMutated valid files (byte flips, splices, truncation, numbers swapped "
                f"for huge, NaN, negative or malformed ones, repeated lines, deep nesting) read by every "
                f"loader (shapes; .npz and .json sequences, whose info, energy and times are also rewritten and "
                f"which must then become the viewer page's data; .csv and .jsonl batch manifests with hostile "
                f"cells, read and checked as `batch` does before running; SVG files of random `<use>` graphs, "
                f"one in five a bomb). {summary} Times are from a 2-core machine "
                f"shared with other jobs (under load).\n\n{text}\n")
        write_section("Reliability", body, f"python3 benchmarks/fuzz.py --inputs {args.inputs} "
                                           f"--workers {args.workers} --write")


if __name__ == "__main__":
    main()
