#!/usr/bin/python3
"""The CalculiX decks' material cards (validation/fem): a scene's St Venant-Kirchhoff wall becomes *ELASTIC, a
Mooney-Rivlin wall *HYPERELASTIC, MOONEY-RIVLIN with CalculiX's D1 = 2 / kappa; another law stops the script naming the
key; and the uniaxial closed form the Mooney-Rivlin check compares CalculiX with is uniaxial (no lateral stress) and
has the law's small-strain Young's modulus. Runs without CalculiX."""
import os
import sys
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "validation"))

from fem import ccx, mooney_rivlin_check, scene_params  # noqa: E402


def card(material):
    deck = ccx.Deck("test")
    deck.material("TISSUE", material, elset="WALL")
    return "".join(deck.parts)


class FemMaterials(unittest.TestCase):
    def test_svk_scene_is_elastic(self):
        path = os.path.join(ROOT, "scenes", "vein-indent.json")
        text = card(scene_params.material(scene_params.load(path), path))
        self.assertIn("*ELASTIC\n500000, 0.45", text)
        self.assertNotIn("HYPERELASTIC", text)

    def test_mooney_rivlin_scene_is_hyperelastic_with_d1_two_over_kappa(self):
        path = os.path.join(ROOT, "validation", "scenes", "vein-indent-mooney-rivlin.json")
        scene = scene_params.load(path)
        text = card(scene_params.material(scene, path))
        self.assertIn("*HYPERELASTIC, MOONEY-RIVLIN\n", text)
        c10, c01, d1 = (float(v) for v in text.split("MOONEY-RIVLIN\n")[1].split("\n")[0].split(","))
        mat = scene["material"]
        self.assertEqual(c10, mat["c10_pa"])
        self.assertEqual(c01, mat["c01_pa"])
        # 12 significant digits are written.
        self.assertAlmostEqual(d1 * mat["bulk_modulus_pa"], 2.0, delta=1e-10)

    def test_other_laws_are_refused_naming_the_key(self):
        scene = {"material": {"law": "neo_hookean", "youngs_modulus_pa": 1e6, "poisson_ratio": 0.45}}
        with self.assertRaises(scene_params.SceneError) as raised:
            scene_params.material(scene, "some.json")
        self.assertIn("material.law", str(raised.exception))

    def test_uniaxial_closed_form_has_no_lateral_stress(self):
        law = mooney_rivlin_check.LAW
        for stretch in (0.8, 1.3):
            axial, lateral = mooney_rivlin_check.closed_form(stretch)
            # Newton stops at 1e-9 kappa; the central differences are good to about 1e-6 Pa here.
            self.assertLess(abs(mooney_rivlin_check.nominal_stress([stretch, lateral, lateral], 1)), 1e-8 * law.kappa)
            self.assertEqual(axial > 0, stretch > 1)

    def test_small_strain_modulus_is_youngs(self):
        law = mooney_rivlin_check.LAW
        mu = 2.0 * (law.c10 + law.c01)
        youngs = 9.0 * law.kappa * mu / (3.0 * law.kappa + mu)
        strain = 1e-4
        axial, _ = mooney_rivlin_check.closed_form(1.0 + strain)
        # The secant modulus at 1e-4 differs from the tangent at zero by O(strain): 1e-3 leaves a factor of ten.
        self.assertAlmostEqual(axial / strain / youngs, 1.0, delta=1e-3)


if __name__ == "__main__":
    unittest.main()
