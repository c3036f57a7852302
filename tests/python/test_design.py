"""layerfit.design against `layerfit design`: to_dict() is its --json
document (but for the provenance's command line), for the whole set, a
choice and a sweep; the options are the command's, by name."""
import json

import pytest

from conftest import run

import layerfit

PLAN = """name,k,R_mm,b_um,interface,delta_max_nm,points,baseline,z0,F0
sphere,2,1,1,frictionless,50,120,no,free,free
sphere+baseline,2,1,1,frictionless,50,120,yes,free,free
k3,3,1,1,frictionless,50,120,no,free,free
bonded,2,1,1,bonded,50,120,yes,free,free
"""


def command(tmp_path, *args):
    out = tmp_path / "d.json"
    rc, _, err = run("design", *args, "--json", out)
    assert rc == 0, err
    return json.loads(out.read_text())


@pytest.mark.parametrize("args,kw", [
    ([], {}),
    (["--choose", "2", "--target", "all"], {"choose": 2, "target": "all"}),
    (["--grid", "k=2:4:3", "--vary", "1"], {"grid": "k=2:4:3", "vary": "1"}),
    (["--noise", "2uN", "--nu", "0.4", "--fix-nu", "--model", "thin"],
     {"noise": "2uN", "nu": 0.4, "fix_nu": True, "model": "thin"}),
])
def test_design_is_the_commands(tmp_path, args, kw):
    plan = tmp_path / "plan.csv"
    plan.write_text(PLAN)
    want = command(tmp_path, plan, "--w", "10mJ/m2", "--E", "1GPa", *args)
    got = layerfit.design(plan, w="10mJ/m2", E="1GPa", **kw).to_dict()
    got["provenance"]["command_line"] = want["provenance"]["command_line"]
    assert got == want


def test_rows_grids_and_errors(tmp_path):
    plan = tmp_path / "plan.csv"
    plan.write_text(PLAN)
    rows = [{"name": "sphere", "k": 2, "R": "1mm", "b": 1e-6, "interface": "frictionless",
             "delta_max": "50nm", "points": 120, "baseline": "no", "z0": "free", "F0": "free"},
            {"name": "k3", "k": 3, "R": 1e-3, "b": "1um", "interface": "frictionless",
             "delta_max": 50e-9, "points": 120, "baseline": "no", "z0": "free", "F0": "free"}]
    a = layerfit.design(rows, w=0.01, E=1e9, grid=("delta_max", [20e-9, 50e-9])).to_dict()
    assert [p["value"] for p in a["sweep"]["points"]] == [20e-9, 50e-9]
    assert a["set"]["candidates"][1]["name"] == "k3"
    with pytest.raises(layerfit.Error) as e:
        layerfit.design(plan, w="10mJ/m2")
    rc, _, err = run("design", plan, "--w", "10mJ/m2")
    assert rc == 2 and err == "layerfit: design: %s\n" % e.value
    with pytest.raises(layerfit.Error) as e:
        layerfit.design(plan, w="10mJ/m2", E="1GPa", noise="loud")
    assert e.value.message.startswith("--noise: 'loud' is not a positive fraction")
