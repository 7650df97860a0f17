#!/usr/bin/env python3
"""Check the files `vascsim ahp` wrote, independently of the C++ code.

Usage: /usr/bin/python3 tests/python/check_ahp_outputs.py OUT_DIR [--bands BANDS.json] [--models N]

Reads OUT_DIR/ahp_weights.csv, ahp_consistency.csv, ahp_scores.csv, ahp_indicator_scores.csv and
ahp_scores.png and checks:
  - the weights: W_i = W_C * W_I, the W_i used add up to 1, every CR <= 0.1;
  - Eq. 40: each complete model's G equals sum W_i * score_i recomputed from the CSVs;
  - Table 2: every measured score equals the linear band mapping of its value, recomputed here from the
    bands file (default: data/ahp/paper-bands.json);
  - the two score CSVs agree on every score and source; the PNG is a real PNG of a sensible size;
  - scripts/plot_ahp.py rejects a malformed CSV with exit code 2 and one stderr line.
Exits non-zero if any check fails. Runs nothing heavy (the CLI run is the ctest's first command).
"""
import csv
import json
import os
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"

failures = []


def check(cond, msg):
    print(("ok   " if cond else "FAIL ") + msg)
    if not cond:
        failures.append(msg)


def read_csv(path):
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def num(s):
    return None if s == "" else float(s)


def band_score(bands, ind, value):
    """Linear Table 2 mapping, written independently of ahp_evaluation.cpp."""
    edges = bands["indicators"][ind]["edges"]
    scores = bands["score_bands"]["edges"]
    sign = 1.0 if edges[-1] > edges[0] else -1.0
    x = [sign * e for e in edges]
    v = sign * value
    if v <= x[0]:
        return scores[0]
    if v >= x[-1]:
        return scores[-1]
    for k in range(len(x) - 1):
        if x[k] <= v <= x[k + 1]:
            return scores[k] + (v - x[k]) / (x[k + 1] - x[k]) * (scores[k + 1] - scores[k])
    raise AssertionError("unreachable")


def main(argv):
    if not argv:
        print(__doc__)
        return 2
    out = argv[0]
    bands_path = os.path.join(ROOT, "data", "ahp", "paper-bands.json")
    n_models = None
    if "--bands" in argv:
        bands_path = argv[argv.index("--bands") + 1]
    if "--models" in argv:
        n_models = int(argv[argv.index("--models") + 1])
    with open(bands_path) as f:
        bands = json.load(f)

    weights = read_csv(os.path.join(out, "ahp_weights.csv"))
    cons = read_csv(os.path.join(out, "ahp_consistency.csv"))
    scores = read_csv(os.path.join(out, "ahp_scores.csv"))
    long = read_csv(os.path.join(out, "ahp_indicator_scores.csv"))

    # weights and consistency
    ids = [w["indicator"] for w in weights]
    check(len(ids) == len(set(ids)) and ids, f"ahp_weights.csv: {len(ids)} distinct indicators")
    prod = max(abs(float(w["criterion_weight"]) * float(w["local_weight"]) - float(w["global_weight"])) for w in weights)
    check(prod < 2e-6, f"W_i = W_C * W_I (max difference {prod:.1e})")
    total = sum(float(w["weight_used"]) for w in weights)
    check(abs(total - 1.0) < 1e-5, f"the W_i used add up to 1 ({total:.6f})")
    check(all(float(c["cr"]) <= 0.1 for c in cons), f"every CR <= 0.1 ({', '.join(c['cr'] for c in cons)})")
    w_used = {w["indicator"]: float(w["weight_used"]) for w in weights}

    # Eq. 40 from the wide CSV
    if n_models is not None:
        check(len(scores) == n_models, f"ahp_scores.csv: {len(scores)} models == {n_models}")
    complete = 0
    for row in scores:
        beta = {i: num(row[i]) for i in ids}
        g = num(row["comprehensive_score"])
        if all(b is not None for b in beta.values()):
            complete += 1
            mine = sum(w_used[i] * beta[i] for i in ids)
            check(g is not None and abs(g - mine) < 2e-3, f"{row['model']}: Eq. 40 G = {g} vs recomputed {mine:.4f}")
        else:
            check(g is None, f"{row['model']}: no G with missing scores ({row['missing']})")
            covered = sum(w_used[i] for i in ids if beta[i] is not None)
            check(abs(covered - float(row["weight_covered"])) < 1e-5, f"{row['model']}: weight covered {covered:.6f}")
    check(complete > 0, f"{complete} model(s) with a complete score set")

    # Table 2 bands for the measured scores; the long CSV agrees with the wide one
    wide = {(r["model"], i): (num(r[i]), r[i + "_source"]) for r in scores for i in ids}
    measured = 0
    agree = True
    for r in long:
        key = (r["model"], r["indicator"])
        agree &= wide.get(key) == (num(r["score"]), r["source"])
        if r["source"] == "measured":
            measured += 1
            mine = band_score(bands, r["indicator"], float(r["value"]))
            check(abs(mine - float(r["score"])) < 1e-3,
                  f"{r['model']} {r['indicator']}: {r['value']} {r['unit']} -> {r['score']} (Table 2 linear: {mine:.3f})")
    check(agree and len(long) == len(scores) * len(ids), "ahp_indicator_scores.csv agrees with ahp_scores.csv")
    check(measured > 0, f"{measured} measured scores checked against the bands")

    # the PNG
    png = os.path.join(out, "ahp_scores.png")
    if os.path.isfile(png):
        with open(png, "rb") as f:
            head = f.read(24)
        width, height = struct.unpack(">II", head[16:24]) if len(head) == 24 else (0, 0)
        check(head[:8] == PNG_MAGIC, "ahp_scores.png: PNG magic bytes")
        check(width >= 800 and height >= 300, f"ahp_scores.png: {width} x {height} pixels")
        check(os.path.getsize(png) > 20000, f"ahp_scores.png: {os.path.getsize(png)} bytes > 20000")
    else:
        check(False, "ahp_scores.png written")

    # the plot script's error path
    with tempfile.TemporaryDirectory() as d:
        bad = os.path.join(d, "bad_scores.csv")
        with open(bad, "w") as f:
            f.write("model,name,comprehensive_score,paper_comprehensive_score,weight_covered,I1,I1_source\n"
                    "x,X,150,,1,90,rated\n")
        p = subprocess.run([sys.executable, os.path.join(ROOT, "scripts", "plot_ahp.py"), bad, "--out",
                            os.path.join(d, "x.png")], capture_output=True, text=True)
        lines = p.stderr.strip().splitlines()
        check(p.returncode == 2 and len(lines) == 1 and "bad_scores.csv" in lines[0] and "comprehensive_score" in lines[0],
              f"plot_ahp.py: a score of 150 -> exit 2, one line ({p.stderr.strip()!r})")
        check(not os.path.exists(os.path.join(d, "x.png")), "plot_ahp.py: no PNG for a bad CSV")

    if failures:
        print(f"\n{len(failures)} check(s) failed")
        return 1
    print("\nall checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
