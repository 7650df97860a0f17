"""CalculiX's *ELASTIC with NLGEOM is the St Venant-Kirchhoff law that vascsim's `svk` implements
(S = lambda tr(E) I + 2 mu E, E the Green-Lagrange strain): one C3D20 unit cube with symmetry conditions on three
faces is stretched uniaxially to 1.3 and compressed to 0.8 in 4 increments each; the force on the moved face
and the lateral stretch must equal the closed form of uniaxial stress in SVK."""
import math

from . import uniaxial_check
from .scene_params import Material

YOUNGS, POISSON = 0.5e6, 0.45  # Pa: the vein's material


def closed_form(stretch):
    """Force on a unit face (per unit reference area, Pa) and lateral stretch of SVK in uniaxial stress."""
    lam = YOUNGS * POISSON / ((1 + POISSON) * (1 - 2 * POISSON))
    mu = YOUNGS / (2 * (1 + POISSON))
    e11 = 0.5 * (stretch ** 2 - 1)
    e22 = -lam * e11 / (2 * lam + 2 * mu)  # S22 = 0
    s11 = lam * (e11 + 2 * e22) + 2 * mu * e11
    return stretch * s11, math.sqrt(1 + 2 * e22)


def main(workdir, out_dir):
    law = Material("svk", youngs=YOUNGS, poisson=POISSON)
    rows, worst = uniaxial_check.compare("svk-check", law, closed_form, workdir, out_dir, "svk")
    print(f"svk-check: {len(rows)} states, stretch 0.8-1.3: largest relative difference between CalculiX and the "
          f"SVK closed form {worst:.2e}")
    return 0 if worst < 1e-5 else 3
