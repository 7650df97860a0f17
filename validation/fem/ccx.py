"""Writing CalculiX decks, running ccx, and reading the totals it prints.

Units in every deck: mm, uN and Pa (= uN/mm^2). CalculiX's convergence checks have absolute thresholds
(a residual printed as 0.000000 counts as zero): with forces of O(1e-5) N in N-mm-MPa units they stop Newton
after 2 iterations with corrections of 1e-3 of the increment; in uN the same deck converges to 1e-8.
"""
import os
import re
import subprocess
import time

MM = 1e-3       # m per deck length unit
MICRONEWTON = 1e-6  # N per deck force unit


def _lines(values, per_line=16):
    values = list(values)
    return "\n".join(", ".join(str(v) for v in values[i:i + per_line]) for i in range(0, len(values), per_line))


class Deck:
    """Accumulates the text of one .inp file."""

    def __init__(self, title):
        self.parts = [f"** {title}\n"]

    def add(self, text):
        self.parts.append(text if text.endswith("\n") else text + "\n")

    def mesh(self, mesh, element_type="C3D20", elset="EALL", blocks=None):
        self.add("*NODE, NSET=NALL")
        self.add("\n".join(f"{n + 1}, {x[0]:.12g}, {x[1]:.12g}, {x[2]:.12g}" for n, x in enumerate(mesh.xyz)))
        groups = {}
        for e, conn in enumerate(mesh.elements):
            name = mesh.element_block[e] if blocks is None else blocks.get(mesh.element_block[e], elset)
            groups.setdefault(name, []).append((e + 1, conn))
        for name, elems in groups.items():
            self.add(f"*ELEMENT, TYPE={element_type}, ELSET={name}")
            for e, conn in elems:
                # 20 node ids do not fit one line of 16 entries: CalculiX continues on the next line.
                self.add(f"{e}, " + ", ".join(map(str, conn[:15])) + ",\n" + ", ".join(map(str, conn[15:])))

    def nset(self, name, ids):
        if not ids:
            raise ValueError(f"node set {name} is empty")
        self.add(f"*NSET, NSET={name}\n" + _lines(sorted(set(ids))))

    def elset(self, name, ids):
        self.add(f"*ELSET, ELSET={name}\n" + _lines(sorted(set(ids))))

    def surface(self, name, faces):
        if not faces:
            raise ValueError(f"surface {name} is empty")
        self.add(f"*SURFACE, NAME={name}, TYPE=ELEMENT\n" + "\n".join(f"{e}, {f}" for e, f in faces))

    def elastic(self, name, youngs_pa, poisson, elset="EALL"):
        self.add(f"*MATERIAL, NAME={name}\n*ELASTIC\n{youngs_pa:.12g}, {poisson:.12g}")
        self.add(f"*SOLID SECTION, ELSET={elset}, MATERIAL={name}")

    def material(self, name, mat, elset="EALL"):
        """scene_params.Material: svk as *ELASTIC (St Venant-Kirchhoff under NLGEOM), mooney_rivlin as
        *HYPERELASTIC, MOONEY-RIVLIN (C10, C01, D1 = 2 / kappa)."""
        if mat.law == "svk":
            return self.elastic(name, mat.youngs, mat.poisson, elset)
        self.add(f"*MATERIAL, NAME={name}\n*HYPERELASTIC, MOONEY-RIVLIN\n"
                 f"{mat.c10:.12g}, {mat.c01:.12g}, {2.0 / mat.kappa:.12g}")
        self.add(f"*SOLID SECTION, ELSET={elset}, MATERIAL={name}")

    def write(self, path):
        with open(path, "w") as f:
            f.write("".join(self.parts))


def time_points(name, n):
    """*TIME POINTS card with the n equal load steps k/n, k = 1..n (the scene's quasi-static steps)."""
    # CalculiX reads at most 8 entries per line of this card.
    return f"*TIME POINTS, NAME={name}\n" + _lines((f"{k / n:.12g}" for k in range(1, n + 1)), per_line=8)


def static_step(steps, body, nlgeom=True):
    """A *STATIC step of `steps` equal increments (CalculiX may cut them back, never grow them), with
    Newton converged to a largest residual of 1e-5 of the average force and a last correction of 1e-4 of the
    increment's change (CalculiX's defaults are 5e-3 and 1e-2). On the vein's bonded patch (geometric mesh,
    levels 1 and 2) the forces agree with those at 1e-6 and 1e-6 to the 6 digits printed."""
    inc = f"{1 / steps:.12g}"
    return (f"*STEP{', NLGEOM' if nlgeom else ''}, INC=1000\n*STATIC\n{inc}, 1.0, 1e-5, {inc}\n"
            "*CONTROLS, PARAMETERS=FIELD\n1e-5, 1e-4, 0.01, , 0.02, 1e-5, 1e-3, 1e-8\n" + body + "*END STEP")


def run(deck_path, log, threads=1):
    """Runs ccx on deck_path (without .inp) in its directory; returns the wall time in s. Raises on a
    non-zero exit or a job that did not finish."""
    work, job = os.path.split(deck_path)
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), CCX_NPROC_STIFFNESS=str(threads),
               CCX_NPROC_EQUATION_SOLVER=str(threads), OPENBLAS_NUM_THREADS="1")
    start = time.monotonic()
    with open(log, "w") as out:
        rc = subprocess.run(["nice", "-n", "19", "ccx", "-i", job], cwd=work or ".", stdout=out,
                            stderr=subprocess.STDOUT, env=env).returncode
    wall = time.monotonic() - start
    text = open(log).read()
    if rc != 0 or "Job finished" not in text:
        tail = "\n".join(text.strip().splitlines()[-15:])
        raise RuntimeError(f"ccx failed on {deck_path}.inp (exit {rc}); last lines of {log}:\n{tail}")
    return wall


_TOTAL = re.compile(r"total force \(fx,fy,fz\) for set (\S+) and time\s+(\S+)")
_NODE_BLOCK = re.compile(r"(displacements|forces) \(\S+\) for set (\S+) and time\s+(\S+)")


def read_totals(dat_path, nset):
    """[(time, (fx, fy, fz))] of the `total force` lines that *NODE PRINT, TOTALS=ONLY wrote for nset."""
    out = []
    lines = open(dat_path).read().splitlines()
    for i, line in enumerate(lines):
        m = _TOTAL.search(line)
        if m and m.group(1).upper() == nset.upper():
            values = next(l for l in lines[i + 1:] if l.strip()).split()
            out.append((float(m.group(2)), tuple(float(v) for v in values[-3:])))
    return out


def read_node_values(dat_path, nset, what="displacements"):
    """{time: {node: (v1, v2, v3)}} of the per-node blocks *NODE PRINT wrote for nset (U or RF)."""
    out = {}
    lines = open(dat_path).read().splitlines()
    i = 0
    while i < len(lines):
        m = _NODE_BLOCK.search(lines[i])
        if m and m.group(1) == what and m.group(2).upper() == nset.upper():
            values = {}
            i += 1
            while i < len(lines) and not lines[i].strip():
                i += 1
            while i < len(lines) and lines[i].strip():
                parts = lines[i].split()
                values[int(parts[0])] = tuple(float(v) for v in parts[1:4])
                i += 1
            out[float(m.group(3))] = values
        else:
            i += 1
    return out


def increments(sta_path):
    """Number of converged increments and the total of iterations from the .sta file."""
    rows = [l.split() for l in open(sta_path).read().splitlines()]
    rows = [r for r in rows if len(r) >= 6 and r[0].isdigit()]
    return len(rows), sum(int(r[3]) for r in rows)
