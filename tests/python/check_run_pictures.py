#!/usr/bin/env python3
"""Watching a run without the viewer: a catheter run writes the tool as a surface series next to the wall's,
render_surface.py --all-frames turns the run into a PNG sequence and an animated GIF titled with the scene and
with the tool drawn, and plot_probes.py plots the tool's force by default.

Usage: /usr/bin/python3 tests/python/check_run_pictures.py VASCSIM [--keep DIR]

Runs tests/data/tiny-catheter.json (about 1,700 nodes, 3 load steps). Exits non-zero on the first failed
check group, printing every check.
"""
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
SCENE = os.path.join(ROOT, "tests", "data", "tiny-catheter.json")
RENDER = os.path.join(ROOT, "scripts", "render_surface.py")
PROBES = os.path.join(ROOT, "scripts", "plot_probes.py")

failures = []


def check(cond, msg):
    print(("ok   " if cond else "FAIL ") + msg)
    if not cond:
        failures.append(msg)


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True)
    return p


def grey_pixels(png):
    """Pixels of the tool's steel grey (saturation below 0.08, brightness 0.25-0.85, not the pane grey)."""
    import matplotlib.image as mpimg

    rgb = mpimg.imread(png)[..., :3]
    sat = rgb.max(axis=2) - rgb.min(axis=2)
    lum = rgb.mean(axis=2)
    return int(np.count_nonzero((sat < 0.08) & (lum > 0.25) & (lum < 0.85)))


def main():
    vascsim = sys.argv[1]
    keep = sys.argv[sys.argv.index("--keep") + 1] if "--keep" in sys.argv else None
    tmp = tempfile.TemporaryDirectory()
    d = keep or tmp.name
    out = os.path.join(d, "run")
    p = run([vascsim, "-q", "run", SCENE, "--out", out])
    check(p.returncode == 0, f"vascsim run tiny-catheter: exit {p.returncode} ({p.stderr.strip()[-300:]})")
    if failures:
        return 1

    # The tool series: one frame per wall frame, triangles around the catheter's axis, moving with the push.
    import meshio

    summary = json.load(open(os.path.join(out, "summary.json")))
    check(summary["outputs"]["tools"] == "vtk/tools.pvd", f"summary.json names the tool series ({summary['outputs']})")
    import xml.etree.ElementTree as ET

    def entries(pvd):
        return [(float(e.get("timestep")), e.get("file")) for e in ET.parse(pvd).getroot().iter("DataSet")]

    tools, wall = entries(os.path.join(out, "vtk", "tools.pvd")), entries(os.path.join(out, "vtk", "surface.pvd"))
    check(len(tools) == len(wall) == 4, f"tools.pvd and surface.pvd have the 4 output points ({len(tools)}, {len(wall)})")
    check([t for t, _ in tools] == [t for t, _ in wall], "the same stamps (load factors)")
    first = meshio.read(os.path.join(out, "vtk", tools[0][1]))
    last = meshio.read(os.path.join(out, "vtk", tools[-1][1]))
    tri = [b for b in first.cells if b.type == "triangle"]
    check(len(tri) == 1 and len(tri[0].data) > 100, "the catheter is a triangle surface")
    # The catheter (radius 1 mm, tip at y = 1.6 mm, pointing along -y) ends 0.6 mm lower: every vertex moves
    # by (0, -0.6 mm, 0) (to 1e-9 m: the ASCII file's 10 digits).
    shift = last.points - first.points
    check(np.allclose(shift, [0.0, -0.6e-3, 0.0], atol=1e-9), f"the tool moves by the push ({shift[0]})")
    check(np.allclose(last.point_data["displacement"], shift, atol=1e-9), "point data 'displacement' is that motion")
    r = np.hypot(first.points[:, 0], first.points[:, 2] - 3e-3)
    check(abs(r.max() - 1e-3) < 1e-9, f"its radius is the catheter's 1 mm ({r.max():.6g} m)")

    # Every frame as PNG, and the GIF with as many frames; the tool drawn (grey pixels that --no-tools lacks).
    frames = os.path.join(d, "frames")
    p = run([sys.executable, RENDER, os.path.join(out, "vtk", "surface.pvd"), "--all-frames", "--out", frames,
             "--color", "displacement", "--size", "5x4", "--dpi", "60"])
    check(p.returncode == 0, f"render_surface.py --all-frames: exit {p.returncode} ({p.stderr.strip()})")
    pngs = sorted(f for f in os.listdir(frames) if f.endswith(".png")) if os.path.isdir(frames) else []
    check(pngs == [f"frame_{i:04d}.png" for i in range(4)], f"one PNG per frame ({pngs})")
    gif = os.path.join(frames, "animation.gif")
    if os.path.isfile(gif):
        from PIL import Image

        with Image.open(gif) as im:
            check(im.n_frames == 4 and im.size == (300, 240), f"animation.gif: {im.n_frames} frames of {im.size}")
    else:
        check(False, "animation.gif written")
    bare = os.path.join(d, "bare")
    p = run([sys.executable, RENDER, os.path.join(out, "vtk", "surface.pvd"), "--all-frames", "--no-gif",
             "--no-tools", "--out", bare, "--color", "displacement", "--size", "5x4", "--dpi", "60"])
    check(p.returncode == 0 and not os.path.exists(os.path.join(bare, "animation.gif")), "--no-gif: PNGs only")
    if pngs and p.returncode == 0:
        with_tool, without = grey_pixels(os.path.join(frames, pngs[-1])), grey_pixels(os.path.join(bare, pngs[-1]))
        # the catheter covers a few hundred pixels of a 300x240 picture
        check(with_tool > without + 200, f"the tool is drawn: {with_tool} grey pixels with it, {without} without")

    # The title: the scene's name (matplotlib writes no text into the PNG, so ask the script's own function).
    sys.path.insert(0, os.path.join(ROOT, "scripts"))
    import render_surface

    name, by_time = render_surface.scene_title(os.path.join(out, "vtk", "surface.pvd"))
    check(name == "tiny-catheter" and by_time is False, f"title from summary.json: {name!r}, stamped by load ({by_time})")

    # plot_probes.py: the catheter's force by default.
    p = run([sys.executable, PROBES, out])
    check(p.returncode == 0 and "(tool catheter)" in p.stdout, f"plot_probes.py plots the tool: {p.stdout.strip()}")
    check(os.path.isfile(os.path.join(out, "force-displacement.png")), "force-displacement.png written")

    if failures:
        print(f"\n{len(failures)} check(s) failed")
        return 1
    print("\nall checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
