"""CalculiX's *ELASTIC with NLGEOM is the St Venant-Kirchhoff law that vascsim's `svk` implements
(S = lambda tr(E) I + 2 mu E, E the Green-Lagrange strain): one C3D20 unit cube with symmetry conditions on three
faces is stretched uniaxially to 1.3 and compressed to 0.8 in 4 increments each; the force on the moved face
and the lateral stretch must equal the closed form of uniaxial stress in SVK."""
import csv
import math
import os

import numpy as np

from . import ccx
from .hexmesh import Mesh

YOUNGS, POISSON = 0.5e6, 0.45  # Pa: the vein's material


def closed_form(stretch):
    """Force on a unit face (per unit reference area, Pa) and lateral stretch of SVK in uniaxial stress."""
    lam = YOUNGS * POISSON / ((1 + POISSON) * (1 - 2 * POISSON))
    mu = YOUNGS / (2 * (1 + POISSON))
    e11 = 0.5 * (stretch ** 2 - 1)
    e22 = -lam * e11 / (2 * lam + 2 * mu)  # S22 = 0
    s11 = lam * (e11 + 2 * e22) + 2 * mu * e11
    return stretch * s11, math.sqrt(1 + 2 * e22)


def run_one(workdir, stretch, steps=4):
    mesh = Mesh()
    mesh.add_block("CUBE", [0.0, 1.0], [0.0, 1.0], [0.0, 1.0], lambda a, b, c: np.array([a, b, c]))
    deck = ccx.Deck(f"svk check, uniaxial stretch {stretch}")
    deck.mesh(mesh, "C3D20", blocks={"CUBE": "CUBE"})
    deck.elastic("SVK", YOUNGS, POISSON, elset="CUBE")
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


def main(workdir, out_dir):
    rows = run_one(os.path.join(workdir, "tension"), 1.3) + run_one(os.path.join(workdir, "compression"), 0.8)
    os.makedirs(out_dir, exist_ok=True)
    worst = 0.0
    with open(os.path.join(out_dir, "svk-check.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stretch", "ccx_nominal_stress_pa", "ccx_lateral_stretch", "svk_nominal_stress_pa",
                    "svk_lateral_stretch"])
        for r in rows:
            w.writerow([f"{r[0]:.6g}", f"{r[1]:.9g}", f"{r[2]:.9g}", f"{r[3]:.9g}", f"{r[4]:.9g}"])
            worst = max(worst, abs(r[1] - r[3]) / abs(r[3]), abs(r[2] - r[4]))
    print(f"svk-check: {len(rows)} states, stretch 0.8-1.3: largest relative difference between CalculiX and the "
          f"SVK closed form {worst:.2e}")
    return 0 if worst < 1e-5 else 3
