"""Shared fixtures of the Python package's tests (tests/python, run by
`make check` through tests/run.sh, which sets PYTHONPATH to src/python,
LAYERFIT_LIBRARY to the build's library and LAYERFIT_BUILD to the build
folder).  The run ends with the line "N passed, N failed" that run.sh adds
to its totals; a skipped test says why (-rs)."""
import json
import os
import subprocess

import pytest

TOP = os.path.abspath(os.path.join(os.path.dirname(__file__), os.pardir, os.pardir))
BUILD = os.environ.get("LAYERFIT_BUILD", os.path.join(TOP, "build"))
LAYERFIT = os.path.join(BUILD, "layerfit")
REALDATA = os.path.normpath(os.path.join(TOP, os.pardir, "shared", "realdata"))


def run(*args, cwd=TOP):
    """The command: (exit status, stdout, stderr)."""
    p = subprocess.run([LAYERFIT] + [str(a) for a in args], cwd=cwd, capture_output=True)
    return p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")


def command_json(tmp_path, *args, name="out.json"):
    """`layerfit fit ARGS --json FILE` as Python objects."""
    out = tmp_path / name
    rc, _, err = run("fit", *args, "--json", out)
    assert rc in (0, 3, 4), err
    return json.loads(out.read_text())


def same_but_command_line(a, b):
    """Two --json documents equal but for the provenance's command line."""
    a, b = json.loads(json.dumps(a)), json.loads(json.dumps(b))
    a["provenance"]["command_line"] = b["provenance"]["command_line"] = None
    return a == b


@pytest.fixture
def realdata():
    if not os.path.isdir(REALDATA):
        pytest.skip("skipped: ../shared/realdata not found")
    return REALDATA


@pytest.fixture(autouse=True)
def at_top(monkeypatch):
    monkeypatch.chdir(TOP)


def pytest_configure(config):
    # the readers' warnings are the package's own (LayerfitWarning), asserted
    # where they matter; elsewhere they are expected and not repeated
    config.addinivalue_line("filterwarnings", "ignore::layerfit._core.LayerfitWarning")


def pytest_terminal_summary(terminalreporter):
    stats = terminalreporter.stats
    passed = len(stats.get("passed", []))
    failed = len(stats.get("failed", [])) + len(stats.get("error", []))
    terminalreporter.write_line("%d passed, %d failed" % (passed, failed))
