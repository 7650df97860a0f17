"""Centre-lines and the quarter-model vessel wall of the reference cases, in mm.

The centre-lines are those of vascsim's scenes (src/vascsim/geometry/centerline.cpp): they start at the
origin along +z with the rotation-minimising frame N = +x, B = +y; a bend turns towards +x in the x-z plane,
so N points to the centre of curvature along the arc and theta = 180 deg is the outside of the bend. A
wall point is C(s) + r (cos(theta) N(s) + sin(theta) B(s)).
"""
import math

import numpy as np

from .hexmesh import Mesh, graded, power_graded, refine


class StraightLine:
    def __init__(self, length):
        self.length = length

    def frame(self, s):
        return np.array([0.0, 0.0, s]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])


class BentLine:
    """Straight leg, circular arc of radius R and angle phi (deg) turning towards +x, straight leg."""

    def __init__(self, radius, angle_deg, leg):
        self.radius, self.angle, self.leg = radius, math.radians(angle_deg), leg
        self.length = 2 * leg + radius * self.angle

    def frame(self, s):
        r, leg = self.radius, self.leg
        if s <= leg:
            return np.array([0.0, 0.0, s]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])
        a = min((s - leg) / r, self.angle)
        c = np.array([r - r * math.cos(a), 0.0, leg + r * math.sin(a)])
        t = np.array([math.sin(a), 0.0, math.cos(a)])
        n = np.array([math.cos(a), 0.0, -math.sin(a)])
        if s > leg + r * self.angle:
            c = c + (s - leg - r * self.angle) * t
        return c, n, np.array([0.0, 1.0, 0.0])

    def tangent(self, s):
        c, n, b = self.frame(s)
        return np.cross(n, b)


def wall_map(line):
    """(r, theta in deg, s) -> point."""
    def mapping(r, theta, s):
        c, n, b = line.frame(s)
        th = math.radians(theta)
        return c + r * (math.cos(th) * n + math.sin(th) * b)
    return mapping


def geometric_wall_breaks(r_in, r_out, patch_theta, half_width, s_patch_start, s_center, base_size, m, growth=1.25):
    """Breakpoints of the quarter wall, "geometric" family: a base mesh with elements of about base_size mm,
    uniform over the patch and one through the wall, growing by `growth` per element away from the patch
    edges; level m splits every base element into m^3 (uniform refinement). Theta runs from the patch centre
    over the patch and on to the opposite side (half the circumference), s from the clamped end over the
    patch to its centre (half the length). The elements at the patch edge shrink like 1/m: robust to the
    full push, but a bonded patch's edge singularity makes the force converge only like h^0.8-1.5."""
    arc = math.radians(half_width) * r_out
    n_patch_t = max(1, round(arc / base_size))
    rest_t = math.radians(180.0 - half_width) * 0.5 * (r_in + r_out)
    n_rest_t = _geometric_count(rest_t, arc / n_patch_t, growth)
    n_patch_s = max(1, round((s_center - s_patch_start) / base_size))
    h_s = (s_center - s_patch_start) / n_patch_s
    n_rest_s = _geometric_count(s_patch_start, h_s, growth)
    t_breaks = (graded(patch_theta, patch_theta + half_width, n_patch_t)
                + graded(patch_theta + half_width, patch_theta + 180.0, n_rest_t,
                         first=math.degrees((arc / n_patch_t) / (0.5 * (r_in + r_out))))[1:])
    rest_s = graded(s_patch_start, 0.0, n_rest_s, first=-h_s)[::-1]
    s_breaks = rest_s + graded(s_patch_start, s_center, n_patch_s)[1:]
    return refine([r_in, r_out], m), refine(t_breaks, m), refine(s_breaks, m)


def _geometric_count(length, first, growth):
    if length <= 0:
        return 0
    return max(1, math.ceil(math.log(1.0 + length * (growth - 1.0) / first) / math.log(growth)))


def power_wall_breaks(r_in, r_out, patch_theta, half_width, s_patch_start, s_center, base_size, m, beta=2.0,
                      beta_patch=2.0, beta_wall=2.0):
    """Breakpoints of the quarter wall, "power" family (same extent as geometric_wall_breaks). Level m has m
    times the base counts (base elements of about base_size mm on
    the patch, 1 through the wall), each interval's uniform parameter grid mapped by a power law that is fine
    at the patch edge: t^beta outside the patch, t^beta_patch inside it, and t^beta_wall through the wall
    towards the outer surface. The patch edges are where a bonded patch has its edge singularity (traction
    ~ d^-1/2 at a distance d from the edge): with uniform elements the force converges like h^1, with
    beta = 2 in both directions across the edge like h^2 (quadratic elements). Measured on the vein's bonded
    patch: level 2 (elements of 0.016 mm at the edge) stops at 0.71 mm, where St Venant-Kirchhoff's
    compressive collapse (docs/model/17-limitations.md) sets in at the edge; the catheter, whose contact edge carries no
    singularity, uses it with uniform elements over the contact zone."""
    arc = math.radians(half_width) * r_out
    n_patch_t = max(1, round(arc / base_size))
    n_rest_t = _matching_count(arc, n_patch_t, beta_patch, math.radians(180.0 - half_width) * r_out, beta)
    n_patch_s = max(1, round((s_center - s_patch_start) / base_size))
    n_rest_s = _matching_count(s_center - s_patch_start, n_patch_s, beta_patch, s_patch_start, beta)
    edge_t = patch_theta + half_width
    t_breaks = (power_graded(edge_t, patch_theta, n_patch_t * m, beta_patch)[::-1]
                + power_graded(edge_t, patch_theta + 180.0, n_rest_t * m, beta)[1:])
    s_breaks = (power_graded(s_patch_start, 0.0, n_rest_s * m, beta)[::-1]
                + power_graded(s_patch_start, s_center, n_patch_s * m, beta_patch)[1:])
    r_breaks = power_graded(r_out, r_in, m, beta_wall)[::-1]
    return r_breaks, t_breaks, s_breaks


def _matching_count(inside, n_inside, beta_inside, outside, beta_outside):
    """Elements outside the patch so that the first one at the edge is no larger than the last one inside."""
    h_edge = inside * (1.0 / n_inside) ** beta_inside
    return max(1, math.ceil((outside / h_edge) ** (1.0 / beta_outside) - 1e-9))


def quarter_wall_mesh(line, r_in, r_out, breaks):
    mesh = Mesh()
    mesh.add_block("WALL", *breaks, wall_map(line))
    return mesh
