"""CalculiX's *HYPERELASTIC, MOONEY-RIVLIN is the law that vascsim's `mooney_rivlin` implements
(psi = C10 (I1bar - 3) + C01 (I2bar - 3) + kappa/2 (J - 1)^2, CalculiX's D1 = 2 / kappa): one C3D20 unit cube with
symmetry conditions on three faces is stretched uniaxially to 1.3 and compressed to 0.8 in 4 increments each; the
force on the moved face and the lateral stretch must equal uniaxial stress in that law, solved here from psi
itself (Newton on the lateral stretch, the stresses by central differences of psi)."""
import numpy as np

from . import uniaxial_check
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


def main(workdir, out_dir):
    rows, worst = uniaxial_check.compare("mooney-rivlin-check", LAW, closed_form, workdir, out_dir, "law")
    print(f"mooney-rivlin-check: {len(rows)} states, stretch 0.8-1.3: largest relative difference between CalculiX "
          f"and the law {worst:.2e}")
    return 0 if worst < 1e-5 else 3
