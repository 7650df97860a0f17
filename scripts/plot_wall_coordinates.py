#!/usr/bin/env python3
"""Draw the wall coordinates of a vessel and the region selectors, for docs/first-scene.md.

    /usr/bin/python3 scripts/plot_wall_coordinates.py --out docs/images/first-scene-coordinates.png

Left: a cross-section of the tutorial's vessel (outer radius 2 mm, wall 0.5 mm, three node layers) with the
angle theta around the centre-line (from N = +x towards B = +y), the depth into the wall from the lumen, the
outward normal, and the angular extent of a wall_patch. Right: the vessel seen from the side (s along the
centre-line, here z), with the two cylinder_end rings, the wall_patch's s extent and a surface_patch (every
outer-wall node within radius_m of centre_m). The numbers are those of the tutorial's scene.
"""
import argparse

import numpy as np

R_OUT, WALL, LENGTH, SPACING = 2.0, 0.5, 16.0, 0.25  # mm
THETA_C, THETA_HALF, S_C, S_HALF = 90.0, 20.0, 8.0, 1.5  # the indenter's wall_patch
SP_CENTRE, SP_RADIUS = (0.0, -2.0, 4.0), 1.0  # a surface_patch (x, y, z) and radius, mm
TISSUE, PATCH, ENDS, SPHERE = "#cc545c", "#1f5fbf", "#2f8f46", "#d98b00"


def cross_section(ax):
    r_in = R_OUT - WALL
    layers = np.linspace(r_in, R_OUT, 3)
    n_around = int(round(2 * np.pi * (r_in + R_OUT) / 2 / SPACING))
    t = np.linspace(0, 2 * np.pi, 400)
    ax.fill(np.r_[R_OUT * np.cos(t), r_in * np.cos(t[::-1])], np.r_[R_OUT * np.sin(t), r_in * np.sin(t[::-1])],
            color=TISSUE, alpha=0.25, lw=0)
    th = np.linspace(0, 2 * np.pi, n_around, endpoint=False)
    for r in layers:
        ax.plot(r * np.cos(th), r * np.sin(th), ".", color="0.35", ms=2.5)
    # the wall_patch on the outer surface: |theta - 90| <= 20, pushed "inward" (-y here)
    a = np.radians(np.linspace(THETA_C - THETA_HALF, THETA_C + THETA_HALF, 50))
    ax.plot(R_OUT * np.cos(a), R_OUT * np.sin(a), color=PATCH, lw=4, solid_capstyle="butt")
    ax.text(-3.1, 3.2, f"wall_patch:\n|θ − {THETA_C:.0f}°| ≤ {THETA_HALF:.0f}°,\nouter surface", color=PATCH, fontsize=8,
            va="top")
    ax.annotate("", xy=(0, R_OUT + 0.08), xytext=(0, R_OUT + 1.2), arrowprops=dict(arrowstyle="-|>", color=PATCH, lw=1.5))
    ax.text(0.12, R_OUT + 0.75, "direction “inward”", color=PATCH, fontsize=8)
    # theta from +x (N) towards +y (B)
    ax.annotate("", xy=(3.0, 0), xytext=(0, 0), arrowprops=dict(arrowstyle="->", color="k", lw=0.8))
    ax.annotate("", xy=(0, 1.2), xytext=(0, 0), arrowprops=dict(arrowstyle="->", color="k", lw=0.8))
    ax.text(3.05, 0.08, "x = N (θ = 0)", fontsize=7)
    ax.text(-0.08, 1.0, "y = B\n(θ = 90°)", fontsize=7, ha="right")
    th_demo = np.radians(-35.0)
    arc = np.linspace(th_demo, 0, 30)
    ax.plot(0.9 * np.cos(arc), 0.9 * np.sin(arc), color="k", lw=1)
    ax.text(0.95, -0.4, "θ", fontsize=10)
    ax.plot([0, r_in * np.cos(th_demo)], [0, r_in * np.sin(th_demo)], color="k", lw=0.6, ls=":")
    # depth: from the inner surface outward; the outward normal at the outer surface
    u = np.array([np.cos(th_demo), np.sin(th_demo)])
    p_in, p_out = r_in * u, R_OUT * u
    ax.annotate("", xy=p_out, xytext=p_in, arrowprops=dict(arrowstyle="<->", color="#6a3d9a", lw=1.2))
    n_end = (R_OUT + 1.0) * u
    ax.annotate("", xy=n_end, xytext=p_out, arrowprops=dict(arrowstyle="-|>", color="#6a3d9a", lw=1.2))
    ax.text(2.3, -0.95, "depth: 0 at the lumen,\n0.5 mm at the outer\nsurface", color="#6a3d9a", fontsize=7)
    ax.text(*(n_end + [-0.2, -0.45]), "outward normal", color="#6a3d9a", fontsize=7)
    ax.text(-0.5, -0.6, "lumen", ha="center", va="center", fontsize=8, color="0.4")
    ax.set_aspect("equal")
    ax.set_xlim(-3.3, 5.0)
    ax.set_ylim(-3.4, 3.5)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title("cross-section at s = 8 mm: θ, depth, outward normal", fontsize=9)


def side_view(ax):
    # the vessel from the side: s (= z for a straight centre-line) horizontal, y vertical
    ax.fill_between([0, LENGTH], R_OUT - WALL, R_OUT, color=TISSUE, alpha=0.25, lw=0)
    ax.fill_between([0, LENGTH], -R_OUT, -R_OUT + WALL, color=TISSUE, alpha=0.25, lw=0)
    ax.plot([0, LENGTH], [R_OUT, R_OUT], color=TISSUE, lw=1)
    ax.plot([0, LENGTH], [-R_OUT, -R_OUT], color=TISSUE, lw=1)
    for s, label, ha in ((0.0, 'cylinder_end\n"start" (s = 0)', "left"), (LENGTH, 'cylinder_end\n"end" (s = L)', "right")):
        ax.plot([s, s], [-R_OUT, R_OUT], color=ENDS, lw=4, solid_capstyle="butt")
        ax.text(s + (0.3 if ha == "left" else -0.3), 0.0, label, color=ENDS, fontsize=8, ha=ha, va="center")
    ax.plot([S_C - S_HALF, S_C + S_HALF], [R_OUT, R_OUT], color=PATCH, lw=5, solid_capstyle="butt")
    ax.annotate("", xy=(S_C + S_HALF, R_OUT + 0.5), xytext=(S_C - S_HALF, R_OUT + 0.5),
                arrowprops=dict(arrowstyle="<->", color=PATCH))
    ax.text(S_C, R_OUT + 0.65, f"wall_patch: |s − {S_C:.0f} mm| ≤ {S_HALF} mm\n(s_center_fraction 0.5)", color=PATCH,
            ha="center", fontsize=8)
    c = np.linspace(0, 2 * np.pi, 100)
    ax.plot(SP_CENTRE[2] + SP_RADIUS * np.cos(c), SP_CENTRE[1] + SP_RADIUS * np.sin(c), color=SPHERE, lw=1, ls="--")
    half = np.sqrt(max(SP_RADIUS**2 - (R_OUT + SP_CENTRE[1]) ** 2, 0.0))
    ax.plot([SP_CENTRE[2] - half, SP_CENTRE[2] + half], [-R_OUT, -R_OUT], color=SPHERE, lw=5, solid_capstyle="butt")
    ax.text(SP_CENTRE[2] + 1.5, -R_OUT - 1.45, "surface_patch: outer-wall nodes within\nradius_m = 1 mm of centre_m = (0, −2, 4) mm",
            color=SPHERE, ha="left", fontsize=8)
    ax.set_aspect("equal")
    ax.set_xlim(-1.0, LENGTH + 2.6)
    ax.set_ylim(-R_OUT - 2.2, R_OUT + 1.9)
    ax.set_xlabel("z = s, arc length along the centre-line (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_title("side view: the selectors along s", fontsize=9)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="docs/images/first-scene-coordinates.png")
    args = ap.parse_args()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(12.5, 4.8), dpi=120, gridspec_kw={"width_ratios": [1, 1.9]})
    cross_section(a)
    side_view(b)
    fig.suptitle("Wall coordinates and region selectors of a straight vessel (outer radius 2 mm, wall 0.5 mm, "
                 "16 mm long)", fontsize=10)
    fig.tight_layout()
    fig.savefig(args.out)
    print(args.out)


if __name__ == "__main__":
    main()
