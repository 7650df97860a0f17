"""Centre-lines and the quarter-model vessel wall of the reference cases, in mm.

The centre-lines are those of vascsim's scenes (src/vascsim/geometry/centerline.cpp): they start at the
origin along +z with the rotation-minimising frame N = +x, B = +y; a bend turns towards +x in the x-z plane,
so N points to the centre of curvature along the arc and theta = 180 deg is the outside of the bend. A
wall point is C(s) + r (cos(theta) N(s) + sin(theta) B(s)).
"""
import math

import numpy as np

from .hexmesh import Mesh, graded, refine


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


def quarter_wall_breaks(r_in, r_out, patch_theta, half_width, s_patch_start, s_center, base_size, growth, m):
    """Breakpoints of the quarter wall: r through the wall; theta from the patch centre over the patch and
    on to the opposite side (half the circumference); s from the clamped end over the patch to its centre
    (half the length). The base mesh has elements of about base_size (mm) on the patch, graded by `growth`
    away from its edges; level m splits every base element into m^3."""
    arc = math.radians(half_width) * r_out
    n_patch_t = max(1, round(arc / base_size))
    rest_t = math.radians(180.0 - half_width) * 0.5 * (r_in + r_out)
    n_rest_t = _graded_count(rest_t, arc / n_patch_t, growth)
    n_patch_s = max(1, round((s_center - s_patch_start) / base_size))
    h_s = (s_center - s_patch_start) / n_patch_s
    n_rest_s = _graded_count(s_patch_start, h_s, growth)
    t_breaks = (graded(patch_theta, patch_theta + half_width, n_patch_t)
                + graded(patch_theta + half_width, patch_theta + 180.0, n_rest_t,
                         first=math.degrees((arc / n_patch_t) / (0.5 * (r_in + r_out))))[1:])
    rest_s = graded(s_patch_start, 0.0, n_rest_s, first=-h_s)[::-1]
    s_breaks = rest_s + graded(s_patch_start, s_center, n_patch_s)[1:]
    return refine([r_in, r_out], m), refine(t_breaks, m), refine(s_breaks, m)


def _graded_count(length, first, growth):
    if length <= 0:
        return 0
    return max(1, math.ceil(math.log(1.0 + length * (growth - 1.0) / first) / math.log(growth)))


def quarter_wall_mesh(line, r_in, r_out, breaks):
    mesh = Mesh()
    mesh.add_block("WALL", *breaks, wall_map(line))
    return mesh
