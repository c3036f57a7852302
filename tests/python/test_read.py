"""Every reader through layerfit.read(): the synthetic exports of
datasets/vendors and the real ones of ../shared/realdata, each compared
with what `layerfit check` reports of the same file (the reader, the
points per segment, what was found and converted; for a file of many
curves, their count and each curve's points)."""
import os
import re
import warnings

import pytest

from conftest import REALDATA, TOP, run

import layerfit

V = os.path.join(TOP, "datasets", "vendors")
# constants a file does not state (the command's options, as datasets/vendors/README.md
# and ../shared/realdata/README.md give them)
VENDORS = {
    "chiaro.txt": {}, "jpk_force.txt": {}, "jpk_volts.txt": {}, "workshop_tb.csv": {},
    "workshop_force.csv": {"spring_constant": "0.032N/m"},
    "ntmdt.txt": {"spring_constant": "1N/m", "sensitivity": "61nm/nA"},
    "hysitron.txt": {}, "text_space_comma.txt": {}, "jpk_force.jpk-force": {},
    "jpk_calibration.jpk-force": {"spring_constant": "0.032N/m", "sensitivity": "50nm/V"},
    "jpk_map.jpk-force-map": {}, "jpk_qi.jpk-qi-data": {}, "nanoscope.spm": {},
    "nanoscope_fv.spm": {}, "nanoscope.pfc": {}, "igor.ibw": {}, "igor_be.ibw": {}, "workshop_map.zip": {},
    "afmformats.tab": {}, "hysitron.hld": {},
}
REAL = {
    "fmt-chiaro-txt_AEBP1_Indentation_002.txt": {},
    "10 wv pc PEGFN S-1 X-1 Y-1 I-1.txt": {}, "10 wv pc PEGFN S-1 X-1 Y-2 I-1.txt": {},
    "fmt-ntmdt-txt-fd_2015_01_17_gel4-0,1_mQ_adh_6B_Curve_DFL_Height_51.txt":
        {"spring_constant": "0.055N/m", "sensitivity": "61nm/nA"},
    "fmt-afm-workshop-fd_single_2018-08-01_13.06.09.csv":
        {"spring_constant": "0.1N/m", "sensitivity": "50nm/V"},
    "fmt-afm-workshop-fd_single_2020-02-14_13.41.25.csv": {"spring_constant": "0.1N/m"},
    "fmt-afm-workshop-fd_single_2021-01-15.csv":
        {"spring_constant": "0.1N/m", "sensitivity": "50nm/V"},
    "force-save-2021.06.30-13.48.08.425.txt": {}, "RobinSteel0000LC.txt": {},
    "fmt-jpk-fd_map2x2_extracted.jpk-force-map": {},
    "fmt-jpk-fd_2020.02.07-16.29.05.036.jpk-qi-data": {},
    "force-save-example.jpk-force": {},
    "fmt-jpk-cl_calibration_force-save-2015.02.04-11.25.21.294.jpk-force":
        {"spring_constant": "0.1N/m", "sensitivity": "50nm/V"},
    "fmt-igor-fd_U3_3_p10004.ibw": {}, "20200904_Egel4-Z1.0_00025.spm": {},
}


def options(constants):
    out = []
    for k, v in constants.items():
        out += ["--" + k.replace("_", "-"), v]
    return out


def check(path, constants):
    rc, out, err = run("check", path, *options(constants))
    assert rc == 0, err
    return out


def segments(text):
    """{"load": 39, "hold": 14, "unload": 39} from check's points line."""
    return {name: int(n) for name, n in re.findall(r"(load|hold|unload) (\d+)", text)}


def agrees_with_check(c, out):
    """A single curve read by read() against `layerfit check`'s report."""
    fmt = re.search(r"^  format +(\S+)", out, re.M).group(1)
    assert c.format == fmt
    points = re.search(r"^  points +(\d+)(.*)$", out, re.M)
    assert c.n == int(points.group(1)) == len(c.depth) == len(c.force) == len(c.segment)
    counts = segments(points.group(2))
    for name, s in layerfit._core.SEGMENTS.items():
        assert sum(1 for x in c.segment if int(x) == s) == counts.get(name, 0), name
    found = re.findall(r"^  found +(.*)$", out, re.M)
    assert c.info == found
    assert all(x == x for x in c.depth) and all(x == x for x in c.force)   # no NaN


def one_file(path, constants):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", layerfit.LayerfitWarning)
        got = layerfit.read(path, **constants)
    out = check(path, constants)
    if isinstance(got, layerfit.CurveFile):
        many = re.search(r"^  curves +(\d+):", out, re.M)
        assert many, out
        assert len(got) == int(many.group(1))
        rows = re.findall(r"^  (\d+) .* (\d+) +(\d+), (\d+), (\d+)$", out, re.M)
        assert len(rows) == len(got)
        for i, n, load, hold, unload in rows[:4]:
            info = got.info(int(i))
            assert info["points"] == int(n)
            assert info["segment_points"] == {"load": int(load), "hold": int(hold),
                                              "unload": int(unload)}
        c = got[0]
        assert c.index == 0 and c.file.endswith("#0")
        agrees_with_check(c, check(path + "#0", constants))
        assert len(got[1:3]) == min(2, len(got) - 1)
    else:
        agrees_with_check(got, out)
    return got


@pytest.mark.parametrize("name", sorted(VENDORS))
def test_vendor_file(name):
    one_file(os.path.join(V, name), VENDORS[name])


def test_every_vendor_file_is_listed():
    files = {f for f in os.listdir(V) if f not in ("README.md", "make_vendors.py", "plan.csv")}
    assert files == set(VENDORS)


@pytest.mark.parametrize("name", sorted(REAL))
def test_real_export(realdata, name):
    one_file(os.path.join(realdata, name), REAL[name])


def test_every_real_export_is_listed(realdata):
    assert {f for f in os.listdir(realdata) if f != "README.md"} == set(REAL)


def test_units_metadata_and_position():
    c = layerfit.read(os.path.join(V, "chiaro.txt"))
    assert c.R == pytest.approx(8e-6)
    assert c.spring_constant == pytest.approx(0.032) and c.spring_constant_source == "file header"
    assert c.metadata["k (N/m)"] == "0.032"
    load_d, load_f = c.points("load")
    assert len(load_d) == 39 and max(c.depth) == pytest.approx(4.5e-6)
    m = layerfit.read(os.path.join(V, "jpk_map.jpk-force-map"))
    c3 = m[3]
    assert c3.grid == (2, 1) and c3.position == (pytest.approx(120e-6), pytest.approx(210e-6))
    assert m.info(3)["grid"] == (2, 1)
    one = layerfit.read(os.path.join(V, "jpk_map.jpk-force-map") + "#3")
    assert one.grid == (2, 1) and list(one.force) == list(c3.force)


def test_a_constant_with_its_unit_or_in_SI():
    a = layerfit.read(os.path.join(V, "workshop_force.csv"), spring_constant="32 mN/m")
    b = layerfit.read(os.path.join(V, "workshop_force.csv"), spring_constant=0.032)
    assert list(a.depth) == list(b.depth) and list(a.force) == list(b.force)


def test_errors_name_the_file_line_and_column(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("depth_nm,force_uN\n1,2\n3,x4\n")
    rc, _, err = run("check", bad)
    assert rc == 2
    with pytest.raises(layerfit.Error) as e:
        layerfit.read(bad)
    assert "layerfit: %s\n" % e.value == err        # as the command prints it
    assert (e.value.file, e.value.line, e.value.column) == (str(bad), 3, 3)
    with pytest.raises(layerfit.Error) as e:
        layerfit.read(os.path.join(V, "workshop_force.csv"), spring_constant="3 GPa")
    assert "--spring-constant" in e.value.message
    with pytest.raises(TypeError):
        layerfit.read(os.path.join(V, "chiaro.txt"), fix_nu=0.3)


def test_a_reader_warning_is_a_python_warning():
    with pytest.warns(layerfit.LayerfitWarning, match="is clamped"):
        c = layerfit.read(os.path.join(V, "chiaro.txt"))
    assert any("is clamped" in w for w in c.warnings)
