"""Richardson extrapolation of a mesh sequence and its uncertainty: the grid convergence index (GCI) of
Celik et al. 2008, "Procedure for estimation and reporting of uncertainty due to discretization in CFD
applications", J. Fluids Eng. 130(7), 078001.

Three meshes with representative sizes h1 < h2 < h3 (fine to coarse) and values f1, f2, f3: the observed
order p solves

    p = |ln|e32/e21| + q(p)| / ln r21,   q(p) = ln((r21^p - s) / (r32^p - s)),   s = sign(e32/e21),

with e21 = f2 - f1, e32 = f3 - f2, r = h_coarse / h_fine; the extrapolated value is
f_ext = (r21^p f1 - f2) / (r21^p - 1), and the fine-mesh uncertainty GCI21 = 1.25 |(f1 - f2)/f1| / (r21^p - 1)
(factor of safety 1.25 for three meshes).
"""
import math


def observed_order(h, f, iterations=200):
    """h, f: three sizes and values, fine to coarse. Returns (p, converged_monotonically)."""
    (h1, h2, h3), (f1, f2, f3) = h, f
    r21, r32 = h2 / h1, h3 / h2
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0.0 or e32 == 0.0:
        return float("nan"), False
    ratio = e32 / e21
    s = 1.0 if ratio > 0 else -1.0
    p = abs(math.log(abs(ratio))) / math.log(r21)
    for _ in range(iterations):
        q = math.log((r21 ** p - s) / (r32 ** p - s))
        p_new = abs(math.log(abs(ratio)) + q) / math.log(r21)
        if abs(p_new - p) < 1e-12:
            p = p_new
            break
        p = p_new
    return p, ratio > 0


def extrapolate(h, f):
    """Richardson extrapolation from three levels (fine to coarse). Returns a dict with the order p, the
    extrapolated value, the fine-mesh GCI as an absolute uncertainty of the extrapolated value (same unit as
    f), and whether the three values converge monotonically (if not, the uncertainty is the spread)."""
    p, monotone = observed_order(h, f)
    f1, f2 = f[0], f[1]
    r21 = h[1] / h[0]
    if not monotone or not math.isfinite(p) or p <= 0.0:
        spread = max(f) - min(f)
        return {"order": p, "value": f1, "uncertainty": 1.25 * spread, "monotone": False}
    value = (r21 ** p * f1 - f2) / (r21 ** p - 1.0)
    gci = 1.25 * abs(f1 - f2) / (r21 ** p - 1.0)
    return {"order": p, "value": value, "uncertainty": gci, "monotone": True}
