#!/usr/bin/env python3
"""Plot `vascsim experiment timing` (the paper's Figs. 11-12): time per step and frames per second against node
count, one curve per model.

Usage: /usr/bin/python3 scripts/plot_timing.py OUT/timing.json --out OUT/timing.png

timing.json holds "points" (one per model and node count) with
  nodes                   node count of the point
  simulation_median_ms    median wall time of one 1 ms simulation step (Model::advance), ms
  surface_map_median_ms   median wall time of the MLS surface map of that step, ms
  frames_per_s            1000 / (simulation + surface map), 1/s
  load_average_start/end  1-minute load average around the point
  machine                 cpu_model, hardware_concurrency, ...
Left panel: simulation time per step (solid) and surface-map time (dashed), log-log. Right panel: frames per
second, with the paper's 30 frames-per-second line.

Errors print one line on stderr, 'plot_timing.py: <file>: <problem>', and exit with code 2.
"""
import argparse
import json
import os
import sys

PROG = "plot_timing.py"
COLORS = ["#000000", "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22"]


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("json", metavar="TIMING_JSON")
    ap.add_argument("--out", required=True, metavar="PNG")
    args = ap.parse_args(argv)
    try:
        with open(args.json) as f:
            doc = json.load(f)
        points = doc["points"]
        if not points:
            raise ValueError("no points")
    except (OSError, ValueError, KeyError) as e:
        print(f"{PROG}: {args.json}: {e}", file=sys.stderr)
        return 2
    if not os.path.isdir(os.path.dirname(os.path.abspath(args.out))):
        print(f"{PROG}: {args.out}: output folder does not exist", file=sys.stderr)
        return 2

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    models = []
    for p in points:
        if p["model"] not in models:
            models.append(p["model"])
    fig, (ax_t, ax_f) = plt.subplots(1, 2, figsize=(11.0, 4.6), dpi=150)
    for i, m in enumerate(models):
        pts = sorted((p for p in points if p["model"] == m), key=lambda p: p["nodes"])
        n = [p["nodes"] for p in pts]
        c = COLORS[i % len(COLORS)]
        ax_t.plot(n, [p["simulation_median_ms"] for p in pts], "o-", color=c, label=m)
        ax_t.plot(n, [p["surface_map_median_ms"] for p in pts], "x--", color=c, alpha=0.6)
        ax_f.plot(n, [p["frames_per_s"] for p in pts], "o-", color=c, label=m)
    ax_t.set_xscale("log")
    ax_t.set_yscale("log")
    ax_t.set_xlabel("nodes")
    ax_t.set_ylabel("wall time per 1 ms step (ms)\nsolid: simulation, dashed: surface map")
    ax_t.grid(True, which="both", alpha=0.3)
    ax_t.legend(fontsize=7, loc="lower right", bbox_to_anchor=(1.0, 0.14))  # between the two sets of lines
    ax_f.axhline(30.0, color="red", linewidth=1.0, linestyle=":", label="30 frames/s")
    ax_f.set_xscale("log")
    ax_f.set_yscale("log")
    ax_f.set_xlabel("nodes")
    ax_f.set_ylabel("frames per second (simulation + surface map)")
    ax_f.grid(True, which="both", alpha=0.3)
    ax_f.legend(fontsize=7, loc="best")
    mach = points[0].get("machine", {})
    loads = [p.get("load_average_start", -1) for p in points] + [p.get("load_average_end", -1) for p in points]
    fig.suptitle(f"{mach.get('cpu_model', '?')}, {mach.get('hardware_concurrency', '?')} cores, "
                 f"{points[0].get('threads', '?')} thread(s); 1-min load average {min(loads):.1f}-{max(loads):.1f}; "
                 f"median of {points[0].get('steps', '?')} steps", fontsize=9)
    fig.tight_layout()
    fig.savefig(args.out)
    plt.close(fig)
    return 0


if __name__ == "__main__":
    sys.exit(main())
