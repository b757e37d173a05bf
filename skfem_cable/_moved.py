"""Old module paths, kept for one release: ``skfem_cable.contract`` is
``skfem_cable.core.contract`` (the same module object), with a ``DeprecationWarning``
naming the new path, whether imported (``import skfem_cable.contract``, ``from
skfem_cable.contract import ...``) or reached as an attribute (``sc.contract``).

The modules of ``PUBLIC`` are public names of ``skfem_cable`` (``sc.forms``,
``sc.sensors``, ``sc.export``): they keep their old paths without a warning.

Written by the relayout of issue 46 (``docs/architecture.md`` shows the layout).
"""

import importlib
import importlib.abc
import importlib.util
import sys
import warnings

MOVED = {
    "analytic": "analysis.analytic",
    "atomic": "util.atomic",
    "bench": "cli.bench",
    "cable": "bodies.cable",
    "cable_options": "bodies.cable_options",
    "cable_shapes": "bodies.cable_shapes",
    "cable_term": "bodies.cable_term",
    "contract": "core.contract",
    "coulomb": "loads.coulomb",
    "deploy": "constraints.deploy",
    "drag": "loads.drag",
    "durations": "util.durations",
    "electrodynamic": "loads.electrodynamic",
    "fields": "bodies.fields",
    "formulation": "bodies.formulation",
    "frames": "space.frames",
    "inputs": "core.inputs",
    "io.jsonable": "util.jsonable",
    "io.labels": "model.labels",
    "layout": "model.layout",
    "linalg": "core.linalg",
    "lines": "core.lines",
    "memory": "bodies.memory",
    "motion": "model.motion",
    "node": "core.node",
    "observing": "solvers.observing",
    "orbit": "space",
    "orbit_gravity": "loads.orbit_gravity",
    "protocols": "core.protocols",
    "quadratic": "core.quadratic",
    "records": "core.records",
    "reel": "bodies.reel",
    "result": "results.result",
    "rigid": "bodies.rigid",
    "section": "bodies.section",
    "spectra": "analysis.spectra",
    "state": "model.state",
    "stretched": "bodies.stretched",
    "system": "model.system",
    "system_deploying": "model.system_deploying",
    "system_evaluation": "model.system_evaluation",
    "tangent_check": "analysis.tangent_check",
    "tension_guard": "runner.tension_guard",
    "timeseries": "results.timeseries",
    "validation": "cli.validation",
    "varying": "bodies.varying",
}

PUBLIC = {
    "export": "io.export",
    "forms": "bodies.forms",
    "sensors": "control.sensors",
}


def new_name(name):
    """The new full name of the old full module name ``name``, or None."""
    short = name[len(__package__) + 1:] if name.startswith(__package__ + ".") else None
    if short in PUBLIC:
        return f"{__package__}.{PUBLIC[short]}"
    if short in MOVED:
        return f"{__package__}.{MOVED[short]}"
    return None


def warn(name):
    """The deprecation of the old module name ``name``, pointing at the user's line (the
    first frame outside this file and the import machinery)."""
    short = name[len(__package__) + 1:]
    if short not in MOVED or short in PUBLIC:
        return
    frame, level = sys._getframe(1), 2
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen "):
            frame = frame.f_back  # the warnings module skips these itself
        elif frame.f_code.co_filename == __file__ or frame.f_globals["__name__"] == __package__:
            frame, level = frame.f_back, level + 1
        else:
            break
    warnings.warn(f"{name} moved to {new_name(name)}; the old path goes in the next "
                  "release", DeprecationWarning, stacklevel=level)


class _Alias(importlib.abc.Loader):
    """Loads an old name as the module of its new name (the same object: the import
    system returns what ``sys.modules`` holds under the old name after ``exec_module``)."""

    def exec_module(self, module):
        warn(module.__name__)
        sys.modules[module.__name__] = importlib.import_module(new_name(module.__name__))


class MovedFinder(importlib.abc.MetaPathFinder):
    """Finds the old module names of ``MOVED`` and ``PUBLIC``."""

    def find_spec(self, fullname, path=None, target=None):
        if new_name(fullname) is None:
            return None
        return importlib.util.spec_from_loader(fullname, _Alias())


def attribute(name):
    """``skfem_cable.<name>`` for an old module name, or None."""
    full = f"{__package__}.{name}"
    if new_name(full) is None:
        return None
    warn(full)
    module = importlib.import_module(new_name(full))
    setattr(sys.modules[__package__], name, module)  # warned once
    return module


def install():
    """Put the finder on ``sys.meta_path`` (once)."""
    if not any(isinstance(f, MovedFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, MovedFinder())  # before an editable install's finder


install()
