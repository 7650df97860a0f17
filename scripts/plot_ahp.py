#!/usr/bin/env python3
"""Plot the AHP score table written by `vascsim ahp` (ahp_scores.csv) into one PNG.

Usage: /usr/bin/python3 scripts/plot_ahp.py OUT/ahp_scores.csv --out OUT/ahp_scores.png [--title TEXT]

ahp_scores.csv has a header row and one row per model:
  model,name,reference,comprehensive_score,paper_comprehensive_score,weight_covered,missing,
  I1,I1_source,I2,I2_source,...
  comprehensive_score        G of Eq. 40 on 0-100; empty if an indicator has no score
  paper_comprehensive_score  G printed in the paper's Table 3; empty if not given
  weight_covered             sum of the weights W_i of the indicators that have a score (0-1)
  Ik, Ik_source              score of indicator Ik on 0-100 (empty if none) and its source:
                             measured, rated, paper or missing
The indicator columns are those that have a matching '<id>_source' column, in file order.

Left panel: the comprehensive score of every model, ours (Eq. 40) next to the paper's printed one; a model
without a complete set of indicator scores shows 'n/a' and the weight its scores cover. Right panel: the
indicator scores as a model x indicator grid, each cell with its score and source (m measured, r rated,
p the paper's); empty cells have no score.

Errors (missing file, missing column, no rows, a value that is not a number in [0, 100]) print one line on
stderr, 'plot_ahp.py: <file>: <problem>', and exit with code 2.
"""
import argparse
import csv
import math
import os
import sys

PROG = "plot_ahp.py"
REQUIRED = ("model", "name", "comprehensive_score", "paper_comprehensive_score", "weight_covered")
SOURCES = {"measured": "m", "rated": "r", "paper": "p", "missing": ""}


class PlotError(Exception):
    """A user-facing error: one line, exit code 2."""


def _score(path, lineno, col, text, lo=0.0, hi=100.0):
    s = text.strip()
    if not s:
        return None
    try:
        v = float(s)
    except ValueError:
        raise PlotError(f"{path}: line {lineno}, column '{col}': not a number: '{s}'")
    if math.isnan(v) or v < lo or v > hi:
        raise PlotError(f"{path}: line {lineno}, column '{col}': {s} is outside [{lo:g}, {hi:g}]")
    return v


def read_scores(path):
    """Returns (indicator ids, rows); each row a dict with name, g, g_paper, covered, scores, sources."""
    if not os.path.isfile(path):
        raise PlotError(f"{path}: not found")
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.reader(f))
    except (OSError, UnicodeDecodeError) as e:
        raise PlotError(f"{path}: cannot read: {getattr(e, 'strerror', None) or e}")
    if not rows:
        raise PlotError(f"{path}: empty (no header row)")
    header = [h.strip() for h in rows[0]]
    for col in REQUIRED:
        if col not in header:
            raise PlotError(f"{path}: missing column '{col}'")
    indicators = [h for h in header if h + "_source" in header]
    if not indicators:
        raise PlotError(f"{path}: no indicator columns (an indicator 'Ik' needs a column 'Ik_source')")
    out = []
    for n, r in enumerate(rows[1:], start=2):
        if not any(x.strip() for x in r):
            continue
        if len(r) != len(header):
            raise PlotError(f"{path}: line {n}: {len(r)} fields, the header has {len(header)}")
        d = dict(zip(header, r))
        row = {
            "name": d["name"] or d["model"],
            "g": _score(path, n, "comprehensive_score", d["comprehensive_score"]),
            "g_paper": _score(path, n, "paper_comprehensive_score", d["paper_comprehensive_score"]),
            "covered": _score(path, n, "weight_covered", d["weight_covered"], 0.0, 1.000001) or 0.0,
            "scores": [_score(path, n, i, d[i]) for i in indicators],
            "sources": [],
        }
        for i in indicators:
            src = d[i + "_source"].strip()
            if src not in SOURCES:
                raise PlotError(f"{path}: line {n}, column '{i}_source': '{src}' is not one of "
                                f"{', '.join(SOURCES)}")
            row["sources"].append(src)
        out.append(row)
    if not out:
        raise PlotError(f"{path}: no data rows")
    return indicators, out


def plot(indicators, rows, out, title):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    n = len(rows)
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13.5, 0.55 * n + 2.6),
                                   gridspec_kw={"width_ratios": [1.0, 1.35]})
    y = np.arange(n)
    h = 0.38
    ours = [r["g"] if r["g"] is not None else 0.0 for r in rows]
    paper = [r["g_paper"] if r["g_paper"] is not None else 0.0 for r in rows]
    ax1.barh(y - h / 2, ours, h, color="#1f77b4", label="ours (Eq. 40)")
    ax1.barh(y + h / 2, paper, h, color="#bbbbbb", label="printed in the paper (Table 3)")
    for i, r in enumerate(rows):
        if r["g"] is None:
            ax1.text(1, i - h / 2, f"n/a (weight covered {r['covered']:.3f})", va="center", fontsize=8)
        else:
            ax1.text(r["g"] + 0.5, i - h / 2, f"{r['g']:.3f}", va="center", fontsize=8)
        if r["g_paper"] is not None:
            ax1.text(r["g_paper"] + 0.5, i + h / 2, f"{r['g_paper']:.3f}", va="center", fontsize=8, color="#555555")
    ax1.set_yticks(y, [r["name"] for r in rows])
    ax1.invert_yaxis()
    ax1.set_xlim(0, 118)
    ax1.set_xlabel("comprehensive score G (0-100)")
    ax1.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1 - 0.6 / n), ncol=2, fontsize=8, frameon=False)
    ax1.set_title("comprehensive score", fontsize=10)

    grid = np.array([[np.nan if s is None else s for s in r["scores"]] for r in rows], dtype=float)
    cmap = matplotlib.colormaps["viridis"].copy()
    cmap.set_bad("#eeeeee")
    im = ax2.imshow(np.ma.masked_invalid(grid), cmap=cmap, vmin=50, vmax=100, aspect="auto")
    for i, r in enumerate(rows):
        for j, s in enumerate(r["scores"]):
            if s is not None:
                ax2.text(j, i, f"{s:.0f} {SOURCES[r['sources'][j]]}", ha="center", va="center", fontsize=8,
                         color="white" if s < 80 else "black")
    if np.isnan(grid).all():
        ax2.text((len(indicators) - 1) / 2, (n - 1) / 2, "no indicator scores\n(none measured or rated in the inputs)",
                 ha="center", va="center", fontsize=10, color="#555555")
    ax2.set_xticks(range(len(indicators)), indicators)
    ax2.set_yticks(range(n), [""] * n)
    ax2.set_title("indicator scores (m measured, r rated, p paper; grey: none)", fontsize=10)
    fig.colorbar(im, ax=ax2, fraction=0.04, label="score")
    if title:
        fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    fig.savefig(out, dpi=120)
    plt.close(fig)


def main(argv):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--title", default="AHP force-tactile perception evaluation (Zhang et al. 2021, Eq. 40)")
    args = ap.parse_args(argv)
    try:
        indicators, rows = read_scores(args.csv)
    except PlotError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 2
    plot(indicators, rows, args.out, args.title)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
