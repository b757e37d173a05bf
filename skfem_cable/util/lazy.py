"""Public names of a package imported on their first use (PEP 562): ``import skfem_cable``
and a command's start-up import only the modules they use (issue 47: every process the
test suite starts, and every ``skfem-cable`` command, pays the import).

A package lists where each of its names lives and hands the module's ``__getattr__`` and
``__dir__`` to ``exports``::

    __getattr__, __dir__ = exports(__name__, {"drive": ("RunScene", "run_static")})

``RunScene`` is then ``package.drive.RunScene``, imported when first named (``from
package import RunScene`` too) and kept as an attribute of the package.
"""

import importlib
import sys


def exports(package, where, modules=None):
    """``(__getattr__, __dir__)`` of the package named ``package``.

    Parameters
    ----------
    package : str
        The package's full name (its ``__name__``).
    where : dict
        ``{submodule relative to the package: names it defines}``.
    modules : dict, optional
        ``{name: submodule relative to the package}``: names that are modules.

    ``__getattr__`` raises ``AttributeError`` for any other name.
    """
    owner = {name: module for module, names in where.items() for name in names}
    modules = modules or {}

    def __getattr__(name):
        if name in owner:
            value = getattr(importlib.import_module(f"{package}.{owner[name]}"), name)
        elif name in modules:
            value = importlib.import_module(f"{package}.{modules[name]}")
        else:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        setattr(sys.modules[package], name, value)
        return value

    def __dir__():
        return sorted({*vars(sys.modules[package]), *owner, *modules})

    return __getattr__, __dir__
