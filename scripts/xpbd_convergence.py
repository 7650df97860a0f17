#!/usr/bin/python3
"""XPBD convergence table (issue 3, docs/model/19-position-based.md / T13): runs a scene once with `quasi_static` (the
reference: static equilibrium of the same point-primitive energy) and then with `xpbd` for every
substeps x iterations pair, each to steady state, and tabulates the relative error of one region's
reaction force and one region's displacement against the reference.

    scripts/xpbd_convergence.py --scene scenes/cantilever.json --configs 8x1,8x4,32x1 \
        --duration 0.6 --ramp 0.1 --damping 60 --force-region clamp --displacement-region tip \
        --out out/xpbd-convergence/cantilever

Writes <out>/convergence.csv and <out>/convergence.md and prints the table. Steady state is checked:
the last two outputs must agree to --steady-tol (relative), otherwise the row is flagged.
Units: forces N, displacements m, wall time s.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time


def run(vascsim, scene, sets, out_dir, threads):
    cmd = [vascsim, "-q", "run", scene, "--out", out_dir]
    for s in sets:
        cmd += ["--set", s]
    env = dict(os.environ, OMP_NUM_THREADS=str(threads))
    t0 = time.monotonic()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.monotonic() - t0
    if proc.returncode != 0:
        sys.exit(f"failed ({proc.returncode}): {' '.join(cmd)}\n{proc.stderr}")
    with open(os.path.join(out_dir, "probes.csv")) as f:
        rows = list(csv.DictReader(f))
    with open(os.path.join(out_dir, "summary.json")) as f:
        summary = json.load(f)
    return rows, summary, wall


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vascsim", default="build/vascsim")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--configs", default="1x1,2x1,4x1,8x1,16x1,32x1,8x2,8x4,8x8",
                    help="comma-separated SUBSTEPSxITERATIONS")
    ap.add_argument("--duration", type=float, required=True, help="simulated time per xpbd run, s")
    ap.add_argument("--ramp", type=float, required=True, help="load ramp time, s")
    ap.add_argument("--damping", type=float, default=60.0, help="mass-proportional damping, 1/s")
    ap.add_argument("--output-interval", type=float, default=None, help="s (default duration/10)")
    ap.add_argument("--force-region", required=True, help="region whose reaction force is compared")
    ap.add_argument("--displacement-region", required=True, help="region whose displacement is compared")
    ap.add_argument("--steady-tol", type=float, default=2e-3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--set", action="append", default=[], help="extra scene overrides for every run")
    ap.add_argument("--reuse-reference", action="store_true",
                    help="reuse OUT/quasi_static if it holds a finished run (it takes minutes on the vein)")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    fcol, dcol = f"{a.force_region}_force_n", f"{a.displacement_region}_displacement_m"

    ref_dir = os.path.join(a.out, "quasi_static")
    if a.reuse_reference and os.path.isfile(os.path.join(ref_dir, "summary.json")):
        with open(os.path.join(ref_dir, "probes.csv")) as f:
            ref_rows, ref_wall = list(csv.DictReader(f)), 0.0
    else:
        ref_rows, _, ref_wall = run(a.vascsim, a.scene, a.set + ["model=quasi_static"], ref_dir, a.threads)
    if fcol not in ref_rows[-1] or dcol not in ref_rows[-1]:
        sys.exit(f"columns {fcol} / {dcol} not in probes.csv; columns: {list(ref_rows[-1])}")
    f_ref, d_ref = float(ref_rows[-1][fcol]), float(ref_rows[-1][dcol])
    print(f"quasi_static: {fcol} = {f_ref:.6g} N, {dcol} = {d_ref:.6g} m ({ref_wall:.1f} s)", file=sys.stderr)

    interval = a.output_interval or a.duration / 10
    results = []
    for cfg in a.configs.split(","):
        sub, it = (int(v) for v in cfg.lower().split("x"))
        sets = a.set + ["model=xpbd", f"xpbd.substeps={sub}", f"xpbd.iterations={it}", f"xpbd.duration_s={a.duration}",
                        f"xpbd.ramp_time_s={a.ramp}", f"xpbd.damping_per_s={a.damping}",
                        f"xpbd.output_interval_s={interval}"]
        rows, summary, wall = run(a.vascsim, a.scene, sets, os.path.join(a.out, f"xpbd-{sub}x{it}"), a.threads)
        f, d = float(rows[-1][fcol]), float(rows[-1][dcol])
        f_prev, d_prev = float(rows[-2][fcol]), float(rows[-2][dcol])
        steady = abs(d - d_prev) <= a.steady_tol * abs(d) and abs(f - f_prev) <= a.steady_tol * abs(f)
        r = dict(substeps=sub, iterations=it, sweeps=sub * it, force_n=f, force_rel_error=(f - f_ref) / f_ref,
                 displacement_m=d, displacement_rel_error=(d - d_ref) / d_ref, steady=steady, wall_s=wall,
                 colours=summary["solver"].get("colours"))
        results.append(r)
        print(f"{sub:>4} x {it:<3} force {f:.5g} N ({r['force_rel_error']:+.4f}), displacement {d:.5g} m "
              f"({r['displacement_rel_error']:+.4f}){'' if steady else ' NOT STEADY'}, {wall:.1f} s", file=sys.stderr)

    with open(os.path.join(a.out, "convergence.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(results[0]))
        w.writeheader()
        w.writerows(results)
    lines = [f"Reference (quasi_static): {a.force_region} force {f_ref:.6g} N, {a.displacement_region} displacement "
             f"{d_ref:.6g} m. xpbd: {a.duration} s simulated, ramp {a.ramp} s, damping {a.damping}/s, "
             f"{a.threads} thread(s).", "",
             "| substeps x iterations | sweeps per step | force rel. error | displacement rel. error | steady | wall s |",
             "|---|---|---|---|---|---|"]
    for r in results:
        lines.append(f"| {r['substeps']} x {r['iterations']} | {r['sweeps']} | {r['force_rel_error']:+.4f} | "
                     f"{r['displacement_rel_error']:+.4f} | {'yes' if r['steady'] else 'NO'} | {r['wall_s']:.1f} |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, "convergence.md"), "w") as f:
        f.write(text)
    print(text)


if __name__ == "__main__":
    main()
