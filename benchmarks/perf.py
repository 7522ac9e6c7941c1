"""Speed of `isotween.interpolate` against the paper's Table 1, dense meshes, scaling.

Every case runs in a fresh process (peak memory is that process's maximum
resident set). Times are end to end inside `interpolate` with default options
and the paper's stopping rule; median, min and max of --runs runs.

Usage: python benchmarks/perf.py [--runs 5] [--skip-large]
"""

import argparse
import json
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
sys.path.insert(0, str(HERE))


def build(case):
    """(source, target) for a case name: 'V/E' (Table 1 counts) or 'grid:NXxNY'."""
    from cases import mesh_pair, table1_pair

    if case.startswith("grid:"):
        nx, ny = map(int, case[5:].split("x"))
        return mesh_pair(nx, ny)
    v, e = map(int, case.split("/"))
    return table1_pair(v, e)


def measure(case, frames, runs, solver, reference, method):
    """Child process: time one case and print a JSON line."""
    import isotween
    from _results import repeat
    from isotween import metrics

    src, tgt = build(case)
    kw = dict(frames=frames, solver=solver, method=method)
    if method == "shapespace":
        kw = dict(frames=frames, method=method)
    isotween.interpolate(src, tgt, **kw)  # warm-up (imports, first page faults)
    med, lo, hi, seq = repeat(lambda: isotween.interpolate(src, tgt, **kw), runs)
    out = dict(median=med, min=lo, max=hi, iterations=seq.iterations,
               energy=metrics.isometric_energy(seq), deviation=metrics.edge_length_deviation(seq),
               flips=metrics.flipped_faces(seq), vertices=src.n_vertices, edges=src.n_edges)
    if reference:
        ref = isotween.interpolate(src, tgt, frames=frames, assembly="per-frame")
        out.update(ref_energy=metrics.isometric_energy(ref),
                   ref_deviation=metrics.edge_length_deviation(ref), ref_seconds=ref.timings["total"])
    out["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(json.dumps(out))


def run_child(case, frames, runs, solver="local", reference=True, method="aiap", timeout=1800):
    cmd = [sys.executable, __file__, "--child", case, str(frames), str(runs), solver,
           "1" if reference else "0", method]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if res.returncode:
        raise RuntimeError(res.stderr)
    return json.loads(res.stdout.strip().splitlines()[-1])


def main():
    from _results import table, write_section
    from cases import FRAMES, TABLE1

    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--skip-large", action="store_true", help="skip the 100k-vertex case")
    ap.add_argument("--kilian", action="store_true", help="also time shapespace (slow)")
    args = ap.parse_args()

    rows, ok = [], True
    for name, v, e, iters, paper, kilian in TABLE1:
        for f, it_paper, t_paper, t_kilian in zip(FRAMES, iters, paper, kilian):
            r = run_child(f"{v}/{e}", f, args.runs)
            g = run_child(f"{v}/{e}", f, args.runs, solver="global", reference=False) if f == 205 else None
            speedup = t_paper / r["median"]
            ok &= speedup >= 100 and r["iterations"] <= it_paper
            q_e = r["energy"] / r["ref_energy"] - 1 if r["ref_energy"] else 0.0
            q_d = 100 * (r["deviation"] - r["ref_deviation"])
            row = [name, v, e, f, f"{1e3 * r['median']:.1f} ({1e3 * r['min']:.1f}-{1e3 * r['max']:.1f})",
                   f"{r['iterations']} / {it_paper}", f"{t_paper:.3f}", f"{speedup:.0f}x",
                   f"{r['peak_mb']:.0f}", f"{100 * q_e:+.2f} %", f"{q_d:+.3f} pp",
                   f"{1e3 * g['median']:.0f} ms" if g else ""]
            if args.kilian:
                k = run_child(f"{v}/{e}", f, 1, reference=False, method="shapespace")
                row.append(f"{k['median']:.2f} s ({k['median'] / r['median']:.0f}x)")
            rows.append(row)
            print(" | ".join(map(str, row)), flush=True)
    header = ["example", "V", "E", "frames", "ms median (min-max)", "iters ours / paper",
              "paper s", "speed-up", "peak MB", "energy vs ref", "edge dev vs ref", "global"]
    if args.kilian:
        header.append("shapespace (ratio)")
    body = table(header, rows)

    dense = [("grid:500x20", 205), ("grid:1000x100", 101)]
    if args.skip_large:
        dense = dense[:1]
    drows = []
    for case, f in dense:
        r = run_child(case, f, max(3, args.runs // 2 if "1000" in case else args.runs),
                      reference="1000" not in case)
        drows.append([case, r["vertices"], r["edges"], f,
                      f"{r['median']:.2f} ({r['min']:.2f}-{r['max']:.2f})", r["iterations"],
                      f"{r['peak_mb']:.0f}",
                      f"{100 * (r['energy'] / r['ref_energy'] - 1):+.2f} %" if "ref_energy" in r else "n/a",
                      r["flips"]])
        print(drows[-1], flush=True)
    body += "\n\nDense meshes (triangulated bars bent by 180 degrees):\n\n" + table(
        ["case", "V", "E", "frames", "s median (min-max)", "iters", "peak MB", "energy vs ref", "flips"],
        drows)

    # scaling with frames (V = 2000) and with vertices (101 frames)
    from matplotlib.figure import Figure

    fr = [21, 41, 81, 161, 321]
    tf = [run_child("grid:200x10", f, 3, reference=False)["median"] for f in fr]
    vs = [(100, 10), (200, 10), (400, 10), (400, 20), (800, 20)]
    tv = [run_child(f"grid:{a}x{b}", 101, 3, reference=False)["median"] for a, b in vs]
    nv = [a * b for a, b in vs]
    fig = Figure(figsize=(9, 3.6))
    for ax, x, y, label in ((fig.add_subplot(121), fr, tf, "frames (2000 vertices)"),
                            (fig.add_subplot(122), nv, tv, "vertices (101 frames)")):
        ax.loglog(x, y, "o-", label="measured")
        ax.loglog(x, y[0] * np.asarray(x) / x[0], "--", label="linear")
        ax.set_xlabel(label)
        ax.set_ylabel("seconds")
        ax.legend()
    fig.tight_layout()
    fig.savefig(HERE / "scaling.png", dpi=110)
    slope_f = np.polyfit(np.log(fr), np.log(tf), 1)[0]
    slope_v = np.polyfit(np.log(nv), np.log(tv), 1)[0]
    body += (f"\n\nScaling (`benchmarks/scaling.png`): log-log slope {slope_f:.2f} in frames, "
             f"{slope_v:.2f} in vertices (1 = linear).\n\n"
             "Reference ('ref') is the straightforward local solver: the paper's weights "
             "1/|e(t_k)| refactorised per frame and iteration (`assembly='per-frame'`); the "
             "default factorises once with frozen weights.")
    print(body)
    write_section("Performance", body, "python benchmarks/perf.py" + (" --skip-large" if args.skip_large else ""))
    return 0 if ok else 1


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        case, frames, runs, solver, reference, method = sys.argv[2:8]
        measure(case, int(frames), int(runs), solver, reference == "1", method)
    else:
        sys.exit(main())
