#!/usr/bin/env python3
"""Plot force-displacement curves written by `vascsim experiment force-displacement`.

Usage: /usr/bin/python3 scripts/plot_force_displacement.py CSV [CSV ...] --out PNG [options]

Each CSV has a header row and comma-separated rows; lines starting with '#' are comments:
  step,displacement_m,force_n,force_x_n,force_y_n,force_z_n,torque_x_n_m,torque_y_n_m,torque_z_n_m,
  contacts,converged
  displacement_m  tool (catheter) displacement along its push direction (m)
  force_n         force along the push (N), as in summary.json: the tool's force on the tissue,
                  positive while it presses (the tissue resists the tool with as much)
  converged       1 if the load step converged, 0 if not (optional)
Columns may come in any order; only displacement_m and force_n are required, others are ignored.

Several CSVs give several curves on one axis; the legend shows --label values (one per CSV) or
else each file's parent folder name. Rows with converged == 0 are marked by a red 'x'.

Units (--units): 'auto' (default) uses mm if the largest |displacement| is below 0.1 m, and mN if
the largest |force| is below 1 N (uN below 1e-3 N); 'si' is m and N; 'mm_mN' is mm and mN.

Examples:
  plot_force_displacement.py out/fd-vein/force_displacement.csv --out fd.png
  plot_force_displacement.py out/a/fd.csv out/b/fd.csv --label stiff --label soft --out cmp.png
  plot_force_displacement.py out/fd/quasi_static/force_displacement.csv out/fd/xpbd/force_displacement.csv \
      --reference --label quasi_static --label xpbd --out models.png   (the first curve is the reference)

Errors (missing file, missing required column, no data rows, a non-numeric or NaN value) print one
line on stderr, 'plot_force_displacement.py: <file>: <problem>', and exit with code 2.
"""
import argparse
import csv
import math
import os
import sys

import numpy as np

PROG = "plot_force_displacement.py"
REQUIRED = ("displacement_m", "force_n")
# tab10 without its red (C3): red is reserved for the non-converged markers
COLORS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"]
FAIL_RGB = "#d62728"


class PlotError(Exception):
    """A user-facing error: one line, exit code 2."""


# ----------------------------------------------------------------------------------------- input
def _number(path, lineno, col, text):
    s = text.strip()
    if not s:
        raise PlotError(f"{path}: line {lineno}, column '{col}': empty value")
    try:
        v = float(s)
    except ValueError:
        raise PlotError(f"{path}: line {lineno}, column '{col}': not a number: '{s}'")
    if math.isnan(v):
        raise PlotError(f"{path}: line {lineno}, column '{col}': NaN value")
    if math.isinf(v):
        raise PlotError(f"{path}: line {lineno}, column '{col}': infinite value '{s}'")
    return v


def read_curve(path):
    """Returns dict with disp (N,) m, force (N,) N, converged (N,) bool; rows in file order."""
    if not os.path.exists(path):
        raise PlotError(f"{path}: not found")
    if not os.path.isfile(path):
        raise PlotError(f"{path}: not a file")
    try:
        with open(path, newline="", encoding="utf-8-sig") as f:
            lines = [(i + 1, ln) for i, ln in enumerate(f.read().splitlines())]
    except (OSError, UnicodeDecodeError) as e:
        raise PlotError(f"{path}: cannot read: {getattr(e, 'strerror', None) or e}")
    # drop comments and blank lines, keep the original line numbers for messages
    lines = [(n, ln) for n, ln in lines if ln.strip() and not ln.lstrip().startswith("#")]
    if not lines:
        raise PlotError(f"{path}: empty (no header row)")
    rows = list(csv.reader([ln for _, ln in lines]))
    header = [h.strip() for h in rows[0]]
    seen = set()
    for h in header:
        if h in seen and h in REQUIRED + ("converged",):
            raise PlotError(f"{path}: duplicate column '{h}' in the header")
        seen.add(h)
    missing = [c for c in REQUIRED if c not in header]
    if missing:
        raise PlotError(f"{path}: missing required column{'s' if len(missing) > 1 else ''} "
                        f"{', '.join(repr(c) for c in missing)} (header: {','.join(header)})")
    idx = {c: header.index(c) for c in REQUIRED}
    i_conv = header.index("converged") if "converged" in header else None

    disp, force, conv = [], [], []
    for (lineno, _), row in zip(lines[1:], rows[1:]):
        if len(row) != len(header):
            raise PlotError(f"{path}: line {lineno}: {len(row)} fields, the header has {len(header)}")
        disp.append(_number(path, lineno, "displacement_m", row[idx["displacement_m"]]))
        force.append(_number(path, lineno, "force_n", row[idx["force_n"]]))
        if i_conv is not None:
            c = _number(path, lineno, "converged", row[i_conv])
            if c not in (0.0, 1.0):
                raise PlotError(f"{path}: line {lineno}, column 'converged': must be 0 or 1, got '{row[i_conv].strip()}'")
            conv.append(c == 1.0)
        else:
            conv.append(True)
    if not disp:
        raise PlotError(f"{path}: no data rows (only a header)")
    return {"disp": np.array(disp), "force": np.array(force), "converged": np.array(conv, dtype=bool)}


def default_labels(paths):
    """Each file's parent folder name; 'folder/file stem' where folder names would collide."""
    folder = [os.path.basename(os.path.dirname(os.path.abspath(p))) or p for p in paths]
    out = []
    for p, d in zip(paths, folder):
        stem = os.path.splitext(os.path.basename(p))[0]
        out.append(f"{d}/{stem}" if folder.count(d) > 1 else d)
    if len(set(out)) < len(out):  # same folder and stem (the same file twice): number them
        out = [f"{lab} ({i + 1})" for i, lab in enumerate(out)]
    return out


# ----------------------------------------------------------------------------------------- units
def pick_units(mode, curves):
    """Returns ((displacement scale, unit), (force scale, unit)): plotted value = SI value * scale."""
    if mode == "si":
        return (1.0, "m"), (1.0, "N")
    if mode == "mm_mN":
        return (1e3, "mm"), (1e3, "mN")
    dmax = max(float(np.max(np.abs(c["disp"]))) for c in curves)
    fmax = max(float(np.max(np.abs(c["force"]))) for c in curves)
    du = (1e3, "mm") if dmax < 0.1 else (1.0, "m")
    if fmax < 1e-3:
        fu = (1e6, "\u00b5N")
    elif fmax < 1.0:
        fu = (1e3, "mN")
    else:
        fu = (1.0, "N")
    return du, fu


# -------------------------------------------------------------------------------------- drawing
def plot(args):
    out_dir = os.path.dirname(os.path.abspath(args.out))
    if not os.path.isdir(out_dir):
        raise PlotError(f"{args.out}: output folder does not exist")
    curves = [read_curve(p) for p in args.csv]
    labels = args.label if args.label else default_labels(args.csv)
    (ds, du), (fs, fu) = pick_units(args.units, curves)

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.8), dpi=150)
    failed_labelled = False
    for i, (c, lab) in enumerate(zip(curves, labels)):
        x, y = c["disp"] * ds, c["force"] * fs
        if i == 0 and args.reference:
            # The reference is the converged solution: a load step that did not converge is not part of it.
            ok = c["converged"]
            ax.plot(x[ok], y[ok], "-", color="black", linewidth=2.6, label=f"{lab} (reference)", zorder=4)
            continue
        else:
            k = i - 1 if args.reference else i
            ax.plot(x, y, "o-", color=COLORS[k % len(COLORS)], markersize=3.5, linewidth=1.4, label=lab)
        bad = ~c["converged"]
        if bad.any():
            ax.plot(x[bad], y[bad], "x", color=FAIL_RGB, markersize=8, markeredgewidth=1.8, zorder=5,
                    label=None if failed_labelled else "not converged")
            failed_labelled = True
    ax.set_xlabel(f"{args.tool} displacement ({du})")
    ax.set_ylabel(f"force on the {args.tool} ({fu})")
    if args.title:
        ax.set_title(args.title, fontsize=10)
    ax.grid(True, alpha=0.35)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    try:
        fig.savefig(args.out, dpi=150)
    except OSError as e:
        raise PlotError(f"{args.out}: cannot write: {e.strerror or e}")
    plt.close(fig)
    return args.out


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", nargs="+", metavar="CSV", help="force-displacement CSV file(s), one curve each")
    ap.add_argument("--out", required=True, metavar="PNG", help="PNG file to write")
    ap.add_argument("--label", action="append", metavar="L",
                    help="legend label, once per CSV in order (default: each file's parent folder name)")
    ap.add_argument("--title", metavar="T", help="axes title (default: none)")
    ap.add_argument("--reference", action="store_true",
                    help="draw the first CSV as the reference curve (thick black line, no markers, its "
                         "non-converged rows left out)")
    ap.add_argument("--tool", default="catheter", metavar="NAME",
                    help="what presses, for the axis labels (default: catheter)")
    ap.add_argument("--units", choices=["auto", "si", "mm_mN"], default="auto",
                    help="axis units: auto (default), si (m, N) or mm_mN (mm, mN)")
    args = ap.parse_args(argv)
    try:
        if args.label and len(args.label) != len(args.csv):
            raise PlotError(f"--label: given {len(args.label)} times for {len(args.csv)} CSV files "
                            "(give it once per CSV, or not at all)")
        out = plot(args)
    except PlotError as e:
        print(f"{PROG}: {e}", file=sys.stderr)
        return 2
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
