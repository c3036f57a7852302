"""What a call from Python costs over the same fit inside C (`make
bench-python`; reported, not asserted).

A 300-point single curve (`layerfit simulate`, seeded, 1% noise, a k = 3 probe
on a 1 um frictionless layer) is fitted by build/bench_call -- options set
by name, lf_fit_job_path, lf_fit_job_free: the calls the package makes --
and by layerfit.fit() from /usr/bin/python3, which adds building the
options from keyword arguments, the ctypes calls and the Result (the
--json document parsed, each curve's points copied).  Rounds of each
alternate; the medians and their ratio are printed.

    python3 tests/bench/python_overhead.py [BUILD] [ROUNDS]
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

TOP = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
BUILD = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(TOP, "build"))
ROUNDS = int(sys.argv[2]) if len(sys.argv) > 2 else 200
sys.path.insert(0, os.path.join(TOP, "src", "python"))
os.environ.setdefault("LAYERFIT_LIBRARY", os.path.join(BUILD, "liblayerfit.so.0"))

import layerfit  # noqa: E402

PROBE = {"k": "3", "R": "1mm", "b": "1um", "interface": "frictionless", "model": "thin"}


def c_times(path, n):
    out = subprocess.run([os.path.join(BUILD, "bench_call"), path, str(n)]
                         + ["%s=%s" % kv for kv in PROBE.items()],
                         capture_output=True, check=True).stdout.decode()
    return [float(x) for x in out.split()]


def py_times(path, n):
    layerfit.fit(path, **PROBE)
    t = []
    for _ in range(n):
        t0 = time.perf_counter()
        layerfit.fit(path, **PROBE)
        t.append(1e6 * (time.perf_counter() - t0))
    return t


def main():
    with tempfile.TemporaryDirectory() as tmp:
        subprocess.run([os.path.join(BUILD, "layerfit"), "simulate", "--out", tmp, "--w",
                        "10mJ/m2", "--E", "1GPa", "--noise", "0.01", "--seed", "11",
                        "--points", "300", "k=3,R=1mm,b=1um,interface=frictionless"],
                       check=True, capture_output=True)
        path = os.path.join(tmp, "curve1.csv")
        r = layerfit.fit(path, **PROBE)
        c, p = [], []
        per = max(1, ROUNDS // 5)
        for _ in range(5):          # alternated, so that a load on the machine hits both
            c += c_times(path, per)
            p += py_times(path, per)
    mc, mp = statistics.median(c), statistics.median(p)
    print("a 300-point single-curve fit (thin model, %s; %r; %r)" % (r.stop, r.w, r.Estar))
    print("%-32s %10s %10s %10s" % ("", "median us", "min us", "fits"))
    print("%-32s %10.0f %10.0f %10d" % ("inside C (bench_call)", mc, min(c), len(c)))
    print("%-32s %10.0f %10.0f %10d" % ("from Python (layerfit.fit)", mp, min(p), len(p)))
    print("overhead of the Python call: %+.1f%% (median), %+.1f%% (min)"
          % (100 * (mp / mc - 1), 100 * (min(p) / min(c) - 1)))


if __name__ == "__main__":
    main()
