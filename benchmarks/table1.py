"""The paper's Table 1.

AIAP (local solver) against the shape-space method of Kilian et al. (`method='shapespace'`), iterations and seconds, on
shapes with the table's vertex and edge counts (benchmarks/cases.py: triangulated bars trimmed to the counts, bent by
180 degrees).

Both methods run in this process on this machine, so the speed-up column is
measured, not taken from the paper. AIAP times are medians of --runs runs
(after a warm-up); shapespace times are medians of --kilian-runs runs at 9 and
45 frames and a single run at 205 frames. A shapespace run whose first
iteration shows it would exceed --budget seconds is capped at the iterations
that fit in the budget (marked in the table).

The short AIAP timings run first at normal priority (under `nice` a 2 ms solve
on a shared machine is measured in scheduler ticks); the process then lowers
its own priority for the long shapespace runs.

Usage: python benchmarks/table1.py [--runs 11] [--kilian-runs 3] [--budget 600]
"""

import argparse
import os
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))
import isotween  # noqa: E402
from _results import repeat, table, write_section  # noqa: E402
from cases import FRAMES, TABLE1, table1_pair  # noqa: E402
from isotween import metrics  # noqa: E402


def shapespace(src, tgt, frames, runs, budget):
    """(median seconds, last sequence, iteration cap or None)."""
    t0 = time.perf_counter()
    isotween.interpolate(src, tgt, frames=frames, method="shapespace", max_iter=1)
    per_iteration = time.perf_counter() - t0
    cap = None
    if per_iteration * 100 > budget:
        cap = max(1, int(budget / per_iteration))
    times, seq = [], None
    while len(times) < (runs if frames < 205 else 1):
        t0 = time.perf_counter()
        seq = isotween.interpolate(src, tgt, frames=frames, method="shapespace", max_iter=cap or 100)
        times.append(time.perf_counter() - t0)
        if times[0] > 30:  # one run is enough for the slow cases
            break
    return statistics.median(times), seq, cap


def paper_kilian_iters(name):
    """Kilian iterations of the paper's Table 1 (SPEC.md)."""
    return {"Fig. 1": (17, 35, 50), "Fig. 3": (7, 6, 13), "Fig. 7": (8, 16, 34), "Fig. 10": (6, 6, 7),
            "Fig. 8": (13, 29, 50), "Fig. 15": (8, 15, 13)}[name]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=11, help="AIAP runs per case (median)")
    ap.add_argument("--kilian-runs", type=int, default=3, help="shapespace runs at 9 and 45 frames")
    ap.add_argument("--budget", type=float, default=600, help="seconds one shapespace run may take")
    args = ap.parse_args()
    cases = [(row, col, frames, table1_pair(row[1], row[2])) for row in TABLE1 for col, frames in enumerate(FRAMES)]
    aiap, load = {}, [os.getloadavg()[0]]
    for row, _col, frames, (src, tgt) in cases:  # all AIAP timings first, away from shapespace's big allocations
        kw = dict(frames=frames, solver="local")
        isotween.interpolate(src, tgt, **kw)  # warm-up
        aiap[row[0], frames] = repeat(lambda src=src, tgt=tgt, kw=kw: isotween.interpolate(src, tgt, **kw), args.runs)
    load.append(os.getloadavg()[0])
    os.nice(10)  # the long shapespace runs yield to other jobs on the shared cores
    rows, faster, capped, worst = [], 0, 0, 0.0
    for (name, V, E, paper_iters, paper_ours, paper_kilian), col, frames, (src, tgt) in cases:
        t_aiap, _, _, seq = aiap[name, frames]
        t_ss, ss, cap = shapespace(src, tgt, frames, args.kilian_runs, args.budget)
        iters_ss = f"{ss.iterations}" + (f" (capped at {cap}, not converged)" if cap and not ss.converged else "")
        row = [name, V, E, frames,
               f"{seq.iterations} / {paper_iters[col]}",
               f"{iters_ss} / {paper_kilian_iters(name)[col]}",
               f"{t_aiap:.4f}", f"{t_ss:.3f}", f"{t_ss / t_aiap:.0f}x",
               f"{paper_ours[col]} / {paper_kilian[col]}", f"{paper_kilian[col] / paper_ours[col]:.0f}x",
               f"{100 * metrics.edge_length_deviation(seq):.2f} / {100 * metrics.edge_length_deviation(ss):.2f}"]
        faster += t_ss < paper_kilian[col]
        capped += bool(cap and not ss.converged)
        worst = max(worst, metrics.edge_length_deviation(seq), metrics.edge_length_deviation(ss))
        rows.append(row)
        print(" | ".join(str(c) for c in row), flush=True)
    header = ["example", "V", "E", "frames", "iters AIAP (ours / paper)", "iters shapespace (ours / paper Kilian)",
              "AIAP s (median)", "shapespace s", "speed-up measured", "paper s (AIAP / Kilian)",
              "paper speed-up", "edge length dev. % (AIAP / shapespace)"]
    body = "\n".join([
        "Shapes: bars with exactly the table's vertex and edge counts (grid bars with diagonals removed or "
        "chords added until the counts match, so edge soups without triangles), bent by 180 degrees "
        "(`benchmarks/cases.py`; the paper's shapes are not public). AIAP: `interpolate(..., solver='local')`, "
        f"defaults otherwise, median of {args.runs} runs after a warm-up (all AIAP cases are timed before any "
        "shapespace run). shapespace: "
        f"`interpolate(..., method='shapespace')` (Kilian et al. 2007 path energy, Gauss-Newton from the "
        f"linear blend, same Eq. (11) stopping rule, tol 5e-4), median of {args.kilian_runs} runs at 9 and 45 "
        f"frames (one run where a run takes over 30 s) and one run at 205 frames; "
        f"runs that would exceed {args.budget:.0f} s are capped at the "
        "iterations that fit (marked). Both in the same process, so the speed-up is measured here; "
        "the paper's columns are from its Table 1 (Intel i5 2.8 GHz, 2013).",
        "",
        table(header, rows),
        "",
        f"shapespace runs capped: {capped}. shapespace here is faster than the paper's Kilian timings on "
        f"{faster} of {len(rows)} rows, so where the measured speed-up exceeds the paper's, the difference "
        "comes from this AIAP implementation being faster than the paper's (see Performance), not from a "
        f"slow baseline. Largest edge-length deviation of either method on any row: {100 * worst:.2f} %. "
        f"1-minute load average before / after the AIAP timings: {load[0]:.2f} / {load[1]:.2f} (2 cores, "
        "shared with other jobs; AIAP timed at normal priority, shapespace at nice 10).",
    ])
    write_section("Table 1 reproduction", body, "python benchmarks/table1.py")


if __name__ == "__main__":
    main()
