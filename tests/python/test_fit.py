"""layerfit.fit and layerfit.batch against the command: to_dict() is the
--json of `layerfit fit` (but for the provenance's command line) for the
demo's joint fit, a plan of exports and a real export; batch rows are the
lines of --out FILE.jsonl; errors carry the file, line and column the
command prints; options are the command's by name; fits run in threads."""
import json
import os
import threading
import warnings

import pytest

from conftest import REALDATA, TOP, command_json, run, same_but_command_line

import layerfit

DEMO = "datasets/demo/plan.csv"
PEG = "10 wv pc PEGFN S-1 X-1 Y-1 I-1.txt"

warnings.simplefilter("ignore", layerfit.LayerfitWarning)


def test_demo_joint_fit_is_the_commands(tmp_path):
    r = layerfit.fit(DEMO)
    assert same_but_command_line(r.to_dict(), command_json(tmp_path, DEMO))
    assert r.to_dict()["provenance"]["command_line"] == "layerfit.fit('%s', model='auto')" % DEMO
    assert r.converged and len(r.curves) == 3
    assert r.w.value == r.to_dict()["parameters"]["w"]["value"]
    assert r.w.ci95_method == "profile likelihood"


def test_a_plan_of_exports_and_options(tmp_path):
    for args, kw in ((["datasets/vendors/plan.csv"], {}),
                     ([DEMO, "--model", "exact", "--intervals", "linear"],
                      {"model": "exact", "intervals": "linear"}),
                     ([DEMO, "--fix-nu", "0.35", "--slope", "--model", "thin"],
                      {"fix_nu": 0.35, "slope": True, "model": "thin"})):
        r = layerfit.fit(args[0], **kw)
        assert same_but_command_line(r.to_dict(), command_json(tmp_path, *args)), args


def test_real_export_is_the_commands(realdata, tmp_path):
    path = os.path.join(realdata, PEG)
    r = layerfit.fit(path, model="halfspace", k=2)
    assert same_but_command_line(r.to_dict(), command_json(tmp_path, path, "--model",
                                                           "halfspace", "--k", "2"))
    # the same from the curve read() gives
    c = layerfit.read(path)
    assert same_but_command_line(layerfit.fit(c, model="halfspace", k=2).to_dict(), r.to_dict())
    assert r.Estar.value == pytest.approx(25.15e3, rel=1e-3)
    assert r.w.value == pytest.approx(1.062e-3, rel=1e-3)
    lo, hi = r.Estar.ci95
    assert lo < r.Estar.value < hi


def test_units_as_the_command_line_takes_them(tmp_path):
    c = os.path.join(TOP, "datasets", "demo", "curve1.csv")
    a = layerfit.fit(c, k=2, R="1mm", b="1 um", interface="frictionless", fix_z0="15nm")
    assert same_but_command_line(a.to_dict(), command_json(
        tmp_path, c, "--k", "2", "--R", "1mm", "--b", "1um", "--interface", "frictionless",
        "--fix-z0", "15nm"))
    # a number is SI: 15nm parses to 15e-9 within rounding
    b = layerfit.fit(c, k=2, R=1e-3, b=1e-6, interface="frictionless", fix_z0=15e-9)
    assert b.curves[0].info["z0"] == pytest.approx(15e-9, rel=1e-15)
    # (a z0 one rounding apart moves the solution within its convergence: by
    # far less than a thousandth of a standard error)
    assert abs(b.w.value - a.w.value) < 1e-3 * a.w.stderr
    assert abs(b.Estar.value - a.Estar.value) < 1e-3 * a.Estar.stderr


def test_rows_held_in_python_fit_as_the_plan(tmp_path):
    rows = [{"file": "datasets/demo/curve1.csv", "k": 2, "R": "1mm", "b": 1e-6,
             "interface": "frictionless"},
            {"file": "datasets/demo/curve2.csv", "k": 3, "R": 1e-3, "b": "1um",
             "interface": "bonded"},
            {"file": "datasets/demo/curve3.csv", "k": 2.5, "R": "500um", "b": "1um",
             "interface": "bonded"}]
    a = layerfit.fit(rows).to_dict()
    b = command_json(tmp_path, DEMO)
    assert [x["file"] for x in a["provenance"]["inputs"]] == \
        [x["file"] for x in b["provenance"]["inputs"][1:]]
    for d in (a, b):
        d["provenance"]["inputs"] = d["provenance"]["command_line"] = None
    assert a == b


def test_curves_from_arrays_and_simulate():
    curves = layerfit.simulate(["k=2,R=1mm,b=1um,interface=frictionless",
                                {"k": 3, "R": "1mm", "b": "1um", "interface": "bonded"}],
                               w="10mJ/m2", E="1GPa", nu=0.35, noise=0.005, seed=7)
    r = layerfit.fit(curves)
    assert r.converged
    assert r.w.ci95[0] < 0.010 < r.w.ci95[1]
    assert r.Estar.ci95[0] < 1e9 < r.Estar.ci95[1]
    again = layerfit.Curve.from_arrays(curves[0].depth, curves[0].force, probe=curves[0].probe)
    assert list(again.force) == list(curves[0].force)


def test_simulate_is_the_commands(tmp_path):
    out = tmp_path / "sim"
    rc, _, err = run("simulate", "--out", out, "--w", "10mJ/m2", "--E", "1GPa", "--nu", "0.3",
                     "--noise", "0.01", "--seed", "3", "k=2,R=1mm,b=1um,interface=bonded")
    assert rc == 0, err
    c = layerfit.simulate(["k=2,R=1mm,b=1um,interface=bonded"], w=0.01, E=1e9, nu=0.3,
                          noise=0.01, seed=3)[0]
    file = layerfit.read(out / "curve1.csv")
    assert list(file.depth) == list(c.depth) and list(file.force) == list(c.force)


def test_model_is_the_commands():
    m = layerfit.model(k=3, R="1mm", b="1um", w="10mJ/m2", E="1GPa", sigma_th="10MPa",
                       points=50)
    rc, out, _ = run("model", "--k", "3", "--R", "1mm", "--b", "1um", "--w", "10mJ/m2",
                     "--E", "1GPa", "--sigma-th", "10MPa", "--json")
    assert rc == 0 and m.to_dict() == json.loads(out)
    rc, out, _ = run("model", "--k", "3", "--R", "1mm", "--b", "1um", "--w", "10mJ/m2",
                     "--E", "1GPa", "--points", "50")
    rows = [line.split(",") for line in out.strip().split("\n")[1:]]
    assert [float(r[0]) for r in rows] == list(m.depth)
    assert [float(r[1]) for r in rows] == list(m.force)
    assert [int(r[4]) for r in rows] == m.stable


def test_model_refuses_what_it_cannot_evaluate():
    # k = 0.01 leaves double precision: the command exits 2, the binding
    # raises with the same words instead of a summary of NaN and zeros
    args = dict(model="thin", k=0.01, R="1mm", b="1um", w="10mJ/m2", E="1MPa")
    rc, _, err = run("model", "--model", "thin", "--k", "0.01", "--R", "1mm", "--b", "1um",
                     "--w", "10mJ/m2", "--E", "1MPa", "--summary")
    assert rc == 2
    with pytest.raises(layerfit.Error) as e:
        layerfit.model(**args)
    assert "cannot be evaluated" in str(e.value) and str(e.value) in err


def test_errors_carry_the_commands_place(tmp_path):
    plan = tmp_path / "plan.csv"
    plan.write_text("file,k,R_m,b_m,interface\n%s/datasets/demo/curve1.csv,2,1e-3,1e-6,glued\n"
                    % TOP)
    rc, _, err = run("fit", plan)
    assert rc == 2
    with pytest.raises(layerfit.Error) as e:
        layerfit.fit(plan)
    assert err == "layerfit: %s\n" % e.value
    line = plan.read_text().splitlines()[1]
    assert (e.value.file, e.value.line, e.value.column) == (str(plan), 2,
                                                            line.index("glued") + 1)
    # rows held in Python: the place is their row and column
    with pytest.raises(layerfit.Error) as e:
        layerfit.fit([{"file": "datasets/demo/curve1.csv", "k": 2, "R": "1mm", "b": "1um",
                       "interface": "glued"}])
    assert (e.value.file, e.value.line) == ("<rows>", 2)
    assert e.value.column == len("datasets/demo/curve1.csv,2,1mm,1um,") + 1


def test_options_are_the_commands_by_name():
    # every option of the table is taken by its name
    assert set(layerfit.OPTIONS) >= {"fix-nu", "intervals", "segment", "guess-E", "k", "R"}
    for kw, flag in (({"fix_nu": "abc"}, "--fix-nu"), ({"max_iter": 0}, "--max-iter"),
                     ({"model": "nope"}, "--model"), ({"guess_w": "3 GPa"}, "--guess-w"),
                     ({"intervals": "none"}, "--intervals"), ({"loss": "l1"}, "--loss")):
        with pytest.raises(layerfit.Error) as e:
            layerfit.fit(DEMO, **kw)
        name, value = next(iter(kw.items()))
        rc, _, err = run("fit", DEMO, flag, value)
        assert rc == 2 and err == "layerfit: fit: %s\n" % e.value, kw
    with pytest.raises(TypeError):
        layerfit.fit(DEMO, no_such_option=1)
    with pytest.raises(TypeError):
        layerfit.fit(DEMO, slope=3)


def test_batch_rows_are_the_commands(tmp_path):
    out = tmp_path / "b.jsonl"
    rc, _, err = run("fit", "--batch", "datasets/vendors/plan.csv", "--out", out, "--quiet")
    assert rc == 0, err
    want = [json.loads(line) for line in out.read_text().splitlines()]
    seen = []
    rows = list(layerfit.batch("datasets/vendors/plan.csv", threads=2,
                               progress=lambda *a: seen.append(a)))
    assert sorted(rows, key=lambda r: r["fit"]) == want
    assert [s[0] for s in seen] == list(range(1, len(want) + 1))
    assert list(layerfit.batch("datasets/vendors/plan.csv", threads=1, ordered=True)) == want
    # a file of many curves with one probe, as fit --batch MAP --k ...
    rc, _, err = run("fit", "--batch", "datasets/vendors/jpk_map.jpk-force-map", "--k", "2",
                     "--R", "8um", "--model", "halfspace", "--out", out, "--quiet")
    want = [json.loads(line) for line in out.read_text().splitlines()]
    got = list(layerfit.batch("datasets/vendors/jpk_map.jpk-force-map", k=2, R="8um",
                              model="halfspace", ordered=True))
    assert got == want and len(got) == 6


def test_batch_results_and_early_stop():
    rows = layerfit.batch(DEMO, results=True, ordered=True, threads=2)
    first = next(rows)
    assert first["result"]["parameters"]["w"]["value"] == first["w_J_m2"]
    rows.close()            # no more fits start
    with pytest.raises(layerfit.Error):
        list(layerfit.batch(DEMO, model="nope"))


def test_threads_fit_at_once_as_alone():
    paths = [DEMO, "datasets/plan.csv", "datasets/vendors/plan.csv"] * 2
    alone = [layerfit.fit(p).to_dict() for p in paths[:3]]
    got = [None] * len(paths)

    def one(i):
        got[i] = layerfit.fit(paths[i]).to_dict()
    ts = [threading.Thread(target=one, args=(i,)) for i in range(len(paths))]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert got == alone * 2


def test_notebook_tables_are_the_reports(tmp_path):
    report = tmp_path / "r.html"
    rc, _, err = run("fit", DEMO, "--report", report)
    assert rc == 0, err
    page = report.read_text()
    tables = page[page.index("</header>\n") + len("</header>\n"):page.index("<section id=\"figures\">")]
    html = layerfit.fit(DEMO)._repr_html_()
    assert html.startswith('<div class="layerfit-report">\n<style>\n')
    assert html[html.index("</style>\n") + len("</style>\n"):] == tables + "</div>\n"


def test_plot_draws_the_commands_panels():
    pytest.importorskip("matplotlib", reason="skipped: python3-matplotlib not installed")
    import matplotlib
    matplotlib.use("Agg")
    r = layerfit.fit(DEMO)
    figs = layerfit.plot(r)
    assert len(figs) == 1 + len(r.curves)
    assert [len(f.axes) for f in figs] == [1] + [3] * len(r.curves)
    d = r.figure_data(0)
    assert d["have"] and d["pulloff"] is not None and set(d["cls"]) == {0, 1, 2}


def test_lists_without_numpy():
    import subprocess
    import sys
    code = ("import sys; sys.modules['numpy'] = None\n"
            "import layerfit, warnings\nwarnings.simplefilter('ignore')\n"
            "c = layerfit.read('datasets/vendors/chiaro.txt')\n"
            "r = layerfit.fit('datasets/demo/plan.csv')\n"
            "print(type(c.depth).__name__, type(r.curves[0].fitted).__name__)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, check=True,
                         env=os.environ).stdout.decode()
    assert out.split() == ["list", "list"]


def test_a_curve_in_memory_is_never_a_file_of_its_name(tmp_path, monkeypatch):
    # files on disk named like curves held in memory are not read for them:
    # a short CSV for fit(), a map of six curves for batch()
    import shutil
    sim = layerfit.simulate(["k=3,R=1mm,b=1um,interface=frictionless"], w=0.01, E=1e9,
                            noise=0.005, seed=5)[0]
    c = layerfit.Curve.from_arrays(sim.depth, sim.force, name="curve.csv")
    probe = dict(k=3, R="1mm", b="1um", interface="frictionless")
    monkeypatch.chdir(tmp_path)
    (tmp_path / "curve.csv").write_text("depth_m,force_N\n0,0\n")
    r = layerfit.fit(c, **probe)
    assert r.converged and len(r.curves[0].depth) == c.n
    (tmp_path / "curve.csv").unlink()
    shutil.copy(os.path.join(TOP, "datasets", "vendors", "jpk_map.jpk-force-map"), "curve.csv")
    rows = list(layerfit.batch([c], threads=1, **probe))
    assert [row["status"] for row in rows] == ["ok"]


def test_probe_shapes_windows_and_observables_are_the_commands(tmp_path):
    path = "datasets/vendors/chiaro.txt"
    for args, kw in ((["--model", "halfspace", "--tip", "sphere"],
                      {"model": "halfspace", "tip": "sphere"}),
                     (["--model", "halfspace", "--half-angle", "70deg", "--depth-range", ":50%"],
                      {"model": "halfspace", "half_angle": "70deg", "depth_range": ":50%"})):
        r = layerfit.fit(path, **kw)
        assert same_but_command_line(r.to_dict(), command_json(tmp_path, path, *args)), args
    c = r.to_dict()["curves"][0]
    assert c["tip"] == "cone" and c["R"] is None
    assert 0 < c["window"]["points_kept"] < c["window"]["points"]
    assert c["adhesion_force_N"] > 0 and c["instrument_Eeff_Pa"] == 25000
    with pytest.raises(layerfit.Error, match="k = 1 is a cone, and R does not shape a cone"):
        layerfit.fit(path, model="halfspace", k=1, R="5um")


def test_curve_files_with_the_probe_are_the_commands(realdata, tmp_path):
    # two exports with R in their headers: `layerfit fit A B --model halfspace
    # --k 2` (no R, b or interface given), as files, as read() curves, in a batch
    paths = [os.path.join(realdata, PEG), os.path.join(realdata, PEG.replace("Y-1", "Y-2"))]
    want = command_json(tmp_path, *paths, "--model", "halfspace", "--k", "2")
    r = layerfit.fit(paths, model="halfspace", k=2)
    assert same_but_command_line(r.to_dict(), want)
    assert len(r.curves) == 2
    curves = [layerfit.read(p) for p in paths]
    assert same_but_command_line(layerfit.fit(curves, model="halfspace", k=2).to_dict(), want)
    # R given as on the command line
    assert same_but_command_line(
        layerfit.fit(paths, model="halfspace", k=2, R="8um").to_dict(),
        command_json(tmp_path, *paths, "--model", "halfspace", "--k", "2", "--R", "8um"))
    rows = list(layerfit.batch(paths, model="halfspace", k=2, ordered=True, threads=1))
    assert [row["status"] for row in rows] == ["ok", "ok"]
    rows = list(layerfit.batch(curves, model="halfspace", k=2, ordered=True, threads=1))
    assert [row["status"] for row in rows] == ["ok", "ok"]


def test_vendor_files_with_the_probe_are_the_commands(tmp_path):
    # the same on a clean clone: a Chiaro export (R in its header) and a copy
    # of it as another place's (Y 2)
    c = "datasets/vendors/chiaro.txt"
    with open(c, "rb") as f:
        data = f.read()
    d = tmp_path / "chiaro Y-2.txt"
    d.write_bytes(data.replace(b"Y (#)\t1", b"Y (#)\t2", 1))
    want = command_json(tmp_path, c, d, "--model", "halfspace", "--k", "2")
    assert same_but_command_line(
        layerfit.fit([c, d], model="halfspace", k=2).to_dict(), want)
    rows = list(layerfit.batch([c, layerfit.read(d)], model="halfspace", k=2, threads=1))
    assert [row["status"] for row in rows] == ["ok", "ok"]


def test_a_curve_file_without_its_probe_is_diagnosed():
    c = "datasets/vendors/chiaro.txt"
    rc, _, msg = run("fit", c)
    assert rc != 0 and "is a curve file, not a plan" in msg
    for call in (lambda: layerfit.fit(c), lambda: layerfit.fit([c, c]),
                 lambda: layerfit.fit([layerfit.read(c)]), lambda: next(layerfit.batch(c)),
                 lambda: next(layerfit.batch([c, c]))):
        with pytest.raises(layerfit.Error) as e:
            call()
        assert e.value.file == c
        assert "a curve file, not a plan" in e.value.message
        assert "k=2, model='halfspace'" in e.value.message and "--k" not in e.value.message
        assert str(e.value).startswith(c + ": ")
