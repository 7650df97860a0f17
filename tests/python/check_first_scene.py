#!/usr/bin/env python3
"""The tutorial's scene still works: docs/first-scene.md's scene (its first JSON block) passes `vascsim check`,
and so does its catheter variant (the `obstacles` block replacing the indenter), whose tool reaches the tissue.

Usage: /usr/bin/python3 tests/python/check_first_scene.py VASCSIM
"""
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


def main():
    vascsim = sys.argv[1]
    found = blocks(open(DOC, encoding="utf-8").read())
    if len(found) < 2:
        sys.exit(f"FAIL {DOC}: expected the scene and the obstacles block as ```json blocks, found {len(found)}")
    scene = json.loads(found[0])
    obstacles = json.loads("{" + found[1].strip().rstrip(",") + "}")["obstacles"]
    with tempfile.TemporaryDirectory() as d:
        out = check(vascsim, scene, d, "my-vessel.json")
        if "  region    indenter: displacement" not in out:
            sys.exit("FAIL the indenter region is not reported")
        scene["regions"] = [r for r in scene["regions"] if r["name"] != "indenter"]
        scene["obstacles"] = obstacles
        out = check(vascsim, scene, d, "my-vessel-catheter.json")
        if "catheter: reaches the tissue" not in out:
            sys.exit("FAIL the tutorial's catheter does not reach the tissue")
    print("ok: the tutorial's scene and its catheter variant pass vascsim check")


if __name__ == "__main__":
    main()
