"""ctypes over liblayerfit: finding the library, the C structures the
package reads, the prototypes of the functions it calls, and errors.

The library is found, in order: the file LAYERFIT_LIBRARY names; next to
the package (layerfit/liblayerfit.so.MAJOR); the folder `make install`
recorded beside the installed package (_install.py); the build tree the
package sits in (src/python/layerfit -> build/); then the usual search of
the dynamic loader (LD_LIBRARY_PATH, ld.so.cache, /usr/lib ...).

ctypes.CDLL releases the GIL during every call into the library, so that
fits run in parallel in Python threads; the library keeps no global state
a fit changes (its caches are locked).
"""
import ctypes
import ctypes.util
import os
from ctypes import (CFUNCTYPE, POINTER, Structure, byref, c_char, c_char_p, c_double, c_int,
                    c_long, c_size_t, c_ubyte, c_uint, c_ulong, c_void_p)

VERSION = "0.1.0"
SONAME = "liblayerfit.so." + VERSION.split(".")[0]

# ---------------------------------------------------------------------------
# Finding and loading the library.
# ---------------------------------------------------------------------------


def _candidates():
    here = os.path.dirname(os.path.abspath(__file__))
    env = os.environ.get("LAYERFIT_LIBRARY")
    if env:
        return [env], True
    found = [os.path.join(here, SONAME)]
    try:
        from . import _install          # written by `make install`
        found.append(os.path.join(_install.LIBDIR, SONAME))
    except ImportError:
        pass
    found.append(os.path.normpath(os.path.join(here, os.pardir, os.pardir, os.pardir, "build",
                                               SONAME)))
    name = ctypes.util.find_library("layerfit")
    found.append(name if name else SONAME)
    return found, False


def _load():
    paths, forced = _candidates()
    tried = []
    for p in paths:
        if os.sep in p and not os.path.exists(p) and not forced:
            tried.append(p + " (no such file)")
            continue
        try:
            return ctypes.CDLL(p), p
        except OSError as e:
            tried.append("%s (%s)" % (p, e))
            if forced:
                break
    raise ImportError("layerfit: cannot load %s; tried:\n  %s\nbuild it with `make`, install it "
                      "with `make install`, or name it in LAYERFIT_LIBRARY"
                      % (SONAME, "\n  ".join(tried)))


lib, path = _load()

# GSL's default error handler would abort() the interpreter on an error
# inside the library; the library checks every GSL status itself.  This is
# process-wide, as it is for the command.
lib.gsl_set_error_handler_off.restype = c_void_p
lib.gsl_set_error_handler_off()

# ---------------------------------------------------------------------------
# Structures (tests/python/test_abi.py checks each against the C compiler's
# layout).
# ---------------------------------------------------------------------------


class LfError(Structure):
    _fields_ = [("status", c_int), ("file", c_char * 512), ("line", c_long),
                ("column", c_long), ("msg", c_char * 512)]


class LfWarnings(Structure):
    _fields_ = [("n", c_size_t), ("msg", POINTER(c_char_p))]


class LfMeta(Structure):
    _fields_ = [("key", c_char_p), ("value", c_char_p)]


class LfCurve(Structure):
    _fields_ = [("file", c_char_p), ("n", c_size_t), ("depth", POINTER(c_double)),
                ("force", POINTER(c_double)), ("time", POINTER(c_double)),
                ("segment", POINTER(c_ubyte)), ("line", POINTER(c_long)),
                ("nmeta", c_size_t), ("meta", POINTER(LfMeta)), ("format", c_char_p),
                ("R", c_double), ("spring_constant", c_double), ("sensitivity", c_double),
                ("spring_constant_source", c_char_p), ("sensitivity_source", c_char_p),
                ("sensitivity_unit", c_char_p), ("info", LfWarnings), ("x", c_double),
                ("y", c_double), ("grid_i", c_long), ("grid_j", c_long), ("index", c_long)]


class LfCurveInfo(Structure):
    _fields_ = [("x", c_double), ("y", c_double), ("grid_i", c_long), ("grid_j", c_long),
                ("points", c_size_t), ("segment_points", c_size_t * 3)]


class LfOption(Structure):
    _fields_ = [("name", c_char_p), ("kind", c_int), ("quantity", c_int)]


class LfProbe(Structure):
    _fields_ = [("k", c_double), ("R", c_double), ("b", c_double), ("base", c_int),
                ("tip", c_int), ("angle", c_double), ("B", c_double)]


class LfMaterial(Structure):
    _fields_ = [("w", c_double), ("Estar", c_double), ("nu", c_double)]


class LfPulloff(Structure):
    _fields_ = [(n, c_double) for n in ("delta_detach", "P_detach", "a_detach", "delta_po",
                                        "P_po", "a_po", "sigma_po", "P_jump", "c")]


class LfEval(Structure):
    _fields_ = [(n, c_double) for n in ("P", "a", "dP_ddelta", "dP_dlogw", "dP_dlogE",
                                        "dP_dnu")]


class LfModelSummary(Structure):
    _fields_ = [("probe", LfProbe), ("mat", LfMaterial), ("type", c_void_p),
                ("pulloff", LfPulloff), ("Z", c_double), ("sigma_th", c_double),
                ("b_cr", c_double), ("b_cr_over_a", c_double), ("from_", c_double),
                ("width", c_double)]


class LfSimSettings(Structure):
    _fields_ = [("points", c_size_t), ("delta_max", c_double), ("delta_min", c_double),
                ("past_c", c_double), ("noise", c_double), ("z0", c_double), ("F0", c_double),
                ("seed", c_ulong), ("branch", c_int)]


class LfBatchSettings(Structure):
    _fields_ = [("json", c_int), ("threads", c_long), ("shard_index", c_long),
                ("shard_count", c_long), ("ordered", c_int), ("results", c_int),
                ("csv_raw", c_int)]


class LfBatchRow(Structure):
    _fields_ = [("fit", c_size_t), ("sample", c_char_p), ("status", c_char_p),
                ("outcome", c_int), ("text", c_void_p), ("len", c_size_t),
                ("result", c_void_p), ("input", c_void_p), ("done", c_size_t),
                ("total", c_size_t), ("failed", c_size_t), ("misfits", c_size_t),
                ("why", c_char_p), ("cause", c_char_p)]


class LfBatchSummary(Structure):
    _fields_ = [("fits", c_size_t), ("total", c_size_t), ("done", c_size_t),
                ("failed", c_size_t), ("misfits", c_size_t), ("stopped", c_int)]


class LfProvenance(Structure):
    _fields_ = [("command_line", c_char_p), ("ninputs", c_size_t), ("input", POINTER(c_char_p)),
                ("sha256", POINTER(c_char_p))]


class LfFitFigure(Structure):
    _fields_ = [("z0", c_double), ("F0", c_double), ("slope", c_double), ("z_po", c_double),
                ("F_po", c_double), ("delta_detach", c_double), ("delta_po", c_double),
                ("have", c_int)]


# every structure mirrored, by its C name (for the layout test)
STRUCTS = {"lf_error": LfError, "lf_warnings": LfWarnings, "lf_meta": LfMeta,
           "lf_curve": LfCurve, "lf_curve_info": LfCurveInfo, "lf_option": LfOption,
           "lf_probe": LfProbe, "lf_material": LfMaterial, "lf_pulloff": LfPulloff,
           "lf_eval": LfEval, "lf_model_summary": LfModelSummary,
           "lf_sim_settings": LfSimSettings, "lf_batch_settings": LfBatchSettings,
           "lf_batch_row": LfBatchRow, "lf_batch_summary": LfBatchSummary,
           "lf_fit_figure": LfFitFigure, "lf_provenance": LfProvenance}

BATCH_FN = CFUNCTYPE(c_int, c_void_p, POINTER(LfBatchRow))

# ---------------------------------------------------------------------------
# Prototypes.
# ---------------------------------------------------------------------------

_E = POINTER(LfError)
_W = POINTER(LfWarnings)
_P = c_void_p


def _proto(name, restype, *argtypes):
    f = getattr(lib, name)
    f.restype = restype
    f.argtypes = list(argtypes)


_proto("lf_version", c_char_p)
_proto("lf_strerror", c_char_p, c_int)
_proto("lf_free", None, c_void_p)
_proto("lf_warnings_free", None, _W)
_proto("lf_quantity_si", c_char_p, c_int)
_proto("lf_units_parse", c_int, c_char_p, c_int, POINTER(c_double), _E)
# options
_proto("lf_fit_options_alloc", _P)
_proto("lf_fit_options_free", None, _P)
_proto("lf_fit_options_set", c_int, _P, c_char_p, c_char_p, _E)
_proto("lf_fit_options_get", c_char_p, _P, c_char_p)
_proto("lf_fit_options_checked", _P, _P, _E)
_proto("lf_fit_options_read", _P, _P, _E)
_proto("lf_fit_options_probe", c_int, _P, POINTER(LfProbe), POINTER(c_int), _E)
# reading
_proto("lf_file_open", c_int, c_char_p, c_uint, _P, POINTER(_P), _W, _E)
_proto("lf_file_open_memory", c_int, c_void_p, c_size_t, c_char_p, _P, POINTER(_P), _W, _E)
_proto("lf_file_count", c_size_t, _P)
_proto("lf_file_format", c_char_p, _P)
_proto("lf_file_sha256", c_char_p, _P)
_proto("lf_file_info", c_int, _P, c_size_t, POINTER(LfCurveInfo), _E)
_proto("lf_file_curve", c_int, _P, c_size_t, POINTER(POINTER(LfCurve)), _W, _E)
_proto("lf_file_close", None, _P)
_proto("lf_curve_free", None, POINTER(LfCurve))
_proto("lf_segment_name", c_char_p, c_int)
_proto("lf_file_kind_of", c_int, c_char_p, POINTER(c_int), _E)
_proto("lf_curve_path_split", c_int, c_char_p, c_char_p, c_size_t, POINTER(c_long))
# plans and fits
_proto("lf_plan_parse", c_int, c_void_p, c_size_t, c_size_t, c_char_p, c_char_p, POINTER(_P),
       _W, _E)
_proto("lf_plan_read", c_int, c_char_p, POINTER(_P), _W, _E)
_proto("lf_plan_of_file", c_int, c_char_p, POINTER(LfProbe), c_int, POINTER(_P), _E)
_proto("lf_plan_of_files", c_int, c_size_t, POINTER(c_char_p), POINTER(LfProbe), c_int,
       POINTER(_P), _E)
_proto("lf_plan_set_source", c_int, _P, c_size_t, _P, c_long, _E)
_proto("lf_plan_free", None, _P)
_proto("lf_fit_job_path", c_int, _P, c_char_p, POINTER(_P), _W, _E)
_proto("lf_fit_job_plan", c_int, _P, _P, POINTER(_P), _W, _E)
_proto("lf_fit_job_result", _P, _P)
_proto("lf_fit_job_status", c_int, _P)
_proto("lf_fit_job_curve", c_size_t, _P, c_size_t, POINTER(POINTER(c_double)),
       POINTER(POINTER(c_double)), POINTER(POINTER(c_double)), POINTER(POINTER(c_double)))
_proto("lf_fit_job_figure", c_int, _P, c_size_t, c_size_t, POINTER(c_double),
       POINTER(c_double), POINTER(c_int), POINTER(LfFitFigure), _E)
_proto("lf_fit_job_json", c_int, _P, c_char_p, POINTER(c_void_p), _E)
_proto("lf_fit_job_free", None, _P)
_proto("lf_fit_result_html", c_int, _P, c_char_p, POINTER(c_void_p), _E)
_proto("lf_batch_settings_default", LfBatchSettings)
_proto("lf_batch_run", c_int, _P, _P, POINTER(LfBatchSettings), BATCH_FN, c_void_p,
       POINTER(LfBatchSummary), _E)
_proto("lf_batch_row_json", c_int, POINTER(LfBatchRow), _P, c_char_p, POINTER(c_void_p), _E)
# models and synthetic data
_proto("lf_model_type_find", _P, c_char_p)
_proto("lf_model_alloc", _P, _P, POINTER(LfProbe), _E)
_proto("lf_model_free", None, _P)
_proto("lf_material_check", c_int, POINTER(LfMaterial), c_int, _E)
_proto("lf_model_eval", c_int, _P, POINTER(LfMaterial), c_int, c_size_t, POINTER(c_double),
       POINTER(LfEval), _E)
_proto("lf_model_summarise", c_int, _P, POINTER(LfMaterial), c_double,
       POINTER(LfModelSummary), _E)
_proto("lf_model_summary_json", c_int, POINTER(LfModelSummary), POINTER(c_void_p), _E)
_proto("lf_sim_settings_default", LfSimSettings)
_proto("lf_simulate", c_int, POINTER(LfSimSettings), _P, POINTER(LfMaterial), c_size_t,
       POINTER(LfProbe), POINTER(POINTER(c_double)), POINTER(POINTER(c_double)),
       POINTER(c_double), _E)
_proto("lf_probe_check", c_int, POINTER(LfProbe), _E)
# design
_proto("lf_design_options_alloc", _P)
_proto("lf_design_options_free", None, _P)
_proto("lf_design_options_set", c_int, _P, c_char_p, c_char_p, _E)
_proto("lf_design_plan_read", c_int, c_char_p, POINTER(_P), _E)
_proto("lf_design_plan_parse", c_int, c_void_p, c_size_t, c_char_p, POINTER(_P), _E)
_proto("lf_design_plan_free", None, _P)
_proto("lf_design_run", c_int, _P, _P, POINTER(_P), _E)
_proto("lf_design_report_json", c_int, _P, c_void_p, POINTER(c_void_p), _E)
_proto("lf_design_report_free", None, _P)

OPTIONS = ctypes.cast(ctypes.addressof(LfOption.in_dll(lib, "lf_fit_option_table")),
                      POINTER(LfOption))
DESIGN_OPTIONS = ctypes.cast(ctypes.addressof(LfOption.in_dll(lib, "lf_design_option_table")),
                             POINTER(LfOption))

if lib.lf_version().decode() != VERSION:
    raise ImportError("layerfit: the package is version %s, the library %s (%s) is version %s: "
                      "install both from one build" % (VERSION, SONAME, path,
                                                       lib.lf_version().decode()))

# ---------------------------------------------------------------------------
# Helpers.
# ---------------------------------------------------------------------------

ENCODING = "utf-8"


def enc(s):
    """Text (or a path) for the library: bytes as they are, str as UTF-8 (a
    path as the file system encodes it)."""
    if s is None:
        return None
    if isinstance(s, bytes):
        return s
    if isinstance(s, os.PathLike):
        return os.fsencode(s)
    return str(s).encode(ENCODING, "surrogateescape")


def dec(b):
    if b is None:
        return None
    return b.decode(ENCODING, "replace")


def take_string(p):
    """A string the library handed over (lf_free'd here)."""
    try:
        return ctypes.string_at(p).decode(ENCODING, "replace")
    finally:
        lib.lf_free(p)


def warnings_list(w):
    out = [dec(w.msg[i]) for i in range(w.n)]
    lib.lf_warnings_free(byref(w))
    w.n = 0
    return out
