"""The summary of a run (``summary.json``): the key numbers of its bodies and of a dynamic
run (``body_outputs``, ``run_outputs``), the orbit of a system in orbit
(``orbit_summary``), the run's warnings (``run_warnings``, ``warn``), the file
(``write_summary``) and the lines the CLI prints (``format_summary``)."""

import json
import sys
from pathlib import Path

import numpy as np

from ..core.protocols import Line
from ..space.orbit import Orbit
from ..util.atomic import write_atomic
from ..util.jsonable import jsonable
from .directory import DESCRIPTIONS, SUMMARY, described_files


def write_summary(out, summary):
    """Write ``summary.json`` into the run directory ``out`` with ``files.described``, the
    run's files and their descriptions (``described_files``); returns its path."""
    files = summary.setdefault("files", {})
    files["described"] = {**described_files(out), SUMMARY: DESCRIPTIONS[SUMMARY]}
    path = Path(out) / SUMMARY
    write_atomic(path, (json.dumps(jsonable(summary), indent=2) + "\n").encode())
    return path


def body_outputs(system, q, t=0.0):
    """Key numbers of every body at coordinates ``q`` and time ``t`` (``Body.outputs``):
    ``{"cables": {name: ...}}`` for the bodies with fields along a line (tip position,
    root and peak tension, length, elements), ``"bodies"`` for the others (a rigid body's
    centre of mass, a reel's length, a user's body's own numbers) when there are any."""
    out = {"cables": {}, "bodies": {}}
    for body in system.bodies:
        group = "cables" if isinstance(body, Line) else "bodies"
        out[group][body.name] = body.outputs(system, q, t)
    return out if out["bodies"] else {"cables": out["cables"]}


def orbit_elements(orbit):
    """The elements of ``orbit`` (an ``Orbit``) for a summary: ``a`` (m), ``e``,
    ``inclination``, ``raan``, ``argp``, ``anomaly`` (the true anomaly at ``t``) and
    ``longitude`` (the true longitude ``raan + argp + anomaly`` in ``[0, 2 pi)``: well
    defined also when a nearly circular or nearly equatorial orbit leaves its terms
    ill-conditioned), all in rad, ``t`` (s, the epoch) and ``period`` (s)."""
    return {"a": orbit.a, "e": orbit.e, "inclination": orbit.inclination,
            "raan": orbit.raan, "argp": orbit.argp, "anomaly": orbit.anomaly,
            "longitude": float(np.remainder(orbit.raan + orbit.argp + orbit.anomaly,
                                            2 * np.pi)),
            "t": orbit.t0, "period": orbit.period}


def centre_of_mass_orbit(system, state, reference=None):
    """The osculating orbit of the centre of mass of ``system`` (in orbit) at ``state``:
    ``Orbit.from_state(mu, R(t) + x_cm, V(t) + v_cm, t)``, with ``x_cm``, ``v_cm`` from
    ``System.centre_of_mass`` and ``R``, ``V`` of the run's ``reference``
    (``Result.reference``; None: the orbit as given)."""
    v = np.zeros_like(state.q) if state.v is None else state.v
    x_cm, v_cm = system.centre_of_mass(state.q), system.centre_of_mass(v)
    reference = system.orbit if reference is None else reference
    return Orbit.from_state(reference.mu, reference.position(state.t) + x_cm,
                            reference.velocity(state.t) + v_cm, state.t)


def orbit_summary(system, first, last, reference=None):
    """The orbit of a run of ``system`` (in orbit) for its summary: ``mu``, the
    ``reference`` orbit's elements and the osculating elements of the centre of mass at
    the ``first`` and ``last`` states (``start``, ``end``; ``orbit_elements``) against the
    run's ``reference`` (``Result.reference``; None: the orbit as given)."""
    return {"mu": system.orbit.mu, "reference": orbit_elements(system.orbit),
            "start": orbit_elements(centre_of_mass_orbit(system, first, reference)),
            "end": orbit_elements(centre_of_mass_orbit(system, last, reference))}


def orbiting_cable_outputs(result, cable):
    """Key numbers of a cable of a run in orbit: the libration angles (rad) of its
    end-to-end line in the orbiting frame (``Orbit.libration``), in the orbit plane
    (``libration_in_plane``, pitch) and out of it (``libration_out_of_plane``, roll), at
    the end and their largest magnitudes over the run, and the centre tension (N, at
    mid-length) at the end and its largest over the run."""
    ends = result.position(cable, np.array([0.0, cable.length]))
    in_plane, out_of_plane = result.reference.libration(result.t, ends[:, 1] - ends[:, 0])
    centre = result.tension(cable, 0.5 * cable.length)
    return {"libration_in_plane": in_plane[-1], "libration_out_of_plane": out_of_plane[-1],
            "max_libration_in_plane_run": np.abs(in_plane).max(),
            "max_libration_out_of_plane_run": np.abs(out_of_plane).max(),
            "centre_tension": centre[-1], "max_centre_tension_run": centre.max()}


def run_outputs(result):
    """Key numbers of a dynamic run: the cables at the end and their tension extremes over
    the run (in orbit also their librations and centre tensions,
    ``orbiting_cable_outputs``), the loads' own numbers (``loads``, keyed by their place
    and kind, from the loads with ``outputs(result)``: an electrodynamic tether's current,
    EMF and power at the end) and the energy budget."""
    system = result.system
    out = body_outputs(system, result.q[-1], result.t[-1])
    for cable in system.cables():
        T = result.tension(cable, cable.mesh.p[0])
        out["cables"][cable.name].update(max_tension_run=T.max(), min_tension_run=T.min())
        if system.orbit is not None:
            out["cables"][cable.name].update(orbiting_cable_outputs(result, cable))
    loads = {f"{k} {type(load).__name__}": load.outputs(result)
             for k, load in enumerate(system.loads) if callable(getattr(load, "outputs",
                                                                        None))}
    if loads:
        out["loads"] = loads
    E = result.energy
    scale = max(np.abs(E["total"]).max(), np.abs(E["kinetic"]).max(), 1e-300)
    out["energy"] = {"total_initial": E["total"][0], "total_final": E["total"][-1],
                     "dissipated": E["dissipated"][-1],
                     "external_work": E["external_work"][-1],
                     "max_abs_balance_relative": np.abs(E["balance"]).max() / scale,
                     "bodies_final": system.energy_parts(result.q[-1], result.v[-1],
                                                         result.t[-1])}
    return out


#: Drift of the energy balance, relative to the energy content, above which a run's
#: summary warns: the time step dissipated (or, within the guard, created) that much.
BALANCE_WARNING = 0.02


def run_warnings(summary):
    """Warnings about a finished dynamic run that its numbers alone would not show."""
    drift = summary["outputs"]["energy"]["max_abs_balance_relative"]
    if drift > BALANCE_WARNING:
        return [f"the energy balance drifted by {100 * drift:.3g} % of the energy content: "
                "the time step dissipates numerically (rho_inf < 1) or resolves the motion "
                "poorly; results may be far from the converged ones: reduce dt"]
    return []


def warn(message):
    """Print a warning of a run on stderr (prefixed ``skfem-cable:``)."""
    print(f"skfem-cable: {message}", file=sys.stderr)


def complete_summary(summary, result, outputs=None, warnings=()):
    """Add a scene's own key numbers ``outputs(result)`` to ``summary["outputs"]`` and the
    run's warnings (``run_warnings`` and ``warnings``), printing each."""
    if outputs is not None:
        summary["outputs"].update(outputs(result))
    summary["warnings"] = run_warnings(summary) + list(warnings)
    for warning in summary["warnings"]:
        warn(warning)


def format_summary(summary):
    """A few readable lines about a finished run (what the CLI prints)."""
    lines = [f"scene {summary['scene']}"]
    if "newton" in summary:
        nw = summary["newton"]
        seconds = summary.get("integration_time", summary["wall_time"])
        lines.append(f"  {summary['steps']} steps in {seconds:.2f} s, "
                     f"{nw['per_step']:.2f} Newton iterations per step, "
                     f"{nw['rejected_steps']} rejected")
        if "compile_time" in summary:
            lines.append(f"  compiling the kernels (or loading them from the cache): "
                         f"{summary['compile_time']:.2f} s")
    elif "integration" in summary:
        it = summary["integration"]
        lines.append(f"  {it['steps']} {it['method']} steps of {it['step']:.3g} s in "
                     f"{summary['wall_time']:.2f} s")
    lines.extend(_format_tree(summary.get("outputs", {}), "  "))
    if "orbit" in summary:
        lines.append("  orbit (osculating elements of the centre of mass; m, rad, s):")
        lines.extend(_format_tree(summary["orbit"], "    "))
    store = summary.get("store")
    if store:
        lines.append(f"  store {store['path']}: {store['saved_steps']} saved steps, "
                     f"{store['bytes'] / 1e6:.3g} MB, {store['status']}")
    return "\n".join(lines)


def _format_value(value):
    """One line for a number or an array (a matrix's rows side by side)."""
    value = np.asarray(value)
    if value.ndim > 1:
        return "[" + " ".join(_format_value(row) for row in value) + "]"
    if value.ndim:
        return np.array2string(value, precision=6, max_line_width=10**6)
    return f"{value.item():.6g}" if value.dtype.kind == "f" else str(value)


#: Printed members of a group of bodies at most (``summary.json`` keeps them all).
MAX_PRINTED = 3


def _format_tree(tree, indent):
    group = len(tree) > MAX_PRINTED + 1 and all(isinstance(v, dict) for v in tree.values())
    for k, (key, value) in enumerate(tree.items()):
        if group and k == MAX_PRINTED:
            yield f"{indent}... {len(tree) - MAX_PRINTED} more in summary.json"
            return
        if isinstance(value, dict):
            yield f"{indent}{key}:"
            yield from _format_tree(value, indent + "  ")
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            yield f"{indent}{key}:"
            columns = list(value[0])
            yield indent + "  " + " ".join(f"{c:>12}" for c in columns)
            for row in value:
                yield indent + "  " + " ".join(f"{_format_value(row[c]):>12}" for c in columns)
        else:
            yield f"{indent}{key}: {_format_value(value)}"
