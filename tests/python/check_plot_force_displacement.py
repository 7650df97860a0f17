#!/usr/bin/env python3
"""Test scripts/plot_force_displacement.py on two small synthetic force-displacement CSVs.

Usage: /usr/bin/python3 tests/python/check_plot_force_displacement.py [--keep DIR]
Exits non-zero if any check fails. --keep DIR writes the inputs and PNGs there (for looking at them).
"""
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.normpath(os.path.join(HERE, "..", "..", "scripts", "plot_force_displacement.py"))
PY = sys.executable
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
HEADER = ("step,displacement_m,force_n,force_x_n,force_y_n,force_z_n,"
          "torque_x_n_m,torque_y_n_m,torque_z_n_m,contacts,converged")

failures = []


def check(cond, msg):
    print(("ok   " if cond else "FAIL ") + msg)
    if not cond:
        failures.append(msg)


def run(*args):
    return subprocess.run([PY, SCRIPT, *map(str, args)], capture_output=True, text=True)


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        f.write(text)
    return path


def fd_csv(stiffness, n=12, dmax=4e-3, fail_steps=()):
    """A stiffening curve F = k d (1 + 300 d) in the simulator's column order, with comment lines."""
    lines = ["# vascsim experiment force-displacement (synthetic test data)", HEADER]
    for s in range(n + 1):
        d = dmax * s / n
        f = stiffness * d * (1.0 + 300.0 * d)
        lines.append(f"{s},{d:.9g},{f:.9g},0,0,{-f:.9g},0,0,0,{min(s, 5)},{0 if s in fail_steps else 1}")
    return "\n".join(lines) + "\n"


def png_ok(path, what, min_bytes=5000):
    if not os.path.isfile(path):
        check(False, f"{what}: {path} written")
        return
    with open(path, "rb") as f:
        head = f.read(8)
    size = os.path.getsize(path)
    check(head == PNG_MAGIC, f"{what}: PNG magic bytes")
    check(size > min_bytes, f"{what}: {size} bytes > {min_bytes}")


def expect_error(name, csv_path, args=(), needle=None, d=None, named=None):
    out = os.path.join(d, "err.png")
    if os.path.exists(out):
        os.remove(out)
    p = run(csv_path, *args, "--out", out)
    lines = p.stderr.strip().splitlines()
    base = os.path.basename(named or csv_path)
    check(p.returncode == 2, f"{name}: exit code {p.returncode} == 2")
    check(len(lines) == 1 and base in lines[0] and lines[0].startswith("plot_force_displacement.py: "),
          f"{name}: one stderr line naming {base} ({p.stderr.strip()!r})")
    if needle:
        check(needle in p.stderr, f"{name}: message mentions '{needle}'")
    check(not os.path.exists(out), f"{name}: no PNG written")


def main():
    keep = None
    if "--keep" in sys.argv:
        keep = sys.argv[sys.argv.index("--keep") + 1]
        os.makedirs(keep, exist_ok=True)
    tmp = tempfile.TemporaryDirectory()
    d = keep or tmp.name

    stiff = write(os.path.join(d, "stiff-wall", "force_displacement.csv"), fd_csv(40.0))
    soft = write(os.path.join(d, "soft-wall", "force_displacement.csv"), fd_csv(12.0, fail_steps=(9, 11)))

    # two curves, one with non-converged rows; default labels (parent folders), auto units (mm, mN)
    png = os.path.join(d, "fd.png")
    p = run(stiff, soft, "--out", png, "--title", "synthetic force-displacement")
    check(p.returncode == 0, f"two curves: exit 0{'' if p.returncode == 0 else ': ' + p.stderr.strip()}")
    check(p.stdout.strip() == f"wrote {png}", f"two curves: prints 'wrote PNG' ({p.stdout.strip()!r})")
    png_ok(png, "two curves")

    # explicit labels, SI units; columns reordered, extra columns, a comment in the middle
    reordered = write(os.path.join(d, "reordered", "fd.csv"),
                      "# comment\nconverged,force_n,extra,displacement_m\n1,0.0,a,0.0\n# mid comment\n"
                      "1,0.02,b,0.001\n0,0.05,c,0.002\n1,0.09,d,0.003\n")
    png2 = os.path.join(d, "fd_si.png")
    p = run(stiff, reordered, "--label", "stiff", "--label", "reordered", "--units", "si", "--out", png2)
    check(p.returncode == 0, f"labels + si + reordered columns: exit 0 ({p.stderr.strip()!r})")
    png_ok(png2, "labels + si")

    # only the required columns (no 'converged'), micronewton range, mm_mN
    minimal = write(os.path.join(d, "minimal", "fd.csv"), "displacement_m,force_n\n0,0\n1e-4,2e-5\n2e-4,5e-5\n")
    p = run(minimal, "--out", os.path.join(d, "fd_min.png"))
    check(p.returncode == 0, f"required columns only: exit 0 ({p.stderr.strip()!r})")
    p = run(minimal, "--units", "mm_mN", "--out", os.path.join(d, "fd_min_mm.png"))
    check(p.returncode == 0, f"--units mm_mN: exit 0 ({p.stderr.strip()!r})")

    # auto units, from the script's own helper: mm below 0.1 m; mN below 1 N, uN below 1e-3 N
    import importlib.util

    import numpy as np

    spec = importlib.util.spec_from_file_location("plot_force_displacement", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)

    def units(dmax, fmax, mode="auto"):
        c = {"disp": np.array([0.0, dmax]), "force": np.array([0.0, -fmax])}
        (_, du), (_, fu) = mod.pick_units(mode, [c])
        return du, fu

    for dmax, fmax, want in [(4e-3, 0.35, ("mm", "mN")), (0.2, 2.0, ("m", "N")), (2e-4, 5e-5, ("mm", "\u00b5N")),
                             (0.099, 0.999, ("mm", "mN")), (0.1, 1.0, ("m", "N"))]:
        check(units(dmax, fmax) == want, f"auto units for |d| <= {dmax:g} m, |F| <= {fmax:g} N: {want}")
    check(units(0.2, 2.0, "mm_mN") == ("mm", "mN") and units(1e-4, 1e-5, "si") == ("m", "N"), "fixed units")

    # errors: exit 2, one stderr line containing the file name
    e = os.path.join(d, "errors")
    os.makedirs(e, exist_ok=True)
    expect_error("missing file", os.path.join(e, "no_such_file.csv"), needle="not found", d=d)
    expect_error("missing required column",
                 write(os.path.join(e, "no_force.csv"), "step,displacement_m,converged\n0,0,1\n1,0.001,1\n"),
                 needle="force_n", d=d)
    expect_error("no data rows", write(os.path.join(e, "header_only.csv"), "# nothing yet\n" + HEADER + "\n"),
                 needle="no data rows", d=d)
    expect_error("empty file", write(os.path.join(e, "empty.csv"), ""), d=d)
    expect_error("non-numeric value",
                 write(os.path.join(e, "non_numeric.csv"), "displacement_m,force_n\n0,0\n0.001,abc\n"),
                 needle="line 3, column 'force_n'", d=d)
    expect_error("NaN value",
                 write(os.path.join(e, "nan_value.csv"), "displacement_m,force_n\n0,0\nnan,0.1\n"),
                 needle="NaN", d=d)
    expect_error("bad converged flag",
                 write(os.path.join(e, "bad_flag.csv"), "displacement_m,force_n,converged\n0,0,1\n0.001,0.1,2\n"),
                 needle="converged", d=d)
    expect_error("short row",
                 write(os.path.join(e, "short_row.csv"), "displacement_m,force_n,contacts\n0,0,1\n0.001,0.1\n"),
                 needle="line 3", d=d)
    # an error in the second of several files names that file
    expect_error("second file bad", stiff, args=(os.path.join(e, "non_numeric.csv"),), needle="line 3", d=d,
                 named="non_numeric.csv")

    # --label count must match the CSV count
    p = run(stiff, soft, "--label", "only-one", "--out", os.path.join(d, "err.png"))
    check(p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1 and "--label" in p.stderr,
          f"--label count mismatch: exit 2, one line ({p.stderr.strip()!r})")

    if failures:
        print(f"\n{len(failures)} check(s) failed")
        return 1
    print("\nall checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
