"""Start-up: what a fresh process pays before and for a small command (issue 21, item 1).

Every number is the median wall time of several fresh processes:

- ``python -c pass`` and ``python -c "import numpy"``: the floor under everything;
- ``python -c "import isotween"``: target at most 0.2 s;
- ``isotween --help``;
- ``isotween interpolate A.svg B.svg -o out.npz`` on a small filled icon pair (a rounded
  square into a circle, written here): target at most 0.5 s; with the seconds its imports
  take (``-X importtime``, top-level modules summed; modules imported through
  ``importlib.import_module`` count only their imports, not their own time);
- the same command writing the animated outputs a web page or an animator takes (SVG,
  Lottie, the HTML viewer, a GIF) instead of a sequence file;
- the same command on real icon pairs (Bootstrap Icons from the benchmark corpus, where
  ``benchmarks/.corpus`` is installed: `corpus.install`), drawings that need the
  correspondence's work (a hole opened into a notch, pieces that appear or vanish);
- the first run after install: numba's cache (``__pycache__/*.nbi``, ``*.nbc`` under the
  package) removed first, so every kernel the command calls is compiled (a problem this
  small runs on numpy, `backend.sized`: none); reported separately, with the run after it;
- a small morph in a fresh process, on the backend `backend.sized` picks for it, and in a
  process that said it is `backend.long_lived` (numba: its import and the kernels the morph
  calls, compiled after install, then loaded from numba's cache).

``--baseline SRC`` times the same commands on another checkout's ``src`` folder (e.g. the
commit before a change, from ``git archive``) in a second column. Its numba cache is
cleared too, for its own first run.

The package's byte code is compiled first (``compileall``), as ``pip install`` does: a process
started with ``PYTHONDONTWRITEBYTECODE=1`` (or from a read-only checkout) writes none, and
would compile every module of isotween from source in every run (about 0.1 s of the
command's time), which no installed copy does.

Run: ``PYTHONPATH=src python benchmarks/startup.py [--runs 7] [--baseline /tmp/before/src]
[--no-write]``; it writes the "Start-up" section of RESULTS.md.
"""

import argparse
import compileall
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from _results import table, write_section

SQUARE = ('<svg xmlns="http://www.w3.org/2000/svg" width="16" height="16" fill="currentColor" viewBox="0 0 16 16">'
          '<path d="M2 0a2 2 0 0 0-2 2v12a2 2 0 0 0 2 2h12a2 2 0 0 0 2-2V2a2 2 0 0 0-2-2H2z"/></svg>\n')
CIRCLE = ('<svg xmlns="http://www.w3.org/2000/svg" width="16" height="16" fill="currentColor" viewBox="0 0 16 16">'
          '<circle cx="8" cy="8" r="8"/></svg>\n')

#: animated outputs timed on A and B (`write_output`'s defaults: one second of motion at 24 frames per second)
OUTPUTS = ("svg", "lottie.json", "html", "gif")
#: real icon pairs, timed as whole commands too where the benchmark corpus is installed (benchmarks/corpus.py)
ICONS = Path(__file__).parent / ".corpus" / "node_modules" / "bootstrap-icons" / "icons"
REAL_PAIRS = (("lock-fill", "unlock-fill"), ("moon-fill", "sun-fill"), ("house-fill", "gear-fill"))

#: in a fresh process (``long``: one that said it is `backend.long_lived`, so that even a small morph runs on
#: numba): a small morph, then the same morph again; prints the backend the morph ran on and the wall and CPU
#: seconds of the first and of the second. On numba the first imports numba and loads the kernels the morph
#: calls from numba's cache (compiles them when the cache is empty)
KERNELS = """
import sys
import time
import numpy as np
import isotween
from isotween.optimisation import backend
if sys.argv[1:] == ["long"]:
    backend.long_lived()
ring = isotween.Shape.from_polygon(np.c_[np.cos(np.arange(12) / 2), np.sin(np.arange(12) / 2)])
name = backend.for_size(ring.n_edges * 5).name
t0, c0 = time.perf_counter(), time.process_time()
isotween.interpolate(ring, ring.rotate(1.0), frames=5)
t1, c1 = time.perf_counter(), time.process_time()
isotween.interpolate(ring, ring.rotate(1.0), frames=5)
t2, c2 = time.perf_counter(), time.process_time()
print(name, t1 - t0, c1 - c0, t2 - t1, c2 - c1)
"""


def _env(src, **extra):
    env = dict(os.environ)
    env["PYTHONPATH"] = str(src)
    env.update(extra)
    return env


def _cli(src):
    """The command that runs the ``isotween`` console script against ``src``."""
    script = Path(sys.executable).with_name("isotween")
    return [str(script)] if script.exists() else [sys.executable, "-m", "isotween"]


def _cpu():
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _seconds(cmd, src, cwd, **env):
    """Wall and CPU (user + system) seconds of one fresh process running ``cmd``."""
    t0, c0 = time.perf_counter(), _cpu()
    subprocess.run(cmd, env=_env(src, **env), cwd=cwd, check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0, _cpu() - c0


def _median(cmd, src, cwd, runs, **env):
    _seconds(cmd, src, cwd, **env)  # warm the file cache and the byte code
    wall, cpu = zip(*(_seconds(cmd, src, cwd, **env) for _ in range(runs)), strict=True)
    return statistics.median(wall), statistics.median(cpu)


def _import_seconds(args, src, cwd):
    """Seconds ``isotween ARGS`` spends importing: the top-level modules of ``-X importtime``, summed."""
    out = subprocess.run([sys.executable, "-X", "importtime", "-m", "isotween", *args],
                         env=_env(src), cwd=cwd, check=True, capture_output=True, text=True)
    top = re.findall(r"^import time:\s+\d+ \|\s+(\d+) \| (\S.*)$", out.stderr, re.M)
    return sum(int(us) for us, _ in top) / 1e6


def _clear_numba_cache(src):
    removed = 0
    for pattern in ("*.nbi", "*.nbc"):
        for path in Path(src, "isotween").rglob(f"__pycache__/{pattern}"):
            path.unlink()
            removed += 1
    return removed


def _compile_byte_code(src):
    """Byte code of every module of the package under ``src``, written as an install writes it."""
    if not compileall.compile_dir(Path(src, "isotween"), quiet=1):
        print(f"warning: some byte code under {src} could not be written", file=sys.stderr)


def _kernels(src, cwd, *args):
    out = subprocess.run([sys.executable, "-c", KERNELS, *args], env=_env(src), cwd=cwd, check=True,
                         capture_output=True, text=True)
    name, *numbers = out.stdout.split()
    first_wall, first_cpu, second_wall, second_cpu = map(float, numbers)
    return name, (first_wall, first_cpu), (second_wall, second_cpu)


def measure(src, cwd, runs):
    """Every row's seconds for the checkout ``src`` (a dict)."""
    cli = _cli(src)
    args = ["interpolate", "A.svg", "B.svg", "-o", "out.npz", "-q"]
    interpolate = [*cli, *args]
    out = {}
    _compile_byte_code(src)
    _clear_numba_cache(src)
    out["first interpolate after install (numba cache cleared)"] = _seconds(interpolate, src, cwd)
    out["the interpolate after it (cache written)"] = _seconds(interpolate, src, cwd)
    out["python -c pass"] = _median([sys.executable, "-c", "pass"], src, cwd, runs)
    out["python -c 'import numpy'"] = _median([sys.executable, "-c", "import numpy"], src, cwd, runs)
    out["python -c 'import isotween'"] = _median([sys.executable, "-c", "import isotween"], src, cwd, runs)
    out["isotween --help"] = _median([*cli, "--help"], src, cwd, runs)
    out["isotween interpolate A.svg B.svg -o out.npz"] = _median(interpolate, src, cwd, runs)
    out["  of which importing (-X importtime, numba's imports at the first kernel call included)"] = \
        statistics.median(_import_seconds(args, src, cwd) for _ in range(3)), None
    out["  the same with ISOTWEEN_NUMBA=0 (numpy backend, no numba)"] = _median(interpolate, src, cwd, runs,
                                                                              ISOTWEEN_NUMBA="0")
    for kind in OUTPUTS:  # the web outputs (text) load no plotting library; the raster ones do (matplotlib, PIL)
        out[f"isotween interpolate A.svg B.svg -o out.{kind}"] = _median([*cli, *args[:3], "-o", f"out.{kind}", "-q"],
                                                                         src, cwd, runs)
    for a, b in REAL_PAIRS if ICONS.is_dir() else ():
        real = [*cli, "interpolate", str(ICONS / f"{a}.svg"), str(ICONS / f"{b}.svg"), "-o", "out.npz", "-q"]
        out[f"isotween interpolate {a}.svg {b}.svg -o out.npz (Bootstrap Icons)"] = _median(real, src, cwd, runs)
    name, first, second = _kernels(src, cwd)
    out[f"first small morph in a process ({name} backend)"] = first
    out["  the same morph again"] = second
    _clear_numba_cache(src)
    name, first, _ = _kernels(src, cwd, "long")
    if name == "numba":
        out["first small morph in a long-lived process after install (numba: import, kernels compiled)"] = first
        name, first, second = _kernels(src, cwd, "long")
        out["  in the next such process (numba: import, kernels loaded from its cache)"] = first
        out["  the same morph again there"] = second
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=7, help="fresh processes per median [7]")
    parser.add_argument("--baseline", type=Path, help="another checkout's src folder, timed in a second column")
    parser.add_argument("--baseline-name", default=None, help="what the baseline is, for RESULTS.md (a commit)")
    parser.add_argument("--no-write", action="store_true", help="print only; leave RESULTS.md alone")
    args = parser.parse_args()
    import isotween

    src = Path(isotween.__file__).parents[1]
    with tempfile.TemporaryDirectory() as tmp:
        Path(tmp, "A.svg").write_text(SQUARE)
        Path(tmp, "B.svg").write_text(CIRCLE)
        after = measure(src, tmp, args.runs)
        before = measure(args.baseline, tmp, args.runs) if args.baseline else None
    def cells(wall, cpu):
        return [f"{wall:.3f}", "" if cpu is None else f"{cpu:.3f}"]

    header = ["fresh process", "wall s", "CPU s"] + (["wall s before", "CPU s before"] if before else [])
    rows = [[name, *cells(*s)] + (cells(*before[name]) if before else []) for name, s in after.items()]
    text = table(header, rows)
    print(text)
    if not args.no_write:
        load = ", ".join(f"{x:.1f}" for x in os.getloadavg())
        body = (f"Load average at the end of the run: {load}; wall times grow with it, CPU times (user + system "
                "of the process and its children) much less. "
                f"Median of {args.runs} fresh processes (one run for the first after install: numba's cache "
                "under the package removed first); the package's byte code compiled first, as an install does. "
                "A and B: a "
                "rounded square and a circle, 16 px filled icons (benchmarks/startup.py writes them); the "
                "Bootstrap Icons rows: real pairs from the benchmark corpus, whose correspondence opens holes "
                "into notches and grows or shrinks pieces (only where benchmarks/.corpus is installed). Targets "
                "(issue 21): `import isotween` at most 0.2 s, the interpolate command at most 0.5 s.\n\n" + text)
        if before:
            body += f"\n\nbefore: the same commands on {args.baseline_name or args.baseline}."
        body += ("\n\nA pair this small runs on numpy (`backend.sized`: numba is not imported), so the interpolate "
                 "command's time is its imports (numpy, scipy, shapely, svgelements, click) and the work "
                 "(correspondence and meshing, the solve, the file), and the ISOTWEEN_NUMBA=0 row is the same "
                 "command again. The long-lived rows show what numba costs where it runs: its import, then the "
                 "kernels the morph calls (compiled after install, loaded from numba's cache after that).")
        write_section("Start-up", body, "PYTHONPATH=src python benchmarks/startup.py" +
                      (f" --baseline {args.baseline}" if args.baseline else ""))


if __name__ == "__main__":
    main()
