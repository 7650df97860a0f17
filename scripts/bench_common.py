"""Helpers the benchmark scripts share: running a command, reading a CSV of numbers, linear interpolation."""
import bisect
import csv
import pathlib
import subprocess
import sys
import time


def sh(cmd, env=None, log=None, ok=(0,)):
    """Runs cmd; exits with its stderr's tail when it fails (an exit code not in ok); returns (stdout, wall
    seconds). log: a file for the command's stdout and stderr."""
    t0 = time.time()
    proc = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, env=env)
    if log:
        pathlib.Path(log).write_text(proc.stdout + proc.stderr)
    if proc.returncode not in ok:
        sys.exit(f"{' '.join(map(str, cmd))} failed ({proc.returncode}): {proc.stderr.strip()[-2000:]}")
    return proc.stdout, time.time() - t0


def read_csv(path):
    """Rows of a numeric CSV with a header (lines starting with # skipped), as dicts of floats."""
    with open(path) as f:
        rows = list(csv.reader(line for line in f if not line.startswith("#")))
    head = rows[0]
    return [{k: float(v) for k, v in zip(head, r)} for r in rows[1:]]


def interpolate(xs, ys, x):
    """ys at x, linear between the (ascending) xs, constant beyond them."""
    i = bisect.bisect_left(xs, x)
    if i <= 0:
        return ys[0]
    if i >= len(xs):
        return ys[-1]
    w = (x - xs[i - 1]) / (xs[i] - xs[i - 1])
    return (1 - w) * ys[i - 1] + w * ys[i]


def force_on_tool(row):
    """|force on the tool| of a force_history.csv row, N (the column was force_n before it was force_magnitude_n:
    cached references of earlier runs still read)."""
    return row["force_magnitude_n"] if "force_magnitude_n" in row else row["force_n"]
