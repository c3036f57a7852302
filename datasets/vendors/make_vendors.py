#!/usr/bin/python3
"""Write the synthetic vendor-layout files of datasets/vendors/ (see README.md).

Every file holds one made-up adhesive contact: the half-space JKR curve of a
sphere (layerfit model --model halfspace --k 2), turned into the signals each
instrument records (piezo or height, cantilever deflection, force) with the
constants stated in datasets/vendors/README.md.  Run from the project root
after `make`:  /usr/bin/python3 datasets/vendors/make_vendors.py
"""
import bisect
import subprocess

LAYERFIT = "build/layerfit"
OUT = "datasets/vendors/"


def model(R, w, E, lo, hi, n, branch):
    out = subprocess.run([LAYERFIT, "model", "--model", "halfspace", "--k", "2", "--R", R,
                          "--b", "1um", "--w", w, "--E", E, "--from", lo, "--to", hi,
                          "--points", str(n), "--branch", branch],
                         check=True, capture_output=True, text=True).stdout.split("\n")[1:]
    rows = [line.split(",") for line in out if line]
    return [float(r[0]) for r in rows], [float(r[1]) for r in rows]


def profile(R="8um", w="1mJ/m2", E="25kPa", lo="-2um", hi="3um", n=40, nhold=12):
    """delta (m), force (N), segment of approach, hold, retract, in time order."""
    dl, fl = model(R, w, E, lo, hi, n, "load")
    du, fu = model(R, w, E, lo, hi, n, "unload")
    du.reverse()
    fu.reverse()
    d = dl + [dl[-1]] * nhold + du
    f = fl + [fl[-1]] * nhold + fu
    seg = ["load"] * n + ["hold"] * nhold + ["unload"] * n
    return d, f, seg


def write(name, text, latin1=False):
    with open(OUT + name, "wb") as fh:
        fh.write(text.encode("latin-1" if latin1 else "utf-8"))


def chiaro():
    k, z0 = 0.032, 1500e-9
    d, f, seg = profile()
    head = ("Date\t01/02/2024\tTime\t10:00\tStatus\tOK\r\n"
            "synthetic layerfit test\r\n"
            "Scan (#)\t1\tX (#)\t1\tY (#)\t1\tIndentation (#)\t1\n\r"
            "k (N/m)\t0.032\r\n"
            "Tip radius (um)\t8.000\r\n"
            "Calibration factor\t2.000\r\n\r\n"
            "Max load (\u00b5N)\t0.050\n\n"
            "Piezo speed  (\u00b5m/s)\t2.000\r\n"
            "E[eff] (Pa)\t25000.000\r\n"
            "Comment: \r\n\r\n"
            "Time (s)\tLoad (uN)\tIndentation (nm)\tCantilever (nm)\tPiezo (nm)\tAuxiliary\r\n")
    rows = []
    for i, (di, fi) in enumerate(zip(d, f)):
        cant = fi / k
        piezo = di + z0 + cant
        rows.append("%.6f\t%.9f\t%.6f\t%.6f\t%.6f\t%.6f\r\n" % (
            0.01 * i, fi * 1e6, max(di, 0.0) * 1e9, cant * 1e9, piezo * 1e9, -0.003))
    write("chiaro.txt", head + "".join(rows), latin1=True)


def jpk(name, unit):
    k, sens, z0 = 0.032, 5.0e-8, 20e-6
    d, f, seg = profile()
    parts = ["# TEXT EXPORT\r\n# data-description.instrument: synthetic\r\n"]
    names = {"load": "extend", "hold": "pause", "unload": "retract"}
    i = 0
    t = 0.0
    for idx, s in enumerate(["load", "hold", "unload"]):
        parts.append("#\r\n# index: 0\r\n# segmentIndex: %d\r\n# segment: %s\r\n" % (idx, names[s]))
        if s == "hold":
            parts.append("# columns: measuredHeight vDeflection seriesTime time\r\n")
        else:
            parts.append("# columns: height measuredHeight vDeflection seriesTime time\r\n")
        parts.append("# sensitivity: 5.0E-8\r\n# springConstant: 0.032\r\n")
        parts.append("# units: %s\r\n#\r\n" % ("m %s s s" % unit if s == "hold" else "m m %s s s" % unit))
        j = 0
        while i < len(d) and seg[i] == s:
            defl = f[i] / k                          # m, positive when pushing
            height = -(d[i] + z0) - defl             # separation -(height + defl)
            v = f[i] if unit == "N" else defl / sens
            t += 0.01
            cells = ["%.8E" % height, "%.8E" % v, "%.4f" % t, "%.4f" % (0.01 * j)]
            if s != "hold":
                cells.insert(0, "%.8E" % (height * 0.98))
            parts.append(" ".join(cells) + "\r\n")
            i += 1
            j += 1
        parts.append("\r\n")
    write(name, "".join(parts))


def workshop(name, force):
    k, gain, z0 = 0.032, 2.5, 4000e-9     # gain in mV/nm
    d, f, seg = profile(nhold=0)
    n = len(d) // 2
    head = ("Force-Distance Curve\r\nSoftware Version:\t4.0.0.62\r\n\r\n"
            "Date:\t1 February 2024\r\nTime:\t10:00:00\r\nMode:\tSingle\r\nPoint:\t1\r\n"
            "X, um:\t25.000000\r\nY, um:\t25.000000\r\n")
    if not force:
        head += "Light Lever Gain, mV/nm:\t%.6f\r\nForce Constant, nN/nm:\t%.6f\r\n" % (gain, k)
    head += "Hold at Surface:\tNo\r\n\r\n"
    sig = "Force(nN)" if force else "T-B(V)"
    head += "Extend Z-Sense(nm),Extend %s,Retract Z-Sense(nm),Retract %s\r\n" % (sig, sig)
    rows = []
    for i in range(n):
        cells = []
        for j in (i, n + i):
            defl = f[j] / k
            z = d[j] + z0 + defl
            cells += ["%.4f" % (z * 1e9), "%.6f" % (f[j] * 1e9 if force else defl * 1e9 * gain * 1e-3)]
        rows.append(",".join(cells) + "\r\n")
    write(name, head + "".join(rows) + "\r\n\r\n")


def ntmdt():
    k, sens, z0 = 1.0, 61e-9 / 1e-9, 2000e-9    # 1 N/m; 61 nm/nA in m/A
    dd, ff = model("8um", "1mJ/m2", "25kPa", "-2um", "3um", 2000, "unload")
    dl, fl = model("8um", "1mJ/m2", "25kPa", "-2um", "3um", 2000, "load")

    def solve(h, dgrid, fgrid):
        # delta with delta = -(h + F(delta)/k) - z0, by bisection on the grid
        lo, hi = 0, len(dgrid) - 1
        g = lambda m: dgrid[m] + (h + fgrid[m] / k) + z0
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if g(mid) > 0:
                hi = mid
            else:
                lo = mid
        return fgrid[lo]

    rows = []
    for i in range(40):                      # deepest height first
        h = -(3.2e-6 + z0) + i * (5e-6 / 39)
        fa, fr = solve(h, dl, fl), solve(h, dd, ff)
        cells = ["%.4f" % (h * 1e9), "%.4f" % (fa / k / sens * 1e9), "%.4f" % (fr / k / sens * 1e9)]
        if i < 3:                            # Nova's padding: a copied value
            cells[1] = cells[2] = "%.4f" % 1.5
        rows.append("\t".join(c.replace(".", ",") for c in cells) + "\r\n")
    write("ntmdt.txt", "".join(rows))


def hysitron():
    d, f, seg = profile(R="5um", w="50mJ/m2", E="2GPa", lo="-10nm", hi="60nm", n=30, nhold=0)
    rows = ["Thu Feb  1 10:00:00 2024\n", "\n", "Number of Points = %d\n" % (len(d) + 12),
            "Depth (nm)\tLoad (\u00b5N)\tTime (s)\tDepth (V)\tLoad (V)\n"]
    t = 0.0
    top = d.index(max(d))
    for i, (di, fi) in enumerate(zip(d, f)):
        reps = 13 if i == top else 1         # a hold at the peak load, creeping
        for r in range(reps):
            depth = di + r * 0.05e-9
            rows.append("%.6f\t%.6f\t%.6f\t%.6f\t%.6f\n" % (
                depth * 1e9, fi * 1e6, t, -depth * 2e5, fi * 1e6 / 900))
            t += 0.05
    write("hysitron.txt", "".join(rows), latin1=True)


def text():
    d, f, seg = profile(nhold=0)
    rows = ["Exported by a synthetic instrument\n", "operator: nobody\n", "\n",
            "time_s depth_nm force_nN\n"]
    for i, (di, fi) in enumerate(zip(d, f)):
        rows.append(("%.3f %.4f %.5f\n" % (0.1 * i, di * 1e9, fi * 1e9)).replace(".", ","))
    write("text_space_comma.txt", "".join(rows))


chiaro()
jpk("jpk_force.txt", "N")
jpk("jpk_volts.txt", "V")
workshop("workshop_tb.csv", False)
workshop("workshop_force.csv", True)
ntmdt()
hysitron()
text()
