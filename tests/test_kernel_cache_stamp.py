"""A cached kernel is recompiled when code it calls in another module changes
(``kernels.cache.PackageLocator.get_source_stamp``): numba's own stamp is the kernel's
source file alone, so an edit of a callee in another module (linked into the caller's
machine code) would load stale code."""

from numba.core import caching

from skfem_cable.kernels import cache, oml_force
from skfem_cable.kernels.oml import collection

KERNELS = cache.PACKAGE / "kernels"


def locator(function):
    """The package's cache locator of the numba function ``function``."""
    return cache.PackageLocator.from_function(function.py_func,
                                              function.py_func.__code__.co_filename)


def test_dependencies_follow_relative_and_absolute_imports():
    """``oml_force`` imports ``oml`` (relative) and, through it, ``lapack``; a module's
    own file is among its dependencies; nothing outside the package is."""
    found = cache.dependencies(KERNELS / "oml_force.py")
    assert {KERNELS / "oml_force.py", KERNELS / "oml.py", KERNELS / "lapack.py"} <= found
    assert all(p.is_relative_to(cache.PACKAGE) for p in found)
    assert cache.dependencies(KERNELS / "lapack.py") >= {KERNELS / "lapack.py"}


def test_a_callees_edit_changes_the_callers_stamp(monkeypatch):
    """The stamp of a kernel of ``oml_force`` changes when ``oml.py`` (its callee's file)
    changes, and not when an unrelated kernel file does."""
    kernel = next(f for f in vars(oml_force).values()
                  if getattr(getattr(f, "py_func", None), "__module__", "") == oml_force.__name__)
    assert collection.py_func  # the callee is a numba function of oml.py
    before = locator(kernel).get_source_stamp()
    original = caching._hash_source_file

    def edited(target):
        def fake(path, mtime, size):
            digest = original(path, mtime, size)
            return digest[::-1] if path.endswith(target) else digest
        return fake

    monkeypatch.setattr(caching, "_hash_source_file", edited("kernels/oml.py"))
    assert locator(kernel).get_source_stamp() != before
    monkeypatch.setattr(caching, "_hash_source_file", edited("kernels/rod_density.py"))
    assert locator(kernel).get_source_stamp() == before
