#!/usr/bin/python3
"""Write the synthetic vendor-layout files of datasets/vendors/ (see README.md).

Every file holds one made-up adhesive contact: the half-space JKR curve of a
sphere (layerfit model --model halfspace --k 2), turned into the signals each
instrument records (piezo or height, cantilever deflection, force) with the
constants stated in datasets/vendors/README.md.  Run from the project root
after `make`:  /usr/bin/python3 datasets/vendors/make_vendors.py

The binary layouts (JPK archives, Nanoscope force files, Igor waves) are
written from their format descriptions (see the readers' comments in src/);
`--big N OUT.jpk-qi-data` writes a QI map of N curves for the reading
benchmark (tests/bench/maps.sh) instead.
"""
import bisect
import json
import math
import struct
import subprocess
import zipfile
import zlib

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


# ---------------------------------------------------------------------------
# Binary layouts

def zip_write(path, entries, zip64=False):
    """A zip archive of (name, bytes, method) entries: method 0 stored, 8
    deflated; zip64 writes every size and offset in ZIP64 records."""
    out, cd = bytearray(), bytearray()
    for name, data, method in entries:
        nb = name.encode()
        crc = zlib.crc32(data) & 0xFFFFFFFF
        if method == 8:
            c = zlib.compressobj(6, zlib.DEFLATED, -15)
            comp = c.compress(data) + c.flush()
        else:
            comp = data
        off = len(out)
        if zip64:
            lx = struct.pack("<HHQQ", 1, 16, len(data), len(comp))
            out += struct.pack("<IHHHHHIIIHH", 0x04034B50, 45, 0, method, 0, 0x21, crc,
                               0xFFFFFFFF, 0xFFFFFFFF, len(nb), len(lx)) + nb + lx + comp
            cx = struct.pack("<HHQQQ", 1, 24, len(data), len(comp), off)
            cd += struct.pack("<IHHHHHHIIIHHHHHII", 0x02014B50, 45, 45, 0, method, 0, 0x21, crc,
                              0xFFFFFFFF, 0xFFFFFFFF, len(nb), len(cx), 0, 0, 0, 0,
                              0xFFFFFFFF) + nb + cx
        else:
            out += struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, method, 0, 0x21, crc,
                               len(comp), len(data), len(nb), 0) + nb + comp
            cd += struct.pack("<IHHHHHHIIIHHHHHII", 0x02014B50, 20, 20, 0, method, 0, 0x21, crc,
                              len(comp), len(data), len(nb), 0, 0, 0, 0, 0, off) + nb
    n, cd_off = len(entries), len(out)
    out += cd
    if zip64:
        rec = len(out)
        out += struct.pack("<IQHHIIQQQQ", 0x06064B50, 44, 45, 45, 0, 0, n, n, len(cd), cd_off)
        out += struct.pack("<IIQI", 0x07064B50, 0, rec, 1)
        out += struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, 0xFFFF, 0xFFFF, 0xFFFFFFFF,
                           0xFFFFFFFF, 0)
    else:
        out += struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, n, n, len(cd), cd_off, 0)
    with open(path, "wb") as fh:
        fh.write(out)


def props(d):
    """A Java properties file (':' escaped as Java writes it)."""
    lines = ["#Thu Feb 01 10:00:00 CET 2024"]
    for k, v in d.items():
        lines.append("%s=%s" % (k, str(v).replace(":", "\\:")))
    return ("\n".join(lines) + "\n").encode("latin-1")


def be_ints(values, fmt):
    return struct.pack(">%d%s" % (len(values), fmt), *values)


def encode(values, mult, off, fmt):
    """Raw integers whose offset + mult x raw give values."""
    lim = {"i": 2 ** 31 - 1, "h": 2 ** 15 - 1}[fmt]
    raw = [int(round((v - off) / mult)) for v in values]
    assert all(-lim <= r <= lim for r in raw), "encoder range"
    return be_ints(raw, fmt)


JPK_K, JPK_SENS, JPK_Z0 = 0.032, 5.0e-8, 20e-6


def jpk_segments(d, f, seg, pause=True):
    """(style, [(delta, force)]) per segment: extend, pause, retract."""
    out = []
    for s, style in (("load", "extend"), ("hold", "pause"), ("unload", "retract")):
        pts = [(di, fi) for di, fi, si in zip(d, f, seg) if si == s]
        if pts and (pause or s != "hold"):
            out.append((style, pts))
    return out


def jpk_signals(pts):
    """vDeflection (V) and measuredHeight (m) of (delta, force) points."""
    volts = [fi / JPK_K / JPK_SENS for di, fi in pts]
    height = [-(di + JPK_Z0) - fi / JPK_K for di, fi in pts]
    return volts, height


def lcd_shared(nseg, styles, vdef_enc, height_enc, shorts=False):
    """shared-data/header.properties: what the segment headers point into."""
    p = {"force-segment-header-infos.count": nseg, "lcd-infos.count": 3}
    for i, st in enumerate(styles):
        p["force-segment-header-info.%d.type" % i] = "spm-force-segment-header"
        p["force-segment-header-info.%d.settings.style" % i] = st
        p["force-segment-header-info.%d.settings.segment-settings.style" % i] = st
    enc = "signedshort" if shorts else "signedinteger"
    # 0: vDeflection, volts -> distance (sensitivity) -> force (spring constant)
    p.update({
        "lcd-info.0.type": "integer-data", "lcd-info.0.channel.name": "vDeflection",
        "lcd-info.0.unit.unit": "V", "lcd-info.0.encoder.type": enc,
        "lcd-info.0.encoder.scaling.type": "linear",
        "lcd-info.0.encoder.scaling.style": "offsetmultiplier",
        "lcd-info.0.encoder.scaling.offset": vdef_enc[1],
        "lcd-info.0.encoder.scaling.multiplier": vdef_enc[0],
        "lcd-info.0.encoder.scaling.unit.unit": "V",
        "lcd-info.0.conversion-set.conversions.list": "distance force",
        "lcd-info.0.conversion-set.conversions.default": "force",
        "lcd-info.0.conversion-set.conversions.base": "volts",
        "lcd-info.0.conversion-set.conversion.volts.defined": "false",
        "lcd-info.0.conversion-set.conversion.distance.defined": "true",
        "lcd-info.0.conversion-set.conversion.distance.base-calibration-slot": "volts",
        "lcd-info.0.conversion-set.conversion.distance.scaling.offset": "0.0",
        "lcd-info.0.conversion-set.conversion.distance.scaling.multiplier": repr(JPK_SENS),
        "lcd-info.0.conversion-set.conversion.distance.scaling.unit.unit": "m",
        "lcd-info.0.conversion-set.conversion.force.defined": "true",
        "lcd-info.0.conversion-set.conversion.force.base-calibration-slot": "distance",
        "lcd-info.0.conversion-set.conversion.force.scaling.offset": "0.0",
        "lcd-info.0.conversion-set.conversion.force.scaling.multiplier": repr(JPK_K),
        "lcd-info.0.conversion-set.conversion.force.scaling.unit.unit": "N",
    })
    # 1: measuredHeight, absolute -> nominal (m)
    p.update({
        "lcd-info.1.type": "integer-data", "lcd-info.1.channel.name": "measuredHeight",
        "lcd-info.1.unit.unit": "m", "lcd-info.1.encoder.type": enc,
        "lcd-info.1.encoder.scaling.offset": height_enc[1],
        "lcd-info.1.encoder.scaling.multiplier": height_enc[0],
        "lcd-info.1.encoder.scaling.unit.unit": "m",
        "lcd-info.1.conversion-set.conversions.list": "nominal",
        "lcd-info.1.conversion-set.conversions.default": "nominal",
        "lcd-info.1.conversion-set.conversions.base": "absolute",
        "lcd-info.1.conversion-set.conversion.nominal.defined": "true",
        "lcd-info.1.conversion-set.conversion.nominal.base-calibration-slot": "absolute",
        "lcd-info.1.conversion-set.conversion.nominal.scaling.offset": "5.0E-6",
        "lcd-info.1.conversion-set.conversion.nominal.scaling.multiplier": "1.0",
        "lcd-info.1.conversion-set.conversion.nominal.scaling.unit.unit": "m",
    })
    # 2: height (the piezo's), a channel the reader does not use here
    p.update({
        "lcd-info.2.type": "integer-data", "lcd-info.2.channel.name": "height",
        "lcd-info.2.unit.unit": "V", "lcd-info.2.encoder.type": enc,
        "lcd-info.2.encoder.scaling.offset": "0.0", "lcd-info.2.encoder.scaling.multiplier": "1.0E-6",
        "lcd-info.2.encoder.scaling.unit.unit": "V",
        "lcd-info.2.conversion-set.conversions.base": "volts",
        "lcd-info.2.conversion-set.conversion.nominal.defined": "true",
        "lcd-info.2.conversion-set.conversion.nominal.base-calibration-slot": "volts",
        "lcd-info.2.conversion-set.conversion.nominal.scaling.offset": "0.0",
        "lcd-info.2.conversion-set.conversion.nominal.scaling.multiplier": "-1.0E-6",
        "lcd-info.2.conversion-set.conversion.nominal.scaling.unit.unit": "m",
    })
    return props(p)


def jpk_curve_entries(prefix, segs, vdef_enc, height_enc, fmt, lcd=True, defined=True):
    """The segment headers and channels of one curve under prefix."""
    entries = []
    for si, (style, pts) in enumerate(segs):
        volts, height = jpk_signals(pts)
        n = len(pts)
        h = {"force-segment-header.type": "spm-force-segment-header",
             "force-segment-header.num-points": n, "force-segment-header.duration": 0.01 * n,
             "force-segment-header.time-stamp": "2024-02-01 10:00:0%d.000 +0100" % si,
             "channels.list": "height vDeflection measuredHeight"}
        if lcd:
            h["force-segment-header.force-segment-header-info.*"] = si
            for ci, ch in enumerate(("vDeflection", "measuredHeight", "height")):
                h["channel.%s.lcd-info.*" % ch] = ci
        else:
            # the older layout: every property in the segment header
            h["force-segment-header.settings.style"] = style
            for ch, enc, unit, base, conv in (
                    ("vDeflection", vdef_enc, "V", "volts", "distance force"),
                    ("measuredHeight", height_enc, "m", "absolute", "nominal")):
                c = "channel.%s." % ch
                h[c + "data.type"] = "integer" if fmt == "i" else "short"
                h[c + "data.encoder.type"] = "signedinteger" if fmt == "i" else "signedshort"
                h[c + "data.encoder.scaling.offset"] = enc[1]
                h[c + "data.encoder.scaling.multiplier"] = enc[0]
                h[c + "data.encoder.scaling.unit.unit"] = unit
                h[c + "conversion-set.conversions.base"] = base
                h[c + "conversion-set.conversions.list"] = conv
                if ch == "vDeflection":
                    for slot, parent, mult, u in (("distance", "volts", JPK_SENS, "m"),
                                                  ("force", "distance", JPK_K, "N")):
                        cs = c + "conversion-set.conversion.%s." % slot
                        h[cs + "defined"] = "true" if defined else "false"
                        if defined:
                            h[cs + "base-calibration-slot"] = parent
                            h[cs + "scaling.offset"] = "0.0"
                            h[cs + "scaling.multiplier"] = repr(mult)
                            h[cs + "scaling.unit.unit"] = u
                else:
                    cs = c + "conversion-set.conversion.nominal."
                    h[cs + "defined"] = "true"
                    h[cs + "base-calibration-slot"] = "absolute"
                    h[cs + "scaling.offset"] = "5.0E-6"
                    h[cs + "scaling.multiplier"] = "1.0"
                    h[cs + "scaling.unit.unit"] = "m"
        for ch in ("height", "vDeflection", "measuredHeight"):
            h["channel.%s.data.file.name" % ch] = "channels/%s.dat" % ch
            h["channel.%s.data.file.format" % ch] = "raw"
            h["channel.%s.data.num-points" % ch] = n
        base = "%ssegments/%d/" % (prefix, si)
        entries.append((base + "segment-header.properties", props(h), 8))
        entries.append((base + "channels/height.dat",
                        encode([-(d + JPK_Z0) * 1e6 for d, f in pts], 1e-6 if fmt == "i" else 1e-3, 0.0, fmt)
                        if fmt == "i" else encode([0.0] * n, 1.0, 0.0, fmt), 8))
        entries.append((base + "channels/vDeflection.dat", encode(volts, vdef_enc[0], vdef_enc[1], fmt), 8))
        entries.append((base + "channels/measuredHeight.dat",
                        encode([hh - 5e-6 for hh in height], height_enc[0], height_enc[1], fmt), 8))
    return entries


def series_header(kind, x, y, index):
    return props({"type": kind, "%s.force-segments.count" % kind: 3,
                  "%s.header.type" % kind: "xy-position-force-scan-series-header",
                  "%s.header.position.x" % kind: repr(x), "%s.header.position.y" % kind: repr(y),
                  "%s.header.position-index" % kind: index,
                  "%s.description.instrument" % kind: "synthetic",
                  "%s.description.source-software" % kind: "layerfit make_vendors.py"})


def jpk_force(name, defined=True):
    """One curve (.jpk-force): extend, pause, retract; newer layout (lcd-info)."""
    d, f, seg = profile()
    segs = jpk_segments(d, f, seg)
    vdef_enc, height_enc = (2e-7, 0.0), (2e-14, -2.0e-5)
    entries = [("header.properties", series_header("force-scan-series", 1.5e-5, -2.5e-5, 7), 8)]
    if defined:
        entries += jpk_curve_entries("", segs, vdef_enc, height_enc, "i")
        entries.append(("shared-data/header.properties",
                        lcd_shared(3, [st for st, p in segs], vdef_enc, height_enc), 8))
    else:   # a calibration curve: no distance or force conversion (older layout)
        entries += jpk_curve_entries("", segs, vdef_enc, height_enc, "i", lcd=False,
                                     defined=False)
    zip_write(OUT + name, entries)


MAP_W = ("0.8mJ/m2", "1mJ/m2", "1.25mJ/m2")     # w along the grid's columns


def jpk_map():
    """A 3 x 2 force map (.jpk-force-map), rows walked back and forth; w
    grows along x; the older layout (every property in the segment header)."""
    il, jl, pitch, x0, y0 = 3, 2, 10e-6, 100e-6, 200e-6
    entries = [("header.properties", props({
        "jpk-data-file": "spm-force-scan-map-file", "type": "force-scan-map",
        "force-scan-map.indexes.type": "range", "force-scan-map.indexes.min": 0,
        "force-scan-map.indexes.max": il * jl - 1,
        "force-scan-map.description.instrument": "synthetic",
        "force-scan-map.position-pattern.type": "grid-position-pattern",
        "force-scan-map.position-pattern.back-and-forth": "true",
        "force-scan-map.position-pattern.grid.xcenter": repr(x0 + pitch * (il - 1) / 2),
        "force-scan-map.position-pattern.grid.ycenter": repr(y0 + pitch * (jl - 1) / 2),
        "force-scan-map.position-pattern.grid.ulength": repr(pitch * il),
        "force-scan-map.position-pattern.grid.vlength": repr(pitch * jl),
        "force-scan-map.position-pattern.grid.ilength": il,
        "force-scan-map.position-pattern.grid.jlength": jl}), 8)]
    for k in range(il * jl):
        j, i = k // il, k % il
        if j % 2 == 1:
            i = il - 1 - i
        d, f, seg = profile(w=MAP_W[i], nhold=0)
        segs = jpk_segments(d, f, seg, pause=False)
        entries.append(("index/%d/header.properties" % k,
                        series_header("force-scan-series", x0 + i * pitch, y0 + j * pitch, k), 8))
        entries += jpk_curve_entries("index/%d/" % k, segs, (2e-7, 0.0), (2e-14, -2.0e-5), "i",
                                     lcd=False)
    zip_write(OUT + "jpk_map.jpk-force-map", entries)


def qi_map(path, n, side, points=40, zip64=True, variants=0):
    """A QI map (.jpk-qi-data) of n curves on a side x side grid, 16-bit
    encoders, stored and deflated entries, ZIP64 records throughout;
    variants > 0: the curves cycle through that many copies of the curve
    with seeded noise on the force (0.2% of its range), every entry
    deflated, as JPK writes them (for the reading benchmark)."""
    import random
    d, f, seg = profile(n=points, nhold=0)
    segs = jpk_segments(d, f, seg, pause=False)
    vdef_enc, height_enc = (0.01, 0.0), (5e-10, -3.3e-5)
    entries = [("header.properties", props({
        "jpk-data-file": "spm-quantitative-image-data-file", "type": "quantitative-imaging-map",
        "quantitative-imaging-map.description.instrument": "synthetic",
        "quantitative-imaging-map.position-pattern.type": "grid-position-pattern",
        "quantitative-imaging-map.position-pattern.back-and-forth": "false",
        "quantitative-imaging-map.position-pattern.grid.xcenter": "0.0",
        "quantitative-imaging-map.position-pattern.grid.ycenter": "0.0",
        "quantitative-imaging-map.position-pattern.grid.ulength": "1.6E-5",
        "quantitative-imaging-map.position-pattern.grid.vlength": "1.6E-5",
        "quantitative-imaging-map.position-pattern.grid.ilength": side,
        "quantitative-imaging-map.position-pattern.grid.jlength": side}), 8),
        ("shared-data/header.properties",
         lcd_shared(2, [st for st, p in segs], vdef_enc, height_enc, shorts=True), 0)]
    if variants > 0:
        rng = random.Random(36)
        span = max(f) - min(f)
        curves = []
        for v in range(variants):
            noisy = [(st, [(di, fi + rng.gauss(0, 0.002 * span)) for di, fi in pts])
                     for st, pts in segs]
            curves.append(jpk_curve_entries("", noisy, vdef_enc, height_enc, "h"))
    else:
        curves = [[(name, data, 0 if "channels" in name else method)
                   for name, data, method in jpk_curve_entries("", segs, vdef_enc, height_enc, "h")]]
    for k in range(n):
        x, y = -8e-6 + (k % side + 0.5) * 1.6e-5 / side, -8e-6 + (k // side + 0.5) * 1.6e-5 / side
        entries.append(("index/%d/header.properties" % k,
                        series_header("quantitative-imaging-series", x, y, k), 8))
        entries += [("index/%d/%s" % (k, name), data, method)
                    for name, data, method in curves[k % len(curves)]]
    zip_write(path, entries, zip64=zip64)


def jpk_all():
    jpk_force("jpk_force.jpk-force")
    jpk_force("jpk_calibration.jpk-force", defined=False)
    jpk_map()
    qi_map(OUT + "jpk_qi.jpk-qi-data", 4, 16)


# --- Bruker Nanoscope ---------------------------------------------------------

NS_K, NS_SENS, NS_ZSENS, NS_HARD, NS_ZHARD = 2.0, 40e-9, 20e-9, 0.000375, 0.006713765
NS_TABLES = {}


def ns_raw(z, z0, w):
    """The raw deflection at piezo Z: the separation solved from Z =
    separation + z0 + F/k with F from the unload branch (both segments; a
    test of the reader), the table of w computed once."""
    if w not in NS_TABLES:
        NS_TABLES[w] = model("8um", w, "25kPa", "-2um", "3um", 4000, "unload")
    dd, ff = NS_TABLES[w]

    def force(delta):
        if delta <= dd[0]:
            return ff[0]
        if delta >= dd[-1]:
            return ff[-1]
        i = bisect.bisect_right(dd, delta) - 1
        t = (delta - dd[i]) / (dd[i + 1] - dd[i])
        return ff[i] + t * (ff[i + 1] - ff[i])

    delta = z - z0
    for _ in range(200):                # delta = z - z0 - F(delta)/k, a contraction here
        delta = z - z0 - force(delta) / NS_K
    return int(round(force(delta) / NS_K / NS_SENS / NS_HARD))


def ns_curve(npts, ramp_v, w="1mJ/m2", z0=0.5e-6):
    """Deflection raw values of one curve, approach then retract, both
    stored from the most extended Z back: Z = (npts - 1 - k) x step (into
    the sample)."""
    step = ramp_v * NS_ZSENS / npts
    return [ns_raw((npts - 1 - k) * step, z0, w) for k in range(npts)] * 2


def nanoscope(name, fv):
    npts, ramp_v, side = 64, 150.0, 3
    bpv = 4 if fv else 2
    ncurves = side * side if fv else 1
    data = bytearray()
    for c in range(ncurves):
        raw = ns_curve(npts, ramp_v, w=MAP_W[c % side] if fv else "1mJ/m2")
        data += struct.pack("<%d%s" % (len(raw), "i" if bpv == 4 else "h"), *raw)
    offset = 8192
    lines = [
        "\\*Force file list", "\\Version: 0x09200000", "\\Date: 10:00:00 AM Thu Feb 01 2024",
        "\\Data length: %d" % offset,
        "\\*Equipment list", "\\Microscope: synthetic",
        "\\*Scanner list", "\\@Sens. Zsens: V %.5f nm/V" % (NS_ZSENS * 1e9),
        "\\*Ciao scan list", "\\Operating mode: %s" % ("Force Volume" if fv else "Force"),
        "\\Scan Size: 3000 nm", "\\X Offset: 0 nm", "\\Y Offset: 0 nm",
        "\\Samps/line: %d" % (side if fv else 256), "\\Lines: %d" % (side if fv else 256),
        "\\PeakForce Capture: Never",
        "\\@Sens. DeflSens: V %.5f nm/V" % (NS_SENS * 1e9),
        "\\*Ciao force list", "\\Samps/line: %d %d" % (npts, npts),
        "\\@4:Ramp size Zsweep: V [Sens. Zsens] (%.9f V/LSB) %.4f V" % (NS_ZHARD, ramp_v),
        "\\Deflection Sensitivity Correction: 1",
        "\\*Ciao force image list", "\\Data offset: %d" % offset, "\\Data length: %d" % len(data),
        "\\Bytes/pixel: 2", "\\Samps/line: %d %d" % (npts, npts),
        "\\Spring Constant: %g" % NS_K,
        "\\@4:Image Data: S [DeflectionError] \"Deflection Error\"",
        "\\@4:Z scale: V [Sens. DeflSens] (%.10f V/LSB) 2.500000 V" % NS_HARD,
        "\\@4:Ramp Size: V [Sens. Zsens] (%.9f V/LSB) %.4f V" % (NS_ZHARD, ramp_v),
        "\\*File list end"]
    head = ("\r\n".join(lines) + "\r\n").encode("latin-1") + b"\x1a"
    assert len(head) <= offset
    with open(OUT + name, "wb") as fh:
        fh.write(head + b"\0" * (offset - len(head)) + data)


def pfc_curve(n, amp, sync, w, z0=0.5e-6):
    """Deflection raw values of one PeakForce Capture curve: 2n samples of
    one period in time order, Z = amp (1 - cos(pi u / n)) with u = (k - sync
    + n) mod 2n (the peak at sample sync); stored as Nanoscope stores them
    (the first n backwards), the first sample in time replaced by the
    marker -32768."""
    timed = [ns_raw(amp * (1 - math.cos(math.pi * ((k - sync + n) % (2 * n)) / n)), z0, w)
             for k in range(2 * n)]
    timed[0] = -32768
    return timed[n - 1::-1] + timed[n:]


def nanoscope_pfc(name):
    """A PeakForce Capture map of 2 x 2 curves, 64 + 64 samples, amplitude
    1500 nm, Sync Distance QNM 171.3 of 256 Sample Points: the peak at
    sample 85.65 of 128 (a decoy Sync Distance that must not be used)."""
    n, side, amp_nm, sync_qnm, points = 64, 2, 1500.0, 171.3, 256
    sync = sync_qnm * 2 * n / points
    data = bytearray()
    for c in range(side * side):
        raw = pfc_curve(n, amp_nm * 1e-9, sync, MAP_W[c % side])
        data += struct.pack("<%dh" % len(raw), *raw)
    offset = 8192
    lines = [
        "\\*Force file list", "\\Version: 0x09400000", "\\Date: 10:00:00 AM Thu Feb 01 2024",
        "\\Data length: %d" % offset,
        "\\*Equipment list", "\\Microscope: synthetic",
        "\\*Ciao scan list", "\\Operating mode: PeakForce Capture",
        "\\Scan Size: 2000 nm", "\\X Offset: 0 nm", "\\Y Offset: 0 nm",
        "\\Samps/line: %d" % side, "\\Lines: %d" % side,
        "\\PeakForce Capture: Allow", "\\Sample Points: %d" % points,
        "\\Sync Distance: 137.833", "\\Sync Distance New: 99.5",
        "\\Sync Distance QNM: %g" % sync_qnm, "\\Auto Sync Distance QNM: On",
        "\\Peak Force Amplitude: %g" % amp_nm, "\\PFT Freq: 2.00000 KHz",
        "\\@Sens. DeflSens: V %.5f nm/V" % (NS_SENS * 1e9),
        "\\*Ciao force list", "\\force/line: %d" % side,
        "\\*Ciao force image list", "\\Data offset: %d" % offset, "\\Data length: %d" % len(data),
        "\\Bytes/pixel: 2", "\\Samps/line: %d %d" % (n, n),
        "\\Spring Constant: %g" % NS_K,
        "\\@4:Image Data: S [DeflectionError] \"Deflection Error\"",
        "\\@4:Z scale: V [Sens. DeflSens] (%.10f V/LSB) 2.500000 V" % NS_HARD,
        "\\*File list end"]
    head = ("\r\n".join(lines) + "\r\n").encode("latin-1") + b"\x1a"
    assert len(head) <= offset
    with open(OUT + name, "wb") as fh:
        fh.write(head + b"\0" * (offset - len(head)) + data)


# --- Asylum Research Igor binary wave ----------------------------------------

IGOR_K, IGOR_Z0 = 0.1, 1.0e-6


def igor(name, little, double, labels, with_indexes):
    d, f, seg = profile(nhold=0)
    n = len(d)
    defl = [fi / IGOR_K for fi in f]
    zs = [di + IGOR_Z0 + de for di, de in zip(d, defl)]
    raw = [z * 1.02 for z in zs]
    cols = {"Raw": raw, "Height": raw, "Defl": defl, "Deflection": defl, "ZSnsr": zs,
            "ZSensor": zs}
    e = "<" if little else ">"
    t, size = (4, 8) if double else (2, 4)
    values = [v for lab in labels for v in cols[lab]]
    data = struct.pack(e + "%d%s" % (len(values), "d" if double else "f"), *values)
    note = ["VerDate:150078", "SpringConstant: %g" % IGOR_K, "InvOLS: 6e-08",
            "XLVDT:%r" % 3.5e-6, "YLVDT:%r" % -2.25e-6, "MicroscopeModel:synthetic",
            "Date:2024-02-01", "Time:10:00:00 AM"]
    if with_indexes:
        top = len(seg) - seg[::-1].index("load") - 1
        note += ["Indexes: 0,%d,%d" % (top + 1, n - 1), "Direction: NaN,1,-1,"]
    note = "\r".join(note).encode("latin-1")
    w = 32
    lab = b"".join(x.encode().ljust(w, b"\0") for x in [""] + labels)
    wave = bytearray(320)
    struct.pack_into(e + "i", wave, 12, n * len(labels))
    struct.pack_into(e + "h", wave, 16, t)
    wave[28:28 + len(b"synthetic_force")] = b"synthetic_force"
    struct.pack_into(e + "4i", wave, 68, n, len(labels), 0, 0)
    struct.pack_into(e + "4d", wave, 84, 1e-3, 1.0, 1.0, 1.0)
    wave[148:149] = b"m"
    binh = bytearray(64)
    struct.pack_into(e + "h", binh, 0, 5)
    struct.pack_into(e + "iiii", binh, 4, 320 + len(data), 0, len(note), 0)
    struct.pack_into(e + "4i", binh, 36, 0, len(lab), 0, 0)
    head = binh + wave
    words = struct.unpack(e + "192h", bytes(head))
    struct.pack_into(e + "h", binh, 2, (-(sum(words)) + 2 ** 15) % 2 ** 16 - 2 ** 15)
    with open(OUT + name, "wb") as fh:
        fh.write(binh + wave + data + note + lab)


# --- AFM Workshop mapping zip, afmformats .tab, Hysitron .hld ---------------

def workshop_map():
    k, gain, z0 = 0.032, 2.5, 4000e-9
    entries = []
    for p in range(4):
        i, j = p % 2, p // 2
        d, f, seg = profile(w=MAP_W[i], nhold=0)
        n = len(d) // 2
        head = ("Force-Distance Curve\r\nFile Format:\t3\r\n\r\nDate:\tThursday, February 1, 2024\r\n"
                "Time:\t10:00:%02d AM\r\nMode:\tMapping\r\nPoint:\t%d\r\nX, um:\t%.6f\r\n"
                "Y, um:\t%.6f\r\nLight Lever Gain, mV/nm:\t%.6f\r\nForce Constant, nN/nm:\t%.6f\r\n\r\n"
                "Extend Z-Sense(nm),Extend T-B(V),Retract Z-Sense(nm),Retract T-B(V)\r\n"
                % (p, p + 1, 5.0 + 10.0 * i, 7.5 + 10.0 * j, gain, k))
        rows = []
        for r in range(n):
            cells = []
            for q in (r, n + r):
                defl = f[q] / k
                cells += ["%.4f" % ((d[q] + z0 + defl) * 1e9), "%.6f" % (defl * 1e9 * gain * 1e-3)]
            rows.append(",".join(cells) + "\r\n")
        entries.append(("map/force-map_%02d.csv" % p, (head + "".join(rows)).encode(), 8))
    zip_write(OUT + "workshop_map.zip", entries)


def tab():
    k, z0 = 0.032, 20e-6
    d, f, seg = profile(nhold=0)
    meta = {"duration": 0.8, "enum": 0, "imaging mode": "force-distance",
            "instrument": "synthetic", "point count": len(d), "position x": 1.25e-05,
            "position y": -2.5e-05, "software": "layerfit make_vendors.py",
            "spring constant": k, "sensitivity": 5e-08}
    lines = ["# afmformats 0.13.3", "#", "# BEGIN METADATA"]
    lines += ["# " + x for x in json.dumps(meta, indent=2, sort_keys=True).split("\n")]
    lines += ["# END METADATA", "#"]
    rows = []
    for i, (di, fi, si) in enumerate(zip(d, f, seg)):
        h = -(di + z0) - fi / k
        rows.append("%.10e\t%.10e\t%.10e\t%s\t%.4f" % (fi, h, h * 0.99, si == "unload", 0.01 * i))
    # afmformats' writer leaves out the line break after the column names
    text = "\n".join(lines) + "\n# force\theight (measured)\theight (piezo)\tsegment\ttime"
    text += "\n".join(rows) + "\n"
    write("afmformats.tab", text)


def hld():
    d, f, seg = profile(R="5um", w="50mJ/m2", E="2GPa", lo="-10nm", hi="60nm", n=30, nhold=12)
    nload, nhold = seg.count("load"), seg.count("hold")
    peak = f[nload - 1] * 1e6
    head = ["File Version: Hysitron TriboScan synthetic", "Test Type: Indentation",
            "Time Stamp: Thu Feb 01 10:00:00 2024", "Contact Threshold: 2 \u00b5N",
            "Number of Segments: 3"]
    for i, (n, b, e) in enumerate(((nload, 0.0, peak), (nhold, peak, peak), (len(d) - nload - nhold, peak, 0.0))):
        head += ["Segment Number: %d" % i, "Segment Type: 0 LINEAR",
                 "Segment Begin Demand: %.4f \u00b5N" % b, "Segment End Demand: %.4f \u00b5N" % e,
                 "Segment Points: %d" % n]
    head += ["Sample Approach Data Points: 4", "Time_s\tMotorDisp_mm\tPiezo Extension_nm"]
    head += ["%.3f\t0.000000\t%.3f" % (0.1 * i, -5.0 + i) for i in range(4)]
    head += ["Drift Measurement Data Points: 5", "Time_s\tDisp_nm"]
    head += ["%.3f\t%.3f" % (0.5 * i, 0.01 * i) for i in range(5)]
    head += ["Test Data Points: %d" % len(d),
             "Time_s\tDisp_nm\tForce_\u00b5N\tLoadCell_nm\tPiezoDisp_nm\tDisp_V\tForce_V\tPiezo_LowV"]
    for i, (di, fi) in enumerate(zip(d, f)):
        head.append("%.6f\t%.6f\t%.6f\t%.6f\t%.6f\t%.6f\t%.6f\t%.6f" % (
            0.05 * i, di * 1e9, fi * 1e6, 0.0, di * 1e9, -di * 2e5, fi * 1e6 / 900, 0.0))
    write("hysitron.hld", "\r\n".join(head) + "\r\n", latin1=True)


def big_qi(n, path):
    side = 1
    while side * side < n:
        side += 1
    qi_map(path, n, side, points=300, variants=64)


if __name__ == "__main__":
    import sys
    if len(sys.argv) == 4 and sys.argv[1] == "--big":
        big_qi(int(sys.argv[2]), sys.argv[3])
        sys.exit(0)
    chiaro()
    jpk("jpk_force.txt", "N")
    jpk("jpk_volts.txt", "V")
    workshop("workshop_tb.csv", False)
    workshop("workshop_force.csv", True)
    ntmdt()
    hysitron()
    text()
    jpk_all()
    nanoscope("nanoscope.spm", False)
    nanoscope("nanoscope_fv.spm", True)
    nanoscope_pfc("nanoscope.pfc")
    igor("igor.ibw", True, False, ["Raw", "Defl", "ZSnsr"], True)
    igor("igor_be.ibw", False, True, ["Height", "Deflection", "ZSensor"], False)
    workshop_map()
    tab()
    hld()
