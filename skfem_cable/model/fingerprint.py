"""The fingerprint of a run: a hash of what defines its equations and its time steps, so
that a run directory is continued or read back only with the system that wrote it.

``fingerprint(system, settings)`` hashes

* every body: class, name, ``n_dofs``, ``q0``, section fields, element law (name,
  expression digest, own values), quadrature order, locking-free flag, mesh nodes;
* the mass matrix (point masses included);
* every constraint: class, name, ``n_eq``, labels, global coordinates (``dofs``) and its
  parameters (Jacobian, offsets, prescribed motions);
* every load: class and parameters;
* the epoch of a system in orbit at one (``System.add_orbit(..., epoch=...)``: the UTC
  instant of ``t = 0``), when it has one;
* the solver settings of ``simulate`` (``run.settings``) but ``t_end`` and ``n_steps``, which
  a continued run may change.

Parameters are described recursively (numbers exactly, arrays by their bytes, bodies by
their index in the system, nodes by body and index); a function by its qualified name,
its byte code and constants, its default arguments, the values it closes over (by name)
and the module globals its code reads (modules by name, functions in turn, to
``MAX_DEPTH``): a number a callable closes over, changed, changes the fingerprint.  The
attributes an object names in its ``caches`` (a tuple of names: values derived from the
others, memos of the last evaluation) are not described: the fingerprint does not depend
on what was evaluated.

``check_fingerprint`` compares a run directory's manifest with a system (and settings)
before it is read or continued.

``describe_system`` is also what a ``System`` compares to notice that it was edited since
its layout was built (``System.current_layout``); ``differences`` names what changed.

The hash is SHA-256 of a canonical JSON text: the same in every process and on every
machine with the same code.
"""

import dataclasses
import functools
import hashlib
import json
import re
import types

import numpy as np

from ..core.protocols import SystemView

#: Settings a continued run may change (not in the fingerprint).
FREE_SETTINGS = ("t_end", "n_steps")

#: The version of the fingerprints a store records (``fingerprint["version"]``): from 2
#: on, what functions close over and read from their globals is described; a store of
#: version 1 (none recorded) is checked as it was written.
VERSION = 2

#: Depth to which the attributes of parameters are described.
MAX_DEPTH = 6

_ADDRESS = re.compile(r" at 0x[0-9a-fA-F]+")

#: The lists of a system's description whose entries ``differences`` names one by one.
_ENTRIES = ("bodies", "constraints", "loads", "point_masses")

#: Keys of described values that ``differences`` leaves out of a path: the wrappers of
#: objects, arrays, numbers and functions.
_WRAPPERS = {"attrs", "parameters", "class", "dtype", "shape", "sha256", "array", "float",
             "complex", "function", "code", "consts", "names", "varnames", "defaults",
             "kwdefaults", "closure", "globals"}


def _digest(data):
    return hashlib.sha256(data).hexdigest()


def _array(a):
    a = np.ascontiguousarray(a)
    if a.dtype.hasobject:
        return {"array": [_plain(x) for x in a.ravel().tolist()], "shape": list(a.shape)}
    return {"dtype": a.dtype.str, "shape": list(a.shape), "sha256": _digest(a.tobytes())}


def _plain(x):
    if isinstance(x, float):
        return _float(x)
    if isinstance(x, (str, int, bool)) or x is None:
        return x
    return {"class": _qualname(type(x))}


def _qualname(cls):
    return f"{getattr(cls, '__module__', '?')}.{getattr(cls, '__qualname__', repr(cls))}"


def _itself(x):
    return x


def _float(x):
    return {"float": float(x).hex()}


#: The description of a value of each of these exact types at once, as ``_Describer``
#: describes it by its checks in turn (most leaves are of these types; their subclasses
#: take the checks).
_LEAVES = {type(None): _itself, bool: _itself, str: _itself, int: int, float: _float,
           np.float64: _float, np.ndarray: _array}


@functools.cache
def _code(code):
    """Byte code, constants and names of a code object (recursively), without addresses
    or line numbers (once per code object: it is immutable; the description is read,
    never changed)."""
    consts = []
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            consts.append(_code(c))
        elif isinstance(c, frozenset):
            consts.append(sorted(repr(x) for x in c))
        else:
            consts.append(_ADDRESS.sub("", repr(c)))
    return {"code": code.co_code.hex(), "consts": consts, "names": list(code.co_names),
            "varnames": list(code.co_varnames)}


class _Describer:
    """Turns parameters into canonical JSON values."""

    def __init__(self, system=None, parts=False, closures=True):
        bodies = () if system is None else system.bodies
        self.bodies = {id(b): {"body": k} for k, b in enumerate(bodies)}
        if parts and system is not None:  # the system's other parts, by reference too
            parts = {"constraints": system.constraints, "loads": system.loads,
                     "point_masses": system.point_masses}
            for key, entries in parts.items():
                self.bodies.update({id(x): {key: k} for k, x in enumerate(entries)})
            if system.orbit is not None:
                self.bodies[id(system.orbit)] = {"orbit": True}
        self.system, self.closures = system, closures

    def __call__(self, obj, depth=0, path=()):
        leaf = _LEAVES.get(type(obj))
        if leaf is not None:
            return leaf(obj)
        if obj is None or isinstance(obj, (bool, str)):
            return obj
        if isinstance(obj, (int, np.integer)):
            return int(obj)
        if isinstance(obj, (float, np.floating)):
            return _float(obj)
        if isinstance(obj, (complex, np.complexfloating)):
            return {"complex": [float(obj.real).hex(), float(obj.imag).hex()]}
        if isinstance(obj, np.ndarray):
            return _array(obj)
        if isinstance(obj, types.ModuleType) and self.closures:  # a global a function reads
            return {"module": obj.__name__}
        if id(obj) in self.bodies:
            return self.bodies[id(obj)]
        if obj is not None and obj is self.system:
            return {"system": True}
        if id(obj) in path or depth > MAX_DEPTH:
            return {"class": _qualname(type(obj))}
        path = path + (id(obj),)
        down = depth + 1
        if isinstance(obj, (list, tuple)):
            return [self(x, down, path) for x in obj]
        if isinstance(obj, (set, frozenset)):
            items = [self(x, down, path) for x in obj]
            return sorted(items, key=lambda x: json.dumps(x, sort_keys=True))
        if isinstance(obj, dict):
            return {str(k): self(v, down, path) for k, v in sorted(obj.items(),
                                                                   key=lambda kv: str(kv[0]))}
        if hasattr(obj, "py_func"):  # a numba dispatcher
            return self(obj.py_func, depth, path)
        if isinstance(obj, types.MethodType):
            return {"method": self(obj.__func__, down, path),
                    "self": self(obj.__self__, down, path)}
        if isinstance(obj, types.FunctionType):
            return self._function(obj, down, path)
        if isinstance(obj, types.BuiltinFunctionType):
            return {"function": _qualname(obj)}
        if hasattr(obj, "func") and hasattr(obj, "args") and hasattr(obj, "keywords"):
            return {"partial": self(obj.func, down, path), "args": self(obj.args, down, path),
                    "keywords": self(obj.keywords, down, path)}
        if isinstance(obj, type):
            return {"type": _qualname(obj)}
        return {"class": _qualname(type(obj)), "attrs": self(_attributes(obj), down, path)}

    def _function(self, f, depth, path):
        """A Python function: its code, default arguments, the values it closes over
        (by their names) and the module globals its code reads (modules by name)."""
        out = {"function": _qualname(f), **_code(f.__code__),
               "defaults": self(f.__defaults__, depth, path)}
        if not self.closures:  # a store of version 1
            return out
        if f.__kwdefaults__:
            out["kwdefaults"] = self(f.__kwdefaults__, depth, path)
        if f.__closure__:
            out["closure"] = {name: self(_cell(cell), depth, path)
                              for name, cell in zip(f.__code__.co_freevars, f.__closure__)}
        read = [name for name in _global_names(f.__code__) if name in f.__globals__]
        if read:
            out["globals"] = {name: self(f.__globals__[name], depth, path) for name in read}
        return out


def _cell(cell):
    """The value of a closure cell (a marker when it is empty)."""
    try:
        return cell.cell_contents
    except ValueError:
        return "<empty cell>"


@functools.cache
def _global_names(code):
    """The names a code object (and the code it defines) may read from its globals,
    sorted."""
    names = set(code.co_names)
    for c in code.co_consts:
        if isinstance(c, types.CodeType):
            names.update(_global_names(c))
    return tuple(sorted(names))


@functools.cache
def _fields(cls):
    """The names of the fields of the dataclass ``cls``, or None if it is none; else the
    names in the ``__slots__`` of ``cls`` and its bases (in the order of its MRO): once per
    class."""
    if dataclasses.is_dataclass(cls):
        return None, tuple(f.name for f in dataclasses.fields(cls))
    return tuple(name for klass in cls.__mro__ for name in getattr(klass, "__slots__", ())
                 if isinstance(name, str)), None


def _attributes(obj):
    """The public and private data attributes of ``obj`` (``__dict__`` and ``__slots__``),
    or its representation when it has none (without memory addresses)."""
    slots, fields = _fields(type(obj))
    if fields is not None:
        attrs = {name: getattr(obj, name, None) for name in fields}
    else:
        attrs = dict(getattr(obj, "__dict__", {}))
        for name in slots:
            if hasattr(obj, name) and name not in attrs:
                attrs[name] = getattr(obj, name)
    if not attrs:
        return _ADDRESS.sub("", repr(obj))
    caches = getattr(obj, "caches", ())
    if not caches:
        return attrs
    caches = set(caches)
    return {k: v for k, v in attrs.items() if k not in caches}


def _body(d, body):
    """The description of one body (``describe_system``'s ``bodies`` entries)."""
    entry = {"class": _qualname(type(body)), "name": getattr(body, "name", None),
             "n_dofs": int(body.n_dofs), "q0": _array(np.asarray(body.q0, dtype=float))}
    section = getattr(body, "section", None)
    if section is not None:
        entry["section"] = d(section, 1)
    for attr in ("intorder", "formulation", "mass", "center_of_mass", "inertia",
                 "radius", "drive"):
        if hasattr(body, attr) and not callable(getattr(body, attr)):
            entry[attr] = d(getattr(body, attr), 1)
    law = getattr(body, "law", None)
    if law is not None:  # an element law: its physics (expressions) and own values
        entry["law"] = {"name": law.name, "key": law.key, "values": d(law.values, 1)}
    mesh = getattr(body, "mesh", None)
    if mesh is not None and hasattr(mesh, "p"):
        entry["mesh"] = {"p": _array(mesh.p), "t": _array(mesh.t)}
    return entry


def describe_bodies(system: SystemView, bodies=None, version=VERSION):
    """The descriptions of ``bodies`` (default: all) of ``system``, as in
    ``describe_system``'s ``bodies`` (fingerprints of ``version``): what a ``Result``
    keeps of what was simulated."""
    d = _Describer(system, closures=version >= 2)
    return [_body(d, body) for body in (system.bodies if bodies is None else bodies)]


def describe_system(system: SystemView, version=VERSION):
    """The canonical description of ``system`` that its fingerprint hashes (a JSON-able
    dict), as fingerprints of ``version`` describe it."""
    d = _Describer(system, closures=version >= 2)
    bodies = describe_bodies(system, version=version)
    M = system.mass_matrix().tocsr()
    M.sort_indices()
    constraints = []
    for c in system.constraints:
        constraints.append({"class": _qualname(type(c)), "name": getattr(c, "name", None),
                            "n_eq": int(c.n_eq), "labels": d(list(getattr(c, "labels", [])), 1),
                            "dofs": _array(np.asarray(c.dofs(system))),
                            "parameters": d(_attributes(c), 1)})
    loads = [{"class": _qualname(type(load)), "parameters": d(_attributes(load), 1)}
             for load in system.loads]
    masses = [{"class": _qualname(type(m)), "parameters": d(_attributes(m), 1)}
              for m in system.point_masses]
    out = {"n_dofs": int(system.n_dofs), "bodies": bodies,
           "mass_matrix": {"data": _array(M.data), "indices": _array(M.indices),
                           "indptr": _array(M.indptr)},
           "constraints": constraints, "loads": loads, "point_masses": masses}
    if system.epoch is not None:  # a system in orbit at an epoch
        out["epoch"] = system.epoch.utc
    return out


def differences(before, after):
    """What differs between two descriptions of a system (``describe_system``), one
    readable line per changed entry: ``loads[0] (Gravity): g``, ``bodies[0] (cable):
    section.rho``, ``mass_matrix``, ``constraints: 2 now, 1 before``.

    Examples
    --------
    >>> from skfem_cable.scenes import classics
    >>> system = classics.pendulum(n_elements=2).system
    >>> before = describe_system(system)
    >>> system.loads[0].g = 2 * system.loads[0].g
    >>> differences(before, describe_system(system))
    ['loads[0] (Gravity): g']
    """
    out = []
    for key in sorted(set(before) | set(after)):
        old, new = before.get(key), after.get(key)
        if old == new:
            continue
        if key in _ENTRIES and len(old) == len(new):
            out += [f"{key}[{k}] ({_label(b)}): {', '.join(dict.fromkeys(_paths(a, b)))}"
                    for k, (a, b) in enumerate(zip(old, new)) if a != b]
        elif key in _ENTRIES:
            out.append(f"{key}: {len(new)} now, {len(old)} before")
        else:
            out.append(key)
    return out


def _label(entry):
    """The name of a described body or constraint, else the class of a load or mass."""
    return entry.get("name") or entry["class"].rsplit(".", 1)[-1]


def _paths(old, new, path=()):
    """The dotted paths of the parts that differ between two described values."""
    if old == new:
        return []
    if isinstance(old, dict) and isinstance(new, dict):
        return [p for k in sorted(set(old) | set(new))
                for p in _paths(old.get(k), new.get(k), path if k in _WRAPPERS else path + (k,))]
    if isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        return [p for i, (a, b) in enumerate(zip(old, new))
                for p in _paths(a, b, path + (f"[{i}]",))]
    return [".".join(path).replace(".[", "[") or "another class"]


def part_digests(description):
    """SHA-256 of each parameter of each body, constraint, load and point mass of a
    system's ``description`` (``describe_system``), keyed by part (``loads[0]
    (SolarWindForce)``) and parameter (``wind``): what a run store keeps to name what
    changed (``changed_parts``) without keeping the parameters."""
    out = {}
    for key in _ENTRIES:
        for k, entry in enumerate(description.get(key, [])):
            fields = entry.get("parameters", entry)
            fields = fields if isinstance(fields, dict) else {"": fields}
            out[f"{key}[{k}] ({_label(entry)})"] = {name: _hash(value)
                                                   for name, value in fields.items()}
    return out


def changed_parts(stored, description):
    """The parts and parameters whose digests in ``stored`` (``part_digests`` of a
    store's system) differ from those of ``description``, one readable line per part:
    ``loads[0] (SolarWindForce): wind``."""
    now = part_digests(description)
    out = []
    for part in sorted(set(stored) | set(now)):
        old, new = stored.get(part, {}), now.get(part, {})
        names = [n or "parameters" for n in sorted(set(old) | set(new))
                 if old.get(n) != new.get(n)]
        if names:
            out.append(f"{part}: {', '.join(names)}")
    return out


def digest(obj, system: SystemView):
    """SHA-256 (hex) of the description of ``obj``, which refers to the parts of
    ``system`` (its bodies, loads, constraints, point masses and orbit) by their place:
    what a controller holds besides numbers and arrays (``control``)."""
    return _hash(_Describer(system, parts=True)(obj))


def code_digest(cls, system: SystemView, stop=()):
    """SHA-256 (hex) of the functions that ``cls`` and its bases but ``stop`` define
    (described as parameters are: code, defaults, closures, globals; the parts of
    ``system`` by reference): what a controller's code is (``control``)."""
    d = _Describer(system, parts=True)
    return _hash({f"{klass.__qualname__}.{name}": d(f) for klass in cls.__mro__
                  if klass not in (*stop, object)
                  for name, f in vars(klass).items() if callable(f)})


def _settings(settings):
    d = _Describer()
    return {k: d(v) for k, v in sorted(settings.items()) if k not in FREE_SETTINGS}


def _hash(value):
    return _digest(json.dumps(value, sort_keys=True, separators=(",", ":")).encode())


def system_fingerprint(system: SystemView, version=VERSION):
    """SHA-256 (hex) of ``describe_system(system, version)``."""
    return _hash(describe_system(system, version))


def settings_fingerprint(settings):
    """SHA-256 (hex) of the solver settings (``run.settings``) but ``t_end``/``n_steps``."""
    return _hash(_settings(settings))


def fingerprint(system: SystemView, settings=None):
    """The fingerprint of a run: SHA-256 (hex) of the system (``system_fingerprint``) and,
    when given, of the solver settings ``settings`` (``run.settings``, without ``t_end``
    and ``n_steps``).

    Examples
    --------
    >>> from skfem_cable.scenes import classics
    >>> a = fingerprint(classics.pendulum(n_elements=4).system)
    >>> a == fingerprint(classics.pendulum(n_elements=4).system)
    True
    >>> a == fingerprint(classics.pendulum(n_elements=5).system)
    False
    """
    parts = {"system": system_fingerprint(system)}
    if settings is not None:
        parts["settings"] = settings_fingerprint(settings)
    return _hash(parts)
