"""The parameters of a bundled vascsim scene that a reference case mirrors, read from its JSON file and
converted to the decks' units (mm, Pa). Anything the FEM does not model (another boundary condition, an
off-centre patch) stops the script with a message naming the scene and the key."""
import json
import math


class SceneError(Exception):
    pass


def load(path):
    with open(path) as f:
        return json.load(f)


def _need(cond, path, key, what):
    if not cond:
        raise SceneError(f"{path}: key '{key}': {what}")


class Material:
    """The scene's strain-energy law in the decks' units (Pa). svk: E and nu. mooney_rivlin: C10, C01 and the bulk
    modulus kappa, psi = C10 (I1bar - 3) + C01 (I2bar - 3) + kappa/2 (J - 1)^2, which is CalculiX's MOONEY-RIVLIN
    with D1 = 2 / kappa."""

    def __init__(self, law, **values):
        self.law = law
        self.__dict__.update(values)


def material(scene, path):
    mat = scene["material"]
    law = mat.get("law", "svk")
    _need(law in ("svk", "mooney_rivlin"), path, "material.law",
          f"the references model St Venant-Kirchhoff (svk) and Mooney-Rivlin (mooney_rivlin), not {law}")
    if law == "svk":
        return Material("svk", youngs=mat["youngs_modulus_pa"], poisson=mat["poisson_ratio"])
    for key in ("c10_pa", "c01_pa", "bulk_modulus_pa"):
        _need(key in mat, path, f"material.{key}", "mooney_rivlin needs it")
    return Material("mooney_rivlin", c10=mat["c10_pa"], c01=mat["c01_pa"], kappa=mat["bulk_modulus_pa"])


def wall(scene, path):
    """Outer radius, thickness (mm) and the centre-line description of a tube or vessel scene."""
    g = scene["geometry"]
    _need(g["type"] in ("tube", "vessel"), path, "geometry.type", "a tube or a swept vessel is needed")
    ro, t = g["outer_radius_m"] * 1e3, g["wall_thickness_m"] * 1e3
    if g["type"] == "tube":
        return ro, t, {"type": "straight", "length": g["length_m"] * 1e3}
    c = g["centerline"]
    if c["type"] == "straight":
        return ro, t, {"type": "straight", "length": c["length_m"] * 1e3}
    _need(c["type"] == "bent", path, "geometry.centerline.type", "straight or bent centre-lines only")
    return ro, t, {"type": "bent", "radius": c["radius_of_curvature_m"] * 1e3, "angle": c["angle_deg"],
                   "leg": c["leg_length_m"] * 1e3}


def clamped_ends(scene, path):
    """Both end annuli fixed (cylinder_end selectors of depth 0: the nodes of the end cross-sections)."""
    ends = [r for r in scene["regions"] if r["select"]["type"] == "cylinder_end"]
    kinds = sorted(r["select"]["end"] for r in ends)
    _need(kinds == ["end", "start"], path, "regions", "both ends must be clamped by cylinder_end selectors")
    for r in ends:
        _need(r["bc"]["type"] == "fixed", path, f"regions.{r['name']}.bc.type", "the ends must be fixed")
        _need(r["select"].get("depth_m", 0.0) == 0.0, path, f"regions.{r['name']}.select.depth_m",
              "the references clamp the end cross-section only (depth 0)")


def bonded_patch(scene, path, length_mm):
    """The displacement-driven wall patch: centre angle, half-width (deg), s centre and half-length (mm),
    push (mm) along the inward radius."""
    patches = [r for r in scene["regions"] if r["select"]["type"] == "wall_patch"]
    _need(len(patches) == 1, path, "regions", "exactly one wall_patch region is needed")
    r = patches[0]
    sel, bc = r["select"], r["bc"]
    key = f"regions.{r['name']}"
    _need(sel.get("surface", "outer") == "outer", path, key + ".select.surface", "outer surface only")
    _need(bc["type"] == "displacement" and bc.get("direction") == "inward", path, key + ".bc",
          "an inward displacement is needed")
    if "s_center_fraction" in sel:
        s_c = sel["s_center_fraction"] * length_mm
    else:
        s_c = sel.get("s_center_m", sel.get("z_center_m", 0.0)) * 1e3
    half = sel.get("s_half_length_m", sel.get("z_half_length_m", 0.0)) * 1e3
    _need(abs(s_c - 0.5 * length_mm) < 1e-9 * length_mm, path, key + ".select",
          "the quarter model needs the patch at mid-length")
    return {"theta": sel.get("angle_center_deg", 0.0), "half_width": sel["angle_half_width_deg"],
            "s_center": s_c, "half_length": half, "push": bc["magnitude_m"] * 1e3}


def load_steps(scene):
    return scene.get("quasi_static", {}).get("load_steps", 1)


def catheter(scene, path):
    tools = [o for o in scene.get("obstacles", []) if o.get("shape") == "catheter"]
    _need(len(tools) == 1, path, "obstacles", "exactly one catheter is needed")
    c = tools[0]
    radius = c["diameter_fr"] / 3.0 * 0.5 if "diameter_fr" in c else c["diameter_m"] * 0.5e3
    return {"radius": radius, "tip": [v * 1e3 for v in c["tip_m"]], "direction": c["direction"],
            "push": c["push_m"] * 1e3, "length": c["length_m"] * 1e3}


def beam(scene, path):
    g = scene["geometry"]
    _need(g["type"] == "beam", path, "geometry.type", "a beam is needed")
    tip = [r for r in scene["regions"] if r["bc"]["type"] == "force"]
    _need(len(tip) == 1, path, "regions", "one force region (the tip load) is needed")
    return {"length": g["length_m"] * 1e3, "width": g["width_m"] * 1e3, "height": g["height_m"] * 1e3,
            "force": tip[0]["bc"]["magnitude_n"], "direction": tip[0]["bc"]["direction"]}


def angle_is(value, target):
    return abs(math.remainder(value - target, 360.0)) < 1e-9
