#!/usr/bin/python3
"""Draws the convergence study `vascsim converge` wrote (convergence.json): for each output, its value against
the node spacing at the deepest step with an estimate, with the extrapolated value and the fitted curve
f_ext + C h^p (left), and the estimated relative error of the scene's spacing at every step with its GCI bound
(right). Usage: plot_convergence.py out/<scene>-converge/convergence.json [--out convergence.png]"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("json", help="convergence.json written by vascsim converge")
    parser.add_argument("--out", default=None, help="picture to write (default: convergence.png beside the JSON)")
    args = parser.parse_args()
    with open(args.json) as f:
        study = json.load(f)
    levels = study.get("levels", [])
    if not levels:
        sys.exit(f"{args.json}: no levels (the study made no estimate: {study.get('refused', '')})")
    h_mm = [1e3 * lvl["spacing_m"] for lvl in levels]
    user = study["user_level"]
    quantities = []
    for row in study["outputs"]:
        if row["quantity"] not in quantities:
            quantities.append(row["quantity"])

    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for q in quantities:
        rows = [r for r in study["outputs"] if r["quantity"] == q]
        est = [r for r in rows if r["status"] == "extrapolated"]
        shown = est[-1] if est else rows[-1]
        scale = 1e3 if shown["unit"] in ("N", "m") else 1.0
        unit = {"N": "mN", "m": "mm"}.get(shown["unit"], shown["unit"])
        label = f"{q} (step {shown['step']}, {unit})"
        line = left.plot(h_mm, [scale * v for v in shown["values"]], "o", label=label)[0]
        left.plot([h_mm[user]], [scale * shown["values"][user]], "s", ms=10, mfc="none", color=line.get_color())
        if shown["status"] == "extrapolated":
            p, fx = shown["observed_order"], shown["extrapolated"]
            c = (shown["values"][0] - fx) / (h_mm[0] ** p)
            hs = [max(h_mm) * k / 50.0 for k in range(51)]
            left.plot(hs, [scale * (fx + c * h ** p) for h in hs], "-", color=line.get_color(), lw=0.8)
            left.plot([0.0], [scale * fx], "*", ms=10, color=line.get_color())
        if est:
            x = [r.get("tool_displacement_m", r["load_factor"]) for r in est]
            xs = [1e3 * v for v in x] if "tool_displacement_m" in est[0] else x
            err = [100.0 * r["error"] for r in est]
            bound = [100.0 * r["error_bound"] for r in est]
            right.errorbar(xs, err, yerr=bound, fmt="o", capsize=3, label=q, color=line.get_color())
    left.set_xlabel("node spacing (mm); square: the scene's, star: extrapolated")
    left.set_ylabel("value (mN or mm)")
    left.set_xlim(left=0.0)
    left.legend(fontsize=8)
    left.grid(alpha=0.3)
    right.axhline(0.0, color="k", lw=0.6)
    right.set_xlabel("tool displacement (mm) or load factor")
    right.set_ylabel("error at the scene's spacing (%)")
    right.set_title("estimated error, bars: its GCI bound", fontsize=10)
    right.grid(alpha=0.3)
    if right.get_legend_handles_labels()[0]:
        right.legend(fontsize=8)
    else:
        right.text(0.5, 0.5, "no step with an estimate", ha="center", va="center", transform=right.transAxes)
    fig.suptitle(f"convergence study: {len(levels)} levels, spacing " + " / ".join(f"{h:.3g}" for h in h_mm) + " mm")
    fig.tight_layout()
    out = args.out or args.json.rsplit("/", 1)[0] + "/convergence.png"
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    main()
