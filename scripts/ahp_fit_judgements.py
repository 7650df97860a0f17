#!/usr/bin/env python3
"""Find Saaty-scale pairwise matrices that reproduce published AHP weights (how data/ahp/paper-hierarchy.json
was made from Table 1 of Zhang et al. 2021).

Usage: /usr/bin/python3 scripts/ahp_fit_judgements.py [HIERARCHY.json] [--top K]

For every matrix of the hierarchy (the criteria, then each criterion's indicators) whose elements all have a
published weight ('paper_weight'), this enumerates every reciprocal matrix with judgements on Saaty's 1-9
scale that
  - keeps the published rank order: the element with the larger weight gets the judgement >= 1;
  - keeps the rank order within every row: a_ij >= a_ik whenever w_j < w_k (an element is not preferred
    more strongly to a more important element than to a less important one);
  - has CR <= 0.1 (Saaty's random index);
and ranks them by the largest absolute difference between the principal-eigenvector weights and the
published weights (then by CR). It prints the best K and the matrix rows of the best, in the file's syntax.
Nothing is written. 9^(n(n-1)/2) candidates: 531,441 for n = 4, a few seconds with numpy.
"""
import argparse
import itertools
import json
import os
import sys

import numpy as np

RI = {1: 0.0, 2: 0.0, 3: 0.58, 4: 0.90, 5: 1.12, 6: 1.24, 7: 1.32, 8: 1.41, 9: 1.45, 10: 1.49}


def principal(mats):
    """Weights (sum 1), lambda_max and CR of a stack of positive matrices (k, n, n)."""
    n = mats.shape[-1]
    vals, vecs = np.linalg.eig(mats)
    idx = np.argmax(vals.real, axis=1)
    lam = vals.real[np.arange(len(mats)), idx]
    w = np.abs(vecs.real[np.arange(len(mats)), :, idx])
    w /= w.sum(axis=1, keepdims=True)
    cr = np.zeros(len(mats)) if n <= 2 else np.maximum(0.0, (lam - n) / (n - 1)) / RI[n]
    return w, lam, cr


def fit(target, chunk=100000):
    t = np.asarray(target, dtype=float)
    n = len(t)
    pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    best = []
    combos = itertools.product(range(1, 10), repeat=len(pairs))
    while True:
        block = list(itertools.islice(combos, chunk))
        if not block:
            break
        v = np.asarray(block, dtype=float)
        a = np.ones((len(v), n, n))
        for p, (i, j) in enumerate(pairs):
            hi, lo = (i, j) if t[i] >= t[j] else (j, i)
            a[:, hi, lo] = v[:, p]
            a[:, lo, hi] = 1.0 / v[:, p]
        # row-wise rank order: for w_j < w_k, a_ij >= a_ik
        ok = np.ones(len(v), dtype=bool)
        for i in range(n):
            for j in range(n):
                for k in range(n):
                    if t[j] < t[k]:
                        ok &= a[:, i, j] >= a[:, i, k] - 1e-12
        a, v = a[ok], v[ok]
        if not len(a):
            continue
        w, lam, cr = principal(a)
        err = np.abs(w - t).max(axis=1)
        keep = cr <= 0.1
        for e, c, l, ww, m in zip(err[keep], cr[keep], lam[keep], w[keep], a[keep]):
            best.append((e, c, l, ww, m))
        best.sort(key=lambda r: (round(r[0], 12), r[1]))
        best = best[:50]
    return best


def fraction(x):
    return str(int(round(x))) if x >= 1 else f"1/{int(round(1 / x))}"


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("hierarchy", nargs="?", default=os.path.join(here, "..", "data", "ahp", "paper-hierarchy.json"))
    ap.add_argument("--top", type=int, default=5)
    args = ap.parse_args()
    with open(args.hierarchy) as f:
        doc = json.load(f)
    groups = [("criteria", [c["id"] for c in doc["criteria"]], [c.get("paper_weight") for c in doc["criteria"]])]
    for c in doc["criteria"]:
        groups.append((f"{c['id']} indicators", [i["id"] for i in c["indicators"]],
                       [i.get("paper_weight") for i in c["indicators"]]))
    for name, ids, target in groups:
        if any(w is None for w in target) or len(target) < 2:
            continue
        print(f"{name} ({', '.join(ids)}), published weights {target}")
        best = fit(target)
        if not best:
            print("  no Saaty-scale matrix with CR <= 0.1 keeps the rank order")
            continue
        for e, c, l, w, _ in best[: args.top]:
            print(f"  max |w - w_paper| = {e:.4f}  CR = {c:.4f}  lambda_max = {l:.4f}  w = {np.round(w, 4).tolist()}")
        rows = [[fraction(x) for x in row] for row in best[0][4]]
        print("  best:", json.dumps(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
