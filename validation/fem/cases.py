"""The reference cases: each builds a CalculiX deck at a refinement level m (every base element split into
m^3) and reads its result back as a curve of (load parameter, value) in SI units.

All vessel cases are quarter models: the bundled scenes are symmetric about the plane through the vessel
axis and the patch (or catheter) centre, and about the cross-section through it; the quarter carries a
quarter of the force. `SymmetryCheck` runs a half model at one level to show that the quarter is exact.
"""
import math
import os

import numpy as np

from . import ccx, scene_params
from .geometry import BentLine, StraightLine, geometric_wall_breaks, power_wall_breaks, quarter_wall_mesh
from .hexmesh import Mesh, graded, refine



def load_factor(time, steps):
    """The exact load factor k/steps of a printed step time (CalculiX prints 7 digits)."""
    k = round(time * steps)
    if abs(time * steps - k) > 1e-4:
        raise RuntimeError(f"step time {time} is not one of the {steps} load steps")
    return k / steps


def _axis(v):
    """Index (0-2) of the coordinate axis a unit vector lies along; the symmetry planes must be axis-aligned
    for the *BOUNDARY cards."""
    a = int(np.argmax(np.abs(v)))
    if abs(abs(v[a]) - 1.0) > 1e-9:
        raise ValueError(f"symmetry plane normal {v} is not along a coordinate axis")
    return a


class WallCase:
    """A vessel wall clamped at both ends, half of it modelled in theta and half in s around a patch or a
    tool at mid-length, theta = theta_c."""

    # Mesh family (geometry.py): "geometric" or "power" with the exponents outside the patch, inside it and
    # through the wall.
    family = "geometric"
    grading = (2.0, 2.0, 2.0)

    def __init__(self, scene_path, base_size_per_thickness=0.85, family=None, whole_circumference=False):
        self.scene_path = scene_path
        if family:
            self.family = family
        # The symmetry check: both halves in theta (a half model, no theta symmetry plane).
        self.whole_circumference = whole_circumference
        self.symmetry_factor = 2.0 if whole_circumference else 4.0
        self.scene = scene_params.load(scene_path)
        scene_params.clamped_ends(self.scene, scene_path)
        self.material = scene_params.material(self.scene, scene_path)
        self.r_out, self.t, line = scene_params.wall(self.scene, scene_path)
        self.r_in = self.r_out - self.t
        if line["type"] == "straight":
            self.line = StraightLine(line["length"])
        else:
            self.line = BentLine(line["radius"], line["angle"], line["leg"])
        self.steps = scene_params.load_steps(self.scene)
        self.base_size = base_size_per_thickness * self.t

    def _symmetry(self, theta_c, s_c):
        """Axes normal to the two symmetry planes: the theta = theta_c plane and the s = s_c cross-section."""
        _, n, b = self.line.frame(s_c)
        th = math.radians(theta_c)
        e_theta = -math.sin(th) * n + math.cos(th) * b
        for s in (0.0, s_c):  # the theta plane must be the same plane along the whole quarter
            _, n2, b2 = self.line.frame(s)
            if np.linalg.norm((-math.sin(th) * n2 + math.cos(th) * b2) - e_theta) > 1e-9:
                raise ValueError("theta_c is not a symmetry plane of this centre-line")
        tangent = np.cross(n, b)
        return _axis(e_theta), _axis(tangent)

    def _wall_mesh(self, theta_c, half_width, s_patch_start, s_c, m):
        if self.family == "geometric":
            breaks = geometric_wall_breaks(self.r_in, self.r_out, theta_c, half_width, s_patch_start, s_c,
                                           self.base_size, m)
        else:
            breaks = power_wall_breaks(self.r_in, self.r_out, theta_c, half_width, s_patch_start, s_c,
                                       self.base_size, m, *self.grading)
        if self.whole_circumference:
            t = breaks[1]
            breaks = (breaks[0], [2.0 * theta_c - x for x in reversed(t)] + t[1:], breaks[2])
        return quarter_wall_mesh(self.line, self.r_in, self.r_out, breaks), breaks

    def _common(self, deck, mesh, theta_c, s_c, sym_theta, sym_s):
        eps = 1e-9
        wall = {"WALL"}
        deck.nset("FIX", mesh.nodes_where_param(lambda r, th, s: abs(s) < eps, wall))
        if not self.whole_circumference:
            deck.nset("SYMT", mesh.nodes_where_param(
                lambda r, th, s: scene_params.angle_is(th, theta_c) or scene_params.angle_is(th, theta_c + 180),
                wall))
        deck.nset("SYMS", mesh.nodes_where_param(lambda r, th, s: abs(s - s_c) < eps, wall))
        deck.material("TISSUE", self.material, elset="WALL")
        bcs = "*BOUNDARY\nFIX, 1, 3\n"
        if not self.whole_circumference:
            bcs += f"SYMT, {sym_theta + 1}, {sym_theta + 1}\n"
        bcs += f"SYMS, {sym_s + 1}, {sym_s + 1}\n"
        return bcs


class BondedPatch(WallCase):
    """The scene's rigid bonded indenter: every node of the outer surface inside the patch (|theta -
    theta_c| <= half width, |s - s_c| <= half length) moves with all three displacement components
    prescribed, push * (-e_r(theta_c)), ramped over the scene's load steps. Result: the force the patch exerts
    on the wall along the push (N) at each push depth (m)."""

    quantity = ("depth_m", "force_n")

    def __init__(self, scene_path, **kw):
        super().__init__(scene_path, **kw)
        self.patch = scene_params.bonded_patch(self.scene, scene_path, self.line.length)
        p = self.patch
        self.s_c = p["s_center"]
        c, n, b = self.line.frame(self.s_c)
        th = math.radians(p["theta"])
        self.push_dir = -(math.cos(th) * n + math.sin(th) * b)

    def deck(self, m, workdir, element="C3D20"):
        p = self.patch
        sym_theta, sym_s = self._symmetry(p["theta"], self.s_c)
        mesh, _ = self._wall_mesh(p["theta"], p["half_width"], self.s_c - p["half_length"], self.s_c, m)
        deck = ccx.Deck(f"{os.path.basename(self.scene_path)}: bonded patch, quarter model, level {m}")
        deck.mesh(mesh, element, blocks={"WALL": "WALL"})
        eps = 1e-9
        patch = mesh.nodes_where_param(
            lambda r, th, s: abs(r - self.r_out) < eps
            and abs(math.remainder(th - p["theta"], 360.0)) <= p["half_width"] + eps
            and s >= self.s_c - p["half_length"] - eps, {"WALL"})
        deck.nset("PATCH", patch)
        bcs = self._common(deck, mesh, p["theta"], self.s_c, sym_theta, sym_s)
        u = p["push"] * self.push_dir
        bcs += "".join(f"PATCH, {k + 1}, {k + 1}, {u[k]:.12g}\n" for k in range(3))
        deck.add(ccx.time_points("TP", self.steps))
        deck.add(ccx.static_step(self.steps, bcs + "*NODE PRINT, NSET=PATCH, TOTALS=ONLY, TIME POINTS=TP\nRF\n"))
        path = os.path.join(workdir, "job")
        deck.write(path + ".inp")
        return path, {"nodes": len(mesh.xyz), "elements": len(mesh.elements)}

    def result(self, path):
        totals = ccx.read_totals(path + ".dat", "PATCH")
        curve = [(load_factor(t, self.steps) * self.patch["push"] * ccx.MM,
                  self.symmetry_factor * ccx.MICRONEWTON * float(np.dot(rf, self.push_dir)))
                 for t, rf in totals]
        if len(curve) != self.steps:
            raise RuntimeError(f"{path}.dat: {len(curve)} of {self.steps} load steps printed")
        return curve


class CatheterPress(WallCase):
    """The scene's catheter: a rigid capsule (hemispherical tip of the catheter's radius on a straight shaft)
    whose tip touches the outer wall at theta_c, s_c and moves `push` along its axis, in frictionless
    contact with the wall (CalculiX face-to-face penalty contact, linear pressure-overclosure of slope
    `penalty` Pa/mm). The catheter is a *RIGID BODY of one layer of C3D20 elements whose outer faces are the
    contact surface; the force is the reaction at its reference node along the push (N)."""

    quantity = ("depth_m", "force_n")
    # The contact edge moves with the push and the pressure vanishes there (no fixed singular line): uniform
    # elements over the contact zone and through the wall, graded only outside the zone.
    family = "power"
    grading = (2.0, 1.0, 1.0)

    def __init__(self, scene_path, penalty=5e7, fine_half_width=45.0, fine_half_length_per_radius=1.25, **kw):
        super().__init__(scene_path, **kw)
        self.tool = scene_params.catheter(self.scene, scene_path)
        self.penalty = penalty
        tip = np.array(self.tool["tip"])
        self.push_dir = np.array(self.tool["direction"], dtype=float)
        self.push_dir /= np.linalg.norm(self.push_dir)
        # The tip must touch the wall at mid-length along the inward radius (what the quarter model mirrors).
        self.s_c = 0.5 * self.line.length
        c, n, b = self.line.frame(self.s_c)
        radial = tip - c
        self.theta_c = math.degrees(math.atan2(radial @ b, radial @ n)) % 360.0
        if abs(np.linalg.norm(radial) - self.r_out) > 1e-9 or np.linalg.norm(
                self.push_dir + radial / np.linalg.norm(radial)) > 1e-9:
            raise scene_params.SceneError(f"{scene_path}: key 'obstacles': the quarter model needs the catheter tip "
                                          "on the outer wall at mid-length, pointing along the inward radius")
        self.fine_half_width = fine_half_width
        self.fine_half_length = fine_half_length_per_radius * self.tool["radius"]
        self.steps = scene_params.load_steps(self.scene)

    def _catheter(self, mesh, m):
        """Quarter of the capsule inside the modelled quarter (theta >= theta_c, s <= s_c): three equal-angle
        cube-sphere patches of the hemisphere (no pole at the tip) and the shaft above its equator, one
        element layer of 10 % of the radius thick. Returns the sphere centre."""
        rad = self.tool["radius"]
        d = self.push_dir
        centre = np.array(self.tool["tip"]) - rad * d
        _, n, b = self.line.frame(self.s_c)
        th = math.radians(self.theta_c)
        a = -math.sin(th) * n + math.cos(th) * b  # towards theta > theta_c
        w = -np.cross(n, b)                         # towards s < s_c
        n_face = max(1, round(0.25 * math.pi * rad / self.base_size))
        ang = refine(graded(0.0, 45.0, n_face), m)
        rho = [0.9 * rad, rad]

        def on_sphere(cube_point):
            def f(r, u, v):
                p = cube_point(math.tan(math.radians(u)), math.tan(math.radians(v)))
                p = p / np.linalg.norm(p)
                return centre + r * (p[0] * a + p[1] * d + p[2] * w)
            return f
        mesh.add_block("CATH", rho, ang, ang, on_sphere(lambda u, v: np.array([u, 1.0, v])))  # around the tip
        mesh.add_block("CATH", rho, ang, ang, on_sphere(lambda u, v: np.array([1.0, u, v])))  # a side
        mesh.add_block("CATH", rho, ang, ang, on_sphere(lambda u, v: np.array([u, v, 1.0])))  # w side
        phi = ang + [90.0 - x for x in reversed(ang)][1:]
        shaft = refine(graded(0.0, rad, max(1, round(rad / (2 * self.base_size)))), m)
        mesh.add_block("CATH", rho, phi, shaft, lambda r, p, h: centre + r * (
            math.cos(math.radians(p)) * a + math.sin(math.radians(p)) * w) - h * d)
        return centre

    def _contact_face(self, centre):
        rad, d, tol = self.tool["radius"], self.push_dir, 1e-7

        def on_surface(x):
            q = x - centre
            h = -(q @ d)  # height above the equator
            return ((h <= tol and abs(np.linalg.norm(q) - rad) < tol)
                    or (h >= -tol and abs(np.linalg.norm(q + h * d) - rad) < tol))
        return on_surface

    def deck(self, m, workdir, element="C3D20"):
        sym_theta, sym_s = self._symmetry(self.theta_c, self.s_c)
        mesh, _ = self._wall_mesh(self.theta_c, self.fine_half_width, self.s_c - self.fine_half_length, self.s_c, m)
        centre = self._catheter(mesh, m)
        ref = mesh.add_node(centre, "REF")
        rot = mesh.add_node(centre + self.push_dir, "REF")
        deck = ccx.Deck(f"{os.path.basename(self.scene_path)}: catheter press, quarter model, level {m}")
        deck.mesh(mesh, element, blocks={"WALL": "WALL", "CATH": "CATH"})
        bcs = self._common(deck, mesh, self.theta_c, self.s_c, sym_theta, sym_s)
        deck.add("*MATERIAL, NAME=RIGID\n*ELASTIC\n1e12, 0.3\n*SOLID SECTION, ELSET=CATH, MATERIAL=RIGID")
        deck.add(f"*RIGID BODY, ELSET=CATH, REF NODE={ref}, ROT NODE={rot}")
        deck.nset("REFNODE", [ref])
        deck.nset("ROTNODE", [rot])
        eps = 1e-9
        zone = lambda r, th, s: (abs(r - self.r_out) < eps and th <= self.theta_c + 1.5 * self.fine_half_width + eps
                                 and s >= self.s_c - 2.0 * self.fine_half_length - eps)
        deck.surface("WALLOUT", mesh.faces_where_param(zone, blocks={"WALL"}))
        deck.surface("TOOL", mesh.faces_where(self._contact_face(centre), blocks={"CATH"}))
        deck.add(f"*SURFACE INTERACTION, NAME=FRICTIONLESS\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n"
                 f"{self.penalty:.6g}, 1e-3")
        deck.add("*CONTACT PAIR, INTERACTION=FRICTIONLESS, TYPE=SURFACE TO SURFACE\nWALLOUT, TOOL")
        u = self.tool["push"] * self.push_dir
        bcs += "".join(f"REFNODE, {k + 1}, {k + 1}, {u[k]:.12g}\n" for k in range(3)) + "ROTNODE, 1, 3\n"
        deck.add(ccx.time_points("TP", self.steps))
        deck.add(ccx.static_step(self.steps, bcs + "*NODE PRINT, NSET=REFNODE, TOTALS=ONLY, TIME POINTS=TP\nRF\n"))
        path = os.path.join(workdir, "job")
        deck.write(path + ".inp")
        return path, {"nodes": sum(1 for p in mesh.param if p[0] == "WALL"), "elements": len(mesh.elements)}

    def result(self, path):
        totals = ccx.read_totals(path + ".dat", "REFNODE")
        curve = [(load_factor(t, self.steps) * self.tool["push"] * ccx.MM,
                  self.symmetry_factor * ccx.MICRONEWTON * float(np.dot(rf, self.push_dir)))
                 for t, rf in totals]
        if len(curve) != self.steps:
            raise RuntimeError(f"{path}.dat: {len(curve)} of {self.steps} load steps printed")
        return curve


def timoshenko_tip_deflection(load, length, width, height, youngs, poisson):
    """The project's reference (src/vascsim/core/beam_theory.hpp): Euler-Bernoulli bending plus Timoshenko
    shear with Cowper's coefficient, any consistent units."""
    inertia = width * height ** 3 / 12.0
    area = width * height
    shear = youngs / (2.0 * (1.0 + poisson))
    kappa = 10.0 * (1.0 + poisson) / (12.0 + 11.0 * poisson)
    return load * length ** 3 / (3.0 * youngs * inertia) + load * length / (kappa * shear * area)


class Cantilever:
    """docs/validation.md T9 as scenes/cantilever.json states it: a square beam clamped over its whole face x = 0 (the
    scene fixes the lattice at x <= 0, which holds that face), the tip load spread uniformly over the end face
    x = L (consistent nodal forces of a uniform traction), NLGEOM in the scene's load steps. Result: the
    area-mean displacement of the end face along the load (m) at each load (N). Base mesh: elements of b/2,
    level m: 2m x 2m x 20m elements."""

    quantity = ("load_n", "tip_deflection_m")

    def __init__(self, scene_path):
        self.scene_path = scene_path
        self.scene = scene_params.load(scene_path)
        self.material = scene_params.material(self.scene, scene_path)
        self.beam = scene_params.beam(self.scene, scene_path)
        self.steps = scene_params.load_steps(self.scene)
        self.load_dir = np.array(self.beam["direction"], dtype=float)
        self.load_dir /= np.linalg.norm(self.load_dir)

    def deck(self, m, workdir, element="C3D20"):
        bm = self.beam
        n_cross = 2 * m
        mesh = Mesh()
        mesh.add_block("BEAM", refine([0.0, bm["length"]], 10 * n_cross), refine([0.0, bm["width"]], n_cross),
                       refine([0.0, bm["height"]], n_cross), lambda x, y, z: np.array([x, y, z]))
        deck = ccx.Deck(f"{os.path.basename(self.scene_path)}: cantilever, level {m}")
        deck.mesh(mesh, element, blocks={"BEAM": "BEAM"})
        deck.material("TISSUE", self.material, elset="BEAM")
        eps = 1e-9
        deck.nset("CLAMP", mesh.nodes_where(lambda x: abs(x[0]) < eps))
        end = lambda x: abs(x[0] - bm["length"]) < eps
        deck.nset("TIP", mesh.nodes_where(end))
        faces = mesh.faces_where(end)
        self.weights = mesh.face_weights(faces)
        area = sum(self.weights.values())
        load = bm["force"] / ccx.MICRONEWTON * self.load_dir
        cload = "*CLOAD\n" + "".join(f"{node}, {k + 1}, {w / area * load[k]:.12g}\n"
                                     for node, w in sorted(self.weights.items()) for k in range(3) if load[k] != 0)
        deck.add(ccx.time_points("TP", self.steps))
        deck.add(ccx.static_step(self.steps, "*BOUNDARY\nCLAMP, 1, 3\n" + cload
                                 + "*NODE PRINT, NSET=TIP, TIME POINTS=TP\nU\n"))
        path = os.path.join(workdir, "job")
        deck.write(path + ".inp")
        with open(path + ".weights", "w") as f:
            f.write("\n".join(f"{n} {w:.17g}" for n, w in sorted(self.weights.items())))
        return path, {"nodes": len(mesh.xyz), "elements": len(mesh.elements)}

    def result(self, path):
        weights = {int(l.split()[0]): float(l.split()[1]) for l in open(path + ".weights")}
        area = sum(weights.values())
        values = ccx.read_node_values(path + ".dat", "TIP", "displacements")
        curve = []
        for t, nodes in sorted(values.items()):
            mean = sum(weights[n] * np.dot(u, self.load_dir) for n, u in nodes.items()) / area
            curve.append((load_factor(t, self.steps) * self.beam["force"], mean * ccx.MM))
        if len(curve) != self.steps:
            raise RuntimeError(f"{path}.dat: {len(curve)} of {self.steps} load steps printed")
        return curve

    def timoshenko(self):
        bm = self.beam
        if self.material.law != "svk":
            return None
        # The scene's beam bends along its height (load along z).
        return timoshenko_tip_deflection(bm["force"], bm["length"] * ccx.MM, bm["width"] * ccx.MM,
                                         bm["height"] * ccx.MM, self.material.youngs, self.material.poisson)
