"""CalculiX's *HYPERELASTIC, MOONEY-RIVLIN is the law that vascsim's `mooney_rivlin` implements
(psi = C10 (I1bar - 3) + C01 (I2bar - 3) + kappa/2 (J - 1)^2, CalculiX's D1 = 2 / kappa): one C3D20 unit cube with
symmetry conditions on three faces is stretched uniaxially to 1.3 and compressed to 0.8 in 4 increments each; the
force on the moved face and the lateral stretch must equal uniaxial stress in that law, solved here from psi
itself (Newton on the lateral stretch, the stresses by central differences of psi)."""
import csv
import os

import numpy as np

from . import ccx
from .hexmesh import Mesh
from .scene_params import Material

# Pa: both terms non-zero so that each is checked; kappa ten times the shear modulus (small-strain nu 0.45).
LAW = Material("mooney_rivlin", c10=60.0e3, c01=26.2e3, kappa=1.724e6)


def energy(stretches, law=LAW):
    """psi of the diagonal deformation gradient diag(stretches), J/m^3."""
    l2 = np.asarray(stretches, dtype=float) ** 2
    J = float(np.prod(stretches))
    i1 = l2.sum()
    i2 = l2[0] * l2[1] + l2[1] * l2[2] + l2[2] * l2[0]
    return (law.c10 * (J ** (-2.0 / 3.0) * i1 - 3.0) + law.c01 * (J ** (-4.0 / 3.0) * i2 - 3.0)
            + 0.5 * law.kappa * (J - 1.0) ** 2)


def nominal_stress(stretches, k, step=1e-6):
    """d psi / d lambda_k, the nominal (first Piola-Kirchhoff) principal stress, Pa."""
    up, down = list(stretches), list(stretches)
    up[k] += step
    down[k] -= step
    return (energy(up) - energy(down)) / (2.0 * step)


def closed_form(stretch):
    """Force on a unit face (per unit reference area, Pa) and lateral stretch in uniaxial stress."""
    lateral = 1.0
    for _ in range(100):
        p = nominal_stress([stretch, lateral, lateral], 1)
        # Both lateral stretches move together.
        slope = (nominal_stress([stretch, lateral + 1e-5, lateral + 1e-5], 1)
                 - nominal_stress([stretch, lateral - 1e-5, lateral - 1e-5], 1)) / 2e-5
        lateral -= p / slope
        if abs(p) < 1e-9 * LAW.kappa:
            break
    return nominal_stress([stretch, lateral, lateral], 0), lateral


def run_one(workdir, stretch, steps=4):
    mesh = Mesh()
    mesh.add_block("CUBE", [0.0, 1.0], [0.0, 1.0], [0.0, 1.0], lambda a, b, c: np.array([a, b, c]))
    deck = ccx.Deck(f"mooney-rivlin check, uniaxial stretch {stretch}")
    deck.mesh(mesh, "C3D20", blocks={"CUBE": "CUBE"})
    deck.material("MR", LAW, elset="CUBE")
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
    with open(os.path.join(out_dir, "mooney-rivlin-check.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["stretch", "ccx_nominal_stress_pa", "ccx_lateral_stretch", "law_nominal_stress_pa",
                    "law_lateral_stretch"])
        for r in rows:
            w.writerow([f"{r[0]:.6g}", f"{r[1]:.9g}", f"{r[2]:.9g}", f"{r[3]:.9g}", f"{r[4]:.9g}"])
            worst = max(worst, abs(r[1] - r[3]) / abs(r[3]), abs(r[2] - r[4]))
    print(f"mooney-rivlin-check: {len(rows)} states, stretch 0.8-1.3: largest relative difference between CalculiX "
          f"and the law {worst:.2e}")
    return 0 if worst < 1e-5 else 3
