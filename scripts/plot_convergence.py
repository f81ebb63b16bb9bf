#!/usr/bin/env python3
"""plot_convergence.py — speed against error from a `wavepath converge` CSV.

Two log-log panels: relMSE against seconds and against spp, one line per configuration
(the geometric mean over runs at each spp checkpoint, plus each run's end point) with its
run-to-run band (min..max over runs), and a reference slope of -1.

usage: scripts/plot_convergence.py CSV -o plot.png [--title TEXT]
"""
import argparse
import csv
import math
import sys
from collections import defaultdict


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("csv")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--title", default="")
    args = ap.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plot_convergence.py: matplotlib is missing: pip install matplotlib "
                 "(or apt-get install python3-matplotlib)")

    # configuration -> spp -> list of (seconds, relmse) over runs (power-of-two checkpoints
    # are shared by all runs; each run's last row is its own end point).
    points = defaultdict(lambda: defaultdict(list))
    order = []
    try:
        with open(args.csv, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"plot_convergence.py: cannot read '{args.csv}': {e.strerror}")
    need = {"configuration", "run", "spp", "seconds", "relmse"}
    if not rows or not need <= set(rows[0]):
        sys.exit(f"plot_convergence.py: '{args.csv}' is not a converge CSV (columns {sorted(need)})")
    for r in rows:
        c = r["configuration"]
        if c not in order:
            order.append(c)
        points[c][int(r["spp"])].append((float(r["seconds"]), float(r["relmse"])))

    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for i, c in enumerate(order):
        colour = f"C{i}"
        runs = max(len(v) for v in points[c].values())
        spp = sorted(s for s, v in points[c].items() if len(v) == runs and s & (s - 1) == 0)
        gm = lambda xs: math.exp(sum(math.log(x) for x in xs) / len(xs))
        secs = [gm([p[0] for p in points[c][s]]) for s in spp]
        rel = [gm([p[1] for p in points[c][s]]) for s in spp]
        lo = [min(p[1] for p in points[c][s]) for s in spp]
        hi = [max(p[1] for p in points[c][s]) for s in spp]
        for ax, x in ((axes[0], secs), (axes[1], spp)):
            ax.plot(x, rel, "-o", color=colour, ms=3, label=f"{c} ({runs} runs)")
            ax.fill_between(x, lo, hi, color=colour, alpha=0.2, lw=0)
        # End points of the runs (equal time).
        ends = [v[0] for s, v in points[c].items() if len(v) < runs or s & (s - 1)]
        if ends:
            axes[0].plot([e[0] for e in ends], [e[1] for e in ends], "x", color=colour, ms=5)
    # Reference slope -1 through the first configuration's middle point.
    for ax, xkey in ((axes[0], 0), (axes[1], 1)):
        lines = ax.get_lines()
        if lines:
            xs, ys = lines[0].get_xdata(), lines[0].get_ydata()
            m = len(xs) // 2
            x0, y0 = xs[m], ys[m]
            xr = [xs[0], xs[-1]]
            ax.plot(xr, [y0 * x0 / x for x in xr], "k--", lw=1, label="slope -1")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_ylabel("relMSE (eps 1e-2)")
    axes[0].set_xlabel("render time (s)")
    axes[1].set_xlabel("samples per pixel")
    axes[0].legend(fontsize=8)
    if args.title:
        fig.suptitle(args.title)
    fig.tight_layout()
    fig.savefig(args.output, dpi=80)
    print(f"plot_convergence.py: wrote {args.output}")


if __name__ == "__main__":
    main()
