#!/usr/bin/env python3
"""Real time at a trainee's hand speed (docs/performance.md, "Real time at hand speed").

A scripted hand presses the tool of a real-time scene into the wall and slides it along the wall, at each of
several speeds, through the 1 kHz haptic loop in realtime mode (the haptic thread at wall-clock 1 kHz, the model
on the other core), and the run is compared with the converged continuum:

  * the deformation: frames per second while the tool is in the wall (median, and the 10th percentile: the slow
    frames), the frames that ended before converging, and the model's tool against the device pose each frame was
    given (tool_lag_m);
  * the force the hand feels: at every 1 kHz tick (haptic_ticks.csv: the tissue's force at the tick's tool pose,
    before the coupling and the output filter) against the reference force at that pose, counted where the
    contact is resolved (its Hertz diameter spans 1.4 node spacings along the wall, docs/validation.md "The
    contact's onset"); each frame's own force likewise; the force latency and the haptic loop's rate and jitter.

The reference is the fine quasi_static scene of the same set-up driven along the same path in lockstep, one
equilibrium every --reference-step of the path (default: the scene's in CASES); the force at a tick is interpolated
along the path at the tick's tool pose. Per scene (--scene, CASES): the vein's catheter against
scenes/hand-dorsal-vein-catheter.json (30,552 nodes, within 0.3 % of the CalculiX reference at 1.2 mm; 35
equilibria, about half an hour on 2 cores); the aorta's 10 mm probe against validation/scenes/aorta-press.json
(34,040 nodes, -0.1 to +1.8 % of the CalculiX reference to 2 mm; 37 equilibria); the retinal artery's micro-probe
against scenes/retinal-artery-twice-bent-probe.json (29,216 nodes, no independent reference; 36 equilibria). The
reference is cached in the output folder, and each scene's is bundled in data/benchmarks/reference-<scene>.csv
with the key it was computed for (the reference scene's SHA-256, the path, the step): a run takes the bundled one
when the key matches, else computes it (--fresh-reference always does; --bundle-reference stores what it computed).

    /usr/bin/python3 scripts/realtime_benchmark.py --vascsim build/vascsim --out out/realtime-benchmark
    /usr/bin/python3 scripts/realtime_benchmark.py --vascsim build/vascsim --scene scenes/realtime/aorta-bent-probe.json \
        --out out/realtime-benchmark-aorta-bent-probe

Run it on an otherwise idle machine: it records the load average and the machine in benchmark.json.
"""
import argparse
import hashlib
import json
import math
import os
import pathlib
import platform
import shutil
import subprocess
import sys
import time

from bench_common import force_on_tool, interpolate, read_csv, sh

ROOT = pathlib.Path(__file__).resolve().parent.parent

# The solver variants a run compares, each a list of scene overrides on the scene as bundled (every bundled
# real-time scene with a tool has its tools on the wall's surface). "multigrid-embedded" is the scene as bundled with
# the implicit model's defaults (contact.surface "embedded": the tools meet the wall's surface; the wall multigrid
# with float products; a 30 ms frame budget; a carried first step per frame, at most three per frame of up to a
# node spacing each; frames hand on below a residual of 0.3 twice in a row, else the last one that did keeps
# serving; the tool at the device pose every frame). "multigrid" has the tools at the wall's nodes instead
# (contact.surface "nodes", an active set: frames above a residual of 1e-2, or with a contact that pulls, hand on
# the last equilibrium's force, and the tool in contact moves towards the device by at most half a node spacing per
# frame and only after a frame that handed on); "multigrid-at-hand" the same with the tool at the device pose every
# frame (implicit.realtime_tool_step 0, which tears the wall under a fast random hand: docs/reliability.md);
# "multigrid-unbudgeted" the nodes' variant with frames that take the time they need; "multigrid-converged" the
# tool at the device pose with frames that take the time they need (measured: frames of seconds,
# docs/performance.md section 12); "multigrid-bounded" the multigrid with the factor's frame logic (below);
# "factor" is the real-time path the multigrid replaced (a sparse factor of the meshless Hessian, the tool following
# the device in steps of 0.25 node spacings, no frame budget, every frame's force handed on). The variants other
# than "multigrid-embedded" say contact.surface "nodes" themselves, so that each means what it meant when the nodes
# were the scenes' contact (the commands of docs/ measure the same thing today).
NODES = "contact.surface=nodes"
VARIANTS = {
    "multigrid-embedded": ["contact.surface=embedded"],
    "multigrid": [NODES],
    "multigrid-at-hand": [NODES, "implicit.realtime_tool_step=0"],
    "multigrid-unbudgeted": [NODES, "implicit.time_budget_s=0"],
    "multigrid-converged": [NODES, "implicit.realtime_tool_step=0", "implicit.time_budget_s=0"],
    "multigrid-bounded": [NODES, "implicit.max_tool_step=0.25", "implicit.time_budget_s=0",
                          "implicit.handoff_max_residual=1e6"],
    "factor": [NODES, "implicit.preconditioner=meshless", "implicit.single_precision=false",
               "implicit.max_tool_step=0.25", "implicit.time_budget_s=0", "implicit.handoff_max_residual=1e6"],
}

# The press-and-slide per scene: the tip starts `lift` above the outer wall at `surface`, is pushed along
# `press_dir` to `depth` below the wall, holds, slides along `slide_dir` by `slide`, and holds; `quaternion` turns
# the tool's tip (along -z in its own frame) onto `press_dir`. `tool_radius`, the material and the node spacing
# along the wall under the path say where the contact is resolved (resolved()); `reference_step`: the path between
# the reference's equilibria; `coupling` (optional): haptics.coupling for the reference and the sessions, for a
# tool whose force would otherwise hold it behind the hand (the proxy is F / stiffness behind the device).
# The vein: a 6 Fr catheter on the straight vein, its tip pointing along -y (a -90 degree turn about x).
CASES = {
    "scenes/realtime/hand-dorsal-vein-catheter.json": {
        "reference_scene": "scenes/hand-dorsal-vein-catheter.json",
        "surface": [0.0, 1.5e-3, 10e-3],
        "press_dir": [0.0, -1.0, 0.0],
        "slide_dir": [0.0, 0.0, 1.0],
        "lift": 0.2e-3, "depth": 1.2e-3, "slide": 2.0e-3, "hold": 0.2,
        "quaternion": [0.7071067811865476, -0.7071067811865476, 0.0, 0.0],
        "tool_radius": 1e-3, "youngs_modulus": 0.5e6, "poisson": 0.45, "spacing_along_wall": 0.3e-3,
        "reference_step": 0.1e-3,
    },
    # The 10 mm probe of validation/scenes/aorta-press.json at the crown of the bent aorta's arch (theta = 180 deg at
    # mid-length, the outer wall at z = 52.5 mm), pressed 2 mm along -z and slid 3 mm along +x, the arch's tangent
    # there (a straight slide: the outer wall, of radius 42.5 mm along the arch, falls 0.11 mm under its end).
    # Its tip points along -z: the identity orientation. The real-time scene is 1.0 mm under the path (a graded
    # window), the reference's spacing.
    "scenes/realtime/aorta-bent-probe.json": {
        "reference_scene": "validation/scenes/aorta-press.json",
        "surface": [30e-3, 0.0, 52.5e-3],
        "press_dir": [0.0, 0.0, -1.0],
        "slide_dir": [1.0, 0.0, 0.0],
        "lift": 0.25e-3, "depth": 2.0e-3, "slide": 3.0e-3, "hold": 0.2,
        "quaternion": [1.0, 0.0, 0.0, 0.0],
        "tool_radius": 5e-3, "youngs_modulus": 1.0e6, "poisson": 0.45, "spacing_along_wall": 1.0e-3,
        "reference_step": 0.15e-3,
        # The default coupling (500 N/m) would hold the tool F/k = 0.5 mm above the hand at 0.27 N: the reference
        # stopped 1.55 mm deep. 10 kN/m: 0.03 mm; a 20 g proxy keeps the 1 kHz coupling stable.
        "coupling": {"stiffness_n_per_m": 1e4, "proxy_mass_kg": 0.02},
    },
    # A micro-probe of 100 um diameter on the twice-bent retinal artery between the bends (theta = 90 deg, the +y
    # side, at mid-length: the centre-line's inflection point (0.25, 0, 0.733) mm, the outer wall at y = 80 um),
    # pressed 32 um (40 % of the radius) along -y and slid 100 um along the centre-line's tangent there (the
    # centre-line leaves that straight line by 10 um at its end, sideways to the press). Orientation as the vein's.
    # The real-time scene is 10 um under the path (a graded window); the reference is the same press at a uniform
    # 10 um (no independent FEM reference for this vessel).
    "scenes/realtime/retinal-artery-twice-bent-probe.json": {
        "reference_scene": "scenes/retinal-artery-twice-bent-probe.json",
        "surface": [0.25e-3, 80e-6, 0.7330127018922193e-3],
        "press_dir": [0.0, -1.0, 0.0],
        "slide_dir": [0.8660254037844386, 0.0, 0.5],
        "lift": 5e-6, "depth": 32e-6, "slide": 100e-6, "hold": 0.2,
        "quaternion": [0.7071067811865476, -0.7071067811865476, 0.0, 0.0],
        "tool_radius": 50e-6, "youngs_modulus": 0.5e6, "poisson": 0.45, "spacing_along_wall": 10e-6,
        "reference_step": 4e-6,
        # A hand at 1-5 mm/s would press this artery (80 um) in 7-37 ms, one to four frames: the speeds of a
        # micro-manipulation, a tenth of the vein's (the 1:10 motion scaling of micro-surgical hands).
        "speeds": "0.1,0.2,0.5",
    },
}






def add(a, b, s=1.0):
    return [x + s * y for x, y in zip(a, b)]


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


class Path:
    """The hand's path: press (from the lift point to the full depth), then slide; arc length l along it."""

    def __init__(self, c):
        self.c = c
        self.top = add(c["surface"], c["press_dir"], -c["lift"])
        self.bottom = add(c["surface"], c["press_dir"], c["depth"])
        self.press_len = c["lift"] + c["depth"]
        self.end = add(self.bottom, c["slide_dir"], c["slide"])
        self.length = self.press_len + c["slide"]

    def point(self, l):
        if l <= self.press_len:
            return add(self.top, self.c["press_dir"], l)
        return add(self.bottom, self.c["slide_dir"], min(l, self.length) - self.press_len)

    def param(self, p):
        """The path parameter of the point of the path nearest p (m)."""
        d = [pi - ti for pi, ti in zip(p, self.top)]
        lp = min(max(dot(d, self.c["press_dir"]), 0.0), self.press_len)
        e = [pi - bi for pi, bi in zip(p, self.bottom)]
        ls = min(max(dot(e, self.c["slide_dir"]), 0.0), self.c["slide"])
        dist_p = math.dist(p, self.point(lp))
        dist_s = math.dist(p, self.point(self.press_len + ls))
        return lp if dist_p <= dist_s else self.press_len + ls

    def depth(self, p):
        """How far p is below the outer wall along the press direction, m."""
        return dot([pi - si for pi, si in zip(p, self.c["surface"])], self.c["press_dir"])

    def schedule(self, speed):
        """(time, l) knots of the motion at `speed` m/s: press, hold, slide, hold."""
        c = self.c
        t1 = self.press_len / speed
        t2 = t1 + c["hold"]
        t3 = t2 + c["slide"] / speed
        return [(0.0, 0.0), (t1, self.press_len), (t2, self.press_len), (t3, self.length), (t3 + c["hold"], self.length)]


def write_trajectory(path, knots, file, dt=1e-3, note=""):
    q = path.c["quaternion"]
    t_end = knots[-1][0]
    with open(file, "w") as f:
        f.write(f"# {note}\n")
        f.write("time_s,x_m,y_m,z_m,qw,qx,qy,qz\n")
        n = int(round(t_end / dt))
        for k in range(n + 1):
            t = k * dt
            for (ta, la), (tb, lb) in zip(knots, knots[1:]):
                if ta <= t <= tb:
                    l = la if tb == ta else la + (lb - la) * (t - ta) / (tb - ta)
                    break
            p = path.point(l)
            f.write(f"{t:.6f},{p[0]:.9g},{p[1]:.9g},{p[2]:.9g},{q[0]},{q[1]},{q[2]},{q[3]}\n")


def scene_with_haptics(scene_file, trajectory, mode_settings, case):
    doc = json.loads(pathlib.Path(scene_file).read_text())
    doc["haptics"] = {"device": {"type": "scripted", "trajectory": str(pathlib.Path(trajectory).resolve())},
                      "ticks_per_step": 10}
    if "coupling" in case:
        doc["haptics"]["coupling"] = dict(case["coupling"])
    for block, values in mode_settings.items():
        doc.setdefault(block, {}).update(values)
    return doc


def reference_key(case, step):
    """What a reference depends on besides the code: the reference scene's text and the path's poses."""
    scene_text = (ROOT / case["reference_scene"]).read_bytes()
    path_keys = ("surface", "press_dir", "slide_dir", "lift", "depth", "slide", "quaternion", "coupling")
    return {"reference_scene": case["reference_scene"], "scene_sha256": hashlib.sha256(scene_text).hexdigest(),
            "path": {k: case[k] for k in path_keys if k in case}, "reference_step_m": step}


def bundled_reference_file(scene):
    """The reference bundled for a real-time scene (data/benchmarks/reference-<scene>.csv)."""
    return ROOT / "data" / "benchmarks" / f"reference-{pathlib.Path(scene).stem}.csv"


def read_reference(file, key=None):
    """(l_m, force_n) of a reference.csv; None when `key` is given and the file's key line differs from it."""
    if key is not None:
        with open(file) as f:
            lines = [line for line in f if line.startswith("# key: ")]
        if not lines or json.loads(lines[0][len("# key: "):]) != key:
            return None
    rows = read_csv(file)
    return [r["l_m"] for r in rows], [r["force_n"] for r in rows]


def reference(args, case, path, out):
    """The fine scene's equilibrium force along the path, one pose every --reference-step (lockstep).

    Taken from --reference when given, else from the output folder's cache, else from the file bundled in
    data/benchmarks when it was computed for the same reference scene, path and step (its key line), else
    computed (8-26 minutes). --fresh-reference computes it whatever is there."""
    step = args.reference_step or case["reference_step"]
    key = reference_key(case, step)
    if args.reference:
        return read_reference(pathlib.Path(args.reference))
    cache = out / "reference.csv"
    if not args.fresh_reference:
        if cache.exists() and (found := read_reference(cache, key)) is not None:
            return found
        bundled = bundled_reference_file(args.scene)
        if bundled.exists() and (found := read_reference(bundled, key)) is not None:
            print(f"reference: {bundled.relative_to(ROOT)} (bundled; --fresh-reference computes it again)", flush=True)
            shutil.copyfile(bundled, cache)
            return found
    n = int(math.ceil(path.length / step))
    frame_s = 0.01  # 10 ticks of 1 ms per pose
    knots = [(k * frame_s, min(k * step, path.length)) for k in range(n + 1)]
    traj = out / "reference-trajectory.csv"
    write_trajectory(path, knots, traj, note="reference poses along the benchmark's path")
    scene = scene_with_haptics(case["reference_scene"], traj, {"quasi_static": {"frame_s": frame_s}}, case)
    scene_file = out / "reference-scene.json"
    scene_file.write_text(json.dumps(scene, indent=1))
    print(f"reference: {n + 1} equilibria of {case['reference_scene']} along the path (lockstep, minutes) ...",
          flush=True)
    _, seconds = sh([args.vascsim, "-q", "run", scene_file, "--out", out / "reference", "--mode", "lockstep", "--yes"],
                    log=out / "reference.log")
    frames = read_csv(out / "reference" / "force_history.csv")
    ls, fs = [], []
    for f in frames:
        l = path.param([f["tool_x_m"], f["tool_y_m"], f["tool_z_m"]])
        if ls and l <= ls[-1] + 1e-12:
            continue
        ls.append(l)
        fs.append(force_on_tool(f))
    with open(cache, "w") as f:
        f.write(f"# {case['reference_scene']} (quasi_static) along the benchmark path; {seconds:.0f} s on "
                f"{machine()}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, vascsim {git_commit()}\n")
        f.write(f"# key: {json.dumps(key, sort_keys=True)}\n")
        f.write("l_m,force_n\n")
        for l, fo in zip(ls, fs):
            f.write(f"{l:.9g},{fo:.9g}\n")
    if args.bundle_reference:
        bundled = bundled_reference_file(args.scene)
        shutil.copyfile(cache, bundled)
        print(f"reference: bundled as {bundled.relative_to(ROOT)}", flush=True)
    return ls, fs


def resolved(case, force):
    """The contact's Hertz diameter 2a = 2 (3 F R / (4 E*))^(1/3) spans 1.4 node spacings along the wall."""
    if force <= 0.0:
        return False
    e_star = case["youngs_modulus"] / (1.0 - case["poisson"] ** 2)
    a = (3.0 * force * case["tool_radius"] / (4.0 * e_star)) ** (1.0 / 3.0)
    return 2.0 * a >= 1.4 * case["spacing_along_wall"]


def quantile(v, q):
    if not v:
        return float("nan")
    s = sorted(v)
    return s[min(len(s) - 1, int(q * (len(s) - 1) + 0.5))]


def session(args, case, path, ref, speed, variant, out):
    run = out / variant / f"speed-{speed * 1e3:g}-mm-s"
    run.mkdir(parents=True, exist_ok=True)
    traj = run / "trajectory.csv"
    write_trajectory(path, path.schedule(speed), traj, note=f"press and slide at {speed * 1e3:g} mm/s")
    scene = scene_with_haptics(args.scene, traj, {}, case)
    mode = "realtime"
    if args.lockstep_frame:
        # Every frame converges, frames of the given length: the work a frame needs at this hand speed.
        mode = "lockstep"
        frame = args.lockstep_frame
        scene["haptics"]["ticks_per_step"] = max(1, int(round(frame * 1e3)))
        scene["implicit"].update({"frame_s": frame, "output_interval_s": frame,
                                  "duration_s": path.schedule(speed)[-1][0]})
    scene_file = run / "scene.json"
    scene_file.write_text(json.dumps(scene, indent=1))
    cmd = [args.vascsim, "-q", "run", scene_file, "--out", run, "--mode", mode]
    for s in VARIANTS[variant] + args.set:
        cmd += ["--set", s]
    # (A lockstep run with frames that did not converge exits 4, with its outputs written.)
    sh(cmd, log=run / "run.log", ok=(0, 4) if args.lockstep_frame else (0,))
    summary = json.loads((run / "summary.json").read_text())
    frames = read_csv(run / "force_history.csv")
    ticks = read_csv(run / "haptic_ticks.csv")
    ref_l, ref_f = ref
    # Frames in the wall: the device pose they were given is below the outer wall.
    wall = [f for f in frames if path.depth([f["pose_x_m"], f["pose_y_m"], f["pose_z_m"]]) > 0.0]
    rates = [1e3 / f["step_wall_ms"] for f in wall if f["step_wall_ms"] > 0.0]
    frame_err = []
    for f in wall:
        fr = interpolate(ref_l, ref_f, path.param([f["tool_x_m"], f["tool_y_m"], f["tool_z_m"]]))
        if resolved(case, fr):
            frame_err.append(abs(force_on_tool(f) - fr) / fr)
    tick_err, felt_max, ref_max, numb = [], 0.0, 0.0, 0
    for t in ticks:
        p = [t["tool_x_m"], t["tool_y_m"], t["tool_z_m"]]
        felt = math.sqrt(t["tissue_fx_n"] ** 2 + t["tissue_fy_n"] ** 2 + t["tissue_fz_n"] ** 2)
        fr = interpolate(ref_l, ref_f, path.param(p)) if path.depth(p) > -1e-4 else 0.0
        felt_max, ref_max = max(felt_max, felt), max(ref_max, fr)
        if resolved(case, fr):
            tick_err.append(abs(felt - fr) / fr)
            numb += 1 if felt < 0.05 * fr else 0  # the hand feels (next to) nothing where the wall pushes
    loop = summary["haptics"]["loop"]
    solver = summary.get("solver", {})
    return {
        "variant": variant,
        "speed_mm_s": speed * 1e3,
        "frames_in_wall": len(wall),
        "frames_per_s_in_wall_median": quantile(rates, 0.5),
        "frames_per_s_in_wall_p10": quantile(rates, 0.1),
        "frames_not_converged_in_wall": sum(1 for f in wall if f["converged"] < 0.5),
        "frames_handing_on_an_older_force": solver.get("frames_handing_on_an_older_force"),
        "newton_iterations": solver.get("newton_iterations"),
        "cg_iterations": solver.get("cg_iterations"),
        "frame_wall_median_ms_in_wall": quantile([f["step_wall_ms"] for f in wall], 0.5),
        "tool_lag_max_mm": max((f["tool_lag_m"] for f in frames), default=0.0) * 1e3,
        "frame_force_error_max": max(frame_err, default=float("nan")),
        "frame_force_error_median": quantile(frame_err, 0.5),
        "frames_compared": len(frame_err),
        "tick_force_error_max": max(tick_err, default=float("nan")),
        "tick_force_error_p95": quantile(tick_err, 0.95),
        "tick_force_error_median": quantile(tick_err, 0.5),
        "ticks_compared": len(tick_err),
        "ticks_feeling_nothing": numb,
        "felt_force_max_mn": felt_max * 1e3,
        "reference_force_max_mn": ref_max * 1e3,
        "haptic_rate_hz": loop["achieved_rate_hz"],
        "jitter_p99_ms": loop["jitter_p99_ms"],
        "force_latency_mean_ms": loop["force_latency_mean_ms"],
        "force_latency_max_ms": loop["force_latency_max_ms"],
        "out": str(run),
    }


def machine():
    """The processor and core count, for the record (platform.processor() is empty on Linux)."""
    cpu = platform.processor() or "unknown cpu"
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            cpu = next((line.split(":", 1)[1].strip() for line in f if line.startswith("model name")), cpu)
    except OSError:
        pass
    return f"{platform.machine()}, {os.cpu_count()} cores ({cpu})"


def git_commit():
    """The checkout's commit (with "+changes" when its work tree differs), or "unknown" outside git."""
    try:
        commit = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                                text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", str(ROOT), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True).stdout.strip()
        return commit + ("+changes" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def percent(value, compared):
    """A relative error as a percentage, or a dash where nothing was compared."""
    return f"{100 * value:.1f} %" if compared else "—"


def markdown(rows, meta):
    lines = [f"Measured {meta['date']} on {meta['machine']} (load average {meta['load_before']} before, "
             f"{meta['load_after']} after); `{meta['command']}`.", "",
             "| solver | hand speed | frames/s in the wall, median (p10) | frames not converged | tool lag | "
             "felt force vs continuum, every tick: max (p95, median) | ticks feeling under 5 % of the force | "
             "frame force: max (frames handing on their own force "
             "where the contact is resolved; — none) | force latency mean (max) | "
             "haptic loop, p99 jitter |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(
            f"| {r['variant']} | {r['speed_mm_s']:g} mm/s | {r['frames_per_s_in_wall_median']:.1f} ({r['frames_per_s_in_wall_p10']:.1f}) | "
            f"{r['frames_not_converged_in_wall']} of {r['frames_in_wall']} | {r['tool_lag_max_mm']:.3f} mm | "
            f"{100 * r['tick_force_error_max']:.1f} % ({100 * r['tick_force_error_p95']:.1f} %, "
            f"{100 * r['tick_force_error_median']:.1f} %), {r['ticks_compared']} ticks | "
            f"{r['ticks_feeling_nothing']} of {r['ticks_compared']} | "
            f"{percent(r['frame_force_error_max'], r['frames_compared'])} | {r['force_latency_mean_ms']:.0f} ms "
            f"({r['force_latency_max_ms']:.0f} ms) | {r['haptic_rate_hz']:.1f} Hz, {r['jitter_p99_ms']:.3f} ms |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--vascsim", default="build/vascsim")
    ap.add_argument("--scene", default="scenes/realtime/hand-dorsal-vein-catheter.json",
                    help="a real-time scene this script knows the path of: " + ", ".join(CASES))
    ap.add_argument("--speeds", help="hand speeds, mm/s (comma-separated; default 1,2,5, and 0.1,0.2,0.5 for the "
                    "retinal artery, whose 32 um press a hand at 1 mm/s makes in 37 ms)")
    ap.add_argument("--out", default="out/realtime-benchmark")
    ap.add_argument("--reference", help="a reference.csv of an earlier run (l_m, force_n) instead of computing it")
    ap.add_argument("--fresh-reference", action="store_true",
                    help="compute the reference even when the output folder or data/benchmarks holds one for the "
                         "same scene, path and step (after a change to the model)")
    ap.add_argument("--bundle-reference", action="store_true",
                    help="copy a reference this run computes to data/benchmarks/reference-<scene>.csv, the one "
                         "later runs take")
    ap.add_argument("--reference-step", type=float, default=None,
                    help="path between reference poses, m (default: the scene's in CASES: 0.1 mm for the vein, "
                         "0.15 mm for the aorta, 4 um for the retinal artery)")
    ap.add_argument("--variants", default="multigrid-embedded,multigrid,multigrid-at-hand,factor",
                    help="solver variants to compare, comma-separated: " + ", ".join(VARIANTS))
    ap.add_argument("--set", action="append", default=[], help="a scene override for the sessions (repeatable)")
    ap.add_argument("--lockstep-frame", type=float, default=0.0,
                    help="run the sessions in lockstep with frames of this length, s (every frame converges: the work "
                         "a frame needs at each hand speed) instead of in realtime; not with --publish")
    ap.add_argument("--publish", action="store_true",
                    help="copy benchmark.json to data/benchmarks/realtime-<scene>.json and regenerate the README's "
                         "\"Real time today\" table from it (scripts/realtime_table.py); only for a run on an idle "
                         "machine with the default variants and speeds")
    args = ap.parse_args()
    variants = args.variants.split(",")
    for v in variants:
        if v not in VARIANTS:
            sys.exit(f"--variants: unknown variant '{v}'; known: {', '.join(VARIANTS)}")
    if args.publish and args.lockstep_frame:
        sys.exit("--publish: the published table is of realtime sessions; drop --lockstep-frame")
    if args.scene not in CASES:
        sys.exit(f"--scene {args.scene}: no press-and-slide path is defined for it; known: {', '.join(CASES)}")
    case = CASES[args.scene]
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    path = Path(case)
    load_before = os.getloadavg()[0]
    ref = reference(args, case, path, out)
    rows = []
    for v in variants:
        for s in (args.speeds or case.get("speeds", "1,2,5")).split(","):
            speed = float(s) * 1e-3
            print(f"{v}: session at {float(s):g} mm/s ...", flush=True)
            rows.append(session(args, case, path, ref, speed, v, out))
    meta = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
            "machine": machine(),
            "load_before": round(load_before, 2), "load_after": round(os.getloadavg()[0], 2),
            "command": " ".join(sys.argv), "scene": args.scene, "reference_scene": case["reference_scene"]}
    (out / "benchmark.json").write_text(json.dumps({"meta": meta, "rows": rows}, indent=1))
    md = markdown(rows, meta)
    (out / "benchmark.md").write_text(md)
    print(md)
    if args.publish:
        published = ROOT / "data" / "benchmarks" / f"realtime-{pathlib.Path(args.scene).stem}.json"
        shutil.copyfile(out / "benchmark.json", published)
        print(f"published {published}")
        subprocess.run([sys.executable, str(ROOT / "scripts" / "realtime_table.py")], check=True)


if __name__ == "__main__":
    main()
