"""The ``[[controllers]]`` tables of a system scene: each names a Python callable,
``callable = "module:function"`` (an importable module) or ``"file.py:function"`` (a file
beside the scene file), which is called as ``function(system, **parameters)`` with the
table's ``parameters`` and returns a ``control.Controller``.  The controllers set the
scene's inputs, the values written ``{input = "name", value = ...}`` (``schema.input_or``).
A scene file that names code runs that code: read it before you run a file you did not
write."""

import importlib
import importlib.util
from pathlib import Path

from ..control.controller import check_controller
from .schema import text


def read_controllers(root, system):
    """The controllers of the ``[[controllers]]`` tables of ``root`` for ``system``."""
    controllers = []
    for t in root.tables("controllers"):
        target = t.get("callable", text)
        parameters = t.table("parameters").data
        function = _load(t, target)
        try:
            controller = function(system, **parameters)
        except Exception as err:
            t.fail("callable", f"{target} failed: {type(err).__name__}: {err}")
        try:
            check_controller(controller)
        except (TypeError, ValueError) as err:
            t.fail("callable", f"{target}: {err}")
        t.finish()
        controllers.append(controller)
    return controllers


def _load(t, target):
    """The function ``target`` (``"module:function"`` or ``"file.py:function"``).  A file
    runs from its text, never from a bytecode cache: Python trusts a cache whose source
    has the same size and modification second, so a controller edited within a second
    (``200.0`` -> ``300.0``) ran its old code, and a resume compared the wrong code."""
    where, _, name = target.rpartition(":")
    if not where or not name:
        t.fail("callable", 'must be "module:function" or "file.py:function"', target)
    try:
        if where.endswith(".py"):
            path = Path(where)
            if not path.is_absolute():
                path = Path(str(t.source)).resolve().parent / path
            spec = importlib.util.spec_from_file_location(path.stem, path)
            module = importlib.util.module_from_spec(spec)
            exec(compile(path.read_bytes(), str(path), "exec", dont_inherit=True),
                 module.__dict__)
        else:
            module = importlib.import_module(where)
        return getattr(module, name)
    except Exception as err:  # a file that does not import: its error, not a traceback
        t.fail("callable", f"cannot be loaded ({type(err).__name__}: {err})", target)
