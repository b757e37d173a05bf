"""The format of a run store (the record schema): what a stored saved step holds, the
variables, their dimensions and attributes, and the files of a run directory.

A run directory's store is three things (``docs/output.md``):

``results.zarr/``
    A Zarr (v3) group that xarray opens as a Dataset (``xarray.open_zarr``): ``time``
    is the dimension of the saved steps and a coordinate; ``q``, ``v`` (``time, dof``),
    ``lam`` (``time, multiplier``), ``iterations``, the energies, the step numbers
    ``step``, the solver counters ``stat_*`` and the values of the system's inputs
    ``input_<name>`` (``inputs.Input``: what controllers set) are variables (``a`` on
    request: the ``fields`` option); the attributes hold the scene parameters, the settings, the
    bodies' coordinate ranges and the constraints' labels.  Chunks of ``chunk`` saved
    steps, float64, compressed (Blosc/Zstandard after a transpose that puts each
    coordinate's history together) and checksummed (CRC32C).

    **Labels** (``io.labels``), so that plain xarray shows what is what: with ``q``, the
    positions of the bodies' points ``r(time, body, node, component)`` (a cable's nodes,
    with their reference arc length ``s(body, node)``; a rigid body's base points; NaN
    where a body has fewer points than the most).  ``body`` and ``component`` (``x y
    z``) are dimensions, hence indexes that ``xarray.open_zarr`` builds by itself:
    ``ds.sel(body="tether3", component="x")`` works without this library.  Zarr keeps
    no other index (a pandas MultiIndex cannot be stored), so ``dof`` and
    ``multiplier`` carry non-index coordinates (``dof_body``, ``dof_node``,
    ``dof_component``, ``dof_label``; ``constraint``, ``equation``; named apart from the
    dimensions of ``r``), selected after ``ds.set_xindex([...])``.  The labels are
    written once, when the store is created; a commit appends ``r`` with the other
    arrays (Zstandard level 1: it repeats values of ``q``).  Units and long names
    follow CF (``units``, ``long_name``, ``standard_name`` for ``time``).  Stores written
    before the labels have none; they load and continue in their own layout.
``checkpoint_NNNNNNNN.npz``
    The integrator's ``snapshot()`` at the last committed step ``NNNNNNNN``: everything a
    bit-for-bit continuation needs (also what ``fields`` leaves out).
``manifest.json``
    The commit record (``io.manifest``): fingerprint of the system and settings, the
    number of committed saved steps, the checkpoint's name and SHA-256, the status.

The observer ``RunStore`` writes it (``io.writer``), ``io.reader`` reads it,
``io.resume`` continues it; ``io.legacy`` reads the format before it.
"""

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from ..core.inputs import system_inputs
from ..core.protocols import SystemView, load_output_shapes
from ..core.records import ENERGIES, FIELDS, INPUT, OUTPUT
from ..model.labels import POSITION, Points, dof_labels, multiplier_labels

#: The Zarr group of a run directory.
STORE = "results.zarr"

#: Fields stored by default (``records.FIELDS`` but the accelerations ``a``).
DEFAULT_FIELDS = ("t", "q", "v", "lam", "iterations") + ENERGIES

#: Solver counters stored at every saved step (variables ``stat_<name>``).
COUNTERS = ("steps", "rejected", "newton", "factorizations")

#: Variable name of a field, where they differ (``FIELD``: the other way).
VARIABLE = {"t": "time"}
FIELD = {"time": "t"}

_DOF_COORDS = ("dof_body", "dof_node", "dof_component", "dof_label")
_MULTIPLIER_COORDS = ("constraint", "equation")

#: CF-style attributes of the variables and coordinates (``units`` as UDUNITS strings).
ATTRS = {
    "time": {"standard_name": "time", "long_name": "time", "units": "s", "axis": "T"},
    "step": {"long_name": "step number (0: the initial state)", "units": "1"},
    "q": {"long_name": "generalized coordinates",
          "comment": "positions in m, slopes in 1 (dof_component x y z or dx dy dz)"},
    "v": {"long_name": "generalized velocities (time derivatives of q)",
          "comment": "m s-1 for positions, s-1 for slopes"},
    "a": {"long_name": "generalized accelerations (second time derivatives of q)",
          "comment": "m s-2 for positions, s-2 for slopes"},
    "lam": {"long_name": "Lagrange multipliers (constraint reactions)"},
    "r": {"long_name": "position of the body's points (cable nodes, rigid base points)",
          "units": "m"},
    "iterations": {"long_name": "Newton iterations of the step", "units": "1"},
    **{e: {"long_name": f"{e.replace('_', ' ')} energy", "units": "J"} for e in ENERGIES},
    **{"stat_" + c: {"long_name": f"{c} so far (solver counter)", "units": "1"}
       for c in COUNTERS},
    "body": {"long_name": "body (System.bodies, name)"},
    "node": {"long_name": "point of the body (cable node, rigid base point)", "units": "1"},
    "component": {"long_name": "Cartesian component (inertial frame)"},
    "s": {"long_name": "reference arc length of the cable node", "units": "m"},
    "dof_body": {"long_name": "body of the coordinate"},
    "dof_node": {"long_name": "point of the body the coordinate belongs to (-1: none)",
                 "units": "1"},
    "dof_component": {"long_name": "component of the coordinate (x y z: position, dx dy "
                                   "dz: slope, else the body's name of it)"},
    "dof_label": {"long_name": "the body's description of the coordinate"},
    "constraint": {"long_name": "constraint of the multiplier"},
    "equation": {"long_name": "equation of the constraint"},
}

#: The coordinates written once, at creation, along each dimension of the variables
#: (xarray shows them through each variable's ``coordinates`` attribute).
_COORDINATES = {"dof": _DOF_COORDS, "multiplier": _MULTIPLIER_COORDS, "node": ("s",)}


def checkpoint_name(index):
    """File name of the checkpoint at step ``index``."""
    return f"checkpoint_{int(index):08d}.npz"


def check_fields(fields):
    """``fields`` (names of ``records.FIELDS``, None for ``DEFAULT_FIELDS``) as a tuple in
    the order of ``FIELDS``, with ``t``."""
    if fields is None:
        return DEFAULT_FIELDS
    if isinstance(fields, str):
        fields = [fields]
    unknown = [f for f in fields if f not in FIELDS]
    if unknown:
        raise ValueError(f"unknown field {unknown[0]!r}: fields are {', '.join(FIELDS)}")
    return tuple(f for f in FIELDS if f in fields or f == "t")


def layout(system: SystemView):
    """Attributes describing the coordinates and multipliers of ``system``."""
    bodies, offset = [], 0
    for body in system.bodies:
        bodies.append({"name": getattr(body, "name", None), "class": type(body).__name__,
                       "first_dof": offset, "n_dofs": int(body.n_dofs)})
        offset += body.n_dofs
    constraints, k = [], 0
    for c in system.constraints:
        constraints.append({"name": c.name, "first": k, "n_eq": int(c.n_eq),
                            "labels": list(getattr(c, "labels", []))})
        k += c.n_eq
    return {"bodies": bodies, "constraints": constraints}


class Variable(NamedTuple):
    """A variable of the store: the record ``key`` its values come from, its ``dims``,
    the ``tail`` of its shape after ``time``, its ``dtype``, for a variable derived
    from another ``derive`` (the block of ``key`` to the block of this variable), and
    its Zstandard ``level``."""

    key: str
    dims: tuple
    tail: tuple
    dtype: str
    derive: Callable | None = None
    level: int = 5

    def block(self, records):
        """The values of the saved steps ``records``, ``(len(records), *tail)``."""
        values = np.asarray([r[self.key] for r in records], dtype=self.dtype)
        if self.derive is not None:
            return self.derive(values)
        return values.reshape(len(records), *self.tail)


def variables(system: SystemView, fields):
    """``{variable: Variable}`` of a store; the positions ``r`` (``labels.Points``) come
    with ``q``."""
    n, m = system.n_dofs, system.n_constraints
    spec = {"time": Variable("t", ("time",), (), "float64"),
            "step": Variable("index", ("time",), (), "int64")}
    for f in fields:
        if f in ("q", "v", "a"):
            spec[f] = Variable(f, ("time", "dof"), (n,), "float64")
        elif f == "lam":
            spec[f] = Variable(f, ("time", "multiplier"), (m,), "float64")
        elif f == "iterations":
            spec[f] = Variable(f, ("time",), (), "int64")
        elif f != "t":
            spec[f] = Variable(f, ("time",), (), "float64")
    for name, x in system_inputs(system).items():
        key = INPUT + name
        spec[key] = Variable(key, ("time", *(f"{key}_{k}" for k in range(x.initial.ndim))),
                             x.initial.shape, "float64")
    for name, shape in load_output_shapes(system).items():
        key = OUTPUT + name
        spec[key] = Variable(key, ("time", *(f"{key}_{k}" for k in range(len(shape)))),
                             shape, "float64")
    points = Points(system)
    if "q" in fields and points:  # q's positions again: level 1, a third of the time
        spec["r"] = Variable("q", ("time", "body", "node", "component"),
                             points.index.shape, "float64", points.positions, level=1)
    for c in COUNTERS:
        spec["stat_" + c] = Variable("stat_" + c, ("time",), (), "int64")
    return spec


def coordinates(system: SystemView, variables):
    """``{name: (dims, values)}`` of the labels of the dimensions of ``variables``:
    written once, when the store is created."""
    dims = {d for var in variables.values() for d in var.dims}
    out = {}
    if "dof" in dims:
        out.update({"dof_" + k: (("dof",), v) for k, v in dof_labels(system).items()})
    if "multiplier" in dims:
        out.update({k: (("multiplier",), v) for k, v in multiplier_labels(system).items()})
    if "body" in dims:
        points = Points(system)
        out.update(body=(("body",), np.array(points.bodies, dtype=str)),
                   node=(("node",), np.arange(points.index.shape[1])),
                   component=(("component",), np.array(POSITION, dtype=str)),
                   s=(("body", "node"), points.arc_length))
    return out


def coordinate_names(dims):
    """The ``coordinates`` attribute of a variable of ``dims`` (CF: its labels)."""
    return " ".join(c for d in dims for c in _COORDINATES.get(d, ()))


