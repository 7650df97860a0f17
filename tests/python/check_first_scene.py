#!/usr/bin/env python3
"""The tutorial says what the program does: docs/first-scene.md's scene (its first JSON block) passes `vascsim
check` with the node count the page shows, and run, its indenter needs the force the page quotes (and its clamps
theirs); its catheter variant (the `obstacles` block replacing the indenter) reaches the tissue and needs the force
the page quotes. The numbers are read from the page, so the page cannot drift from the program.

Usage: /usr/bin/python3 tests/python/check_first_scene.py VASCSIM
"""
import csv
import json
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
DOC = os.path.normpath(os.path.join(HERE, "..", "..", "docs", "first-scene.md"))


def blocks(text):
    return re.findall(r"```json\n(.*?)```", text, re.S)


def check(vascsim, scene, folder, name):
    path = os.path.join(folder, name)
    with open(path, "w") as f:
        json.dump(scene, f, indent=2)
    p = subprocess.run([vascsim, "-q", "check", path], capture_output=True, text=True)
    print(p.stdout)
    if p.returncode != 0:
        sys.exit(f"FAIL vascsim check {name}: exit {p.returncode}: {p.stderr.strip()}")
    return p.stdout


def run(vascsim, path, out):
    p = subprocess.run([vascsim, "-q", "run", path, "--out", out], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"FAIL vascsim run {path}: exit {p.returncode}: {p.stderr.strip()}")
    with open(os.path.join(out, "probes.csv")) as f:
        return list(csv.DictReader(f))[-1]


def quoted(text, pattern, what):
    m = re.search(pattern, text)
    if not m:
        sys.exit(f"FAIL {DOC}: the page no longer quotes {what} (pattern {pattern!r})")
    return [float(g) for g in m.groups()]


# The page prints forces in mN to three digits: a run agrees when within half a unit of the last digit (0.05 mN)
# plus what the solver's relative tolerance and the BLAS's rounding move (well under 0.01 mN here).
TOLERANCE_MN = 0.06


def expect_force(what, got_n, quoted_mn):
    got_mn = 1e3 * float(got_n)
    print(f"{what}: {got_mn:.3f} mN, the page says {quoted_mn} mN")
    if abs(got_mn - quoted_mn) > TOLERANCE_MN:
        sys.exit(f"FAIL {what}: {got_mn:.3f} mN, docs/first-scene.md says {quoted_mn} mN")


def main():
    vascsim = sys.argv[1]
    text = open(DOC, encoding="utf-8").read()
    found = blocks(text)
    if len(found) < 2:
        sys.exit(f"FAIL {DOC}: expected the scene and the obstacles block as ```json blocks, found {len(found)}")
    scene = json.loads(found[0])
    obstacles = json.loads("{" + found[1].strip().rstrip(",") + "}")["obstacles"]
    for o in obstacles:
        if "node_radius_m" in o:
            sys.exit("FAIL the tutorial's catheter sets node_radius_m (node contact and a pre-indent, not the "
                     "validated surface contact)")
    (nodes,) = quoted(text, r"body +(\d+) nodes", "the node count of check's output")
    indenter, clamp_a, clamp_b = quoted(text, r"The indenter needs ([0-9.]+) mN at 0\.8 mm.*?clamps hold ([0-9.]+) mN "
                                        r"and\s+([0-9.]+) mN", "the indenter's and the clamps' forces")
    (catheter,) = quoted(text, r"the catheter needs ([0-9.]+) mN at 0\.8 mm", "the catheter's force")
    with tempfile.TemporaryDirectory() as d:
        out = check(vascsim, scene, d, "my-vessel.json")
        if "  region    indenter: displacement" not in out:
            sys.exit("FAIL the indenter region is not reported")
        m = re.search(r"body +(\d+) nodes", out)
        if not m or int(m.group(1)) != int(nodes):
            sys.exit(f"FAIL check reports {m.group(1) if m else '?'} nodes, the page {int(nodes)}")
        row = run(vascsim, os.path.join(d, "my-vessel.json"), os.path.join(d, "indenter"))
        expect_force("indenter at 0.8 mm", row["indenter_force_n"], indenter)
        expect_force("clamp_start", row["clamp_start_force_n"], clamp_a)
        expect_force("clamp_end", row["clamp_end_force_n"], clamp_b)
        scene["regions"] = [r for r in scene["regions"] if r["name"] != "indenter"]
        scene["obstacles"] = obstacles
        out = check(vascsim, scene, d, "my-vessel-catheter.json")
        if "catheter: reaches the tissue" not in out:
            sys.exit("FAIL the tutorial's catheter does not reach the tissue")
        row = run(vascsim, os.path.join(d, "my-vessel-catheter.json"), os.path.join(d, "catheter"))
        expect_force("catheter at 0.8 mm", row["catheter_force_n"], catheter)
    print("ok: the tutorial's scene and its catheter variant give the node count and the forces the page shows")


if __name__ == "__main__":
    main()
