#!/usr/bin/env python3
"""Calibrate the cost model of `vascsim check` (and of the estimate `vascsim run` prints) on this machine.

Runs the bundled scenes at a few node spacings with each calibrated model, headless and without output files,
and measures per run the wall time of one model step (a load step of quasi_static, a frame of implicit, a
1 ms step of xpbd, a substep of explicit) and the peak resident memory of the whole process. Per model it fits
both as power laws of the number of neighbour pairs, in log space,

    seconds per step = exp(c0 + c_tools t) * pairs^c1,      peak bytes = exp(c0) * pairs^c1,

with t = 1 for a scene with tools (contact refactors the preconditioner: quasi_static's catheter runs cost about 3.9
times a bonded run of the same size) and 0 without; c_tools is fitted only where a model has runs of both kinds. The
uncertainty is the scatter: log_sigma, the standard deviation of ln(measured / fitted) with the fitted parameters
taken off. It writes data/calibration/cost_model.json (read by vascsim; --out elsewhere) with every run it
measured, and prints a table.

    /usr/bin/python3 scripts/calibrate_cost_model.py --vascsim build/vascsim
    /usr/bin/python3 scripts/calibrate_cost_model.py --refit     # the fits again from the file's own runs

Takes 20-60 minutes on 2 cores. Run it on the machine the estimates are for; the load average before and
after is recorded, since other work on the machine slows every run (docs/performance.md).
"""
import argparse
import json
import math
import os
import pathlib
import subprocess
import sys
import tempfile
import time

NO_FILES = ["output.surface=false", "output.vtk=false", "discretization.max_growths=10", "mapping.max_growths=6"]

# model: (what one step is, the solver-info key holding its length (dynamic models), runs: (scene, overrides))
RUNS = {
    "quasi_static": ("load step", "", [
        ("scenes/vein-indent.json", ["geometry.node_spacing_m=0.3e-3"]),
        ("scenes/vein-indent.json", ["geometry.node_spacing_m=0.2e-3"]),
        ("scenes/vein-indent.json", []),
        ("scenes/aorta-bent.json", ["geometry.node_spacing_m=2.2e-3"]),
        ("scenes/aorta-bent.json", ["geometry.node_spacing_m=1.5e-3"]),
        ("scenes/retinal-artery-twice-bent.json", ["geometry.node_spacing_m=20e-6"]),
        ("scenes/retinal-artery-twice-bent.json", ["geometry.node_spacing_m=15e-6"]),
        ("scenes/hand-dorsal-vein-catheter.json", ["geometry.node_spacing_m=0.3e-3"]),
        ("scenes/hand-dorsal-vein-catheter.json", ["geometry.node_spacing_m=0.2e-3"]),
    ]),
    # 0.3 s with the whole push in it (ramp 0.3 s): four times the real-time scenes' push speed, so a frame
    # here works at least as hard as one of theirs.
    "implicit": ("frame", "frame_s", [
        ("scenes/realtime/hand-dorsal-vein.json", ["implicit.duration_s=0.3", "implicit.ramp_time_s=0.3"]),
        ("scenes/realtime/hand-dorsal-vein.json", ["implicit.duration_s=0.2", "implicit.ramp_time_s=0.2",
                                                    "geometry.node_spacing_m=0.2e-3"]),
        ("scenes/realtime/hand-dorsal-vein.json", ["implicit.duration_s=0.3", "implicit.ramp_time_s=0.3",
                                                    "geometry.node_spacing_m=0.4e-3"]),
        ("scenes/realtime/aorta-bent.json", ["implicit.duration_s=0.3", "implicit.ramp_time_s=0.3"]),
        ("scenes/realtime/retinal-artery-twice-bent.json", ["implicit.duration_s=0.3", "implicit.ramp_time_s=0.3"]),
    ]),
    "xpbd": ("time step", "step_s", [
        ("scenes/vein-indent.json", ["model=xpbd", "xpbd.duration_s=0.02", "xpbd.output_interval_s=0.01",
                                     "geometry.node_spacing_m=0.3e-3"]),
        ("scenes/vein-indent.json", ["model=xpbd", "xpbd.duration_s=0.02", "xpbd.output_interval_s=0.01",
                                     "geometry.node_spacing_m=0.2e-3"]),
        ("scenes/vein-indent.json", ["model=xpbd", "xpbd.duration_s=0.01", "xpbd.output_interval_s=0.01"]),
        ("scenes/aorta-bent.json", ["model=xpbd", "xpbd.duration_s=0.02", "xpbd.output_interval_s=0.01",
                                    "geometry.node_spacing_m=2.2e-3"]),
    ]),
    "explicit": ("time step", "dt_s", [
        ("scenes/vein-indent.json", ["model=explicit", "explicit.duration_s=2e-4", "explicit.output_interval_s=1e-4",
                                     "geometry.node_spacing_m=0.3e-3"]),
        ("scenes/vein-indent.json", ["model=explicit", "explicit.duration_s=1e-4", "explicit.output_interval_s=1e-4",
                                     "geometry.node_spacing_m=0.2e-3"]),
        ("scenes/vein-indent.json", ["model=explicit", "explicit.duration_s=5e-5", "explicit.output_interval_s=5e-5"]),
    ]),
}


def loadavg():
    with open("/proc/loadavg") as f:
        return [float(v) for v in f.read().split()[:3]]


def run(vascsim, scene, sets, nice):
    """One `vascsim run`: its summary.json and the process's peak resident set (bytes)."""
    with tempfile.TemporaryDirectory() as out:
        cmd = ["nice", "-n", str(nice), vascsim, "-q", "run", scene, "--out", out, "--yes"]
        for s in NO_FILES + sets:
            cmd += ["--set", s]
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        _, _, usage = os.wait4(proc.pid, 0)
        stdout, stderr = proc.communicate()
        code = proc.returncode if proc.returncode is not None else 0
        summary_file = pathlib.Path(out) / "summary.json"
        if not summary_file.is_file():
            sys.exit(f"{' '.join(cmd)} failed: {stderr.strip()}")
        summary = json.loads(summary_file.read_text())
    return summary, usage.ru_maxrss * 1024, code


def steps_of(summary, step_key):
    solver = summary["solver"]
    if not step_key:
        return len(summary["steps"]) - 1
    return math.ceil(solver["duration_s"] / solver[step_key] - 1e-9)


def fit(xs, ys, tools=None):
    """Least squares of ln y = c0 + c1 ln x (+ c_tools t where `tools` holds both values); log_sigma with the
    fitted parameters taken off the degrees of freedom."""
    import numpy as np
    columns = [np.ones(len(xs)), np.log(xs)]
    with_tools = tools is not None and 0 < sum(tools) < len(tools)
    if with_tools:
        columns.append(np.asarray(tools, dtype=float))
    A, ly = np.column_stack(columns), np.log(ys)
    c = np.linalg.lstsq(A, ly, rcond=None)[0]
    n, k = A.shape
    sigma = math.sqrt(float(np.sum((ly - A @ c) ** 2)) / (n - k)) if n > k else float("nan")
    out = {"c0": float(c[0]), "c1": float(c[1]), "log_sigma": sigma, "runs": n}
    if with_tools:
        out["c_tools"] = float(c[2])
    return out


def has_tools(scene):
    """Whether a bundled scene file has tools (obstacles)."""
    return bool(json.loads(pathlib.Path(scene).read_text()).get("obstacles"))


def time_fit(runs):
    return fit([r["pairs"] for r in runs], [r["seconds_per_step"] for r in runs], [has_tools(r["scene"]) for r in runs])


def print_fit(model, step, t, m):
    tools = f", x{math.exp(t['c_tools']):.2f} with tools" if "c_tools" in t else ""
    print(f"{model}: seconds per {step} = exp({t['c0']:.3f}) pairs^{t['c1']:.3f}{tools}, scatter factor "
          f"{math.exp(t['log_sigma']):.2f}; peak bytes = exp({m['c0']:.3f}) pairs^{m['c1']:.3f}, scatter factor "
          f"{math.exp(m['log_sigma']):.2f}", flush=True)


def refit(path):
    """The fits again from the runs recorded in the calibration file (no run)."""
    doc = json.loads(pathlib.Path(path).read_text())
    for model, m in doc["models"].items():
        m["seconds_per_step"] = time_fit(m["runs"])
        print_fit(model, m["step"], m["seconds_per_step"], m["peak_bytes"])
    pathlib.Path(path).write_text(json.dumps(doc, indent=2) + "\n")
    print(f"wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vascsim", default="build/vascsim")
    ap.add_argument("--out", default="data/calibration/cost_model.json")
    ap.add_argument("--models", default=",".join(RUNS), help="comma-separated subset (default: all)")
    ap.add_argument("--nice", type=int, default=19)
    ap.add_argument("--refit", action="store_true", help="fit again from the runs recorded in --out; run nothing")
    args = ap.parse_args()
    if args.refit:
        return refit(args.out)
    before = loadavg()
    started = time.time()
    models = {}
    for model in args.models.split(","):
        step, step_key, runs = RUNS[model]
        measured = []
        for scene, sets in runs:
            summary, peak, code = run(args.vascsim, scene, sets, args.nice)
            steps = steps_of(summary, step_key)
            row = {"scene": scene, "sets": sets, "nodes": summary["nodes"], "pairs": summary["neighbour_pairs"],
                   "threads": summary["threads"], "steps": steps, "solve_s": summary["timings_s"]["solve"],
                   "seconds_per_step": summary["timings_s"]["solve"] / steps, "peak_bytes": peak,
                   "exit_code": code}
            measured.append(row)
            print(f"{model:12s} {scene:45s} {row['nodes']:7d} nodes {row['pairs']:9d} pairs: "
                  f"{row['seconds_per_step']:.4g} s per {step} ({steps} steps), peak {peak / 2**20:.0f} MiB, "
                  f"{row['threads']} threads", flush=True)
        pairs = [r["pairs"] for r in measured]
        models[model] = {
            "step": step, "step_length_key": step_key,
            "seconds_per_step": time_fit(measured),
            "peak_bytes": fit(pairs, [r["peak_bytes"] for r in measured]),
            "pairs_range": [min(pairs), max(pairs)],
            "runs": measured,
        }
        print_fit(model, step, models[model]["seconds_per_step"], models[model]["peak_bytes"])
    after = loadavg()
    doc = {
        "description": "Cost model of `vascsim check` and of the estimate `vascsim run` prints: per model, the wall "
                       "time of one model step and the run's peak resident memory as power laws of the neighbour "
                       "pairs, fitted in log space; log_sigma is the scatter (1 sigma of ln(measured / fitted)). "
                       "Measured with vascsim's default threads under nice -n 19.",
        "measured": f"{time.strftime('%Y-%m-%d %H:%M')}, {os.uname().nodename}, {os.cpu_count()} cores, load "
                    f"average {before[0]:.1f} before and {after[0]:.1f} after, {time.time() - started:.0f} s",
        "regenerate": "/usr/bin/python3 scripts/calibrate_cost_model.py --vascsim build/vascsim",
        "models": models,
    }
    path = pathlib.Path(args.out)
    if path.is_file() and args.models != ",".join(RUNS):  # a subset keeps the other models' calibration
        old = json.loads(path.read_text())
        old["models"].update(models)
        doc["models"] = old["models"]
        doc["measured"] += f" ({args.models}; the others as before: {old['measured']})"
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(doc, indent=2) + "\n")
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
