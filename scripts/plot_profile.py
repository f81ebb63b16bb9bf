#!/usr/bin/env python3
"""plot_profile.py — per-stage device time per wave as stacked bars, from the JSON that
`wavepath render --profile PROFILE.json` writes (stages[].name and the per-wave times in
the trace next to it, PROFILE.trace.json; without the trace, one bar of ms per spp). A wave
is the batch of samples the path pool runs together (several passes of a small image, or
part of one pass of a large one).

usage: scripts/plot_profile.py PROFILE.json -o profile.png [--max-waves N]
"""
import argparse
import json
import os
import sys
from collections import defaultdict


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("profile")
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--max-waves", type=int, default=64, help="waves shown (the first N)")
    args = ap.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plot_profile.py: matplotlib is missing: pip install matplotlib "
                 "(or apt-get install python3-matplotlib)")
    try:
        with open(args.profile) as f:
            prof = json.load(f)
    except (OSError, ValueError) as e:
        sys.exit(f"plot_profile.py: cannot read '{args.profile}': {e}")
    if "stages" not in prof:
        sys.exit(f"plot_profile.py: '{args.profile}' is not a wavepath profile (no 'stages')")
    stages = [s["name"] for s in prof["stages"]]

    # Per wave and stage: sum of launch durations, from the Chrome trace (ms).
    per = defaultdict(lambda: defaultdict(float))
    trace = prof.get("trace") or ""
    if trace and not os.path.isabs(trace):
        trace = os.path.join(os.path.dirname(os.path.abspath(args.profile)), os.path.basename(trace))
    frames = []
    if trace and os.path.exists(trace):
        with open(trace) as f:
            for e in json.load(f).get("traceEvents", []):
                fr = (e.get("args") or {}).get("wave")
                if e.get("ph") == "X" and fr is not None and fr >= 0:
                    per[fr][e["name"]] += e["dur"] / 1000.0
        frames = sorted(per)[: args.max_waves]
    if not frames:  # no per-wave data: one bar of ms per spp
        frames = [0]
        for s in prof["stages"]:
            per[0][s["name"]] = s["ms_per_spp"]

    fig, ax = plt.subplots(figsize=(max(5, 0.18 * len(frames) + 3), 4))
    bottom = [0.0] * len(frames)
    for i, name in enumerate(stages):
        h = [per[f][name] for f in frames]
        ax.bar(frames, h, bottom=bottom, color=f"C{i % 10}", label=name, width=0.85)
        bottom = [b + x for b, x in zip(bottom, h)]
    ax.set_xlabel("wave")
    ax.set_ylabel("device time (ms)")
    st = prof.get("settings", {})
    ax.set_title(f"{prof.get('scene', {}).get('name', '')} {st.get('width', '')}x"
                 f"{st.get('height', '')}, depth {st.get('depth', '')}: per-stage time per wave")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=80)
    print(f"plot_profile.py: wrote {args.output}")


if __name__ == "__main__":
    main()
