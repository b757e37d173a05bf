"""Old module paths keep working for one release (``skfem_cable/_moved.py``): the same
module object under the old name, with a ``DeprecationWarning`` naming the new path."""

import importlib
import json
import subprocess
import sys
import warnings

import pytest

import skfem_cable as sc
from skfem_cable import _moved

#: What the tests below run in a fresh interpreter, each its own old names (none imported
#: by another snippet before it), as the source ``<string>`` of its own.
SNIPPETS = {
    "old path": "import skfem_cable.drag as old, skfem_cable.loads.drag as new;"
                "print(old is new, old.__name__, old.__spec__.name)",
    "from import": "from skfem_cable.orbit import Orbit, MU_EARTH;"
                   "from skfem_cable.space.orbit import Orbit as New; print(Orbit is New)",
    "attribute": "import skfem_cable as sc; m = sc.coulomb; print(m.__name__, sc.coulomb is m)",
    "public": "import skfem_cable as sc, skfem_cable.forms, skfem_cable.sensors,"
              "skfem_cable.export; print(sc.forms.__name__, sc.sensors.__name__,"
              "sc.export.__name__)",
}

#: Runs each snippet of ``argv[1]`` (JSON) in turn, its stdout and stderr (the warnings)
#: caught apart; prints them as JSON.
DRIVER = """
import contextlib, io, json, sys
outputs = {}
for name, code in json.loads(sys.argv[1]).items():
    caught = io.StringIO()
    with contextlib.redirect_stdout(caught), contextlib.redirect_stderr(caught):
        exec(compile(code, "<string>", "exec"), {"__name__": "__main__"})
    outputs[name] = caught.getvalue()
print(json.dumps(outputs))
"""


@pytest.fixture(scope="module")
def fresh():
    """The output of each of ``SNIPPETS``, run in one fresh interpreter (one start-up for
    the four: the old names they import are their own)."""
    out = subprocess.run([sys.executable, "-W", "always::DeprecationWarning", "-c", DRIVER,
                          json.dumps(SNIPPETS)], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_import_of_an_old_path_is_the_new_module(fresh):
    out = fresh["old path"]
    assert "True skfem_cable.loads.drag skfem_cable.loads.drag" in out
    assert "DeprecationWarning: skfem_cable.drag moved to skfem_cable.loads.drag" in out
    assert "<string>:1" in out  # the warning points at the importing line


def test_from_import_of_an_old_path(fresh):
    out = fresh["from import"]
    assert "True" in out and "skfem_cable.orbit moved to skfem_cable.space" in out


@pytest.mark.parametrize("old", sorted(_moved.MOVED))
def test_every_old_path_imports(old):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        module = importlib.import_module(f"skfem_cable.{old}")
    assert module is importlib.import_module(_moved.new_name(f"skfem_cable.{old}"))
    assert module.__name__ == f"skfem_cable.{_moved.MOVED[old]}"
    if f"skfem_cable.{old}" not in sys.modules or sys.modules[f"skfem_cable.{old}"] is module:
        assert all(w.category is DeprecationWarning for w in caught)


def test_attribute_access_warns(fresh):
    out = fresh["attribute"]
    assert "skfem_cable.loads.coulomb True" in out
    assert "<string>:1: DeprecationWarning: skfem_cable.coulomb moved" in out


def test_public_modules_keep_their_names_without_warning(fresh):
    out = fresh["public"]
    assert "skfem_cable.bodies.forms skfem_cable.control.sensors skfem_cable.io.export" in out
    assert "DeprecationWarning" not in out


def test_unknown_names_still_fail():
    with pytest.raises(AttributeError, match="no attribute 'nothing_here'"):
        sc.__getattr__("nothing_here")
    with pytest.raises(ModuleNotFoundError):
        importlib.import_module("skfem_cable.nothing_here")


def test_public_api_unchanged():
    for name in sc.__all__:
        assert getattr(sc, name) is not None, name
    assert sc.Cable.__module__ == "skfem_cable.bodies.cable"
    assert sc.SolarWindForce.__module__ == "skfem_cable.loads.coulomb"
