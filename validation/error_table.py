#!/usr/bin/python3
"""Error of vascsim's quasi_static solution against the CalculiX references (validation/references), at
several node spacings: the error-versus-nodes table of docs/validation.md.

    /usr/bin/python3 validation/error_table.py [--vascsim build/vascsim] [--cases vein-indent,...]
        [--out out/error-table] [--figure docs/images/error-vs-nodes.png] [--reuse] [--threads 2]
        [--set KEY=VALUE ...]

Every run is `nice -n 19 vascsim -q run SCENE --set model=quasi_static --set geometry.node_spacing_m=D
--set discretization.max_growths=10 ... --out OUT/<case>/<label>` (with --reuse a finished run is read
back instead; every --set is added to every run, so that the table of an option, e.g. `--set
contact.surface=embedded --set discretization.basis=quadratic --set discretization.wall_reach=thickness`, comes
from the same command). Writes OUT/error_table.csv (one row per case, resolution and load step: SI units and the
relative error), OUT/error_table.md (per case and resolution: nodes, the error at a few depths, the largest
|error| where the reference is converged, solve time) and the figure (force or deflection against depth with the
FEM reference band per case where it is converged, and the signed largest error where the reference is converged
against the node count). For scale, the table and the last panel also show CalculiX's own mesh levels against their
extrapolation, counted in nodes of the whole problem (four times the quarter model's). "Converged": the extrapolation's
uncertainty is at most TRUSTED_UNCERTAINTY (5 %) of the force.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

GROWTHS = "discretization.max_growths=10"
# The wall scenes have four node layers through the wall; the rows with three show the through-wall error the fourth
# removes (docs/validation.md, "Layers through the wall").
THREE_LAYERS = "geometry.min_layers=3"
# The quadratic fit without the through-wall cube (the default until 2026-11-27, docs/model/05-local-fit.md section 5.3): one row per
# wall case at the scene's resolution, drawn but not in the last panel.
NO_CUBE = "discretization.wall_cube=false"


def graded_at_crown(spacing_mm):
    """scenes/aorta-bent-graded.json's refinement (the bonded patch at the arch's crown and 6 mm round it, steps
    growing 1.2 times outside up to the scene's 4 mm) with the given spacing over the patch."""
    return ('geometry.refine={"angle_center_deg":180,"angle_half_width_deg":15,"s_center_fraction":0.5,'
            f'"s_half_length_m":5e-3,"node_spacing_m":{spacing_mm}e-3,"margin_m":6e-3,"growth":1.2}}')


# What each case runs: the scene, the column of probes.csv compared, the resolutions (label, overrides[, the scene
# instead of the case's]).
CASES = {
    "vein-indent": {
        "scene": "scenes/vein-indent.json", "column": "indenter", "x": "depth", "unit": ("mm", "mN"),
        # Four CalculiX levels to 0.9 mm (the committed three-level vein-indent.csv, to 1.2 mm, reads 0.4-1.1 % high
        # where both are converged; docs/validation.md, "The vein with its bonded indenter").
        "reference": "vein-indent-900um",
        # The patch's nodes on its edges (geometry.fit_lattice_to_patch "edges"): the bonded surface a finite element
        # mesh with nodes on the patch's edges has (docs/validation.md, "The bonded patch: strips or edges"); and the
        # plain lattice at the default spacing (geometry.fit_lattice_to_patch "none"), whose patch nodes span less (drawn,
        # not in the last panel).
        "runs": [(f"{d} mm, edges", [f"geometry.node_spacing_m={d}e-3", GROWTHS, "geometry.fit_lattice_to_patch=edges"])
                 for d in ("0.15", "0.2", "0.3")]
        + [(f"{d} mm, edges, 3 layers", [f"geometry.node_spacing_m={d}e-3", GROWTHS, "geometry.fit_lattice_to_patch=edges",
                                         THREE_LAYERS]) for d in ("0.15", "0.3")]
        + [("0.15 mm, unfitted lattice", ["geometry.node_spacing_m=0.15e-3", GROWTHS, "geometry.fit_lattice_to_patch=none"])]
        + [("0.15 mm, edges, without the cube", ["geometry.node_spacing_m=0.15e-3", GROWTHS,
                                                 "geometry.fit_lattice_to_patch=edges", NO_CUBE])],
    },
    "vein-catheter": {
        "scene": "scenes/hand-dorsal-vein-catheter.json", "column": "catheter", "x": "depth", "unit": ("mm", "mN"),
        "runs": [(f"{d} mm", [f"geometry.node_spacing_m={d}e-3", GROWTHS]) for d in ("0.15", "0.2", "0.3", "0.4")]
        + [(f"{d} mm, 3 layers", [f"geometry.node_spacing_m={d}e-3", GROWTHS, THREE_LAYERS]) for d in ("0.15", "0.3", "0.4")]
        + [("0.15 mm, without the cube", ["geometry.node_spacing_m=0.15e-3", GROWTHS, NO_CUBE])]
        # The bundled graded scene: 0.15 mm round the catheter's tip, 0.4 mm elsewhere, three layers.
        + [("graded, 0.15 mm round the tip, 3 layers", [], "scenes/hand-dorsal-vein-catheter-graded.json")],
    },
    "aorta-bent": {
        "scene": "scenes/aorta-bent.json", "column": "indenter", "x": "depth", "unit": ("mm", "N"),
        # Four CalculiX levels to 2 mm (aorta-bent.csv, three levels to 5 mm, reads 0.4-1.1 % high to 1.5 mm).
        "reference": "aorta-bent-2mm",
        # The lattice fitted to the patch's edges, as the vein's (the unfitted lattices select 0.78-1.22 times the
        # asked area, docs/validation.md); 2.2 mm is the real-time scene's spacing.
        "runs": [(f"{d} mm, edges", [f"geometry.node_spacing_m={d}e-3", GROWTHS, "output.surface=false",
                                     "geometry.fit_lattice_to_patch=edges"])
                 for d in ("1.0", "1.5", "2.2")]
        + [(f"{d} mm, edges, 3 layers", [f"geometry.node_spacing_m={d}e-3", GROWTHS, "output.surface=false",
                                         "geometry.fit_lattice_to_patch=edges", THREE_LAYERS]) for d in ("1.0", "2.2")]
        + [("1.0 mm, edges, without the cube", ["geometry.node_spacing_m=1.0e-3", GROWTHS, "output.surface=false",
                                                "geometry.fit_lattice_to_patch=edges", NO_CUBE])]
        # The bundled graded lattice (scenes/aorta-bent-graded.json: 1.5 mm over the patch), and 1.0 mm there.
        + [(f"graded, {d} mm at the patch", ["output.surface=false", graded_at_crown(d)], "scenes/aorta-bent-graded.json")
           for d in ("1.5", "1.0")],
    },
    "aorta-press": {
        # The curved vessel's contact case: a rigid 10 mm probe on the crown of the arch (no bonded edge).
        "scene": "validation/scenes/aorta-press.json", "column": "probe", "x": "depth", "unit": ("mm", "N"),
        "runs": [(f"{d} mm", [f"geometry.node_spacing_m={d}e-3", GROWTHS, "output.surface=false"])
                 for d in ("1.0", "1.5", "2.2")]
        + [("1.0 mm, without the cube", ["geometry.node_spacing_m=1.0e-3", GROWTHS, "output.surface=false", NO_CUBE])]
        # The bonded case's graded lattice round the same crown (not tuned to the probe).
        + [(f"graded, {d} mm at the crown", ["geometry.node_spacing_m=4e-3", GROWTHS, "output.surface=false",
                                             graded_at_crown(d)]) for d in ("1.5", "1.0")]
        # A compact window round the probe (docs/validation.md, "A compact window"): 0.5 mm over +-5 deg x +-1 mm,
        # 1 mm of margin, each step 1.3 times the last up to 6 mm.
        + [("graded, 0.5 mm round the probe", ["geometry.node_spacing_m=6e-3", GROWTHS, "output.surface=false",
                                               'geometry.refine={"around":"probe","angle_half_width_deg":5,'
                                               '"s_half_length_m":1e-3,"node_spacing_m":0.5e-3,"margin_m":1e-3,'
                                               '"growth":1.3}'])],
    },
    # The two bonded patches with a Mooney-Rivlin wall of the same small-strain E and nu (validation/scenes): a law that
    # does not soften in compression, so the references converge at every depth, where the svk ones stop at 0.8 / 2 mm
    # (docs/validation.md, "The bonded patches with a law that does not soften in compression").
    "vein-indent-mooney-rivlin": {
        "scene": "validation/scenes/vein-indent-mooney-rivlin.json", "column": "indenter", "x": "depth",
        "unit": ("mm", "mN"),
        "runs": [(f"{d} mm, edges", [f"geometry.node_spacing_m={d}e-3", GROWTHS]) for d in ("0.15", "0.2", "0.3")]
        + [("0.3 mm, edges, 3 layers", ["geometry.node_spacing_m=0.3e-3", GROWTHS, THREE_LAYERS])],
    },
    "aorta-bent-mooney-rivlin": {
        "scene": "validation/scenes/aorta-bent-mooney-rivlin.json", "column": "indenter", "x": "depth",
        "unit": ("mm", "N"), "legend": "lower right",
        "runs": [(f"{d} mm, edges", [f"geometry.node_spacing_m={d}e-3", GROWTHS]) for d in ("1.0", "1.5", "2.2")]
        + [("graded, 1.5 mm at the patch", ["geometry.node_spacing_m=4e-3", "geometry.fit_lattice_to_patch=none", GROWTHS,
                                            graded_at_crown("1.5")])],
    },
    "cantilever": {
        "scene": "scenes/cantilever.json", "column": "tip", "x": "load", "unit": ("uN", "um"),
        "runs": [(f"n = {n}", [f"geometry.node_spacing_m={0.01 / n:.6g}", "output.vtk=false"]) for n in (2, 3, 4, 6)],
        # The beam is modelled whole in CalculiX; the vessels as quarters (validation/fem/cases.py).
        "fem_model_share": 1,
    },
}
# Nodes of the whole vessel per node of CalculiX's quarter model: its levels are compared with vascsim per node of the
# same (whole) problem. Four times the quarter counts the nodes on the two symmetry planes twice, a few per cent.
QUARTER_MODEL_SHARE = 4
SCALE = {"mm": 1e3, "mN": 1e3, "N": 1.0, "uN": 1e6, "um": 1e6}
# A reference point judges vascsim only where the extrapolation is converged: relative uncertainty at most this.
# (Past it, e.g. the vein beyond 0.9 mm or the buckled aorta beyond 2.5 mm, the extrapolation is not a reference.)
TRUSTED_UNCERTAINTY = 0.05


def trusted_steps(ref):
    """Indices of the reference points whose relative uncertainty is at most TRUSTED_UNCERTAINTY."""
    return [k for k, (_, y, u) in enumerate(ref) if abs(y) > 0 and u / abs(y) <= TRUSTED_UNCERTAINTY]


def reference_name(case):
    """The file stem of a case's reference in validation/references (the case's own name unless it names another)."""
    return CASES[case].get("reference", case)


def read_reference(case):
    """Rows of the case's reference CSV: (x, y, uncertainty) in SI units."""
    with open(os.path.join(HERE, "references", f"{reference_name(case)}.csv")) as f:
        rows = list(csv.DictReader(f))
    xk, yk = [k for k in rows[0] if k not in ("step",)][:2]
    uk = next(k for k in rows[0] if k.startswith("uncertainty_"))
    return [(float(r[xk]), float(r[yk]), float(r[uk])) for r in rows], (xk, yk)


def read_fem_levels(case):
    """CalculiX's own meshes of the reference: [(level, element, nodes of the whole problem, [y per step in SI])]."""
    with open(os.path.join(HERE, "references", f"{reference_name(case)}-meshes.csv")) as f:
        meshes = list(csv.DictReader(f))
    with open(os.path.join(HERE, "references", f"{reference_name(case)}.csv")) as f:
        rows = list(csv.DictReader(f))
    share = CASES[case].get("fem_model_share", QUARTER_MODEL_SHARE)
    out = []
    for m in meshes:
        column = next(k for k in rows[0] if k.endswith(f"_level{m['level']}"))
        out.append((int(m["level"]), m["element"], share * int(m["nodes"]), [float(r[column]) for r in rows]))
    return out


def run_vascsim(vascsim, scene, sets, out_dir, reuse, threads):
    summary = os.path.join(out_dir, "summary.json")
    if not (reuse and os.path.isfile(summary)):
        cmd = ["nice", "-n", "19", vascsim, "-q", "run", os.path.join(ROOT, scene), "--set", "model=quasi_static",
               "--out", out_dir]
        for s in sets:
            cmd += ["--set", s]
        print(" ".join(cmd), file=sys.stderr, flush=True)
        t0 = time.monotonic()
        env = dict(os.environ, OMP_NUM_THREADS=str(threads))
        if subprocess.run(cmd, env=env).returncode != 0:
            sys.exit(f"error_table.py: vascsim failed on {scene} with {sets}")
        print(f"  {time.monotonic() - t0:.0f} s", file=sys.stderr)
    with open(summary) as f:
        return json.load(f)


def curve(summary, column, x_kind):
    """(x, y) per load step from summary.json: depth and force of a region or tool, or load and deflection."""
    out = []
    for st in summary["steps"][1:]:
        r = st["regions"][column]
        if x_kind == "load":
            out.append((abs(r["force_n"]), r["displacement_m"]))
        else:
            out.append((r["displacement_m"], r["force_n"]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vascsim", default=os.path.join(ROOT, "build", "vascsim"))
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "error-table"))
    ap.add_argument("--figure", default=None, help="figure path (default OUT/error-vs-nodes.png)")
    ap.add_argument("--reuse", action="store_true", help="read finished runs back instead of running them")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a scene override added to every run (repeatable), e.g. --set contact.surface=embedded: the "
                         "table of an option instead of the defaults (use another --out)")
    a = ap.parse_args()
    for kv in a.set:
        if "=" not in kv:
            ap.error(f"--set {kv}: expected KEY=VALUE")
    if not os.path.isfile(a.vascsim):
        sys.exit(f"error_table.py: {a.vascsim} not found; build first (make build)")
    results = {}
    for case in a.cases.split(","):
        spec = CASES[case]
        ref, _ = read_reference(case)
        results[case] = []
        for label, sets, *scene in spec["runs"]:
            out_dir = os.path.join(a.out, case, label.replace(" ", "").replace(",", "-").replace("=", ""))
            summary = run_vascsim(a.vascsim, scene[0] if scene else spec["scene"], sets + a.set, out_dir, a.reuse,
                                  a.threads)
            c = curve(summary, spec["column"], spec["x"])
            # A reference may stop short of the run (its extrapolation converged only so far): its steps are the
            # run's first ones.
            if len(c) < len(ref) or any(abs(p[0] - r[0]) > 1e-6 * max(abs(r[0]), 1e-30) for p, r in zip(c, ref)):
                sys.exit(f"error_table.py: {case} {label}: the run's load steps do not match the reference's")
            results[case].append({"label": label, "nodes": summary["nodes"], "curve": c,
                                  "solve_s": summary["timings_s"]["solve"],
                                  "unconverged": summary.get("unconverged_steps", 0),
                                  "errors": [p[1] / r[1] - 1.0 for p, r in zip(c, ref)]})
    os.makedirs(a.out, exist_ok=True)
    write_csv(results, os.path.join(a.out, "error_table.csv"))
    md = markdown(results)
    with open(os.path.join(a.out, "error_table.md"), "w") as f:
        f.write(md)
    print(md)
    figure(results, a.figure or os.path.join(a.out, "error-vs-nodes.png"))
    return 0


def write_csv(results, path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case", "resolution", "nodes", "step", "x_si", "vascsim_si", "reference_si", "reference_uncertainty_si",
                    "relative_error", "solve_s"])
        for case, runs in results.items():
            ref, _ = read_reference(case)
            for r in runs:
                for k, ((x, y), (_, yr, ur)) in enumerate(zip(r["curve"], ref)):
                    w.writerow([case, r["label"], r["nodes"], k + 1, f"{x:.6g}", f"{y:.6g}", f"{yr:.6g}", f"{ur:.3g}",
                                f"{y / yr - 1:.5f}", f"{r['solve_s']:.1f}"])


def markdown(results):
    lines = []
    for case, runs in results.items():
        ref, _ = read_reference(case)
        spec = CASES[case]
        xu, yu = spec["unit"]
        n = len(ref)
        picks = sorted({0, n // 4, n // 2 - 1, n - 1}) if n > 1 else [0]
        head = [f"{ref[k][0] * SCALE[xu]:.3g} {xu}" for k in picks]
        trusted = trusted_steps(ref)
        lines.append(f"**{case}** (`{spec['scene']}`; reference `{reference_name(case)}` at its last {spec['x']}: "
                     f"{ref[-1][1] * SCALE[yu]:.4g} ± {ref[-1][2] * SCALE[yu]:.2g} {yu}; converged to "
                     f"{100 * TRUSTED_UNCERTAINTY:.0f} % up to {ref[trusted[-1]][0] * SCALE[xu]:.3g} {xu})\n")
        lines.append("| resolution | nodes | " + " | ".join(f"error at {h}" for h in head)
                     + " | max \\|error\\| where converged | solve time |")
        lines.append("|---" * (4 + len(picks)) + "|")
        for r in runs:
            errs = " | ".join(f"{100 * r['errors'][k]:+.1f} %" for k in picks)
            largest = abs(worst(r["errors"], trusted))
            note = f" ({r['unconverged']} steps unconverged)" if r["unconverged"] else ""
            lines.append(f"| {r['label']} | {r['nodes']:,} | {errs} | {100 * largest:.1f} % | {r['solve_s']:.0f} s{note} |")
        # For scale, per node: the FEM's own levels against their extrapolation.
        for level, element, nodes, ys in read_fem_levels(case):
            errs = " | ".join(f"{100 * (ys[k] / ref[k][1] - 1):+.1f} %" for k in picks)
            largest = abs(worst([y / r[1] - 1 for y, r in zip(ys, ref)], trusted))
            lines.append(f"| CalculiX level {level} ({element}) | {nodes:,} | {errs} | {100 * largest:.1f} % | |")
        lines.append("")
    return "\n".join(lines)


def worst(errors, steps):
    """The signed error of largest magnitude among the given steps: what a target "at every depth" judges."""
    return max((errors[k] for k in steps), key=abs)


def run_kind(label):
    """The group a run is drawn with in the last panel: "graded", "3 layers" or "" (the scene's own layering)."""
    return "graded" if label.startswith("graded") else "3 layers" if "3 layers" in label else ""


def figure(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    cases = list(results)
    panels = len(cases) + 1
    rows = 1 if panels <= 4 else 2
    cols = -(-panels // rows)
    fig, grid = plt.subplots(rows, cols, figsize=(4.2 * cols, 4.0 * rows + 1.2), squeeze=False)  # + the last legend
    axes = list(grid.flat)
    for ax in axes[panels:]:
        ax.set_visible(False)
    axes = axes[:panels]
    for ax, case in zip(axes, cases):
        ref, _ = read_reference(case)
        xu, yu = CASES[case]["unit"]
        xs = [r[0] * SCALE[xu] for r in ref]
        ys = [r[1] * SCALE[yu] for r in ref]
        us = [r[2] * SCALE[yu] for r in ref]
        keep = trusted_steps(ref)  # the extrapolation is drawn only where it is converged
        xs, ys, us = [xs[k] for k in keep], [ys[k] for k in keep], [us[k] for k in keep]
        ax.fill_between(xs, [y - u for y, u in zip(ys, us)], [y + u for y, u in zip(ys, us)], color="0.8")
        ax.plot(xs, ys, "k-" if len(xs) > 1 else "k_", lw=2, ms=14,
                label=f"CalculiX, extrapolated (where within ±{100 * TRUSTED_UNCERTAINTY:.0f} %)")
        for r in results[case]:
            ax.plot([p[0] * SCALE[xu] for p in r["curve"]], [p[1] * SCALE[yu] for p in r["curve"]], "o-", ms=3,
                    label=f"vascsim {r['label']} ({r['nodes']:,} nodes)")
        ax.set_title(case)
        ax.set_xlabel(f"{CASES[case]['x']} ({xu})")
        ax.set_ylabel(("force" if CASES[case]["x"] == "depth" else "tip deflection") + f" ({yu})")
        # The force-depth curves rise to the right: their upper left is free for the legend (the buckling aorta's
        # falls again, its lower right is free).
        if "legend" in CASES[case]:
            ax.set_ylim(bottom=0.0)  # room below the curves for it
            ax.legend(fontsize=6, loc=CASES[case]["legend"])
        else:
            ax.legend(fontsize=7, loc="upper left" if CASES[case]["x"] == "depth" else "best")
        ax.grid(alpha=0.3)
    ax = axes[-1]
    for case in cases:
        ref, _ = read_reference(case)
        trusted = trusted_steps(ref)
        last = trusted[-1]
        xu, _ = CASES[case]["unit"]
        # The scenes' own layering solid, the three-layer rows of the same case dashed in the same colour.
        colour = None
        # Graded lattices as diamonds, unjoined.
        for kind, style in (("", "o-"), ("3 layers", "s--"), ("graded", "D")):
            runs = [r for r in results[case] if "lattice" not in r["label"] and "without" not in r["label"]
                    and run_kind(r["label"]) == kind]
            if not runs:
                continue
            runs.sort(key=lambda r: r["nodes"])
            line, = ax.plot([r["nodes"] for r in runs], [100 * worst(r["errors"], trusted) for r in runs], style,
                            color=colour,
                            label=f"{case} to {ref[last][0] * SCALE[xu]:.3g} {xu}" + (f", {kind}" if kind else ""))
            colour = line.get_color()
        levels = read_fem_levels(case)
        ax.plot([lv[2] for lv in levels],
                [100 * worst([y / r[1] - 1 for y, r in zip(lv[3], ref)], trusted) for lv in levels], "x:", color=colour)
    ax.plot([], [], "kx:", label="CalculiX's own levels (whole-problem nodes)")
    ax.axhspan(-5, 5, color="0.9")
    ax.axhline(0, color="k", lw=0.8)
    ax.set_xscale("log")
    ax.set_xlabel("nodes")
    ax.set_ylabel("largest error where the reference is converged (%)")
    ax.set_title("error against node count")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)  # below: the points fill the axes
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    fig.savefig(path, dpi=110)
    print(f"error_table.py: figure {path}", file=sys.stderr)


if __name__ == "__main__":
    sys.exit(main())
