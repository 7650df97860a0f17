#!/usr/bin/python3
"""Run one scene with several models and plot their force-displacement curves on one figure (issue 3).

    /usr/bin/python3 scripts/compare_models.py [--scene scenes/vein-indent.json] \
        [--models quasi_static,explicit,xpbd,paper_literal] [--region indenter] [--out out/compare-models] \
        [--reuse] [--set key=value ...]

For every model: `vascsim run SCENE --set model=NAME --out OUT/NAME` (skipped with --reuse when OUT/NAME
already holds a finished run), then OUT/force-displacement.png (two panels: linear and logarithmic force
axis, since the models differ by orders of magnitude) and OUT/force-displacement.csv (one row per model and
output point). Units: displacement mm, force mN on the plot; SI (m, N) in the CSV.
Dynamic models (explicit, xpbd, paper_literal) report the force at each output time of their load ramp;
quasi_static reports equilibria. Wall times are printed per model.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

COLOURS = {"quasi_static": "#1f4e79", "explicit": "#2e8b57", "xpbd": "#b22222", "paper_literal": "#8a2be2"}


def run_model(vascsim, scene, model, out_dir, sets, reuse):
    summary = os.path.join(out_dir, "summary.json")
    if reuse and os.path.isfile(summary) and os.path.isfile(os.path.join(out_dir, "probes.csv")):
        print(f"{model}: reusing {out_dir}", file=sys.stderr)
        return None
    cmd = [vascsim, "run", scene, "--set", f"model={model}", "--out", out_dir]
    for s in sets:
        cmd += ["--set", s]
    print(f"{model}: {' '.join(cmd)}", file=sys.stderr)
    t0 = time.monotonic()
    proc = subprocess.run(cmd)
    if proc.returncode != 0:
        sys.exit(f"compare_models: {model} failed with exit code {proc.returncode}")
    return time.monotonic() - t0


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vascsim", default="build/vascsim")
    ap.add_argument("--scene", default="scenes/vein-indent.json")
    ap.add_argument("--models", default="quasi_static,explicit,xpbd,paper_literal")
    ap.add_argument("--region", default="indenter")
    ap.add_argument("--out", default="out/compare-models")
    ap.add_argument("--reuse", action="store_true", help="keep finished runs found in OUT/<model>")
    ap.add_argument("--set", action="append", default=[], help="scene override for every model")
    a = ap.parse_args()
    if not os.path.isfile(a.vascsim):
        sys.exit(f"compare_models: {a.vascsim} not found; build first (make build)")
    models = [m for m in a.models.split(",") if m]
    os.makedirs(a.out, exist_ok=True)

    curves = {}
    for m in models:
        out_dir = os.path.join(a.out, m)
        wall = run_model(a.vascsim, a.scene, m, out_dir, a.set, a.reuse)
        with open(os.path.join(out_dir, "probes.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        with open(os.path.join(out_dir, "summary.json")) as f:
            summary = json.load(f)
        dcol, fcol = f"{a.region}_displacement_m", f"{a.region}_force_n"
        if dcol not in rows[0]:
            sys.exit(f"compare_models: region '{a.region}' not in {out_dir}/probes.csv")
        curves[m] = dict(d=[float(r[dcol]) for r in rows], f=[float(r[fcol]) for r in rows],
                         t=[float(r["time_s"]) for r in rows], nodes=summary.get("nodes"),
                         wall=wall if wall is not None else summary.get("timings_s", {}).get("total"))
        last = curves[m]
        print(f"{m}: {a.region} force {1e3 * last['f'][-1]:.4g} mN at {1e3 * last['d'][-1]:.4g} mm "
              f"({last['wall']:.0f} s wall)", file=sys.stderr)

    with open(os.path.join(a.out, "force-displacement.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["model", "time_s", f"{a.region}_displacement_m", f"{a.region}_force_n"])
        for m, c in curves.items():
            for t, d, fo in zip(c["t"], c["d"], c["f"]):
                w.writerow([m, t, d, fo])

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), dpi=120)
    for ax, log in zip(axes, (False, True)):
        for m, c in curves.items():
            # The rest state (zero displacement, round-off force) has no place on a log axis.
            pts = [(1e3 * d, 1e3 * fo) for d, fo in zip(c["d"], c["f"]) if not log or (fo > 0 and d > 0)]
            if not pts:
                continue
            ax.plot(*zip(*pts), "o-", ms=3, color=COLOURS.get(m), label=f"{m} ({c['wall']:.0f} s)")
        ax.set_xlabel(f"{a.region} displacement [mm]")
        ax.set_ylabel(f"{a.region} force [mN]")
        if log:
            ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_title(("log" if log else "linear") + " force axis", fontsize=10)
    axes[0].legend(fontsize=8)
    nodes = next(iter(curves.values()))["nodes"]
    fig.suptitle(f"{os.path.basename(a.scene)}: {a.region} force vs displacement, {nodes} nodes, every model's "
                 "defaults", fontsize=10)
    fig.tight_layout()
    png = os.path.join(a.out, "force-displacement.png")
    fig.savefig(png)
    print(f"compare_models: wrote {png}")


if __name__ == "__main__":
    main()
