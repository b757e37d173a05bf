"""Old module paths keep working for one release (``skfem_cable/_moved.py``): the same
module object under the old name, with a ``DeprecationWarning`` naming the new path."""

import importlib
import subprocess
import sys
import warnings

import pytest

import skfem_cable as sc
from skfem_cable import _moved


def fresh(code):
    """Run ``code`` in a fresh interpreter (an old name not imported yet); its output."""
    out = subprocess.run([sys.executable, "-W", "always::DeprecationWarning", "-c", code],
                         capture_output=True, text=True, check=True)
    return out.stdout + out.stderr


def test_import_of_an_old_path_is_the_new_module():
    out = fresh("import skfem_cable.drag as old, skfem_cable.loads.drag as new;"
                "print(old is new, old.__name__, old.__spec__.name)")
    assert "True skfem_cable.loads.drag skfem_cable.loads.drag" in out
    assert "DeprecationWarning: skfem_cable.drag moved to skfem_cable.loads.drag" in out
    assert "<string>:1" in out  # the warning points at the importing line


def test_from_import_of_an_old_path():
    out = fresh("from skfem_cable.orbit import Orbit, MU_EARTH;"
                "from skfem_cable.space.orbit import Orbit as New; print(Orbit is New)")
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


def test_attribute_access_warns():
    out = fresh("import skfem_cable as sc; m = sc.coulomb; print(m.__name__, sc.coulomb is m)")
    assert "skfem_cable.loads.coulomb True" in out
    assert "<string>:1: DeprecationWarning: skfem_cable.coulomb moved" in out


def test_public_modules_keep_their_names_without_warning():
    out = fresh("import skfem_cable as sc, skfem_cable.forms, skfem_cable.sensors,"
                "skfem_cable.export; print(sc.forms.__name__, sc.sensors.__name__,"
                "sc.export.__name__)")
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
