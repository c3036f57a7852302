"""The ctypes mirrors of the library's structures are laid out as the C
compiler lays them out (build/tests/python_abi prints the C side): a field
added to a mirrored structure in layerfit.h fails here until the mirror in
src/python/layerfit/_lib.py follows."""
import ctypes
import json
import os
import subprocess

from conftest import BUILD

from layerfit import _lib


def c_layouts():
    out = subprocess.run([os.path.join(BUILD, "tests", "python_abi")], capture_output=True,
                         check=True).stdout
    return json.loads(out)


def test_every_mirror_is_checked():
    assert set(_lib.STRUCTS) == set(c_layouts())


def test_layouts():
    c = c_layouts()
    for name, cls in _lib.STRUCTS.items():
        assert ctypes.sizeof(cls) == c[name]["size"], name
        fields = {f[0].rstrip("_"): getattr(cls, f[0]).offset for f in cls._fields_}
        assert fields == c[name]["fields"], name
