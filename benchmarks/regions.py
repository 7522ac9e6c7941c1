"""Every region meshed: correspondence over many more corpus pairs than the drawings benchmark morphs.

Usage: python benchmarks/regions.py [--icons 500] [--glyphs 200] [--strokes 100] [--skip 60] [--no-write]

`isotween.prepare_pair` (correspondence and compatible meshes, no solve) on the corpus pairs of
benchmarks/corpus.py after the first ``--skip`` icon pairs (the drawings benchmark's), one process,
at most 60 s a pair. A region that cannot be meshed is kept as a bare outline (the report says so
and why): the morph then has no triangles there, and its outline may cross itself. The table counts
such pairs per set and names the reasons; writes the "Every region meshed" section of RESULTS.md.
"""

import argparse
import collections
import re
import signal
import statistics
import time
import warnings

import corpus
import isotween
from _results import table, write_section


def _alarm(*_):
    raise TimeoutError("over 60 s")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--icons", type=int, default=500)
    parser.add_argument("--glyphs", type=int, default=200)
    parser.add_argument("--strokes", type=int, default=100)
    parser.add_argument("--skip", type=int, default=60, help="icon pairs the drawings benchmark morphs [60]")
    parser.add_argument("--no-write", action="store_true", help="print only; leave RESULTS.md alone")
    args = parser.parse_args()
    pairs = corpus.pairs(args.icons, args.glyphs, n_strokes=args.strokes)
    icons = [k for k, p in enumerate(pairs) if p[0] == "icon"]
    pairs = [p for k, p in enumerate(pairs) if p[0] != "classic" and k not in icons[:args.skip]]
    signal.signal(signal.SIGALRM, _alarm)
    count, bare, errors, seconds = collections.Counter(), collections.Counter(), collections.Counter(), []
    why = collections.Counter()
    for kind, a, b in pairs:
        signal.alarm(60)
        t = time.perf_counter()
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                summary = isotween.prepare_pair(a, b).report.summary()
        except Exception as exc:  # counted, named below
            summary = ""
            errors[kind] += 1
            why[f"error: {type(exc).__name__}"] += 1
            print(kind, a.name, b.name, f"{type(exc).__name__}: {exc}", flush=True)
        finally:
            signal.alarm(0)
        seconds.append(time.perf_counter() - t)
        count[kind] += 1
        found = re.search(r"as outlines \(region \d+: (.*)\)$", summary)
        if found:
            bare[kind] += 1
            reason = re.sub(r"[-\d.]+", "N", found.group(1)).split(";")[0]
            why[reason[:90]] += 1
            print(kind, a.name, b.name, found.group(1)[:160], flush=True)
    rows = [[kind, count[kind], bare[kind], errors[kind]] for kind in count]
    rows.append(["all", sum(count.values()), sum(bare.values()), sum(errors.values())])
    text = table(["set", "pairs", "a region left as an outline", "errors"], rows)
    text += "\n\n" + table(["reason", "pairs"], [[r, n] for r, n in why.most_common()])
    text += f"\n\nMedian {statistics.median(seconds):.3f} s per pair (correspondence and meshing, one process)."
    print(text)
    if not args.no_write:
        body = __doc__.split("\n\n", 2)[2].strip() + "\n\n" + text
        write_section("Every region meshed", body, f"python benchmarks/regions.py --icons {args.icons} "
                      f"--glyphs {args.glyphs} --strokes {args.strokes} --skip {args.skip}")


if __name__ == "__main__":
    main()
