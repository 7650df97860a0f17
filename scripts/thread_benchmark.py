#!/usr/bin/env python3
"""Time per model step under different OpenMP thread settings, on an idle and on a loaded machine.

docs/performance.md, "Threads on a loaded machine". For each setting it runs one scene headless
(`vascsim run`, no output files) and reads the wall time of every output step from summary.json; then it
starts LOAD busy-loop processes of its own (the "loaded machine": each spins one core at the same nice level
as vascsim) and runs every setting again.

    /usr/bin/python3 scripts/thread_benchmark.py --vascsim build/vascsim --load 2 --out out/thread-benchmark

Settings (each also with the other environment as the caller has it):
  -j 1                          one OpenMP thread
  -j 2, OMP_WAIT_POLICY=active  two threads that spin while they wait (libgomp's behaviour when asked to)
  -j 2, OMP_WAIT_POLICY=passive two threads that sleep while they wait
  default                       what vascsim does when the user sets nothing (OMP_WAIT_POLICY unset)

Per run it reports the median and the largest wall time per model step (s per step = an output step's wall
time divided by the model steps in it), and writes everything to OUT/thread-benchmark.json.
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import time

DEFAULT_SCENE = "scenes/realtime/hand-dorsal-vein.json"
# 0.3 s of the real-time vein: 30 frames of 10 ms in 3 output steps; no files but summary.json.
DEFAULT_SETS = ["implicit.duration_s=0.3", "implicit.output_interval_s=0.1", "output.surface=false"]

SETTINGS = [
    ("-j 1", ["-j", "1"], {}),
    ("-j 2, OMP_WAIT_POLICY=active", ["-j", "2"], {"OMP_WAIT_POLICY": "active"}),
    ("-j 2, OMP_WAIT_POLICY=passive", ["-j", "2"], {"OMP_WAIT_POLICY": "passive"}),
    ("default", [], {}),
]


def busy_loops(n, nice):
    code = "while True:\n    pass\n"
    return [subprocess.Popen(["nice", "-n", str(nice), sys.executable, "-c", code]) for _ in range(n)]


def steps_per_output(summary):
    """Model steps in one output step: frames (implicit), steps (xpbd), substeps (explicit), 1 (load steps)."""
    solver = summary["solver"]
    interval = solver.get("output_interval_s")
    for key in ("frame_s", "step_s", "dt_s"):
        if interval and solver.get(key):
            return max(1, round(interval / solver[key]))
    return 1


def run_once(args, label, flags, env_extra, folder):
    env = dict(os.environ)
    env.pop("OMP_WAIT_POLICY", None)
    env.update(env_extra)
    cmd = ["nice", "-n", str(args.nice), args.vascsim, "-q", *flags, "run", args.scene, "--out", str(folder)]
    for s in args.set:
        cmd += ["--set", s]
    t0 = time.time()
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
    wall = time.time() - t0
    if proc.returncode not in (0, 4):
        sys.exit(f"{' '.join(cmd)} failed ({proc.returncode}): {proc.stderr.strip()}")
    summary = json.loads((folder / "summary.json").read_text())
    per = steps_per_output(summary)
    step_s = [s["wall_s"] / per for s in summary["steps"][1:]]
    return {"setting": label, "threads": summary["threads"], "nodes": summary["nodes"],
            "median_step_s": statistics.median(step_s), "max_step_s": max(step_s),
            "solve_s": summary["timings_s"]["solve"], "process_s": wall}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vascsim", default="build/vascsim")
    ap.add_argument("--scene", default=DEFAULT_SCENE)
    ap.add_argument("--set", action="append", help="scene override (repeatable; default: a 0.3 s run of the "
                    "real-time vein without output files)")
    ap.add_argument("--load", type=int, default=2, help="busy-loop processes for the loaded runs (default 2)")
    ap.add_argument("--nice", type=int, default=19, help="nice level of vascsim and of the busy loops")
    ap.add_argument("--repeat", type=int, default=1, help="runs per setting and load")
    ap.add_argument("--out", default="out/thread-benchmark")
    args = ap.parse_args()
    if args.set is None:
        args.set = DEFAULT_SETS
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for load in (0, args.load):
        loops = busy_loops(load, args.nice)
        try:
            for rep in range(args.repeat):
                for label, flags, env in SETTINGS:
                    row = run_once(args, label, flags, env, out / f"run-{load}-{rep}-{len(rows)}")
                    row["busy_loops"] = load
                    rows.append(row)
                    print(f"load {load}: {label:32s} threads {row['threads']}: median {1e3 * row['median_step_s']:8.1f} ms"
                          f" per step, max {1e3 * row['max_step_s']:8.1f} ms, process {row['process_s']:6.1f} s",
                          flush=True)
        finally:
            for p in loops:
                p.kill()
                p.wait()
    with open("/proc/loadavg") as f:
        loadavg = f.read().split()[:3]
    (out / "thread-benchmark.json").write_text(json.dumps(
        {"scene": args.scene, "sets": args.set, "busy_loops": args.load, "nice": args.nice,
         "loadavg_at_end": loadavg, "rows": rows}, indent=2) + "\n")
    print(f"wrote {out / 'thread-benchmark.json'}")


if __name__ == "__main__":
    main()
