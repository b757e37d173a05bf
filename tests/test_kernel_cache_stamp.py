"""A cached kernel is recompiled when code it calls in another module changes
(``kernels.cache.PackageLocator.get_source_stamp``): numba's own stamp is the kernel's
source file alone, so an edit of a callee in another module (linked into the caller's
machine code) would load stale code."""

import ast

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


def _imports_of_the_whole_tree(path):
    """What ``cache.imports`` finds, from the module's whole syntax tree (slow: the
    reference of the statement scan)."""
    inside = path.is_relative_to(cache.PACKAGE)
    package = path.relative_to(cache.PACKAGE.parent).parent.parts if inside else ()
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found += [cache._source(alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and (inside or not node.level):
            base = package[:len(package) - node.level + 1] if node.level else ()
            name = ".".join([*base, *([node.module] if node.module else [])])
            found += [cache._source(name)]
            found += [cache._source(f"{name}.{alias.name}") for alias in node.names]
    return {f for f in found if f is not None}


def test_the_statement_scan_finds_every_import():
    """``cache.imports`` finds the import statements by a pattern: in every module of the
    package and every generated module of the cache folder, it finds each import the
    module's syntax tree holds (a docstring's line may add one, never hide one)."""
    modules = [*cache.PACKAGE.rglob("*.py"), *cache.cache_dir("laws").glob("*.py"),
               *cache.cache_dir("steps").glob("*.py")]
    assert len(modules) > 100
    for path in modules:
        stat = path.stat()
        assert set(cache.imports(path, stat.st_mtime, stat.st_size)) >= \
            _imports_of_the_whole_tree(path), path
