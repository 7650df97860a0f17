#!/usr/bin/env python3
"""Plot a run's force-displacement curve from probes.csv (vascsim run output).

Usage: /usr/bin/python3 scripts/plot_probes.py OUT_DIR [--region NAME]

Plots <name>_force_n against <name>_displacement_m for the driven region or tool and writes
OUT_DIR/force-displacement.png. Units on the axes: mm and mN. Default: the scene's first tool (obstacle, e.g.
the catheter: its force on the tissue against its travel) when the run has one, else the region named
'indenter', else the first region with a non-zero force.
"""
import argparse
import csv
import json
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_dir", help="a vascsim run's output folder (holds probes.csv and summary.json)")
    ap.add_argument("--region", help="region or tool to plot (default: the first tool, else indenter, else the first "
                    "loaded region)")
    args = ap.parse_args()

    csv_path = os.path.join(args.out_dir, "probes.csv")
    if not os.path.isfile(csv_path):
        sys.exit(f"plot_probes: {csv_path}: not found (run 'vascsim run SCENE --out {args.out_dir}' first)")
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"plot_probes: {csv_path}: no rows")
    regions = [c[: -len("_force_n")] for c in rows[0] if c.endswith("_force_n")]
    summary_path = os.path.join(args.out_dir, "summary.json")
    summary = None
    if os.path.isfile(summary_path):
        with open(summary_path) as f:
            summary = json.load(f)
    tools = [o["name"] for o in (summary or {}).get("parameters", {}).get("obstacles", []) if o.get("name") in regions]
    region = args.region
    if region is None:
        loaded = [r for r in regions if any(abs(float(row[r + "_force_n"])) > 0 for row in rows[1:])]
        region = tools[0] if tools else "indenter" if "indenter" in regions else (loaded[0] if loaded else None)
    if region not in regions:
        sys.exit(f"plot_probes: region '{region}' not in {csv_path}; regions: {', '.join(regions)}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    d = [1e3 * float(r[region + "_displacement_m"]) for r in rows]
    fn = [1e3 * float(r[region + "_force_n"]) for r in rows]
    what = "tool" if region in tools else "region"
    title = f"{region} ({what})"
    if summary is not None:
        s = summary
        title = f"{s.get('scene', '')}: {what} {region} ({s.get('model', '')}, {s.get('nodes', '?')} nodes)"
    fig, ax = plt.subplots(figsize=(6, 4.2), dpi=120)
    ax.plot(d, fn, "o-", color="#b22222")
    ax.set_xlabel(f"{region} {'travel' if what == 'tool' else 'displacement'} [mm]")
    ax.set_ylabel(f"{region} force {'on the tissue ' if what == 'tool' else ''}[mN]")
    ax.set_title(title, fontsize=10)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    png = os.path.join(args.out_dir, "force-displacement.png")
    fig.savefig(png)
    print(f"plot_probes: wrote {png} ({what} {region})")


if __name__ == "__main__":
    main()
