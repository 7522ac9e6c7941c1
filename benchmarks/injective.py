"""What the fold-free refinement costs and gains: methods 'convex' and 'injective' on corpus pairs.

Usage: python benchmarks/injective.py [--icons 20] [--glyphs 10] [--pairs 8] [--runs 3] [--write]

Pairs from the drawings corpus (benchmarks/corpus.py, the same seed as benchmarks/correspondence.py)
are put in correspondence once; then both methods interpolate 9 frames, each timed ``--runs``
times (median). The table gives per pair the mesh size, the median seconds of each method
(the completed disc's meshing is in both), the difference (what the refinement adds), its
Newton iterations, and the edge-length deviation of the drawn outline
(benchmarks/correspondence.py's measure).
"""

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))
import corpus  # noqa: E402
from _results import machine, repeat, table, write_section  # noqa: E402
from correspondence import outline_measures  # noqa: E402


def main():
    """Print (and with --write, record) the table."""
    import isotween

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--icons", type=int, default=20)
    parser.add_argument("--glyphs", type=int, default=10)
    parser.add_argument("--pairs", type=int, default=8, help="this many of the pairs, spread over the list")
    parser.add_argument("--frames", type=int, default=9)
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--write", action="store_true", help="record the table in RESULTS.md")
    args = parser.parse_args()

    pairs = corpus.pairs(args.icons, args.glyphs)
    picks = np.unique(np.linspace(0, len(pairs) - 1, args.pairs).round().astype(int))
    rows, added = [], []
    for k in picks:
        kind, a, b = pairs[k]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            try:
                src, tgt, _ = isotween.correspond(isotween.io.load(str(a)), isotween.io.load(str(b)))
            except isotween.errors.IsotweenError as exc:
                print(f"pair {k}: {exc}", file=sys.stderr)
                continue
        if not src.n_faces:
            continue
        res = {}
        for method in ("convex", "injective"):
            try:
                med, _, _, seq = repeat(lambda s=src, t=tgt, m=method: isotween.interpolate(
                    s, t, frames=args.frames, method=m), args.runs)
            except isotween.errors.IsotweenError as exc:
                print(f"pair {k} {method}: {exc}", file=sys.stderr)
                break
            crossings, dev = outline_measures(seq)
            flips = int(isotween.metrics.flipped_faces(seq))
            res[method] = (med, dev, flips + sum(crossings), seq.iterations)
        if len(res) < 2:
            continue
        added.append(res["injective"][0] - res["convex"][0])
        rows.append([int(k), kind, src.n_vertices, f"{res['convex'][0]:.2f}", f"{res['injective'][0]:.2f}",
                     f"{added[-1]:+.2f}", res["injective"][3], f"{res['convex'][1]:.3f}",
                     f"{res['injective'][1]:.3f}", res["convex"][2] + res["injective"][2]])
        print(rows[-1], flush=True)
    header = ["pair", "set", "vertices", "convex (s)", "injective (s)", "added (s)", "Newton iterations",
              "outline edge dev. convex", "injective", "folds (both)"]
    text = "\n".join([
        f"{len(rows)} pairs of `correspondence.py --icons {args.icons} --glyphs {args.glyphs}`, {args.frames} frames, "
        f"median of {args.runs} runs each, on {machine()}.",
        "",
        table(header, rows),
        "",
        f"The refinement adds {np.median(added):.2f} s per pair (median; max {np.max(added):.2f} s)."
        if added else "No pair could be run.",
    ])
    print(text)
    if args.write:
        write_section("Fold-free refinement", text, " ".join(["python benchmarks/injective.py", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
