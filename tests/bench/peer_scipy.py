"""peer_scipy.py PLAN.csv [LAYERFIT_SECONDS]: the peer of bench_fit.c.

Reads the plan and curve files `layerfit simulate` (or bench_fit) writes,
fits the same thin-layer model (seed paper Eq. 10, 22: w, E*, nu shared; z0
and F0 per curve) with scipy.optimize.least_squares (trust-region
reflective, analytic-free 2-point Jacobian, curves weighted by their
max |force|), and prints the median time of repeated fits and the
estimates.  Its starting point is the truth times 1.1 (scipy has no
automatic guess), which favours scipy.  Run with /usr/bin/python3."""
import csv
import math
import os
import sys
import time

import numpy as np
from scipy.optimize import least_squares


def read_plan(path):
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            z, F = [], []
            with open(os.path.join(os.path.dirname(path), r["file"])) as g:
                for c in csv.DictReader(g):
                    z.append(float(c["depth_m"]))
                    F.append(float(c["force_N"]))
            rows.append(dict(k=float(r["k"]), R=float(r["R_m"]), b=float(r["b_m"]),
                             bonded=r["interface"] == "bonded",
                             z=np.array(z), F=np.array(F)))
    return rows


def force(c, w, E, nu, z0, F0):
    k, R, b = c["k"], c["R"], c["b"]
    Z = (1 - nu) ** 2 / (1 - 2 * nu) if c["bonded"] else 1.0
    M = Z * E
    cc = math.sqrt(2 * b * w / M)
    C = math.pi * M / b * k ** ((k + 2) / k) / (k + 2) * R ** (2 * (k - 1) / k)
    d1 = c["z"] - z0 + cc
    d1p = np.where(d1 > 0, d1, 0.0)
    return np.where(d1 > 0, C * d1p ** (2 / k) * (d1p - (k + 2) / k * cc), 0.0) + F0


def residuals(p, curves):
    w, E, nu = math.exp(p[0]), math.exp(p[1]), 0.25 * (1 + math.tanh(p[2]))
    out = []
    for j, c in enumerate(curves):
        z0, F0 = p[3 + 2 * j] * 1e-9, p[4 + 2 * j] * c["scale"]
        out.append((force(c, w, E, nu, z0, F0) - c["F"]) / c["scale"])
    return np.concatenate(out)


def main():
    curves = read_plan(sys.argv[1])
    for c in curves:
        c["scale"] = np.max(np.abs(c["F"]))
    x0 = [math.log(12.3e-3 * 1.1), math.log(1.85e9 * 1.1), math.atanh(4 * 0.35 * 1.02 - 1)]
    for c in curves:
        x0 += [15.0 * 1.1, 0.0]
    times = []
    for _ in range(20):
        t0 = time.perf_counter()
        sol = least_squares(residuals, x0, args=(curves,), method="trf", xtol=1e-12, ftol=1e-12)
        times.append(time.perf_counter() - t0)
    t = sorted(times)[len(times) // 2]
    p = sol.x
    print("scipy:    median %.1f us over %d fits (least_squares trf, start = truth x 1.1), status %d"
          % (1e6 * t, len(times), sol.status))
    print("scipy:    w = %.6g J/m^2, E* = %.6g Pa, nu = %.6g"
          % (math.exp(p[0]), math.exp(p[1]), 0.25 * (1 + math.tanh(p[2]))))
    if len(sys.argv) > 2:
        print("ratio scipy / layerfit = %.1f" % (t / float(sys.argv[2])))


main()
