#!/usr/bin/env python3
"""Checks scripts/plot_timing.py: a PNG from a small timing.json (two models, two node counts), and the one-line
error with exit code 2 for a file without points."""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "..", "..", "scripts", "plot_timing.py")


def point(model, nodes, sim_ms):
    return {"model": model, "nodes": nodes, "simulation_median_ms": sim_ms, "surface_map_median_ms": 0.1,
            "frames_per_s": 1000.0 / (sim_ms + 0.1), "load_average_start": 1.0, "load_average_end": 1.5,
            "threads": 1, "steps": 200, "machine": {"cpu_model": "test CPU", "hardware_concurrency": 2}}


def main():
    with tempfile.TemporaryDirectory() as d:
        doc = {"points": [point("a", 1000, 5.0), point("a", 2000, 12.0), point("b", 1000, 50.0), point("b", 2000, 90.0)]}
        src = os.path.join(d, "timing.json")
        with open(src, "w") as f:
            json.dump(doc, f)
        png = os.path.join(d, "timing.png")
        r = subprocess.run([sys.executable, SCRIPT, src, "--out", png], capture_output=True, text=True)
        assert r.returncode == 0, r.stderr
        with open(png, "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n", "not a PNG"
        empty = os.path.join(d, "empty.json")
        with open(empty, "w") as f:
            json.dump({"points": []}, f)
        r = subprocess.run([sys.executable, SCRIPT, empty, "--out", png], capture_output=True, text=True)
        assert r.returncode == 2, r.returncode
        assert r.stderr.startswith("plot_timing.py: "), r.stderr
    print("check_plot_timing: 2 passed, 0 failed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
