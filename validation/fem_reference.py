#!/usr/bin/python3
"""Independent finite-element references for vascsim's bundled scenes, computed with CalculiX (ccx, the
Debian package calculix-ccx), mesh-converged by Richardson extrapolation.

For each case and refinement level m the script writes a CalculiX deck (structured 20-node hexahedra,
generated here), runs ccx under `nice -n 19`, reads the curve back, and after the last level writes

  validation/references/<case>.csv         the extrapolated curve with its uncertainty and every level's curve
  validation/references/<case>-meshes.csv  the mesh of every level (nodes, elements, degrees of freedom,
                                           Newton iterations, wall time)

Richardson extrapolation uses the three finest levels (observed order and the GCI of Celik et al. 2008, see
fem/richardson.py). The decks and ccx's outputs stay in --work (default out/fem/<case>/L<m>); a level that
already ran to the end with the same deck is read back instead of run again unless --rerun is given.

Cases (scene files are read for every dimension, material and boundary condition):
  vein-indent     scenes/vein-indent.json            bonded patch on the straight vein, force vs depth
  vein-catheter   scenes/hand-dorsal-vein-catheter.json  rigid frictionless catheter on the same vein
  aorta-bent      scenes/aorta-bent.json             bonded patch on the crown of the 180 deg arch
  aorta-press     validation/scenes/aorta-press.json rigid frictionless 10 mm probe on the same crown
  cantilever      scenes/cantilever.json             docs/validation.md T9 beam, tip deflection vs load
  svk-check       one element stretched to 1.3 and compressed to 0.8 against St Venant-Kirchhoff's closed
                  form (shows that *ELASTIC with NLGEOM is the SVK law)
  mooney-rivlin-check  the same for *HYPERELASTIC, MOONEY-RIVLIN against vascsim's mooney_rivlin energy (a scene
                  with material.law "mooney_rivlin" is written as that law, D1 = 2 / bulk_modulus_pa)

Example (the committed references; hours on a shared 2-core machine, see docs/validation.md):
  /usr/bin/python3 validation/fem_reference.py vein-indent --levels 1,2,3
The catheter's check with reduced-integration elements (validation/references/vein-catheter-c3d20r.csv):
  /usr/bin/python3 validation/fem_reference.py vein-catheter --levels 2,3,4 --element C3D20R --name vein-catheter-c3d20r
The vein's with reduced-integration elements, to 0.9 mm (validation/references/vein-indent-c3d20r.csv; 11 minutes):
  /usr/bin/python3 validation/fem_reference.py vein-indent --levels 2,3,4 --element C3D20R \
      --scene validation/scenes/vein-indent-900um.json --name vein-indent-c3d20r
The same with the committed elements, levels 2-4 (validation/references/vein-indent-900um.csv; 18 minutes):
  /usr/bin/python3 validation/fem_reference.py vein-indent --levels 2,3,4 \
      --scene validation/scenes/vein-indent-900um.json --name vein-indent-900um
The bonded aorta, four levels to 2 mm (validation/references/aorta-bent-2mm.csv; 9 minutes):
  /usr/bin/python3 validation/fem_reference.py aorta-bent --levels 2,3,4 \
      --scene validation/scenes/aorta-bent-2mm.json --name aorta-bent-2mm
The aorta pressed by a probe (validation/references/aorta-press.csv; 43 minutes):
  /usr/bin/python3 validation/fem_reference.py aorta-press --levels 2,3,4
The aorta's, to 2 mm (validation/references/aorta-bent-c3d20r.csv):
  /usr/bin/python3 validation/fem_reference.py aorta-bent --levels 2,3,4 --element C3D20R \
      --scene validation/scenes/aorta-bent-2mm.json --name aorta-bent-c3d20r
"""
import argparse
import csv
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)

from fem import cases, ccx, mooney_rivlin_check, richardson, svk_check  # noqa: E402

def scene(a, bundled):
    """The case's scene file: --scene, or the bundled one."""
    return a.scene or os.path.join(ROOT, "scenes", bundled)


CASES = {
    "vein-indent": lambda a: cases.BondedPatch(scene(a, "vein-indent.json"), family=a.family,
                                               whole_circumference=a.whole_circumference),
    "vein-catheter": lambda a: cases.CatheterPress(scene(a, "hand-dorsal-vein-catheter.json"), penalty=a.penalty),
    "aorta-bent": lambda a: cases.BondedPatch(scene(a, "aorta-bent.json"), family=a.family),
    "aorta-press": lambda a: cases.CatheterPress(a.scene or os.path.join(HERE, "scenes", "aorta-press.json"),
                                                 penalty=a.penalty),
    "cantilever": lambda a: cases.Cantilever(scene(a, "cantilever.json")),
}


def run_level(case, m, workdir, element, rerun):
    """Writes the level's deck and runs ccx, unless the same deck already ran to the end here (job.wall is
    written after a finished run; a changed deck or an interrupted run is run again)."""
    os.makedirs(workdir, exist_ok=True)
    path = os.path.join(workdir, "job")
    previous = open(path + ".inp").read() if os.path.exists(path + ".inp") else None
    path, info = case.deck(m, workdir, element)
    done = os.path.exists(path + ".wall") and previous == open(path + ".inp").read()
    if rerun or not done:
        if os.path.exists(path + ".wall"):
            os.remove(path + ".wall")
        wall = ccx.run(path, path + ".log")
        with open(path + ".wall", "w") as f:
            f.write(f"{wall:.1f}\n")
    wall = float(open(path + ".wall").read())
    increments, iterations = ccx.increments(path + ".sta")
    info.update({"level": m, "element": element, "dofs": 3 * info["nodes"], "increments": increments,
                 "newton_iterations": iterations, "wall_time_s": wall})
    return case.result(path), info


def write_reference(name, case, levels, curves, infos, out_dir):
    """Extrapolates from the three finest levels and writes the two CSV files."""
    xname, yname = case.quantity
    fine = sorted(levels)[-3:]
    h = [1.0 / m for m in reversed(fine)]  # fine to coarse
    rows = []
    for k, (x, _) in enumerate(curves[fine[-1]]):
        f = [curves[m][k][1] for m in reversed(fine)]
        ext = richardson.extrapolate(h, f)
        row = {"step": k + 1, xname: f"{x:.9g}", yname: f"{ext['value']:.9g}",
               "uncertainty_" + yname.rsplit("_", 1)[-1]: f"{ext['uncertainty']:.3g}",
               "observed_order": f"{ext['order']:.3f}", "monotone": int(ext["monotone"])}
        for m in sorted(levels):
            row[f"{yname}_level{m}"] = f"{curves[m][k][1]:.9g}"
        rows.append(row)
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, f"{name}.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    keys = ["level", "element", "elements", "nodes", "dofs", "increments", "newton_iterations", "wall_time_s"]
    with open(os.path.join(out_dir, f"{name}-meshes.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for m in sorted(levels):
            w.writerow(infos[m])
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case", choices=sorted(CASES) + ["svk-check", "mooney-rivlin-check"])
    ap.add_argument("--levels", default="1,2,3", help="refinement levels m (comma list; the finest three "
                    "are extrapolated)")
    ap.add_argument("--element", default="C3D20", choices=["C3D20", "C3D20R"])
    ap.add_argument("--family", default=None, choices=["geometric", "power"],
                    help="wall mesh family of the bonded patches (default geometric; fem/geometry.py)")
    ap.add_argument("--whole-circumference", action="store_true",
                    help="vein-indent: model both halves in theta (the check of the theta symmetry plane)")
    ap.add_argument("--penalty", type=float, default=5e7, help="vein-catheter, aorta-press: contact penalty slope, Pa/mm")
    ap.add_argument("--work", default=None, help="deck directory (default out/fem/<case>)")
    ap.add_argument("--out", default=os.path.join(HERE, "references"), help="where the CSV files go")
    ap.add_argument("--name", default=None, help="file name of the reference (default: the case)")
    ap.add_argument("--scene", default=None, help="a scene file of the case's kind instead of the bundled one "
                    "(e.g. the catheter scene with another material; give --name too)")
    ap.add_argument("--rerun", action="store_true", help="run ccx even where a level's results exist")
    a = ap.parse_args()
    if a.case == "svk-check":
        return svk_check.main(os.path.join(a.work or os.path.join(ROOT, "out", "fem", "svk-check")), a.out)
    if a.case == "mooney-rivlin-check":
        return mooney_rivlin_check.main(a.work or os.path.join(ROOT, "out", "fem", "mooney-rivlin-check"), a.out)
    levels = [int(v) for v in a.levels.split(",")]
    if len(levels) < 3:
        ap.error("three levels at least are needed for the extrapolation")
    case = CASES[a.case](a)
    name = a.name or a.case
    work = a.work or os.path.join(ROOT, "out", "fem", name)
    curves, infos = {}, {}
    for m in sorted(levels):
        curves[m], infos[m] = run_level(case, m, os.path.join(work, f"L{m}"), a.element, a.rerun)
        last = curves[m][-1]
        print(f"{name}: level {m}: {infos[m]['nodes']} nodes, {infos[m]['newton_iterations']} Newton iterations, "
              f"{infos[m]['wall_time_s']} s; {case.quantity[1]} at {case.quantity[0]} {last[0]:.6g}: {last[1]:.6g}",
              flush=True)
    rows = write_reference(name, case, levels, curves, infos, a.out)
    y = case.quantity[1]
    u = "uncertainty_" + y.rsplit("_", 1)[-1]
    print(f"{name}: extrapolated {y} at the last step {rows[-1][y]} +- {rows[-1][u]} "
          f"(observed order {rows[-1]['observed_order']}); written to {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
