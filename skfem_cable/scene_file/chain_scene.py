"""A rod-chain scene (``skfem_cable.rodchain``) from a scene file: the ``[rod_chain]``
table (rods, material, anchor), ``[loads]``, ``[initial]``, ``[solver]`` and
``[output]``, each read by one function; ``run`` fills a run directory
(``rodchain.run.run_chain``).  The schema is in ``docs/rodchain.md``."""

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..rodchain import METHODS, RodChain, circular_anchor
from .schema import boolean, choice, count, number, one_of, positive, text, vector3

#: Material presets of ``[rod_chain]``: defaults for the keys not given.  ``"steel"`` is
#: the paper's steel tether (Ma & Wang, Sect. 3): 1.1 m of 1 mm-radius steel wire.
PRESETS = {"steel": {"density": 7801.0, "radius": 1e-3, "E": 207e9, "length": 1.1}}


@dataclass
class ChainSceneSpec:
    """A rod-chain scene read from a file.

    Attributes
    ----------
    title : str
    chain : RodChain
    initial : (ndarray, ndarray)
        Rod vectors and rates (n, 3).
    loads : dict
        ``RodChain.simulate`` keywords: ``gravity``, ``tip_force``, ``line_load``,
        ``anchor``.
    solver : dict
        ``t_end``, ``dt`` (spacing of the saved steps), ``method``, ``max_strain`` and,
        when given, ``step`` (the RK4 step), ``rtol``, ``atol``.
    series_every : int
        A ``.vtu`` for every ``series_every``-th saved step.
    parameters : dict
        What the file says about the chain, for the summary.
    """

    title: str
    chain: RodChain
    initial: tuple
    loads: dict
    solver: dict
    series_every: int = 1
    parameters: dict = field(default_factory=dict)


def _total_or_material(t, preset, keys, area, factor, meaning):
    """A quantity given either in total (``keys[0]``) or as a material constant
    (``keys[1]``, from the table or the ``preset``) times ``area * factor``."""
    total, material = keys
    key, value = one_of(t, keys, positive)
    if key is None and material in preset:
        key, value = material, preset[material]
    if key is None:
        t.fail(total, f"is required ({meaning})")
    if key == material:
        if area is None:
            t.fail(material, "needs the section: A or radius", value)
        value = value * area * factor
    return value


def read_chain(t, elements=None):
    """``[rod_chain]``: ``rods`` equal rods over the total rest ``length``, their mass
    (``mass`` in total, or ``density`` with the section), section (``A`` or ``radius``),
    axial stiffness (``EA``, or ``E`` with the section), ``compression``; a ``preset``
    supplies the material keys not given.  Returns the chain and its parameters."""
    preset_name = t.get("preset", choice(*PRESETS), None)
    preset = PRESETS.get(preset_name, {})
    n = t.get("rods", count, elements)
    if n is None:
        t.fail("rods", "is required")
    n = elements or n
    length = t.get("length", positive, preset.get("length"))
    if length is None:
        t.fail("length", "is required (the total rest length, m)")
    key, value = one_of(t, ("A", "radius"), positive)
    if key is None and "radius" in preset:
        key, value = "radius", preset["radius"]
    area = None if key is None else (value if key == "A" else np.pi * value**2)
    mass = _total_or_material(t, preset, ("mass", "density"), area, length,
                              "total mass in kg, or density with A or radius")
    stiffness = _total_or_material(t, preset, ("EA", "E"), area, 1.0,
                                   "axial stiffness in N, or E with A or radius")
    compression = t.get("compression", boolean, True)
    chain = RodChain(np.full(n, mass / n), np.full(n, length / n), np.full(n, stiffness),
                     compression)
    parameters = {"rods": n, "length": length, "mass": mass, "EA": stiffness,
                  "compression": compression, "preset": preset_name}
    return chain, parameters


def read_anchor(t):
    """``anchor`` of ``[rod_chain]``: a fixed point ``[x, y, z]`` (default the origin) or a
    table ``{ motion = "circular", radius, omega, center, normal, phase }``
    (``circular_anchor``)."""
    value = t.data.get("anchor")
    if not isinstance(value, dict):
        return t.get("anchor", vector3, np.zeros(3))
    a = t.inline("anchor")
    a.get("motion", choice("circular"))
    motion = circular_anchor(a.get("radius", positive), a.get("omega", number),
                             center=a.get("center", vector3, np.zeros(3)),
                             normal=a.get("normal", vector3, np.array([0.0, 0.0, 1.0])),
                             phase=a.get("phase", number, 0.0))
    a.finish()
    return motion


def read_loads(t):
    """``[loads]``: ``gravity`` (m/s^2), ``tip_force`` (N, at the free end), ``line_load``
    (N per metre of current length, uniform); all default to zero."""
    loads = {"gravity": t.get("gravity", vector3, np.zeros(3))}
    for key in ("tip_force", "line_load"):
        value = t.get(key, vector3, None)
        if value is not None:
            loads[key] = value
    t.finish()
    return loads


def read_initial(t, chain, loads):
    """``[initial]``: ``shape = "straight"`` (default; unstretched along ``direction``,
    default ``[1, 0, 0]``) or ``"equilibrium"`` (the static equilibrium under gravity and
    the tip force), turning about the anchor at ``angular_velocity`` (rad/s, default 0:
    rod rates ``omega x q_i``)."""
    shape = t.get("shape", choice("straight", "equilibrium"), "straight")
    if shape == "straight":
        d = t.get("direction", vector3, np.array([1.0, 0.0, 0.0]))
        if not np.linalg.norm(d) > 0:
            t.fail("direction", "must be a non-zero vector", list(d))
        q0 = np.outer(chain.lengths, d / np.linalg.norm(d))
    else:
        try:
            q0 = chain.static_equilibrium(loads["gravity"], loads.get("tip_force"))
        except ValueError:
            q0 = None
        if q0 is None:
            t.fail("shape", "needs gravity or a tip force that tensions every rod "
                   "([loads])", shape)
    omega = t.get("angular_velocity", vector3, np.zeros(3))
    t.finish()
    return q0, np.cross(omega, q0)


def read_solver(t, chain):
    """``[solver]``: ``t_end``, ``dt`` (spacing of the saved steps), ``method``, ``step``
    (RK4 step, default the largest below 0.7 ``stable_dt`` that divides ``dt``), ``rtol``
    and ``atol`` (adaptive methods), ``max_strain``."""
    s = {"t_end": t.get("t_end", positive), "dt": t.get("dt", positive),
         "method": t.get("method", choice(*METHODS), "rk4")}
    rk4 = s["method"] == "rk4"
    for key in ("step", "rtol", "atol"):
        if key in t.data and rk4 != (key == "step"):
            t.fail(key, "applies to method = " + ("'rk4' only" if key == "step" else
                                                   "'RK45' or 'DOP853' only"), t.data[key])
        value = t.get(key, positive, None)
        if value is not None:
            s[key] = value
    s["max_strain"] = t.get("max_strain", positive, 1.0)
    if abs(round(s["t_end"] / s["dt"]) * s["dt"] - s["t_end"]) > 1e-9 * s["t_end"]:
        t.fail("t_end", f"must be a multiple of dt = {s['dt']:g} s", s["t_end"])
    if "step" in s:
        if s["step"] > chain.stable_dt():
            t.fail("step", f"exceeds the RK4 stability limit of this chain, "
                   f"{chain.stable_dt():.6g} s", s["step"])
        k = round(s["dt"] / s["step"])
        if k < 1 or abs(k * s["step"] - s["dt"]) > 1e-9 * s["dt"]:
            t.fail("step", f"must divide dt = {s['dt']:g} s", s["step"])
    t.finish()
    return s


def build(root, elements=None):
    """The ``ChainSceneSpec`` of the root table ``root``; ``elements`` overrides the
    number of rods (at fixed total length and mass)."""
    title = root.get("title", text, "")
    spec = root.table("rod_chain")
    chain, parameters = read_chain(spec, elements)
    anchor = read_anchor(spec)
    spec.finish()
    loads = read_loads(root.table("loads"))
    initial = read_initial(root.table("initial"), chain, loads)
    if callable(anchor):
        loads["anchor"] = anchor
    elif np.any(anchor != 0):
        loads["anchor"] = anchor
    solver = read_solver(root.table("solver"), chain)
    out = root.table("output")
    series_every = out.get("series_every", count, 1)
    out.finish()
    root.finish()
    return ChainSceneSpec(title, chain, initial, loads, solver, series_every, parameters)


def run(path, spec, options):
    """Run the ``ChainSceneSpec`` read from ``path`` into the run directory
    ``options.out`` (``rodchain.run.run_chain``); returns the summary."""
    from ..rodchain.run import run_chain

    options.reject(Path(path).name, "frame")  # a rod chain is never in orbit (yet)
    parameters = {"file": str(path), "title": spec.title, **spec.parameters}
    defaults = {**spec.solver, "series_every": spec.series_every}
    return run_chain(Path(path).stem, spec.chain, spec.initial, options, defaults,
                     loads=spec.loads, parameters=parameters)[0]
