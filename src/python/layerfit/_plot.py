"""plot(result): the figures of `layerfit fit --plot` drawn with matplotlib.

The panels are the command's: an overview of every curve on shared axes
(indentation delta = z - z0 against force - F0), then per curve the
measured points with the fitted model -- solid where it is stable under
force control, dashed where it is not, the baseline out of contact and the
pull-off point (after the seed paper's Fig. 3) -- over its residuals, and
the part around pull-off.  What is drawn comes from the library
(lf_fit_job_figure: the model on a grid, the offsets, the pull-off), as
the command's figures take it.
"""
import math

PALETTE = ["#1b6ca8", "#c0392b", "#27ae60", "#8e44ad", "#d35400", "#2c3e50", "#16a085",
           "#7f8c8d"]
GRID = 400


def _force_unit(fmax):
    for scale, name in ((1.0, "N"), (1e-3, "mN"), (1e-6, "µN"), (1e-9, "nN")):
        if fmax >= scale:
            return scale, name
    return 1e-12, "pN"


def _human(x, unit):
    """A value with an SI prefix ("12.3 mJ/m^2"); "not determined" for None."""
    if x is None or x != x:
        return "not determined"
    if x == 0 or math.isinf(x):
        return "%s %s" % ("0" if x == 0 else "infinite", unit)
    for scale, p in ((1e12, "T"), (1e9, "G"), (1e6, "M"), (1e3, "k"), (1, ""), (1e-3, "m"),
                     (1e-6, "µ"), (1e-9, "n"), (1e-12, "p")):
        if abs(x) >= scale * 0.9995:
            break
    return "%.4g %s%s" % (x / scale, p, unit)


def _runs(z, F, cls, want):
    """The model's points of class `want` as contiguous runs (neighbours
    shared, so that the parts join)."""
    runs, cur = [], None
    n = len(z)
    for i in range(n):
        here = cls[i] == want or (i > 0 and cls[i - 1] == want) or \
            (i + 1 < n and cls[i + 1] == want)
        if here:
            if cur is None:
                cur = ([], [])
                runs.append(cur)
            cur[0].append(z[i])
            cur[1].append(F[i])
        else:
            cur = None
    return runs


def _layers(ax, z, F, fig, fs, color, xscale=1e9, dz=0.0, dF=0.0, titles=True):
    for want, style, label in ((1, "-", "fit, stable"), (2, "--", "fit, unstable"),
                               (0, ":", "out of contact")):
        for k, (xs, ys) in enumerate(_runs(z, F, fig["cls"], want)):
            ax.plot([(x - dz) * xscale for x in xs], [(y - dF) / fs for y in ys], style,
                    color=color if want else "#444444", lw=2.0,
                    label=label if titles and k == 0 else None)


def plot(result, curves=True, show=False):
    """Draw the figures of result (a layerfit.Result); returns the list of
    matplotlib figures: the overview, then one per curve (curves=False:
    the overview alone)."""
    try:
        import matplotlib
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError("layerfit.plot needs matplotlib (Debian: python3-matplotlib)") from e
    figs = []
    w, E = result.w.value, result.Estar.value
    data = [result.figure_data(i, GRID) for i in range(len(result.curves))]

    # the overview: every curve against indentation, force less its offset
    fpeak = max((abs(f - d["F0"]) for c, d in zip(result.curves, data) for f in c.force),
                default=1.0)
    fs, fu = _force_unit(fpeak)
    fig, ax = plt.subplots(figsize=(10, 7))
    for j, (c, d) in enumerate(zip(result.curves, data)):
        col = PALETTE[j % len(PALETTE)]
        ax.plot([(z - d["z0"]) * 1e9 for z in c.depth], [(f - d["F0"]) / fs for f in c.force],
                "o", mfc="none", ms=3, color=col,
                label="%d: k = %g, %s" % (j + 1, c.info["k"], _human(c.info["R"], "m")))
        if d["have"]:
            for want, style in ((1, "-"), (2, "--")):
                for xs, ys in _runs(d["z"], d["F"], d["cls"], want):
                    ax.plot([(x - d["z0"]) * 1e9 for x in xs], [(y - d["F0"]) / fs for y in ys],
                            style, color=col, lw=2.5)
        if d["pulloff"] is not None:
            ax.plot([(d["pulloff"][0] - d["z0"]) * 1e9], [(d["pulloff"][1] - d["F0"]) / fs],
                    "o", ms=7, color=col)
    n = len(result.curves)
    ax.set_title("%d curve%s, w = %s, E* = %s, %s model" % (
        n, "" if n == 1 else "s", _human(w, "J/m²"), _human(E, "Pa"), result.model))
    ax.set_xlabel("indentation δ = z - z₀ (nm)")
    ax.set_ylabel("force - F₀ (%s)" % fu)
    ax.grid(color="#e0e0e0")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    figs.append(fig)

    for j, (c, d) in enumerate(zip(result.curves, data)) if curves else ():
        info = c.info
        fs, fu = _force_unit(max((abs(f) for f in c.force), default=1.0))
        layer = "half-space" if info["b"] is None else "b = %s, %s" % (
            _human(info["b"], "m"), info["interface"])
        name = (c.file or "curve").rsplit("/", 1)[-1]
        fig = plt.figure(figsize=(12, 7.6))
        fig.suptitle("%s: k = %g, R = %s, %s;  w = %s, E* = %s" % (
            name, info["k"], _human(info["R"], "m"), layer, _human(w, "J/m²"),
            _human(E, "Pa")))
        main = fig.add_axes([0.09, 0.36, 0.51, 0.54])
        resid = fig.add_axes([0.09, 0.09, 0.51, 0.25], sharex=main)
        main.plot([z * 1e9 for z in c.depth], [f / fs for f in c.force], "o", mfc="none", ms=3,
                  color="#7f8c8d", label="data")
        if d["have"]:
            _layers(main, d["z"], d["F"], d, fs, PALETTE[0])
        if d["pulloff"] is not None:
            main.plot([d["pulloff"][0] * 1e9], [d["pulloff"][1] / fs], "o", ms=8,
                      color="#c0392b", label="pull-off %s" % _human(info["P_po"], "N"))
        main.set_ylabel("force (%s)" % fu)
        main.legend(loc="upper left")
        main.grid(color="#e0e0e0")
        main.tick_params(labelbottom=False)
        resid.plot([z * 1e9 for z in c.depth], [r / fs for r in c.residual], ".", ms=3,
                   color=PALETTE[0])
        resid.axhline(0.0, color="#444444", ls=":")
        resid.set_xlabel("depth z (nm)")
        resid.set_ylabel("residual (%s)" % fu)
        resid.grid(color="#e0e0e0")
        if d["pulloff"] is not None and d["have"]:
            _around_pulloff(fig, c, d, fs, fu)
        figs.append(fig)
    if show:
        plt.show()
    return figs


def _around_pulloff(fig, c, d, fs, fu):
    """The right panel: from just past detachment to a few pull-off widths
    into contact (at least a twentieth of the data's depth span)."""
    z0, F0, s = d["z0"], d["F0"], d["slope"] or 0.0
    delta_detach, delta_po = d["delta_detach"], d["delta_po"]
    if not (delta_detach == delta_detach and delta_po >= delta_detach):
        return
    dd = [z - z0 for z in c.depth]
    span = max(delta_po - delta_detach, 0.05 * (max(dd) - min(dd)))
    x0, x1 = delta_detach - 0.4 * span, delta_po + 3.0 * span
    ys = [f for x, f in zip(dd, c.force) if x0 <= x <= x1]
    y0 = min(ys + [d["pulloff"][1]])
    y1 = max(ys + [F0 + s * x1])
    pad = 0.1 * (y1 - y0) or (0.1 * abs(y0) if y0 else 1e-12)
    ax = fig.add_axes([0.70, 0.36, 0.28, 0.54])
    ax.plot([z * 1e9 for z in c.depth], [f / fs for f in c.force], "o", mfc="none", ms=3,
            color="#7f8c8d")
    _layers(ax, d["z"], d["F"], d, fs, PALETTE[0], titles=False)
    ax.plot([d["pulloff"][0] * 1e9], [d["pulloff"][1] / fs], "o", ms=8, color="#c0392b")
    ax.set_xlim((x0 + z0) * 1e9, (x1 + z0) * 1e9)
    ax.set_ylim((y0 - pad) / fs, (y1 + pad) / fs)
    ax.set_title("around pull-off")
    ax.set_xlabel("depth z (nm)")
    ax.set_ylabel("force (%s)" % fu)
    ax.grid(color="#e0e0e0")
