#!/usr/bin/env python3
"""Test scripts/render_surface.py on a synthetic dented, bent tube (outer + inner wall).

Usage: /usr/bin/python3 tests/python/test_render_surface.py [--keep DIR]
Exits non-zero on the first failure. --keep DIR writes the inputs and PNGs there (for looking at them).
"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.normpath(os.path.join(HERE, "..", "..", "scripts", "render_surface.py"))
PY = sys.executable


def bent_tube(n_s=25, n_t=20, dent=True):
    """A 100-degree bend of a 3 mm tube (wall 0.5 mm) in metres, dented from above mid-length.

    Returns points (N,3), triangles (M,3), displacement (N,3), normal (N,3), outer (M,)."""
    Rb, ro, ri = 15e-3, 3e-3, 2.5e-3
    s = np.linspace(0.0, 1.0, n_s)
    phi = np.radians(100.0) * s
    c = np.column_stack([Rb * np.sin(phi), Rb * (1 - np.cos(phi)), 4e-3 * s])  # centreline, rising in z
    tang = np.column_stack([np.cos(phi), np.sin(phi), np.full(n_s, 4e-3 / (Rb * np.radians(100.0)))])
    tang /= np.linalg.norm(tang, axis=1, keepdims=True)
    e1 = np.cross(tang, [0.0, 0.0, 1.0])
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(e1, tang)  # ~ +z
    th = np.linspace(0.0, 2 * np.pi, n_t, endpoint=False)
    radial = np.cos(th)[None, :, None] * e1[:, None, :] + np.sin(th)[None, :, None] * e2[:, None, :]  # (n_s,n_t,3)

    # grid triangles (periodic in theta)
    i, j = np.meshgrid(np.arange(n_s - 1), np.arange(n_t), indexing="ij")
    a = i * n_t + j
    b = i * n_t + (j + 1) % n_t
    cc = (i + 1) * n_t + (j + 1) % n_t
    d = (i + 1) * n_t + j
    quads = np.stack([a, b, cc, d], axis=-1).reshape(-1, 4)
    tri_grid = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])

    # dent: inward push around theta = 90 deg (top), mid-length
    w = np.exp(-((s[:, None] - 0.5) / 0.12) ** 2 - (np.angle(np.exp(1j * (th[None, :] - np.pi / 2))) / 0.6) ** 2)
    depth = 1.2e-3 if dent else 0.0

    pts, disp, nrm, tris, outer = [], [], [], [], []
    for k, (r, sign, flag) in enumerate([(ro, 1.0, 1), (ri, -1.0, 0)]):
        X = c[:, None, :] + r * radial
        u = -depth * (w * (1.0 if flag else 0.8))[:, :, None] * radial
        pts.append((X + u).reshape(-1, 3))
        disp.append(u.reshape(-1, 3))
        nrm.append((sign * radial).reshape(-1, 3))
        t = tri_grid + k * n_s * n_t
        tris.append(t if flag else t[:, ::-1])  # inner wall faces the lumen
        outer.append(np.full(len(t), flag, dtype=np.int32))
    return np.vstack(pts), np.vstack(tris), np.vstack(disp), np.vstack(nrm), np.concatenate(outer)


def write_vtu(path, pts, tri, disp, nrm, outer, binary=False):
    import meshio

    meshio.write(path, meshio.Mesh(pts, [("triangle", tri)],
                                   point_data={"displacement": disp, "normal": nrm},
                                   cell_data={"outer": [outer]}), file_format="vtu", binary=binary)


def write_sim_vtu(path, pts, cells, vtk_type, point_vectors=(), uv=None, outer=None):
    """An ASCII .vtu laid out exactly like vascsim's io/vtk_writer.cpp (write_grid) writes it."""
    def vectors(name, v):
        rows = "".join(" ".join(f"{x:.10g}" for x in r) + "\n" for r in v)
        return (f'        <DataArray type="Float64" Name="{name}" NumberOfComponents="{v.shape[1]}" format="ascii">\n'
                f"{rows}        </DataArray>\n")

    with open(path, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian">\n')
        f.write(f'  <UnstructuredGrid>\n    <Piece NumberOfPoints="{len(pts)}" NumberOfCells="{len(cells)}">\n')
        f.write('      <PointData Vectors="displacement">\n')
        for name, v in point_vectors:
            f.write(vectors(name, v))
        if uv is not None:
            f.write(vectors("uv", uv))
        f.write("      </PointData>\n      <CellData>\n")
        if outer is not None:
            f.write('        <DataArray type="UInt8" Name="outer" format="ascii">\n')
            f.write("".join(f"{int(o)}\n" for o in outer) + "        </DataArray>\n")
        f.write("      </CellData>\n      <Points>\n" + vectors("Points", pts) + "      </Points>\n      <Cells>\n")
        f.write('        <DataArray type="Int32" Name="connectivity" format="ascii">\n')
        f.write("".join(" ".join(map(str, c)) + "\n" for c in cells))
        f.write('        </DataArray>\n        <DataArray type="Int32" Name="offsets" format="ascii">\n')
        f.write("".join(f"{cells.shape[1] * (i + 1)}\n" for i in range(len(cells))))
        f.write('        </DataArray>\n        <DataArray type="UInt8" Name="types" format="ascii">\n')
        f.write(f"{vtk_type}\n" * len(cells))
        f.write("        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n")


def run(*args):
    t0 = time.perf_counter()
    p = subprocess.run([PY, SCRIPT, *map(str, args)], capture_output=True, text=True)
    return p, time.perf_counter() - t0


failures = []


def check(cond, msg):
    print(("ok   " if cond else "FAIL ") + msg)
    if not cond:
        failures.append(msg)


def check_png(path, w_px, h_px, what):
    import matplotlib.image as mpimg

    if not os.path.isfile(path):
        check(False, f"{what}: {path} written")
        return
    img = mpimg.imread(path)
    check(img.shape[0] == h_px and img.shape[1] == w_px, f"{what}: size {img.shape[1]}x{img.shape[0]} == {w_px}x{h_px}")
    rgb = img[..., :3]
    var = float(rgb.var())
    # a blank or one-colour image has ~0 variance; the rendered tube gives ~0.01 and more
    check(var > 2e-3, f"{what}: pixel variance {var:.4f} > 0.002")
    # the tube must cover part of the canvas with coloured (non-grey) pixels; axes/text are grey
    sat = rgb.max(axis=2) - rgb.min(axis=2)
    frac = float(np.mean(sat > 0.15))
    check(frac > 0.03, f"{what}: coloured pixel fraction {frac:.3f} > 0.03")
    # and be shaded, not flat: the coloured pixels span a range of brightness
    lum = rgb[sat > 0.15].mean(axis=1)
    spread = float(np.percentile(lum, 95) - np.percentile(lum, 5)) if lum.size else 0.0
    check(spread > 0.15, f"{what}: brightness spread of the coloured pixels {spread:.2f} > 0.15")


def main():
    keep = None
    if "--keep" in sys.argv:
        keep = sys.argv[sys.argv.index("--keep") + 1]
        os.makedirs(keep, exist_ok=True)
    tmp = tempfile.TemporaryDirectory()
    d = keep or tmp.name

    pts, tri, disp, nrm, outer = bent_tube()
    print(f"synthetic tube: {len(pts)} points, {len(tri)} triangles")
    vtu = os.path.join(d, "surface_0001.vtu")
    write_vtu(vtu, pts, tri, disp, nrm, outer, binary=True)  # meshio, binary
    p0, t0_, d0, n0, o0 = bent_tube(dent=False)  # frame 0: undeformed, in the simulator's own ASCII layout
    uv = np.column_stack([np.arange(len(p0)) % 7, np.arange(len(p0)) // 7]) / 7.0
    write_sim_vtu(os.path.join(d, "surface_0000.vtu"), p0, t0_, 5, [("displacement", d0), ("normal", n0)], uv, o0)
    pvd = os.path.join(d, "surface.pvd")
    with open(pvd, "w") as f:
        f.write('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n  <Collection>\n'
                '    <DataSet timestep="0" part="0" file="surface_0000.vtu"/>\n'
                '    <DataSet timestep="0.5" part="0" file="surface_0001.vtu"/>\n  </Collection>\n</VTKFile>\n')
    # a node file for --nodes as the simulator writes it: mid-wall points with (virtual) tets, no cell data
    import meshio

    mid = 0.5 * (pts[: len(pts) // 2] + pts[len(pts) // 2:])
    tets = np.arange(len(mid) - len(mid) % 4).reshape(-1, 4)
    nodes = os.path.join(d, "nodes_0001.vtu")
    write_sim_vtu(nodes, mid, tets, 10, [("displacement", np.zeros_like(mid))])

    cases = [
        ("vtu-tissue", [vtu], 8, 6, 100),
        ("vtu-displacement", [vtu, "--color", "displacement", "--title", "dented tube"], 8, 6, 100),
        ("pvd-last-displacement", [pvd, "--color", "displacement", "--outer-only"], 6, 4, 120),
        ("pvd-frame0-tissue", [pvd, "--frame", "0", "--elev", "35", "--azim", "-120"], 5, 5, 80),
        ("pvd-frame0-displacement", [pvd, "--frame", "0", "--color", "displacement"], 5, 4, 80),  # |u| == 0
        ("nodes", [vtu, "--nodes", nodes, "--outer-only"], 6, 5, 100),
    ]
    for name, args, w, h, dpi in cases:
        png = os.path.join(d, f"{name}.png")
        p, dt = run(*args, "--out", png, "--size", f"{w}x{h}", "--dpi", dpi)
        check(p.returncode == 0, f"{name}: exit 0 ({dt:.1f} s){'' if p.returncode == 0 else ': ' + p.stderr.strip()}")
        check(p.stdout.strip() == png, f"{name}: prints the written path")
        check_png(png, int(round(w * dpi)), int(round(h * dpi)), name)

    # default size/dpi: 8x6 in at 150 dpi
    png = os.path.join(d, "default.png")
    p, _ = run(vtu, "--out", png)
    check(p.returncode == 0, "default size: exit 0")
    check_png(png, 1200, 900, "default size")

    # errors: one stderr line naming the file, exit code 2
    missing = os.path.join(d, "no_such_surface.vtu")
    p, _ = run(missing, "--out", os.path.join(d, "x.png"))
    check(p.returncode == 2, f"missing file: exit code {p.returncode} == 2")
    check("no_such_surface.vtu" in p.stderr and len(p.stderr.strip().splitlines()) == 1,
          f"missing file: one stderr line naming the file ({p.stderr.strip()!r})")
    check(not os.path.exists(os.path.join(d, "x.png")), "missing file: no PNG written")

    p, _ = run(pvd, "--frame", "5", "--out", os.path.join(d, "x.png"))
    check(p.returncode == 2 and "surface.pvd" in p.stderr, f"bad frame: exit 2 naming the .pvd ({p.stderr.strip()!r})")

    p, _ = run(nodes, "--out", os.path.join(d, "x.png"))
    check(p.returncode == 2 and "nodes_0001.vtu" in p.stderr and "triangle" in p.stderr,
          f"no triangle cells (tet node file): exit 2 naming the file ({p.stderr.strip()!r})")

    p, _ = run(vtu, "--nodes", missing, "--out", os.path.join(d, "x.png"))
    check(p.returncode == 2 and "no_such_surface.vtu" in p.stderr, "missing --nodes file: exit 2 naming it")

    # missing optional fields: triangles + points only; displacement colouring is then an error
    bare = os.path.join(d, "bare.vtu")
    meshio.write(bare, meshio.Mesh(pts, [("triangle", tri)]), file_format="vtu")
    p, _ = run(bare, "--outer-only", "--out", os.path.join(d, "bare.png"), "--dpi", 60)
    check(p.returncode == 0, f"no optional fields: renders ({p.stderr.strip()!r})")
    p, _ = run(bare, "--color", "displacement", "--out", os.path.join(d, "x.png"), "--dpi", 60)
    check(p.returncode == 2 and "bare.vtu" in p.stderr and "displacement" in p.stderr,
          "no displacement field + --color displacement: exit 2")

    bad = os.path.join(d, "corrupt.vtu")
    with open(bad, "w") as f:
        f.write("this is not XML\n")
    p, _ = run(bad, "--out", os.path.join(d, "x.png"))
    check(p.returncode == 2 and "corrupt.vtu" in p.stderr and len(p.stderr.strip().splitlines()) == 1,
          f"unreadable .vtu: exit 2, one stderr line naming it ({p.stderr.strip()!r})")

    # large mesh: ~50k triangles must render well within 30 s
    pb, tb, db, nb, ob = bent_tube(n_s=125, n_t=100)
    big = os.path.join(d, "big.vtu")
    write_vtu(big, pb, tb, db, nb, ob, binary=True)
    png = os.path.join(d, "big.png")
    p, dt = run(big, "--color", "displacement", "--out", png)
    check(p.returncode == 0 and dt < 30.0, f"{len(tb)} triangles: rendered in {dt:.1f} s < 30 s")
    check_png(png, 1200, 900, "large mesh")

    if failures:
        print(f"\n{len(failures)} check(s) failed")
        return 1
    print("\nall checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
