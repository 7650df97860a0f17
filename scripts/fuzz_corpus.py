#!/usr/bin/env python3
"""Writes the seed corpus of one fuzz target (fuzz/, docs/reliability.md) from the bundled files.

    fuzz_corpus.py TARGET FOLDER      TARGET: scene, mesh, trajectory or recording

Seeds are small (a few KB): the bundled scenes and trajectories as they are (scenes with some --set overrides
after a NUL byte, as fuzz/fuzz_scene.cpp reads them), and for meshes the first 64 triangles of
data/vessels/vmtk-aorta-surface.stl and a tetrahedron in every format the importer takes (binary and ASCII STL,
OBJ, ASCII and binary PLY), each behind the byte that picks the format in fuzz/fuzz_mesh.cpp.
"""
import glob
import os
import struct
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
STL, OBJ, PLY = b"\x00", b"\x01", b"\x02"  # fuzz_mesh.cpp: data[0] % 3
CSV, JSON = b"\x00", b"\x01"  # fuzz_trajectory.cpp: data[0] % 2


def read(path):
    with open(os.path.join(ROOT, path), "rb") as f:
        return f.read()


def scene_seeds():
    files = sorted(glob.glob(os.path.join(ROOT, "scenes", "**", "*.json"), recursive=True))
    files += sorted(glob.glob(os.path.join(ROOT, "tests", "data", "*.json")))
    overrides = [b"model=xpbd\nxpbd.step_s=1e-3", b"haptics.rate_hz=500\nhaptics.force_limit_n=0.5",
                 b"geometry.node_spacing_m=1e-3\nregions.0.bc.type=fixed", b"output.vtk=true\nmaterial.poisson_ratio=0.3"]
    seeds = {}
    for i, path in enumerate(files):
        text = read(path)
        name = os.path.splitext(os.path.basename(path))[0]
        seeds[name] = text
        seeds[name + "-set"] = text + b"\x00" + overrides[i % len(overrides)]
    return seeds


def aorta_triangles(count=64):
    data = read("data/vessels/vmtk-aorta-surface.stl")
    tris = []
    for k in range(count):
        v = struct.unpack_from("<12f", data, 84 + 50 * k)
        tris.append((v[3:6], v[6:9], v[9:12]))
    return tris


TETRA = [((0, 0, 0), (0, 1, 0), (1, 0, 0)), ((0, 0, 0), (1, 0, 0), (0, 0, 1)),
         ((0, 0, 0), (0, 0, 1), (0, 1, 0)), ((1, 0, 0), (0, 1, 0), (0, 0, 1))]


def indexed(tris):
    vertices, index, faces = [], {}, []
    for t in tris:
        face = []
        for p in t:
            if p not in index:
                index[p] = len(vertices)
                vertices.append(p)
            face.append(index[p])
        faces.append(face)
    return vertices, faces


def mesh_formats(tris):
    binary_stl = b"seed".ljust(80, b" ") + struct.pack("<I", len(tris))
    for t in tris:
        binary_stl += struct.pack("<12f", 0, 0, 0, *t[0], *t[1], *t[2]) + b"\x00\x00"
    ascii_stl = "solid seed\n" + "".join(
        "facet normal 0 0 0\nouter loop\n" + "".join(f"vertex {p[0]!r} {p[1]!r} {p[2]!r}\n" for p in t)
        + "endloop\nendfacet\n" for t in tris) + "endsolid seed\n"
    vertices, faces = indexed(tris)
    obj = "".join(f"v {p[0]!r} {p[1]!r} {p[2]!r}\n" for p in vertices)
    obj += "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)
    header = (f"ply\nformat {{}} 1.0\nelement vertex {len(vertices)}\nproperty float x\nproperty float y\n"
              f"property float z\nelement face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
    ply_ascii = header.format("ascii") + "".join(f"{p[0]!r} {p[1]!r} {p[2]!r}\n" for p in vertices)
    ply_ascii += "".join(f"3 {a} {b} {c}\n" for a, b, c in faces)
    ply_binary = header.format("binary_little_endian").encode()
    ply_binary += b"".join(struct.pack("<3f", *p) for p in vertices)
    ply_binary += b"".join(struct.pack("<B3i", 3, *f) for f in faces)
    return {"binary.stl": STL + binary_stl, "ascii.stl": STL + ascii_stl.encode(), "mesh.obj": OBJ + obj.encode(),
            "ascii.ply": PLY + ply_ascii.encode(), "binary.ply": PLY + ply_binary}


def mesh_seeds():
    seeds = {}
    for name, tris in (("aorta", aorta_triangles()), ("tetra", TETRA)):
        for fmt, data in mesh_formats(tris).items():
            seeds[f"{name}-{fmt}"] = data
    return seeds


def trajectory_seeds():
    return {"vein-press.csv": CSV + read("scenes/trajectories/vein-press.csv"),
            "haptic-press.csv": CSV + read("tests/data/haptic-press.csv"),
            "aorta-bent-advance.json": JSON + read("scenes/trajectories/aorta-bent-advance.json")}


def recording_seeds():
    # A session recording (session.csv) of the vein press: the trajectory's rows with buttons and forces.
    rows = [line for line in read("scenes/trajectories/vein-press.csv").decode().splitlines()
            if line and not line.startswith("#")][1:]
    text = "time_s,x_m,y_m,z_m,qw,qx,qy,qz,buttons,fx_n,fy_n,fz_n\n"
    text += "".join(f"{row},0,0,{0.1 * k!r},0\n" for k, row in enumerate(rows))
    return {"session.csv": text.encode(), "header-only.csv": text.splitlines()[0].encode() + b"\n"}


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("scene", "mesh", "trajectory", "recording"):
        sys.exit(__doc__)
    seeds = {"scene": scene_seeds, "mesh": mesh_seeds, "trajectory": trajectory_seeds,
             "recording": recording_seeds}[sys.argv[1]]()
    os.makedirs(sys.argv[2], exist_ok=True)
    for name, data in seeds.items():
        with open(os.path.join(sys.argv[2], name), "wb") as f:
            f.write(data)
    print(f"fuzz_corpus: {len(seeds)} seeds for {sys.argv[1]} in {sys.argv[2]}")


if __name__ == "__main__":
    main()
