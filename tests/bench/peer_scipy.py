#!/usr/bin/python3
"""peer_scipy.py: scipy.optimize.least_squares on layerfit's data, so the
speed and accuracy comparison can be rerun by anyone.  Run it with Debian's
python3-scipy (/usr/bin/python3).  Two modes:

peer_scipy.py DIR (used by `layerfit bench`): fit every case file
DIR/case_S_N.txt the bench wrote with each peer and print, per case and
peer, one line

    case S N median_time_us rms_rel_err_w rms_rel_err_E rms_abs_err_nu converged_fraction PEER

(err_nu is nan when nu is not fitted).  The peers:
    lm-truth, trf-truth   scipy least_squares, method 'lm' (MINPACK) or
                          'trf', analytic Jacobian, from the truth
    lm-auto, trf-auto     the same from a simple automatic start (below),
                          its cost included in the time
    lmfit-truth           lmfit.minimize (Debian python3-lmfit), 'leastsq'
                          with its own finite-difference Jacobian, from the
                          truth; skipped when lmfit is missing
The simple automatic start, per curve, from the data alone: F0 = the force
of the shallowest point, the deepest point gives M with the closed form,
the lowest force its pull-off P_po = -C (2c/k)^(2/k) c, hence c, w = M c^2
/ (2b) and z0 (two passes); w and E* are the geometric means over the
curves (E* from frictionless curves where there are any).  Case file: '# key values' header
lines (scene, noise, truth w E nu, free_nu, free_offsets, seeds, ncurves,
then 'curve j k R b base' and 'offsets j z0 F0'), then rows 'seed curve z F'.
Parameters: ln w, ln E*, u = atanh(4 nu - 1) when nu is free, then z0 and F0
of each curve when the case frees them; residuals weighted by each curve's
largest |force| (the noise is a fixed fraction of it); analytic Jacobian,
method 'trf', x_scale 'jac', default tolerances; the fit starts from the
truth, the most favourable start scipy can have.

peer_scipy.py PLAN.csv [LAYERFIT_SECONDS] (used by bench_fit.c, `make
bench-fit`): reads the plan and curve files `layerfit simulate` (or
bench_fit) writes, fits w, E*, nu shared and z0, F0 per curve with a 2-point
Jacobian from the truth times 1.1, and prints the median time of repeated
fits and the estimates.

The model in both is the thin-layer closed form of the seed paper
(Papangelo, Eq. 10-11, 22-23):

    M = Z E*, Z = 1 (frictionless) or (1-nu)^2/(1-2nu) (bonded)
    c = sqrt(2 b w / M), d1 = z - z0 + c
    P = C d1^(2/k) (d1 - (k+2)/k c),  C = pi M/b k^((k+2)/k)/(k+2) R^(2(k-1)/k)
    P = 0 where d1 <= 0;  F = P + F0
"""
import csv
import glob
import math
import os
import sys
import time

import numpy as np
from scipy.optimize import least_squares

try:
    import lmfit
except ImportError:     # Debian python3-lmfit; its peer is then skipped
    lmfit = None


# ---- plan mode (bench_fit.c) -------------------------------------------

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


def plan_force(c, w, E, nu, z0, F0):
    k, R, b = c["k"], c["R"], c["b"]
    Z = (1 - nu) ** 2 / (1 - 2 * nu) if c["bonded"] else 1.0
    M = Z * E
    cc = math.sqrt(2 * b * w / M)
    C = math.pi * M / b * k ** ((k + 2) / k) / (k + 2) * R ** (2 * (k - 1) / k)
    d1 = c["z"] - z0 + cc
    d1p = np.where(d1 > 0, d1, 0.0)
    return np.where(d1 > 0, C * d1p ** (2 / k) * (d1p - (k + 2) / k * cc), 0.0) + F0


def plan_residuals(p, curves):
    w, E, nu = math.exp(p[0]), math.exp(p[1]), 0.25 * (1 + math.tanh(p[2]))
    out = []
    for j, c in enumerate(curves):
        z0, F0 = p[3 + 2 * j] * 1e-9, p[4 + 2 * j] * c["scale"]
        out.append((plan_force(c, w, E, nu, z0, F0) - c["F"]) / c["scale"])
    return np.concatenate(out)


def plan_main():
    curves = read_plan(sys.argv[1])
    for c in curves:
        c["scale"] = np.max(np.abs(c["F"]))
    x0 = [math.log(12.3e-3 * 1.1), math.log(1.85e9 * 1.1), math.atanh(4 * 0.35 * 1.02 - 1)]
    for c in curves:
        x0 += [15.0 * 1.1, 0.0]
    times = []
    for _ in range(20):
        t0 = time.perf_counter()
        sol = least_squares(plan_residuals, x0, args=(curves,), method="trf", xtol=1e-12, ftol=1e-12)
        times.append(time.perf_counter() - t0)
    t = sorted(times)[len(times) // 2]
    p = sol.x
    print("scipy:    median %.1f us over %d fits (least_squares trf, start = truth x 1.1), status %d"
          % (1e6 * t, len(times), sol.status))
    print("scipy:    w = %.6g J/m^2, E* = %.6g Pa, nu = %.6g"
          % (math.exp(p[0]), math.exp(p[1]), 0.25 * (1 + math.tanh(p[2]))))
    if len(sys.argv) > 2:
        print("ratio scipy / layerfit = %.1f" % (t / float(sys.argv[2])))


# ---- case-directory mode (layerfit bench) -------------------------------

def read_case(path):
    head = {"curves": [], "offsets": {}}
    with open(path) as f:
        for line in f:
            if not line.startswith("#"):
                break
            key, *vals = line[1:].split()
            if key == "curve":
                head["curves"].append((float(vals[1]), float(vals[2]), float(vals[3]),
                                       vals[4] == "bonded"))
            elif key == "offsets":
                head["offsets"][int(vals[0])] = (float(vals[1]), float(vals[2]))
            elif key == "truth":
                head["truth"] = tuple(float(v) for v in vals)
            elif key == "scene":
                head["scene"] = vals[0]
            else:
                head[key] = float(vals[0])
    data = np.loadtxt(path, comments="#", ndmin=2)
    return head, data


def curve_model(k, R, b, bonded, w, E, nu, z, z0):
    """P and its derivatives dP/dln w, dP/dln M, dP/ddelta at depths z."""
    Z = (1 - nu) ** 2 / (1 - 2 * nu) if bonded else 1.0
    M = Z * E
    c = math.sqrt(2 * b * w / M)
    C = math.pi * M / b * k ** ((k + 2) / k) / (k + 2) * R ** (2 * (k - 1) / k)
    d1 = z - z0 + c
    on = d1 > 0
    d = np.where(on, d1, 0.0)
    g = np.where(on, np.maximum(d, 1e-9 * c) ** (2 / k - 1), 0.0)
    P = np.where(on, C * d ** (2 / k) * (d - (k + 2) / k * c), 0.0)
    dlogw = -C * (k + 2) / k ** 2 * c * c * g
    dlogM = P - dlogw
    ddelta = C * (k + 2) / k * g * (d - 2 * c / k)
    dlogZ_dnu = 2 * nu / ((1 - nu) * (1 - 2 * nu)) if bonded else 0.0
    return P, dlogw, dlogM, ddelta, dlogZ_dnu


def fit_one(head, rows, peer):
    curves = head["curves"]
    free_nu = bool(head["free_nu"])
    free_off = bool(head["free_offsets"])
    w0, E0, nu0 = head["truth"]
    z = [rows[rows[:, 1] == j, 2] for j in range(len(curves))]
    F = [rows[rows[:, 1] == j, 3] for j in range(len(curves))]
    scale = [np.max(np.abs(f)) for f in F]
    L = [np.ptp(zz) for zz in z]
    nmat = 3 if free_nu else 2

    def unpack(x):
        w, E = math.exp(x[0]), math.exp(x[1])
        nu = 0.25 * (1 + math.tanh(x[2])) if free_nu else nu0
        return w, E, nu

    def offsets(x, j):
        if not free_off:
            return 0.0, 0.0
        return x[nmat + 2 * j] * L[j], x[nmat + 2 * j + 1] * scale[j]

    def res(x):
        w, E, nu = unpack(x)
        out = []
        for j, (k, R, b, bonded) in enumerate(curves):
            z0, F0 = offsets(x, j)
            P = curve_model(k, R, b, bonded, w, E, nu, z[j], z0)[0]
            out.append((P + F0 - F[j]) / scale[j])
        return np.concatenate(out)

    def jac(x):
        w, E, nu = unpack(x)
        blocks = []
        for j, (k, R, b, bonded) in enumerate(curves):
            z0, F0 = offsets(x, j)
            P, dlw, dlM, dd, dlZ = curve_model(k, R, b, bonded, w, E, nu, z[j], z0)
            J = np.zeros((len(z[j]), len(x)))
            J[:, 0] = dlw
            J[:, 1] = dlM
            if free_nu:
                J[:, 2] = dlM * dlZ * 0.25 * (1 - math.tanh(x[2]) ** 2)
            if free_off:
                J[:, nmat + 2 * j] = -dd * L[j]
                J[:, nmat + 2 * j + 1] = scale[j]
            blocks.append(J / scale[j])
        return np.vstack(blocks)

    def auto_start():
        """The simple automatic start described at the top."""
        lw, lE, nw, nE, offs = 0.0, 0.0, 0, 0, []
        any_fl = any(not cv[3] for cv in curves)
        for j, (k, R, b, bonded) in enumerate(curves):
            zz, ff = z[j], F[j]
            if free_off:
                F0 = ff[np.argmin(zz)]
                z0 = 0.0
            else:
                z0, F0 = head["offsets"][j]
            C1 = math.pi / b * k ** ((k + 2) / k) / (k + 2) * R ** (2 * (k - 1) / k)
            Pmin = min(float(np.min(ff)) - F0, -1e-300)
            zm = float(zz[np.argmin(ff)])
            c = 0.0
            for _ in range(2):
                d1 = max(float(np.max(zz)) - z0 + c, 1e-300)
                M = max((float(np.max(ff)) - F0) / (C1 * d1 ** (2 / k) * max(d1 - (k + 2) / k * c, 1e-300)), 1e-300)
                c = (-Pmin / (C1 * M * (2 / k) ** (2 / k))) ** (k / (k + 2))
                if free_off:
                    z0 = zm + c - 2 * c / k
            Z = (1 - nu0) ** 2 / (1 - 2 * nu0) if bonded else 1.0
            if not bonded or not any_fl:
                lE += math.log(M / Z)
                nE += 1
            lw += math.log(M * c * c / (2 * b))
            nw += 1
            offs.append((z0, F0))
        return math.exp(lw / nw), math.exp(lE / nE), offs

    def start(auto):
        if auto:
            w_s, E_s, offs = auto_start()
        else:
            w_s, E_s, offs = w0, E0, [head["offsets"].get(j, (0.0, 0.0)) for j in range(len(curves))]
        x0 = [math.log(w_s), math.log(E_s)]
        if free_nu:
            x0.append(math.atanh(4 * (0.3 if auto else nu0) - 1))
        if free_off:
            for j in range(len(curves)):
                x0 += [offs[j][0] / L[j], offs[j][1] / scale[j]]
        return np.array(x0)

    t = time.perf_counter()
    if peer == "lmfit-truth":
        x0 = start(False)
        pars = lmfit.Parameters()
        for i, v in enumerate(x0):
            pars.add("p%d" % i, value=float(v))
        out = lmfit.minimize(lambda P: res(np.array([P["p%d" % i].value for i in range(len(x0))])),
                             pars, method="leastsq")
        x = np.array([out.params["p%d" % i].value for i in range(len(x0))])
        ok = bool(out.success)
    else:
        method, auto = peer.split("-")
        x0 = start(auto == "auto")
        sol = least_squares(res, x0, jac=jac, method=method,
                            x_scale="jac" if method == "trf" else 1.0)
        x, ok = sol.x, sol.status > 0
    t = time.perf_counter() - t
    w, E, nu = unpack(x)
    return t, ok and math.isfinite(w) and math.isfinite(E), w, E, nu


PEERS = ["lm-truth", "trf-truth", "lm-auto", "trf-auto", "lmfit-truth"]


def bench_main():
    peers = [p for p in PEERS if lmfit is not None or not p.startswith("lmfit")]
    for path in sorted(glob.glob(os.path.join(sys.argv[1], "case_*_*.txt"))):
        s, n = os.path.basename(path)[5:-4].split("_")
        head, data = read_case(path)
        w0, E0, nu0 = head["truth"]
        rows = [data[data[:, 0] == seed] for seed in range(int(head["seeds"]))]
        for peer in peers:
            times, ew, eE, en, conv = [], [], [], [], 0
            for r in rows:
                with np.errstate(all="ignore"):
                    try:
                        t, ok, w, E, nu = fit_one(head, r, peer)
                    except (ValueError, ArithmeticError, np.linalg.LinAlgError):
                        t, ok, w, E, nu = float("nan"), False, 0.0, 0.0, 0.0
                times.append(t)
                if ok:
                    conv += 1
                    ew.append(w / w0 - 1)
                    eE.append(E / E0 - 1)
                    en.append(nu - nu0)
            rms = lambda v: math.sqrt(sum(e * e for e in v) / len(v)) if v else float("nan")
            print("case %s %s %.6g %.6g %.6g %s %.6g %s" % (
                s, n, 1e6 * float(np.nanmedian(times)), rms(ew), rms(eE),
                "%.6g" % rms(en) if head["free_nu"] else "nan", conv / len(times), peer))
            sys.stdout.flush()


def main():
    if len(sys.argv) < 2:
        sys.exit("usage: peer_scipy.py DIR | PLAN.csv [LAYERFIT_SECONDS]")
    if os.path.isdir(sys.argv[1]):
        bench_main()
    else:
        plan_main()


if __name__ == "__main__":
    main()
