#!/usr/bin/env python3
"""scripts/realtime_table.py renders one table per published scene, the vein first, in a stable order.

Builds a folder of three published results (the vein's data/benchmarks file, copied as the aorta's and the retinal
artery's probe scenes, and written in an order unlike the README's), a README with the markers, and checks that the
script writes one table per scene in the order of its ORDER whatever the files' names sort to, that --check then
passes, and that it fails once the table is edited.

    /usr/bin/python3 tests/python/check_realtime_table_scenes.py
"""
import json
import os
import pathlib
import subprocess
import sys
import tempfile

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "realtime_table.py"
VEIN = ROOT / "data" / "benchmarks" / "realtime-hand-dorsal-vein-catheter.json"
SCENES = [("scenes/realtime/hand-dorsal-vein-catheter.json", "scenes/hand-dorsal-vein-catheter.json"),
          ("scenes/realtime/aorta-bent-probe.json", "validation/scenes/aorta-press.json"),
          ("scenes/realtime/retinal-artery-twice-bent-probe.json", "scenes/retinal-artery-twice-bent-probe.json")]


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True, text=True)


def main():
    sys.path.insert(0, str(SCRIPT.parent))
    import realtime_table  # noqa: E402  (the markers)

    base = json.loads(VEIN.read_text())
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        data = pathlib.Path(tmp) / "benchmarks"
        data.mkdir()
        for scene, reference in reversed(SCENES):  # written last-first: the order must not come from the disk
            doc = json.loads(json.dumps(base))
            doc["meta"]["scene"], doc["meta"]["reference_scene"] = scene, reference
            (data / f"realtime-{pathlib.Path(scene).stem}.json").write_text(json.dumps(doc))
        readme = pathlib.Path(tmp) / "README.md"
        readme.write_text(f"# x\n\n{realtime_table.BEGIN}\n{realtime_table.END}\n\nafter\n")
        r = run("--readme", readme, "--data", data)
        if r.returncode != 0:
            failures.append(f"writing the table failed: {r.stderr}")
        text = readme.read_text()
        starts = [text.find(f"`{scene}` against the converged continuum (`{reference}`") for scene, reference in SCENES]
        if any(s < 0 for s in starts):
            failures.append(f"a scene has no table: {starts}")
        elif starts != sorted(starts):
            failures.append(f"the tables are not in the order vein, aorta, retinal artery: {starts}")
        if text.count("| **target** |") != len(SCENES):
            failures.append(f"{text.count('| **target** |')} tables for {len(SCENES)} scenes")
        if not text.endswith("\n\nafter\n"):
            failures.append("the text after the markers changed")
        r = run("--readme", readme, "--data", data, "--check")
        if r.returncode != 0:
            failures.append(f"--check fails on the table it wrote: {r.stderr}")
        readme.write_text(text.replace("| **target** |", "| target |", 1))
        r = run("--readme", readme, "--data", data, "--check")
        if r.returncode != 1:
            failures.append(f"--check passes an edited table (exit {r.returncode})")
    for f in failures:
        print(f"check_realtime_table_scenes: {f}", file=sys.stderr)
    if not failures:
        print(f"check_realtime_table_scenes: {len(SCENES)} scenes, one table each, the vein first")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
