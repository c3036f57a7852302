"""The layerfit API over liblayerfit: read, fit, batch, model, simulate.

Everything a result says comes from the library: a fit's to_dict() is the
JSON `layerfit fit --json` writes (lf_fit_job_json), its notebook display
the tables of the --report page (lf_fit_result_html), a batch row the line
`layerfit fit --batch --out FILE.jsonl` writes.  Options are the command's,
set by name (lf_fit_options_set), so that every option the command takes
works here with '_' for '-', with the command's checks and messages.
"""
import ctypes
import json
import os
import queue
import threading
import warnings as _warnings
from collections.abc import Sequence
from functools import cached_property
from ctypes import POINTER, byref, c_char_p, c_double, c_int, c_long, c_void_p

from . import _lib
from ._lib import (LfBatchRow, LfBatchSettings, LfBatchSummary, LfCurve, LfCurveInfo, LfError,
                   LfEval, LfFitFigure, LfMaterial, LfModelSummary, LfProbe, LfWarnings, dec,
                   enc, lib, take_string)

try:
    import numpy as _np
except ImportError:         # lists where numpy is not installed
    _np = None

LF_INPUT_STREAM = 1
SEGMENTS = {"unload": 0, "load": 1, "hold": 2}
_KIND_FLAG, _KIND_TEXT, _KIND_NUMBER, _KIND_COUNT, _KIND_QUANTITY = range(5)
_Q_DIMENSIONLESS = 5


class Error(Exception):
    """A failure the library reports: its message and, where the cause sits
    in a file, the file, line and column (1-based; None when not known), as
    the command prints them ("FILE:LINE:COLUMN: message")."""

    def __init__(self, message, file=None, line=None, column=None, status=None):
        super().__init__(message)
        self.message = message
        self.file = file
        self.line = line
        self.column = column
        self.status = status

    def __str__(self):
        where = ""
        if self.file:
            where = self.file + ":"
            if self.line:
                where += "%d:" % self.line
            if self.column:
                where += "%d:" % self.column
            where += " "
        return where + self.message


class LayerfitWarning(UserWarning):
    """What the readers and the fitter warn about (the command's
    "layerfit: warning: ...")."""


def _error(err, context=None):
    msg = dec(err.msg) or dec(lib.lf_strerror(err.status))
    if context:
        msg = "%s: %s" % (context, msg)
    return Error(msg, dec(err.file) or None, err.line or None, err.column or None,
                 dec(lib.lf_strerror(err.status)))


def _check(status, err, context=None):
    if status != 0:
        raise _error(err, context)


def _warn(lines):
    for w in lines:
        _warnings.warn(w, LayerfitWarning, stacklevel=3)


def _array(ptr, n, ctype=float):
    """n values at ptr as a numpy array (a copy) or a list."""
    if n == 0 or not ptr:
        return _np.zeros(0) if _np is not None else []
    if _np is not None:
        return _np.ctypeslib.as_array(ptr, shape=(n,)).copy()
    return [ctype(ptr[i]) for i in range(n)]


def _to_list(x):
    if _np is not None and isinstance(x, _np.ndarray):
        return x.tolist()
    return list(x)


# ---------------------------------------------------------------------------
# Options: the command's, by name.
# ---------------------------------------------------------------------------

def _option_table(table):
    out = {}
    i = 0
    while table[i].name is not None:
        o = table[i]
        out[o.name.decode()] = (o.kind, o.quantity)
        i += 1
    return out


OPTIONS = _option_table(_lib.OPTIONS)
"""The fit options by their command-line names ("fix-nu": (kind, quantity))."""
READ_OPTIONS = ("format", "spring-constant", "sensitivity", "depth-unit", "force-unit",
                "skip-bad-rows")
PROBE_OPTIONS = ("k", "R", "b", "interface")
# the options that state the probe of curve files (the command's cli_probe_given)
_PROBE_STATEMENT = PROBE_OPTIONS + ("tip", "half-angle", "B")


def _option_name(key, table=None, command="fit"):
    table = OPTIONS if table is None else table
    name = key.replace("_", "-")
    if name not in table:
        raise TypeError("unknown option %r: the options are those of `layerfit %s` with '_' "
                        "for '-' (%s)" % (key, command, ", ".join(sorted(
                            n.replace("-", "_") for n in table))))
    return name


def _option_text(name, value, table=None):
    """The text of an option's value as a command line gives it: a number of
    a dimensional option is SI (its unit added), a string is as written
    ("1mm")."""
    kind, q = (OPTIONS if table is None else table)[name]
    if kind == _KIND_FLAG:
        raise TypeError("%s is a flag: give True or leave it out" % name.replace("-", "_"))
    if isinstance(value, bool):
        raise TypeError("%s takes a value, not %r" % (name.replace("-", "_"), value))
    if isinstance(value, (str, bytes)):
        return enc(value)
    if isinstance(value, os.PathLike):
        return enc(value)
    if isinstance(value, (int, float)) and (kind == _KIND_QUANTITY or
                                            (kind == _KIND_TEXT and q != _Q_DIMENSIONLESS)):
        return enc("%r %s" % (float(value), dec(lib.lf_quantity_si(q))))
    if kind == _KIND_COUNT and isinstance(value, int):
        return enc(str(value))
    if isinstance(value, (int, float)):
        return enc(repr(float(value)))
    return enc(str(value))


class _Options:
    """An lf_fit_options (or lf_design_options) set from keyword arguments."""
    alloc, free, set_ = (lib.lf_fit_options_alloc, lib.lf_fit_options_free,
                         lib.lf_fit_options_set)
    command = "fit"

    def __init__(self, kw):
        self.h = self.alloc()
        if not self.h:
            raise MemoryError("layerfit: out of memory")
        table = OPTIONS if self.command == "fit" else DESIGN_OPTIONS
        err = LfError()
        for key, value in kw.items():
            if value is None or value is False:
                continue
            name = _option_name(key, table, self.command)
            text = None if value is True and table[name][0] == _KIND_FLAG \
                else _option_text(name, value, table)
            _check(self.set_(self.h, enc(name), text, byref(err)), err)

    def read_opts(self):
        err = LfError()
        p = lib.lf_fit_options_read(self.h, byref(err))
        if not p:
            raise _error(err)
        return p

    def request(self):
        err = LfError()
        p = lib.lf_fit_options_checked(self.h, byref(err))
        if not p:
            raise _error(err)
        return p

    def probe(self):
        """(probe, given): the probe options as lf_fit_options_probe reads them."""
        err = LfError()
        p = LfProbe()
        single = c_int()
        _check(lib.lf_fit_options_probe(self.h, byref(p), byref(single), byref(err)), err)
        return p, bool(single.value)

    def __del__(self):
        if getattr(self, "h", None):
            self.free(self.h)
            self.h = None


def _call_text(fn, args, kw):
    """How a call reads, for the provenance record ("layerfit.fit(...)")."""
    parts = [repr(a) if isinstance(a, (str, int, float)) else "<%s>" % type(a).__name__
             for a in args]
    parts += ["%s=%r" % (k, v) for k, v in kw.items() if v is not None]
    return "layerfit.%s(%s)" % (fn, ", ".join(parts))


# ---------------------------------------------------------------------------
# Reading curves.
# ---------------------------------------------------------------------------

class _File:
    """An open lf_file (and what must outlive it)."""

    def __init__(self, handle, keep=()):
        self.h = handle
        self.keep = keep

    def __del__(self):
        if getattr(self, "h", None):
            lib.lf_file_close(self.h)
            self.h = None


class Curve:
    """One force-depth curve in SI, points in file order.

    depth (m, positive into the layer), force (N, compressive positive),
    segment (per point: 0 unload, 1 load, 2 hold), time (s, or None);
    metadata (the file's header, key -> value), info (what the reader
    detected: columns and units, conversions), warnings; format (the
    reader), file, index (its place in its file); R (the probe radius the
    file states, m, or None), spring_constant, sensitivity and where they
    came from; position (x, y in m, or None) and grid (i, j, or None) on a
    force map.  probe: the probe of a simulated curve (a dict), used by
    fit() when no probe is given.
    """

    def __init__(self, c, source, index, read_kw):
        n = c.n
        self.file = dec(c.file)
        self.n = n
        self.depth = _array(c.depth, n)
        self.force = _array(c.force, n)
        self.time = _array(c.time, n) if c.time else None
        self.segment = _array(c.segment, n, int)
        if _np is not None:
            self.segment = self.segment.astype(int)
        self.meta = [(dec(c.meta[i].key), dec(c.meta[i].value)) for i in range(c.nmeta)]
        self.metadata = dict(self.meta)
        self.format = dec(c.format)

        def num(x):
            return None if x != x else x
        self.R = num(c.R)
        self.spring_constant = num(c.spring_constant)
        self.spring_constant_source = dec(c.spring_constant_source)
        self.sensitivity = num(c.sensitivity)
        self.sensitivity_source = dec(c.sensitivity_source)
        self.sensitivity_unit = dec(c.sensitivity_unit)
        self.info = [dec(c.info.msg[i]) for i in range(c.info.n)]
        self.position = None if c.x != c.x else (c.x, num(c.y))
        self.grid = None if c.grid_i < 0 else (c.grid_i, c.grid_j)
        self.index = c.index
        self.warnings = []
        self.probe = None
        self._source = source           # the _File it was decoded from
        self._index = index             # its index there
        self._read_kw = dict(read_kw)   # how it was read
        self._memory = False            # held in memory (from_arrays), not a file's

    def points(self, segment="unload"):
        """(depth, force) of one segment ("unload", "load", "hold")."""
        s = SEGMENTS[segment]
        keep = [i for i in range(self.n) if int(self.segment[i]) == s]
        if _np is not None:
            return self.depth[keep], self.force[keep]
        return [self.depth[i] for i in keep], [self.force[i] for i in keep]

    @classmethod
    def from_arrays(cls, depth, force, segment="unload", name="curve", probe=None):
        """A curve from arrays in SI (depth m, force N; segment one name for
        every point, or one per point), held in memory: fit() reads it as it
        would read the same points from a file."""
        depth, force = _to_list(depth), _to_list(force)
        if len(depth) != len(force):
            raise ValueError("depth and force differ in length (%d, %d)"
                             % (len(depth), len(force)))
        segs = [segment] * len(depth) if isinstance(segment, str) else _to_list(segment)
        names = {v: k for k, v in SEGMENTS.items()}
        lines = ["depth_m,force_N,segment"]
        for d, f, s in zip(depth, force, segs):
            lines.append("%r,%r,%s" % (float(d), float(f), names.get(s, s)))
        text = ("\n".join(lines) + "\n").encode()
        buf = ctypes.create_string_buffer(text, len(text))
        err = LfError()
        h = c_void_p()
        w = LfWarnings()
        _check(lib.lf_file_open_memory(buf, len(text), enc(name), None, byref(h), byref(w),
                                       byref(err)), err)
        f = _File(h.value, (buf,))
        _lib.warnings_list(w)
        c = _decode(f, 0, {})
        c.probe = probe
        c._memory = True
        return c

    def __repr__(self):
        return "<layerfit.Curve %s: %d points, %s>" % (self.file, self.n, self.format)


def _decode(f, i, read_kw):
    err = LfError()
    w = LfWarnings()
    cp = POINTER(LfCurve)()
    _check(lib.lf_file_curve(f.h, i, byref(cp), byref(w), byref(err)), err)
    try:
        c = Curve(cp.contents, f, i, read_kw)
    finally:
        lib.lf_curve_free(cp)
    c.warnings = _lib.warnings_list(w)
    return c


class CurveFile(Sequence):
    """The curves of a file of many (a force map, QI data, a force volume),
    decoded one at a time as they are asked for: len(), [i], iteration;
    info(i) says where curve i sits without decoding it."""

    def __init__(self, f, path, read_kw, warnings):
        self._f = f
        self.file = path
        self.format = dec(lib.lf_file_format(f.h))
        self.sha256 = dec(lib.lf_file_sha256(f.h))
        self.warnings = warnings
        self._n = lib.lf_file_count(f.h)
        self._read_kw = read_kw

    def __len__(self):
        return self._n

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[j] for j in range(*i.indices(self._n))]
        if i < 0:
            i += self._n
        if not 0 <= i < self._n:
            raise IndexError("curve %d of a file of %d" % (i, self._n))
        c = _decode(self._f, i, self._read_kw)
        _warn(c.warnings)
        return c

    def info(self, i):
        """{"position": (x, y) or None, "grid": (i, j) or None, "points": n,
        "segment_points": {"unload": n, "load": n, "hold": n}}."""
        err = LfError()
        inf = LfCurveInfo()
        _check(lib.lf_file_info(self._f.h, i, byref(inf), byref(err)), err)
        return {"position": None if inf.x != inf.x else (inf.x, inf.y),
                "grid": None if inf.grid_i < 0 else (inf.grid_i, inf.grid_j),
                "points": inf.points,
                "segment_points": dict(zip(("unload", "load", "hold"), inf.segment_points))}

    def __repr__(self):
        return "<layerfit.CurveFile %s: %d curves, %s>" % (self.file, self._n, self.format)


def _split(path):
    """FILE#N as (FILE, N); else (path, -1)."""
    buf = ctypes.create_string_buffer(4096)
    idx = c_long()
    if lib.lf_curve_path_split(enc(path), buf, len(buf), byref(idx)) != 0:
        raise Error("path too long", os.fsdecode(path))
    return buf.value, idx.value


def read(path, format=None, **constants):
    """The curve(s) of any export layerfit reads, in SI.

    path: a file, or FILE#N for curve N of a file of many.  format: the
    reader ("csv", "chiaro", "jpk", ...; sniffed when None).  constants, as
    the command's options: spring_constant ("0.032N/m" or 0.032 in N/m),
    sensitivity ("61nm/nA"), depth_unit, force_unit (units of columns whose
    header gives none), skip_bad_rows=True.  Returns a Curve, or for a file
    of many curves a CurveFile (a sequence of its curves, decoded as they
    are asked for).  Readers' warnings are LayerfitWarning warnings and
    kept in .warnings.  Raises layerfit.Error with the file, line and
    column of what is wrong.
    """
    kw = dict(constants, format=format)
    for k in kw:
        if _option_name(k) not in READ_OPTIONS:
            raise TypeError("read() takes format, spring_constant, sensitivity, depth_unit, "
                            "force_unit, skip_bad_rows; not %r" % k)
    opts = _Options(kw)
    ro = opts.read_opts()
    file, index = _split(path)
    err = LfError()
    w = LfWarnings()
    h = c_void_p()
    _check(lib.lf_file_open(file, LF_INPUT_STREAM, ro, byref(h), byref(w), byref(err)), err)
    f = _File(h.value, (opts,))
    warns = _lib.warnings_list(w)
    _warn(warns)
    read_kw = {k: v for k, v in kw.items() if v is not None}
    count = lib.lf_file_count(f.h)
    if index >= 0:
        if index >= count:
            raise Error("holds %d curve%s: there is no curve %d" % (count, "" if count == 1
                                                                      else "s", index),
                        os.fsdecode(file))
        c = _decode(f, index, read_kw)
    elif count == 1:
        c = _decode(f, 0, read_kw)
    else:
        return CurveFile(f, os.fsdecode(file), read_kw, warns)
    c.warnings = warns + c.warnings
    _warn(c.warnings[len(warns):])
    return c


# ---------------------------------------------------------------------------
# Plans from rows and curves held in Python.
# ---------------------------------------------------------------------------

_PLAN_COLUMNS = ("file", "k", "R", "b", "interface", "nu", "segment", "sample", "z0", "F0",
                 "format", "index")
_PLAN_UNITS = {"R": "m", "b": "m", "z0": "m", "F0": "N"}


def _cell(col, v):
    if v is None:
        return ""
    if isinstance(v, bool):
        raise TypeError("plan column %s: %r is not a value" % (col, v))
    if col in _PLAN_UNITS and isinstance(v, (int, float)):
        v = "%r %s" % (float(v), _PLAN_UNITS[col])
    elif isinstance(v, float):
        v = repr(v)
    v = str(v) if not isinstance(v, os.PathLike) else os.fspath(v)
    if any(ch in v for ch in ',"\r\n') or v != v.strip():
        v = '"' + v.replace('"', '""') + '"'
    return v


class _Plan:
    """An lf_plan made from rows held in Python (plan CSV text parsed by the
    library, so that its checks and messages are a plan file's), with the
    rows of Curve objects reading from their open files."""

    def __init__(self, items, probe_kw, name="<rows>"):
        rows, sources = [], []
        for item in items:
            row = {}
            if isinstance(item, dict):
                row.update(item)
                item = row.pop("curve", None) if "curve" in row else None
            if isinstance(item, Curve):
                row.setdefault("file", item.file)
                for k, v in (item.probe or {}).items():
                    row.setdefault(k, v)
                sources.append((len(rows), item))
            elif item is not None:
                row.setdefault("file", os.fspath(item))
            for k in PROBE_OPTIONS:
                if probe_kw.get(k) is not None:
                    row.setdefault(k, probe_kw[k])
            unknown = set(row) - set(_PLAN_COLUMNS)
            if unknown:
                raise TypeError("plan rows take %s; not %s" % (", ".join(_PLAN_COLUMNS),
                                                              ", ".join(sorted(unknown))))
            rows.append(row)
        if not rows:
            raise ValueError("no curves to fit")
        cols = [c for c in _PLAN_COLUMNS if any(c in r for r in rows)]
        lines = [",".join(cols)] + [",".join(_cell(c, r.get(c)) for c in cols) for r in rows]
        text = ("\n".join(lines) + "\n").encode()
        err = LfError()
        w = LfWarnings()
        h = c_void_p()
        _check(lib.lf_plan_parse(text, len(text), 0, enc(name), None, byref(h), byref(w),
                                 byref(err)), err)
        self.h = h.value
        self.warnings = _lib.warnings_list(w)
        self._read_from(sources)

    def _read_from(self, sources):
        """Rows r read curve c from its open file, for (r, c) in sources."""
        err = LfError()
        self.curves = []
        for r, c in sources:
            self.curves.append(c)       # their files stay open while the plan lives
            _check(lib.lf_plan_set_source(self.h, r, c._source.h, c._index, byref(err)), err)

    def __del__(self):
        if getattr(self, "h", None):
            lib.lf_plan_free(self.h)
            self.h = None


class _FilesPlan(_Plan):
    """Curve files (and curves read from files) with one probe, a plan of
    one row each as the command makes it of `layerfit fit FILE... --k 2`
    (lf_plan_of_files: R NaN is each file's header's, b NaN a half-space;
    the segment is the fit options')."""

    def __init__(self, items, paths, probe):
        err = LfError()
        h = c_void_p()
        arr = (c_char_p * len(paths))(*[enc(p) for p in paths])
        _check(lib.lf_plan_of_files(len(paths), arr, byref(probe), 0, byref(h), byref(err)),
               err)
        self.h = h.value
        self.warnings = []
        self._read_from([(r, c) for r, c in enumerate(items) if isinstance(c, Curve)])


def _curve_file_error(path):
    """The command's diagnosis of a curve file given without its probe."""
    path = os.fsdecode(path)
    return Error("a curve file, not a plan: state the probe of its curves, e.g. k=2, "
                 "model='halfspace' (R from the file's header, or R='8um'; b and interface for "
                 "a layer), or tip='sphere', 'cone', 'berkovich' or 'pyramid'", path)


def _curve_files(items):
    """The paths of items when every one is a curve file or a curve read
    from one (without a probe of its own), else None."""
    paths = []
    for item in items:
        if isinstance(item, (str, bytes, os.PathLike)):
            paths.append(os.fsdecode(item))
        elif isinstance(item, Curve) and not item._memory and item.probe is None:
            paths.append(item.file)
        else:
            return None
    return paths or None


def _plan_of(items, kw, probe):
    """(plan, fit options) of a list fit() and batch() take.  Curve files
    and curves read from files are fitted as the command fits `layerfit fit
    FILE... --k 2 --model halfspace`: the probe stated once by the options
    (lf_fit_options_probe), the files a plan of one row each; other lists
    are plan rows (_Plan), probe keywords filling the cells they leave
    empty."""
    items = [items] if isinstance(items, (Curve, dict)) else list(items)
    paths = _curve_files(items)
    if paths is None:
        return _Plan(items, probe), _Options(kw)
    p, single = _Options(dict(kw, **probe)).probe()
    if not single:
        raise _curve_file_error(paths[0])
    rest = {k: v for k, v in kw.items() if _option_name(k) not in _PROBE_STATEMENT}
    return _FilesPlan(items, paths, p), _Options(rest)


# ---------------------------------------------------------------------------
# Fits.
# ---------------------------------------------------------------------------

class Estimate:
    """An estimate of w, E*, nu or M: value, stderr, ci95 (lo, hi) and
    ci95_method, free, determined, upper_bound_only, why_not_determined
    (SI; None where the report says nothing)."""

    def __init__(self, name, d, unit):
        self.name = name
        self.unit = unit
        self.value = d["value"]
        self.stderr = d["stderr"]
        self.ci95 = tuple(d["ci95"])
        self.ci95_method = d["ci95_method"]
        self.free = d["free"]
        self.determined = d["determined"]
        self.upper_bound_only = d["upper_bound_only"]
        self.why_not_determined = d.get("why_not_determined")

    def __repr__(self):
        if self.upper_bound_only and self.ci95[1] is not None:
            return "%s < %.4g %s (95%%, one-sided)" % (self.name, self.ci95[1], self.unit)
        if not self.determined:
            return "%s not determined%s" % (self.name, ": " + self.why_not_determined
                                            if self.why_not_determined else "")
        if not self.free:
            return "%s = %.4g %s (fixed)" % (self.name, self.value, self.unit)
        lo, hi = self.ci95
        return "%s = %.4g +- %.2g%s, 95%% [%s, %s] (%s)" % (
            self.name, self.value, self.stderr, " " + self.unit if self.unit else "",
            "?" if lo is None else "%.4g" % lo, "?" if hi is None else "%.4g" % hi,
            self.ci95_method)


class CurveFit:
    """One curve of a fit: what the JSON says of it (to_dict() of the
    result, "curves") as attributes of .info, and its points: depth, force,
    fitted, residual, contact_radius (SI)."""

    def __init__(self, info, depth, force, fitted, radius):
        self.info = info
        self.file = info.get("file")
        self.depth = depth
        self.force = force
        self.fitted = fitted
        self.contact_radius = radius
        if _np is not None:
            self.residual = force - fitted
        else:
            self.residual = [a - b for a, b in zip(force, fitted)]

    def __repr__(self):
        return "<layerfit.CurveFit %s: %d points, %s, %s>" % (
            self.file, len(self.depth), self.info.get("model"), self.info.get("agreement"))


class Result:
    """A fit as `layerfit fit` makes it.

    to_dict() is the command's --json document; w, Estar, nu, M are
    Estimates; curves (CurveFit: per-curve offsets, agreement, points);
    correlations {(a, b): rho} of the free parameters; identifiability and
    warnings in words; converged, stop, stop_reason, chi2, dof, model.  In a
    notebook it shows the tables of the --report page; plot() draws the
    figures of --plot (matplotlib).
    """

    def __init__(self, job, call, warnings):
        # what the result says is read from the library when first asked
        # for: a fit returns as soon as the library has made it
        self._job = job
        self._call = call
        self.notes = warnings

    @cached_property
    def _doc(self):
        return self.to_dict()

    def _estimate(self, key, name, unit):
        return Estimate(name, self._doc["parameters"][key], unit)

    w = cached_property(lambda self: self._estimate("w", "w", "J/m^2"))
    Estar = cached_property(lambda self: self._estimate("Estar", "E*", "Pa"))
    nu = cached_property(lambda self: self._estimate("nu", "nu", ""))
    M = cached_property(lambda self: self._estimate("M", "M", "Pa"))
    converged = property(lambda self: self._doc["fit"]["converged"])
    stop = property(lambda self: self._doc["fit"]["stop"])
    stop_reason = property(lambda self: self._doc["fit"]["stop_reason"])
    chi2 = property(lambda self: self._doc["fit"]["chi2"])
    dof = property(lambda self: self._doc["fit"]["dof"])
    model = property(lambda self: self._doc["fit"]["model"])
    free_parameters = property(lambda self: self._doc["free_parameters"])
    values = property(lambda self: self._doc["values"])
    covariance = property(lambda self: self._doc["covariance"])
    identifiability = property(lambda self: self._doc["identifiability"])
    warnings = property(lambda self: self._doc["warnings"])

    @cached_property
    def curves(self):
        return [self._curve(i, c) for i, c in enumerate(self._doc["curves"])]

    def _curve(self, i, info):
        ptrs = [POINTER(c_double)() for _ in range(4)]
        n = lib.lf_fit_job_curve(self._job, i, *[byref(p) for p in ptrs])
        return CurveFit(info, *[_array(p, n) for p in ptrs])

    @property
    def correlations(self):
        names, cov = self.free_parameters, self.covariance
        out = {}
        for i, a in enumerate(names):
            for j, b in enumerate(names):
                c, sa, sb = cov[i][j], cov[i][i], cov[j][j]
                out[(a, b)] = (None if c is None or not sa or not sb
                               else c / (sa * sb) ** 0.5)
        return out

    def to_dict(self):
        """The JSON document of `layerfit fit --json` as Python objects (its
        provenance command_line: this call)."""
        err = LfError()
        p = c_void_p()
        _check(lib.lf_fit_job_json(self._job, enc(self._call), byref(p), byref(err)), err)
        return json.loads(take_string(p))

    def to_json(self):
        return json.dumps(self.to_dict(), indent=2)

    def _repr_html_(self):
        err = LfError()
        p = c_void_p()
        _check(lib.lf_fit_result_html(lib.lf_fit_job_result(self._job), b"layerfit-report",
                                      byref(p), byref(err)), err)
        return take_string(p)

    def figure_data(self, i, points=400):
        """What the figure of curve i draws: {"z", "F", "cls"} of the fitted
        model (instrument coordinates; cls 0 out of contact, 1 stable,
        2 unstable) and "z0", "F0", "slope", "pulloff" (z, F) or None."""
        z = (c_double * points)()
        F = (c_double * points)()
        cls = (c_int * points)()
        fig = LfFitFigure()
        err = LfError()
        _check(lib.lf_fit_job_figure(self._job, i, points, z, F, cls, byref(fig), byref(err)),
               err)
        out = {"z0": fig.z0, "F0": fig.F0, "slope": fig.slope, "have": bool(fig.have),
               "pulloff": None if fig.z_po != fig.z_po else (fig.z_po, fig.F_po),
               "delta_detach": fig.delta_detach, "delta_po": fig.delta_po}
        if fig.have:
            out.update(z=_array(z, points), F=_array(F, points), cls=list(cls))
        return out

    def plot(self, **kw):
        from ._plot import plot
        return plot(self, **kw)

    def __repr__(self):
        return "<layerfit.Result: %d curve%s, model %s, %s; %r; %r>" % (
            len(self.curves), "" if len(self.curves) == 1 else "s", self.model,
            "converged" if self.converged else "NOT CONVERGED (%s)" % self.stop_reason,
            self.w, self.Estar)

    def __del__(self):
        if getattr(self, "_job", None):
            lib.lf_fit_job_free(self._job)
            self._job = None


def _split_kw(model, k, R, b, interface, nu, options):
    kw = dict(options)
    kw["model"] = model
    if nu is not None:
        kw["nu"] = nu
    probe = {"k": k, "R": R, "b": b, "interface": interface}
    return kw, probe


def fit(curves_or_plan, model="auto", k=None, R=None, b=None, interface=None, nu=None,
        **options):
    """Fit w, E* and (where the curves determine it) nu as `layerfit fit` does.

    curves_or_plan: a plan file, or a curve file (FILE#N for one of many)
    with its probe k, R (from the file's header when None), b and interface
    (neither for model="halfspace"); or a Curve (from read(), simulate(),
    Curve.from_arrays()), or a list of Curves, curve files and plan rows
    (dicts with the plan's columns: file or curve, k, R, b, interface, nu,
    segment, sample, z0, F0, format, index) fitted jointly, k, R, b and
    interface applying to the rows that give none.  A list of curve files
    and curves read from files only is the command's `layerfit fit FILE...
    --k 2 --model halfspace`: one probe stated by the keywords (R from each
    file's header when None).  model: auto, thin,
    exact or halfspace.  nu: hold nu (the command's --nu).  options: every
    option of `layerfit fit`, '_' for '-' (intervals="linear", fix_nu=0.3,
    fix_z0="5nm", segment="load", slope=True, guess_w="10mJ/m2", ...): a
    dimensional value is SI or a string with its unit.  Returns a Result
    (also when the fit did not converge: result.converged); raises
    layerfit.Error on bad input, with its file, line and column.
    """
    call = _call_text("fit", (curves_or_plan,), dict(model=model, k=k, R=R, b=b,
                                                     interface=interface, nu=nu, **options))
    kw, probe = _split_kw(model, k, R, b, interface, nu, options)
    err = LfError()
    w = LfWarnings()
    job = c_void_p()
    item = curves_or_plan
    if isinstance(item, Curve) and not item._memory and item.probe is None:
        # a curve read from a file: fitted as the command fits that file
        kw = dict(item._read_kw, **kw)
        item = item.file
    if isinstance(item, (str, bytes, os.PathLike)):
        opts = _Options(dict(kw, **probe))
        if not opts.probe()[1] and _is_curve_file(item):
            raise _curve_file_error(item)
        status = lib.lf_fit_job_path(opts.h, enc(item), byref(job), byref(w), byref(err))
    else:
        plan, opts = _plan_of(item, kw, probe)
        status = lib.lf_fit_job_plan(opts.h, plan.h, byref(job), byref(w), byref(err))
    notes = _lib.warnings_list(w)
    _check(status, err)
    _warn(notes)
    return Result(job.value, call, notes)


# ---------------------------------------------------------------------------
# Batches.
# ---------------------------------------------------------------------------

def _is_curve_file(path):
    """As the command decides --batch's value: a curve file (a force map, any
    curve file) rather than a plan."""
    file, index = _split(path)
    if index >= 0:
        return True
    kind = c_int()
    err = LfError()
    return (os.path.isfile(file) and lib.lf_file_kind_of(file, byref(kind), byref(err)) == 0
            and kind.value == 0)


def batch(plan_or_curves, threads=0, progress=None, ordered=False, shard=None, results=False,
          model="auto", k=None, R=None, b=None, interface=None, nu=None, **options):
    """Fit every curve of a plan (or every sample's curves) on its own, as
    `layerfit fit --batch` does, on `threads` threads (0: one per
    processor), yielding each row as a dict -- the line `--out FILE.jsonl`
    writes: fit, sample, file, status (ok, misfit, noconv, error), w_J_m2,
    Estar_Pa, their errors and intervals, message, ... -- as the fits
    finish (ordered=True: in plan order).  plan_or_curves: a plan file, a
    file of many curves (a force map: every curve with the probe k, R, b,
    interface), or a list as fit() takes.  progress(done, total, failed)
    is called as rows are yielded.  shard=(i, n): only the i-th of n
    shares.  results=True: each row's "result" is its fit's --json
    document.  Options as fit()'s.  Closing the generator early stops the
    batch (no new fit starts).
    """
    call = _call_text("batch", (plan_or_curves,), dict(model=model, k=k, R=R, b=b,
                                                       interface=interface, nu=nu, **options))
    kw, probe = _split_kw(model, k, R, b, interface, nu, options)
    err = LfError()
    w = LfWarnings()
    h = c_void_p()
    keep = []
    if isinstance(plan_or_curves, (str, bytes, os.PathLike)):
        if _is_curve_file(plan_or_curves):
            opts = _Options(dict(kw, **probe))
            p, single = opts.probe()
            if not single:
                raise _curve_file_error(plan_or_curves)
            _check(lib.lf_plan_of_file(enc(plan_or_curves), byref(p), 0, byref(h), byref(err)),
                   err)
        else:
            opts = _Options(kw)
            _check(lib.lf_plan_read(enc(plan_or_curves), byref(h), byref(w), byref(err)), err)
            _warn(_lib.warnings_list(w))
        plan_h = h.value
        owned = True
    else:
        plan, opts = _plan_of(plan_or_curves, kw, probe)
        keep.append(plan)
        plan_h = plan.h
        owned = False
    try:
        req = opts.request()
    except Exception:
        if owned:
            lib.lf_plan_free(plan_h)
        raise
    bs = lib.lf_batch_settings_default()
    bs.json = 1
    bs.threads = threads
    bs.ordered = 1 if ordered else 0
    bs.results = 1 if results else 0
    if shard is not None:
        bs.shard_index, bs.shard_count = shard
    return _batch_rows(plan_h, owned, keep, opts, req, bs, progress, results, call)


_END = object()


def _batch_rows(plan_h, owned, keep, opts, req, bs, progress, results, call):
    q = queue.Queue()
    stop = threading.Event()
    failure = []

    def each(ctx, rowp):
        try:
            row = rowp.contents
            d = json.loads(ctypes.string_at(row.text, row.len).decode("utf-8", "replace"))
            if results and row.result:
                p = c_void_p()
                e = LfError()
                if lib.lf_batch_row_json(rowp, req, enc(call), byref(p), byref(e)) == 0:
                    d["result"] = json.loads(take_string(p))
            q.put((d, row.done, row.total, row.failed))
        except BaseException as e:          # never through C
            failure.append(e)
            return 1
        return 1 if stop.is_set() else 0

    fn = _lib.BATCH_FN(each)
    summary = LfBatchSummary()
    err = LfError()
    status = []

    def run():
        try:
            status.append(lib.lf_batch_run(plan_h, req, byref(bs), fn, None, byref(summary),
                                           byref(err)))
        finally:
            q.put(_END)

    t = threading.Thread(target=run, name="layerfit-batch", daemon=True)
    t.start()
    try:
        while True:
            item = q.get()
            if item is _END:
                break
            d, done, total, failed = item
            if progress is not None:
                progress(done, total, failed)
            yield d
        if failure:
            raise failure[0]
        if status and status[0] != 0:
            raise _error(err)
    finally:
        stop.set()
        t.join()
        if owned:
            lib.lf_plan_free(plan_h)
        del keep[:]
        del opts


# ---------------------------------------------------------------------------
# Models and synthetic data.
# ---------------------------------------------------------------------------

def _quantity(name, value, q, required=True, example=None):
    """A dimensional argument: a number in SI or a string with its unit."""
    if value is None:
        if required:
            raise Error("--%s is required (e.g. %s=%r)" % (name, name, example))
        return float("nan")
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return float(value)
    x = c_double()
    err = LfError()
    _check(lib.lf_units_parse(enc(value), q, byref(x), byref(err)), err, "--" + name)
    return x.value


_Q_LENGTH, _Q_FORCE, _Q_ADHESION, _Q_PRESSURE = 0, 1, 2, 3
_BASES = {"frictionless": 0, "bonded": 1}


def _probe(k, R, b, interface, model_type):
    if interface not in _BASES:
        raise Error("--interface: unknown interface %r (frictionless or bonded)" % interface)
    if k is None:
        raise Error("--k is required (e.g. k=2)")
    Rv = _quantity("R", R, _Q_LENGTH, example="1mm")
    halfspace = model_type == "halfspace"
    bv = _quantity("b", b, _Q_LENGTH, required=not halfspace, example="1um")
    p = LfProbe(float(k), Rv, Rv if bv != bv else bv, _BASES[interface])
    err = LfError()
    _check(lib.lf_probe_check(byref(p), byref(err)), err)
    return p


class ModelCurve:
    """A model curve as `layerfit model` writes it -- depth, force, radius,
    b_over_a (None out of contact or for a half-space), stable (force-
    controlled stability) -- and summary, the document of
    `layerfit model --json` (to_dict())."""

    def __init__(self, summary, depth, ev, layer_b):
        self.summary = summary
        self.depth = depth
        P = [e.P for e in ev]
        a = [e.a for e in ev]
        self.force = _np.array(P) if _np is not None else P
        self.radius = _np.array(a) if _np is not None else a
        self.b_over_a = [layer_b / x if layer_b is not None and x > 0 else None for x in a]
        self.stable = [int(e.a > 0 and e.dP_ddelta > 0) for e in ev]

    def to_dict(self):
        return dict(self.summary)

    def __repr__(self):
        s = self.summary
        return "<layerfit.ModelCurve %s k=%g: P_po = %.4g N at a = %.4g m>" % (
            s["model"], s["k"], s["P_po_N"] or float("nan"), s["a_po_m"] or float("nan"))


def model(k=None, R=None, b=None, w=None, E=None, nu=None, interface="frictionless",
          model="thin", branch="unload", from_=None, to=None, points=200, sigma_th=None):
    """Force against indentation of a power-law probe on an adhesive layer,
    as `layerfit model` computes it: the curve over [from_, to] (default:
    from detachment over ten pull-off widths) and the pull-off summary
    (to_dict(): the --json document; sigma_th adds the critical thickness
    of Eq. 19).  Dimensional values in SI or with their unit."""
    mt = lib.lf_model_type_find(enc(model))
    if not mt:
        raise Error("--model: unknown model %r (e.g. model='thin')" % model)
    if branch not in ("unload", "load"):
        raise Error("--branch: unknown branch %r (unload or load)" % branch)
    p = _probe(k, R, b, interface, model)
    mat = LfMaterial(_quantity("w", w, _Q_ADHESION, example="10mJ/m2"),
                     _quantity("E", E, _Q_PRESSURE, example="1GPa"),
                     0.0 if nu is None else float(nu))
    if interface == "bonded" and nu is None:
        raise Error("--nu is required for a bonded layer (e.g. nu=0.3)")
    err = LfError()
    m = lib.lf_model_alloc(mt, byref(p), byref(err))
    if not m:
        raise _error(err)
    try:
        _check(lib.lf_material_check(byref(mat), p.base, byref(err)), err)
        s = LfModelSummary()
        sig = _quantity("sigma_th", sigma_th, _Q_PRESSURE, required=False)
        _check(lib.lf_model_summarise(m, byref(mat), sig, byref(s), byref(err)), err)
        js = c_void_p()
        _check(lib.lf_model_summary_json(byref(s), byref(js), byref(err)), err)
        summary = json.loads(take_string(js))
        lo = _quantity("from", from_, _Q_LENGTH, required=False)
        hi = _quantity("to", to, _Q_LENGTH, required=False)
        if lo != lo:
            lo = s.from_
        if hi != hi:
            hi = lo + s.width
        n = int(points)
        if n < 1 or (n > 1 and not hi > lo):
            raise Error("the range is empty: give from_ and to with to > from_, points >= 1")
        depth = [lo if n == 1 else lo + (hi - lo) * i / (n - 1) for i in range(n)]
        d = (c_double * n)(*depth)
        ev = (LfEval * n)()
        _check(lib.lf_model_eval(m, byref(mat), SEGMENTS[branch], n, d, ev, byref(err)), err)
        layer_b = None if model == "halfspace" else p.b
        return ModelCurve(summary, _np.array(depth) if _np is not None else depth, ev, layer_b)
    finally:
        lib.lf_model_free(m)


def _probe_spec(spec):
    """A probe as a dict, or as the command's PROBE text
    "k=2,R=1mm,b=1um,interface=frictionless"."""
    if isinstance(spec, dict):
        d = dict(spec)
    else:
        d = {}
        for part in str(spec).split(","):
            if "=" not in part:
                raise Error("probe %r: %r is not key=value (e.g. "
                            "k=2,R=1mm,b=1um,interface=frictionless)" % (spec, part))
            key, value = part.split("=", 1)
            d[key.strip()] = value.strip()
    d.setdefault("interface", "frictionless")
    return d


def simulate(probes, w, E, nu=None, noise=0.0, seed=1, z0=0.0, F0=0.0, points=None,
             delta_max=None, delta_min=None, past_c=None, branch="unload", model="thin"):
    """Synthetic curves as `layerfit simulate` makes them (one generator,
    GSL's mt19937 seeded once, draws the noise of every curve in order):
    one Curve per probe (a dict or the command's "k=2,R=1mm,b=1um,
    interface=bonded"), held in memory, each with its probe (fit() uses
    it) and .truth (w, E*, nu, z0, F0, noise sd).  points (300), delta_max
    (50nm), delta_min (-past_c * c), past_c (1.2): the command's defaults
    where None."""
    mt = lib.lf_model_type_find(enc(model))
    if not mt:
        raise Error("--model: unknown model %r" % model)
    specs = [_probe_spec(s) for s in probes]
    ps = (LfProbe * len(specs))(*[_probe(float(s["k"]), s.get("R"), s.get("b"),
                                         s["interface"], model) for s in specs])
    bonded = any(s["interface"] == "bonded" for s in specs)
    if bonded and nu is None:
        raise Error("--nu is required by bonded probes (e.g. nu=0.3)")
    mat = LfMaterial(_quantity("w", w, _Q_ADHESION), _quantity("E", E, _Q_PRESSURE),
                     0.0 if nu is None else float(nu))
    err = LfError()
    _check(lib.lf_material_check(byref(mat), 1 if bonded else 0, byref(err)), err)
    st = lib.lf_sim_settings_default()
    if points is not None:
        st.points = int(points)
    if delta_max is not None:
        st.delta_max = _quantity("delta_max", delta_max, _Q_LENGTH)
    if delta_min is not None:
        st.delta_min = _quantity("delta_min", delta_min, _Q_LENGTH)
    if past_c is not None:
        st.past_c = float(past_c)
    st.noise = float(noise)
    st.z0 = _quantity("z0", z0, _Q_LENGTH)
    st.F0 = _quantity("F0", F0, _Q_FORCE)
    st.seed = int(seed)
    st.branch = SEGMENTS[branch]
    n = len(specs)
    bufs = [((c_double * st.points)(), (c_double * st.points)()) for _ in range(n)]
    dp = (POINTER(c_double) * n)(*[ctypes.cast(d, POINTER(c_double)) for d, _ in bufs])
    fp = (POINTER(c_double) * n)(*[ctypes.cast(f, POINTER(c_double)) for _, f in bufs])
    sigma = (c_double * n)()
    _check(lib.lf_simulate(byref(st), mt, byref(mat), n, ps, dp, fp, sigma, byref(err)), err)
    curves = []
    for j, s in enumerate(specs):
        c = Curve.from_arrays(list(bufs[j][0]), list(bufs[j][1]), branch,
                              name="curve%d.csv" % (j + 1), probe=s)
        c.truth = {"w": mat.w, "Estar": mat.Estar, "nu": nu, "z0": st.z0, "F0": st.F0,
                   "noise_sd": sigma[j], "seed": st.seed, "model": model}
        curves.append(c)
    return curves


def version():
    """The library's version (the package's is layerfit.__version__)."""
    return dec(lib.lf_version())


# ---------------------------------------------------------------------------
# Planning a test.
# ---------------------------------------------------------------------------

DESIGN_OPTIONS = _option_table(_lib.DESIGN_OPTIONS)
"""The options of `layerfit design` by their command-line names."""


class _DesignOptions(_Options):
    alloc, free, set_ = (lib.lf_design_options_alloc, lib.lf_design_options_free,
                         lib.lf_design_options_set)
    command = "design"


class Design:
    """What `layerfit design` answers: to_dict() is its --json document
    (truth, noise, model, set, without, choice, sweep, provenance); set,
    without, choice and sweep are its parts."""

    def __init__(self, doc):
        self._doc = doc
        for k in ("truth", "noise", "model", "set", "without"):
            setattr(self, k, doc[k])
        self.choice = doc.get("choice")
        self.sweep = doc.get("sweep")

    def to_dict(self):
        return json.loads(json.dumps(self._doc))

    def __repr__(self):
        s = self.set
        return "<layerfit.Design: %d candidates; w se %s, E* se %s, nu se %s>" % (
            len(s["candidates"]), s["w"]["stderr"], s["Estar"]["stderr"], s["nu"]["stderr"])


_DESIGN_COLUMNS = ("name", "k", "R", "b", "interface", "delta_max", "delta_min", "points",
                   "baseline", "z0", "F0", "segment", "noise")


def design(plan, w=None, E=None, **options):
    """What a planned test would measure, as `layerfit design PLAN` answers
    it: the Cramer-Rao standard errors of w, E* and nu a joint fit of the
    candidate curves would reach, what they would not determine and why,
    what each adds; choose=N picks the N best for target ("w", "E", "nu",
    "all"); grid="k=2,2.5,3" (or ("k", [2, 2.5, 3])) sweeps a factor,
    vary=ROW only one candidate's.  plan: a design plan file, or rows
    (dicts with its columns: name, k, R, b, interface, delta_max,
    delta_min, points, baseline, z0, F0, segment, noise).  w, E and the
    other options as the command's (nu, fix_nu, noise "1%" or "2uN",
    points, delta_max, model, model_tol), dimensional values in SI or with
    their unit.  Returns a Design (to_dict(): the --json document)."""
    import hashlib
    call = _call_text("design", (plan,), dict(w=w, E=E, **options))
    grid = options.get("grid")
    if isinstance(grid, (tuple, list)):
        factor, values = grid
        unit = " m" if factor in ("delta_max", "depth", "b", "R", "baseline") else ""
        options["grid"] = "%s=%s" % (factor, ",".join(
            v if isinstance(v, str) else "%r%s" % (float(v), unit) for v in values))
    opts = _DesignOptions(dict(options, w=w, E=E))
    err = LfError()
    h = c_void_p()
    inputs = []
    if isinstance(plan, (str, bytes, os.PathLike)):
        path = os.fsdecode(plan)
        _check(lib.lf_design_plan_read(enc(plan), byref(h), byref(err)), err)
        with open(path, "rb") as f:
            inputs.append((path, hashlib.sha256(f.read()).hexdigest()))
    else:
        rows = [dict(r) for r in plan]
        cols = [c for c in _DESIGN_COLUMNS if any(c in r for r in rows)]
        units = {"R": "m", "b": "m", "delta_max": "m", "delta_min": "m", "baseline": "m"}
        lines = [",".join(cols)]
        for r in rows:
            cells = []
            for c in cols:
                v = r.get(c)
                if c in units and isinstance(v, (int, float)) and not isinstance(v, bool):
                    v = "%r %s" % (float(v), units[c])
                cells.append(_cell("", v))
            lines.append(",".join(cells))
        text = ("\n".join(lines) + "\n").encode()
        _check(lib.lf_design_plan_parse(text, len(text), b"<rows>", byref(h), byref(err)), err)
    rep = c_void_p()
    try:
        _check(lib.lf_design_run(opts.h, h, byref(rep), byref(err)), err)
        prov = _lib.LfProvenance(enc(call), len(inputs),
                                 (c_char_p * max(1, len(inputs)))(*[enc(p) for p, _ in inputs]),
                                 (c_char_p * max(1, len(inputs)))(*[enc(s) for _, s in inputs]))
        p = c_void_p()
        _check(lib.lf_design_report_json(rep, byref(prov), byref(p), byref(err)), err)
        return Design(json.loads(take_string(p)))
    finally:
        lib.lf_design_report_free(rep)
        lib.lf_design_plan_free(h)
