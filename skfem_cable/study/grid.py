"""The points of a parameter study: grids, their dimensions, the name of each point's run
directory, and parameters given on the command line (``NAME=V1,V2,...``)."""

import hashlib
import inspect
import itertools
import json
import re

#: Dimension of a study given as a list of parameter dicts.
RUN_DIM = "run"

_UNSAFE = re.compile(r"[^A-Za-z0-9.=+_-]+")


def points(grid):
    """The points of ``grid`` and the dimensions of the study's dataset.

    Parameters
    ----------
    grid : dict or list of dict
        ``{name: [values]}``: the outer product, one dimension per name (in order);
        or a list of ``{name: value}`` dicts with the same names: one dimension ``run``.

    Returns
    -------
    dims : dict
        ``{dimension: coordinate values}``.
    points : list of (tuple, dict)
        Per point, its index along ``dims`` and its parameters.
    coords : dict
        ``{name: (dims, values)}``: the coordinates (for a list, each parameter along
        ``run``).

    Examples
    --------
    >>> dims, pts, _ = points({"alpha": [0, 10], "voltage": [1.0]})
    >>> list(dims), pts[1]
    (['alpha', 'voltage'], ((1, 0), {'alpha': 10, 'voltage': 1.0}))
    """
    if isinstance(grid, dict):
        if not grid:
            raise ValueError("grid is empty: give at least one parameter with its values")
        dims = {}
        for name, values in grid.items():
            values = list(values) if _iterable(values) else [values]
            if not values:
                raise ValueError(f"parameter {name!r} of the grid has no values")
            if len(set(map(_canonical, values))) != len(values):
                raise ValueError(f"parameter {name!r} of the grid repeats a value: {values}")
            dims[name] = values
        pts = [(index, {name: dims[name][i] for name, i in zip(dims, index)})
               for index in itertools.product(*(range(len(v)) for v in dims.values()))]
        return dims, pts, {name: ((name,), values) for name, values in dims.items()}
    grid = list(grid)
    if not grid or not all(isinstance(p, dict) for p in grid):
        raise ValueError("grid must be a dict of value lists or a non-empty list of dicts")
    names = list(grid[0])
    for k, p in enumerate(grid):
        if list(p) != names:
            raise ValueError(f"grid point {k} has the parameters {sorted(p)}, point 0 has "
                             f"{sorted(names)}: every point must name the same parameters")
    if len({_canonical(p) for p in grid}) != len(grid):
        raise ValueError("grid repeats a point")
    coords = {name: ((RUN_DIM,), [p[name] for p in grid]) for name in names}
    return {RUN_DIM: list(range(len(grid)))}, [((k,), dict(p)) for k, p in enumerate(grid)], \
        coords


def _iterable(values):
    return not isinstance(values, (str, bytes)) and hasattr(values, "__iter__")


def check_names(build, names):
    """Raise ``ValueError`` unless ``build`` takes every parameter of ``names`` as a
    keyword, naming the ones it accepts."""
    try:
        signature = inspect.signature(build)
    except (TypeError, ValueError):  # a builtin or C function: nothing to check
        return
    params = signature.parameters.values()
    if any(p.kind is p.VAR_KEYWORD for p in params):
        return
    accepted = [p.name for p in params if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]
    unknown = [n for n in names if n not in accepted]
    if unknown:
        raise ValueError(f"{build_name(build)} does not take the parameter {unknown[0]!r}: its "
                         f"parameters are {', '.join(accepted) or 'none'}")


def build_name(build):
    """``module:qualname`` of ``build`` (recorded in the study, hashed into run names)."""
    return f"{getattr(build, '__module__', '?')}:{getattr(build, '__qualname__', repr(build))}"


def _canonical(value):
    """``value`` as canonical JSON: numbers as floats (``10`` and ``10.0`` are one value),
    dicts sorted."""
    def plain(x):
        if isinstance(x, dict):
            return {str(k): plain(v) for k, v in sorted(x.items())}
        if isinstance(x, (list, tuple)):
            return [plain(v) for v in x]
        if isinstance(x, bool) or x is None or isinstance(x, str):
            return x
        try:
            return float(x).hex()
        except (TypeError, ValueError):
            return repr(x)
    return json.dumps(plain(value), sort_keys=True)


def run_name(build, params):
    """Name of the run directory of the point ``params`` of a study of ``build``: the
    parameters in readable form and a hash of the build function's name and all
    parameters (``10`` and ``10.0`` are the same value), so that a re-run of the study
    finds it again, whatever the order or the other points of the grid.

    Examples
    --------
    >>> run_name(run_name, {"voltage": 2e4, "alpha": 10.0})[:25]
    'alpha=10_voltage=20000-0x'
    """
    digest = hashlib.sha256(_canonical({"build": build_name(build), "parameters": params})
                            .encode()).hexdigest()[:12]
    readable = "_".join(f"{k}={_short(v)}" for k, v in sorted(params.items()))
    return f"{_UNSAFE.sub('-', readable)[:80]}-0x{digest}"


#: Words of the command line read as booleans (any case).
BOOLEANS = {"true": True, "false": False}


def _short(value):
    """``value`` for a directory name: numbers as ``:g`` (``10`` and ``10.0`` alike)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    return f"{value:g}"


def parse_value(text):
    """A value of the command line: ``true``/``false`` (``BOOLEANS``), an integer, a
    float, else the text."""
    if text.lower() in BOOLEANS:
        return BOOLEANS[text.lower()]
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def parse_param(text):
    """``"NAME=V1,V2,..."`` as ``(name, [values])`` (``parse_value``); the values of one
    parameter are all floats when one is.

    Examples
    --------
    >>> parse_param("alpha=0,10,22.5")
    ('alpha', [0.0, 10.0, 22.5])
    """
    name, sep, values = text.partition("=")
    name = name.strip()
    if not sep or not name.isidentifier() or not values.strip():
        raise ValueError(f"--param {text!r}: expected NAME=V1,V2,... (e.g. alpha=0,10,20)")
    parsed = [parse_value(v.strip()) for v in values.split(",")]
    if any(isinstance(v, float) for v in parsed) and all(
            isinstance(v, (int, float)) and not isinstance(v, bool) for v in parsed):
        parsed = [float(v) for v in parsed]
    return name, parsed
