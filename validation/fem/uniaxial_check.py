"""The shared half of the material checks (svk_check.py, mooney_rivlin_check.py): one C3D20 unit cube with symmetry
conditions on three faces, stretched uniaxially to 1.3 and compressed to 0.8 in 4 increments each, its force on the
moved face and its lateral stretch against a law's closed form of uniaxial stress."""
import csv
import os

import numpy as np

from . import ccx
from .hexmesh import Mesh


def run_one(workdir, stretch, material, closed_form, title, steps=4):
    """Rows (stretch, CalculiX's nominal stress Pa, its lateral stretch, the closed form's stress, its lateral
    stretch) per increment; closed_form(stretch) -> (nominal stress Pa, lateral stretch)."""
    mesh = Mesh()
    mesh.add_block("CUBE", [0.0, 1.0], [0.0, 1.0], [0.0, 1.0], lambda a, b, c: np.array([a, b, c]))
    deck = ccx.Deck(f"{title}, uniaxial stretch {stretch}")
    deck.mesh(mesh, "C3D20", blocks={"CUBE": "CUBE"})
    deck.material("LAW", material, elset="CUBE")
    for axis, name in enumerate("XYZ"):
        deck.nset(name + "0", mesh.nodes_where(lambda x, a=axis: abs(x[a]) < 1e-9))
    deck.nset("X1", mesh.nodes_where(lambda x: abs(x[0] - 1) < 1e-9))
    deck.nset("CORNER", mesh.nodes_where(lambda x: np.linalg.norm(x - 1) < 1e-9))
    deck.add(ccx.time_points("TP", steps))
    deck.add(ccx.static_step(steps, f"*BOUNDARY\nX0, 1, 1\nY0, 2, 2\nZ0, 3, 3\nX1, 1, 1, {stretch - 1:.12g}\n"
                             "*NODE PRINT, NSET=X1, TOTALS=ONLY, TIME POINTS=TP\nRF\n"
                             "*NODE PRINT, NSET=CORNER, TIME POINTS=TP\nU\n"))
    os.makedirs(workdir, exist_ok=True)
    path = os.path.join(workdir, "job")
    deck.write(path + ".inp")
    ccx.run(path, path + ".log")
    forces = ccx.read_totals(path + ".dat", "X1")
    corner = ccx.read_node_values(path + ".dat", "CORNER")
    rows = []
    for t, rf in forces:
        lam1 = 1 + t * (stretch - 1)
        (u,) = corner[t].values()
        # Deck units: 1 mm cube, forces in uN; the face is 1 mm^2, so uN/mm^2 = Pa.
        rows.append((lam1, rf[0], 1 + u[1], *closed_form(lam1)))
    return rows


def compare(name, material, closed_form, workdir, out_dir, law_label):
    """Tension and compression, written to out_dir/<name>.csv; returns the rows and the largest difference between
    CalculiX and the closed form (relative in the stress, absolute in the lateral stretch)."""
    rows = (run_one(os.path.join(workdir, "tension"), 1.3, material, closed_form, name)
            + run_one(os.path.join(workdir, "compression"), 0.8, material, closed_form, name))
    os.makedirs(out_dir, exist_ok=True)
    worst = 0.0
    with open(os.path.join(out_dir, f"{name}.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stretch", "ccx_nominal_stress_pa", "ccx_lateral_stretch", f"{law_label}_nominal_stress_pa",
                    f"{law_label}_lateral_stretch"])
        for r in rows:
            w.writerow([f"{r[0]:.6g}", f"{r[1]:.9g}", f"{r[2]:.9g}", f"{r[3]:.9g}", f"{r[4]:.9g}"])
            worst = max(worst, abs(r[1] - r[3]) / abs(r[3]), abs(r[2] - r[4]))
    return rows, worst
