"""layerfit from Python: the library where scientists work.

Adhesion (w) and elasticity (E*, nu) of thin coatings from indentation
curves taken with power-law probes, through liblayerfit (ctypes, the
standard library only; numpy arrays where numpy is installed, lists
otherwise).

    import layerfit
    c = layerfit.read("curve.txt")                   # any export, in SI
    r = layerfit.fit("curve.txt", model="halfspace", k=2)
    print(r.Estar, r.w)                               # estimates, 95% intervals
    r.to_dict()                                       # = layerfit fit --json
    for row in layerfit.batch("plan.csv", threads=4): # rows as they finish
        print(row["fit"], row["status"], row["w_J_m2"])
    layerfit.design("design.csv", w="10mJ/m2", E="1GPa", choose=2)  # before the lab

Errors raise layerfit.Error (message, file, line, column).  Fits release
the GIL: threads run them in parallel.  See the README's "Python" section.
"""
from ._core import (DESIGN_OPTIONS, OPTIONS, Curve, CurveFile, CurveFit, Design, Error,
                    Estimate, LayerfitWarning, ModelCurve, Result, batch, design, fit, model, read,
                    simulate, version)
from ._lib import VERSION as __version__
from ._lib import path as library_path


def plot(result, **kw):
    """The figures of `layerfit fit --plot` for a Result, drawn with
    matplotlib (when it is installed): an overview of every curve, then per
    curve the data with the fitted model and its residuals, and the part
    around pull-off.  Returns the matplotlib figures."""
    from ._plot import plot as _plot
    return _plot(result, **kw)


__all__ = ["read", "fit", "batch", "model", "simulate", "design", "plot", "Error",
           "LayerfitWarning", "Curve", "CurveFile", "Result", "Estimate", "CurveFit", "ModelCurve",
           "Design", "OPTIONS", "DESIGN_OPTIONS", "version", "library_path", "__version__"]
