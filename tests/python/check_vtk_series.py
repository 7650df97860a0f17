#!/usr/bin/env python3
"""Reads a run's VTK series back with an independent reader (meshio) and checks it against summary.json.

Usage: /usr/bin/python3 tests/python/check_vtk_series.py OUT_DIR
OUT_DIR is the --out folder of `vascsim run` on a scene with output.vtk and output.surface true.
Exits 1 with a message on the first failed check.

Checks, per series (nodes.pvd, surface.pvd):
  * every file the .pvd lists exists and parses; the .pvd lists one file per output step;
  * point counts equal summary.json's `nodes` / `surface_map.vertices`, cell counts its tetrahedra /
    triangles, the cell types are tetra / triangle;
  * displacement = points - rest points (points of step 0 minus its displacement), to 1e-9 of the
    largest coordinate (the ASCII files carry 10 significant digits);
  * step 0 has zero displacement; the last step moved (max |u| > 0);
  * surface: unit normals, uv in [0, 1], cell data `outer` in {0, 1} with both present.
"""
import json
import os
import sys
import xml.etree.ElementTree as ET

import meshio
import numpy as np


def fail(msg):
    print(f"check_vtk_series: FAIL: {msg}", file=sys.stderr)
    sys.exit(1)


def series(vtk_dir, pvd_name):
    root = ET.parse(os.path.join(vtk_dir, pvd_name)).getroot()
    files = [d.get("file") for d in root.iter("DataSet")]
    times = [float(d.get("timestep")) for d in root.iter("DataSet")]
    if not files:
        fail(f"{pvd_name} lists no files")
    if times != sorted(times):
        fail(f"{pvd_name}: timesteps not increasing: {times}")
    return [os.path.join(vtk_dir, f) for f in files]


def check_series(files, n_points, n_cells, cell_type, surface):
    rest = None
    for k, path in enumerate(files):
        if not os.path.exists(path):
            fail(f"{path} is listed but missing")
        m = meshio.vtu.read(path)
        name = os.path.basename(path)
        if len(m.points) != n_points:
            fail(f"{name}: {len(m.points)} points, summary says {n_points}")
        cells = [c for c in m.cells if c.type == cell_type]
        if len(cells) != 1 or len(cells[0].data) != n_cells:
            fail(f"{name}: expected {n_cells} {cell_type} cells, got {[(c.type, len(c.data)) for c in m.cells]}")
        if cells[0].data.max() >= n_points or cells[0].data.min() < 0:
            fail(f"{name}: connectivity out of range")
        u = m.point_data.get("displacement")
        if u is None or u.shape != (n_points, 3):
            fail(f"{name}: no displacement field of shape ({n_points}, 3)")
        scale = np.abs(m.points).max()
        if k == 0:
            if np.abs(u).max() > 0.0:
                fail(f"{name}: the rest state has a non-zero displacement {np.abs(u).max():.3g}")
            rest = m.points.copy()
        elif np.abs(m.points - u - rest).max() > 1e-9 * scale:
            fail(f"{name}: points - displacement differs from the rest points by "
                 f"{np.abs(m.points - u - rest).max():.3g} m")
        if surface:
            nrm = m.point_data.get("normal")
            if nrm is None or np.abs(np.linalg.norm(nrm, axis=1) - 1.0).max() > 1e-6:
                fail(f"{name}: normals missing or not unit length")
            uv = m.point_data.get("uv")
            if uv is None or uv.min() < 0.0 or uv.max() > 1.0:
                fail(f"{name}: uv missing or outside [0, 1]")
            outer = m.cell_data.get("outer")
            if outer is None or set(np.unique(outer[0])) != {0, 1}:
                fail(f"{name}: cell data 'outer' missing or not both 0 and 1")
    last = meshio.vtu.read(files[-1]).point_data["displacement"]
    if not np.abs(last).max() > 0.0:
        fail(f"{os.path.basename(files[-1])}: the last step did not move")
    return np.abs(last).max()


def main():
    if len(sys.argv) != 2:
        fail("usage: check_vtk_series.py OUT_DIR")
    out = sys.argv[1]
    summary = json.load(open(os.path.join(out, "summary.json")))
    vtk_dir = os.path.join(out, "vtk")
    steps = len(summary["steps"])
    nodes = series(vtk_dir, "nodes.pvd")
    surf = series(vtk_dir, "surface.pvd")
    if len(nodes) != steps or len(surf) != steps:
        fail(f"{steps} output steps but {len(nodes)} node files and {len(surf)} surface files")
    un = check_series(nodes, summary["nodes"], summary["virtual_tetrahedra"], "tetra", False)
    sm = summary["surface_map"]
    us = check_series(surf, sm["vertices"], sm["triangles"], "triangle", True)
    print(f"check_vtk_series: OK: {steps} steps, {summary['nodes']} nodes (max |u| {un:.3g} m), "
          f"{sm['vertices']} surface vertices (max |u| {us:.3g} m)")


if __name__ == "__main__":
    main()
