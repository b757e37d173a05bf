"""Time histories of a simulation: the saved steps, held in memory.

``simulate`` returns a ``Result``; a run directory written by ``io.RunStore`` is read back
with ``Result.load`` (xarray users open its store directly, see
``docs/output.md``).  Nothing here touches the disk except ``load``.
"""

import numpy as np

from ..core.protocols import IntegrableSystem, SystemView
from ..core.records import FIELDS, OUTPUT, input_records, prefixed_records
from ..model.fingerprint import describe_bodies, describe_system, differences
from ..model.state import State
from ..space.reference import Reference


class Result:
    """Saved steps of a run: ``t, q, v, a, lam`` (leading axis: time), ``iterations``
    (Newton iterations of each saved step), ``energy`` and ``stats``.

    Parameters
    ----------
    system : System
        The system that was run (the fields along cables, ``position``, ``tension``, ...,
        read an ``IntegrableSystem``; a run store hands a rod chain's run its
        ``SystemView``).
    records : dict of array_like
        The ``FIELDS``, each with the saved steps along its first axis.
    stats : dict, optional
        Solver counters.
    description : dict, optional
        The system as it was simulated (``io.fingerprint.describe_system``: a solver's
        ``Layout.description``); default: the system as it is now.
    reference : orbit.Reference, optional
        In orbit, the run's reference (the orbit and the rebases of its rectification);
        default: the system's orbit as given, without rebases.

    Attributes
    ----------
    system : System
    t : ndarray (nt,)
        Saved times (s).
    q, v, a : ndarray (nt, n_dofs)
        Coordinates, velocities and accelerations (NaN where a store left them out).
    lam : ndarray (nt, n_constraints)
        Lagrange multipliers.
    iterations : ndarray (nt,)
        Newton iterations of each saved step.
    kinetic, axial, bending, potential, dissipated, external_work : ndarray (nt,)
        The energies (J) of ``ENERGIES``; ``energy`` combines them.
    stats : dict
        Solver counters: ``steps``, ``newton``, ``rejected``, ``wall_time``,
        ``compile_time`` and ``integration_time`` (``simulate``), ...
    inputs : dict
        The values the system's inputs (``inputs.Input``) held at each saved step, by
        name (``(nt, *shape)``; what controllers set: ``control``).
    outputs : dict
        The loads' numbers at each saved step (``Term.outputs``), by the names the loads
        declare (``step_outputs``): ``(nt,)`` arrays (e.g. the OML current,
        ``ElectrodynamicForce``), and ``(nt, *shape)`` for the arrays they declare
        (``step_arrays``: a contact's forces per element).
    reference : orbit.Reference or None
        In orbit, the reference the offsets were computed against (the run's: the
        orbit's arcs and the rectification's rebases); its ``position(t)``, ``lvlh(t)``,
        ... turn the saved offsets into absolute positions and orbiting frames.  None out
        of orbit.

    Notes
    -----
    A result answers from what was simulated: it keeps a description of the bodies and
    the constraints' names as they were run (``description``).  After
    the system was edited (``cable.section = ...``), ``tension`` and ``curvature`` of an
    edited cable and ``multipliers`` after a constraint was added raise
    ``SystemChanged`` naming the edit, where they would mix the stored motion with the
    edited system; ``position``, ``velocity``, ``state`` and the energies are the stored
    data (``state(-1)`` is where a run of the edited system may start).

    See Also
    --------
    simulate : returns a ``Result``.
    State : one configuration; ``state(i)``.

    Examples
    --------
    A pendulum released from horizontal, 20 steps of 1 ms:

    >>> import skfem_cable as sc
    >>> sec = sc.Section.circular(radius=0.01, E=7e10, rho=7800.0)
    >>> cable = sc.Cable.straight([0, 0, 0], [1.2, 0, 0], 4, sec)
    >>> system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
    >>> result = sc.simulate(system, t_end=0.02, dt=1e-3, every=10)
    >>> len(result), result.t.tolist(), result.position(cable, 1.2).shape
    (3, [0.0, 0.01, 0.02], (3, 3))
    >>> round(float(result.position(cable, 1.2)[-1, 1]), 4)   # tip height (m)
    -0.0024
    >>> bool(abs(result.energy["balance"]).max() < 1e-5)     # energy books close (J)
    True
    >>> result.state(-1).q.shape, list(result.multipliers)
    ((30,), ['pin Node(cable, 0)'])
    """

    def __init__(self, system: SystemView, records, stats=None, description=None,
                 reference=None):
        self.system = system
        orbit = system.orbit
        self.reference = reference if reference is not None or orbit is None else \
            Reference(orbit)
        for name in FIELDS:
            setattr(self, name, np.asarray(records[name]))
        self.inputs = input_records(records)
        self.outputs = prefixed_records(records, OUTPUT)
        self.stats = dict(stats or {})
        description = describe_system(system) if description is None else description
        self._simulated = {"bodies": description["bodies"],
                           "constraints": [(c["name"], c["n_eq"])
                                           for c in description["constraints"]]}

    @property
    def energy(self):
        """Dict of arrays: ``kinetic``, ``elastic`` (= ``axial`` + ``bending``),
        ``potential`` (constant loads and gravity), ``dissipated`` (internal damping, time
        integral of its power), ``external_work`` (time-dependent loads and moments),
        ``total`` (= kinetic + elastic + potential) and ``balance`` (total + dissipated -
        external_work - total at the first saved step; nonzero only through time
        discretisation and numerical dissipation)."""
        elastic = self.axial + self.bending
        total = self.kinetic + elastic + self.potential
        budget = total + self.dissipated - self.external_work
        return {"kinetic": self.kinetic, "axial": self.axial, "bending": self.bending,
                "elastic": elastic, "potential": self.potential,
                "dissipated": self.dissipated, "external_work": self.external_work,
                "total": total, "balance": budget - budget[0]}

    def _fields(self, cable, coords, s, k):
        return cable.interpolate(coords[:, self.system.dofs(cable)], s)[k]

    def position(self, cable, s):
        """Positions ``(nt,) + s.shape + (3,)`` at reference arc lengths ``s``."""
        return self._fields(cable, self.q, s, 0)

    def velocity(self, cable, s):
        """Velocities ``(nt,) + s.shape + (3,)`` at reference arc lengths ``s``."""
        return self._fields(cable, self.v, s, 0)

    def tension(self, cable, s):
        """Axial forces (N) ``(nt,) + s.shape`` at reference arc lengths ``s``
        (``Cable.tension``) of the cable as simulated (``SystemChanged`` if it was edited
        since)."""
        return cable.tension(self.q[:, self._simulated_dofs(cable, "tension")], s,
                             self.system.stretch(cable, self.t, self.q), self.t)

    def curvature(self, cable, s):
        """Curvatures (1/m) ``(nt,) + s.shape`` at reference arc lengths ``s`` of the
        cable as simulated (``SystemChanged`` if it was edited since)."""
        return cable.curvature(self.q[:, self._simulated_dofs(cable, "curvature")], s,
                               self.system.stretch(cable, self.t, self.q))

    def _simulated_dofs(self, cable, what):
        """The coordinates of ``cable``, once it is known to be the cable as simulated:
        else ``SystemChanged`` naming the edit, since its ``what`` would come from the
        edited cable (its section, law, mesh, ...) and the stored motion of the other."""
        dofs = self.system.dofs(cable)
        k = next(k for k, body in enumerate(self.system.bodies) if body is cable)
        old = self._simulated["bodies"]
        new = [*old[:k], *describe_bodies(self.system, [cable]), *old[k + 1:]]
        _refuse_changed(differences({"bodies": old}, {"bodies": new}), what)
        return dofs

    @property
    def multipliers(self):
        """Multipliers of each constraint by name, ``(nt, n_eq)``, of the constraints as
        simulated (``SystemChanged`` if constraints were added since)."""
        now, then = _constraint_names(self.system), self._simulated["constraints"]
        if now != then:
            _refuse_changed([f"constraints: {len(now)} now, {len(then)} simulated"],
                            "multipliers")
        out, k = {}, 0
        for c in self.system.constraints:
            out[c.name] = self.lam[:, k: k + c.n_eq]
            k += c.n_eq
        return out

    def state(self, i):
        """The ``i``-th saved step as a ``State``."""
        return State(self.system, self.q[i], self.lam[i], v=self.v[i], t=self.t[i])

    def __len__(self):
        return len(self.t)

    def __repr__(self):
        """What the result holds: saved steps, time span, bodies and saved fields, e.g.
        ``<Result: 301 saved steps, t = 0 … 3 s, bodies: hub (RigidBody), tether1 …
        tether12 (12 × Cable, 5 elements), fields: q, v, lam, iterations, energy>``
        (one line, three when longer)."""
        steps = f"{len(self)} saved step{'' if len(self) == 1 else 's'}"
        if len(self):
            steps += f", t = {self.t[0]:.6g} … {self.t[-1]:.6g} s"
        status = self.stats.get("status")
        if status not in (None, "complete"):
            steps += f" ({status})"
        parts = [steps, "bodies: " + _describe_bodies(self.system.bodies),
                 "fields: " + (", ".join(self._saved_fields()) or "none")]
        line = ", ".join(parts)
        return f"<Result: {line}>" if len(line) <= 110 else "<Result: " + ",\n ".join(parts) + ">"

    def _saved_fields(self):
        """The fields held (those a store left out are NaN, ``iterations`` -1; read at the
        first saved step) and ``energy``."""
        if not len(self):
            return []
        held = [name for name in ("q", "v", "a", "lam")
                if getattr(self, name)[0].size and not np.isnan(getattr(self, name)[0]).all()]
        if self.iterations[0] >= 0:
            held.append("iterations")
        if not np.isnan(self.kinetic[0]):
            held.append("energy")
        return held

    @classmethod
    def load(cls, path, system: IntegrableSystem, check=True):
        """Read the saved steps of a run directory written by ``io.RunStore`` (its Zarr
        store ``results.zarr``, up to the last commit of its manifest; old directories of
        ``chunk_*.npz`` files too).

        ``system`` must be the one that wrote it: a store of another system (its
        fingerprint, ``io.fingerprint``) raises ``io.StoreMismatch`` (``check=False``
        skips the test; sizes must still match).  Fields the store left out (by default
        the accelerations ``a``) are NaN.  ``stats``: the solver counters at the last
        saved step, ``status`` and ``stopped``.  In orbit, ``reference`` holds the run's
        rebases from its checkpoint; ``system`` is left as it is (its ``orbit`` too).
        """
        from ..io.reader import read_result

        records, stats, reference = read_result(path, system, check=check)
        return cls(system, records, stats, reference=reference)


def _constraint_names(system):
    """The constraints' names and numbers of equations (what ``multipliers`` keys)."""
    return [(c.name, int(c.n_eq)) for c in system.constraints]


def _refuse_changed(changed, what):
    """Raise ``SystemChanged`` when the system was ``changed`` (lines of
    ``io.fingerprint.differences``) since a result's run: its ``what`` would mix the
    stored motion with the edited system."""
    from ..model.system import SystemChanged

    if changed:
        raise SystemChanged(
            f"the system changed since this result was simulated: {'; '.join(changed)}.  "
            f"The result's {what} would come from the edited system and the motion of the "
            "one simulated: take it before editing the system, or from a result of the "
            "edited system (simulate again; Result.load with the system that wrote a run)")


def _describe_body(body):
    """``Cable, 5 elements``: the body's class and, if it has elements, their number."""
    elements = getattr(body, "n_elements", None)
    kind = type(body).__name__
    return kind if elements is None else f"{kind}, {elements} elements"


def _describe_bodies(bodies):
    """The bodies by name and kind, runs of three or more of one kind shortened to
    ``first … last (count kind)``."""
    groups = []
    for body in bodies:
        kind = _describe_body(body)
        if groups and groups[-1][1] == kind:
            groups[-1][0].append(body)
        else:
            groups.append(([body], kind))
    out = []
    for members, kind in groups:
        names = [getattr(b, "name", None) or "?" for b in members]
        if len(members) < 3:
            out += [f"{name} ({kind})" for name in names]
        else:
            out.append(f"{names[0]} … {names[-1]} ({len(members)} × {kind})")
    return ", ".join(out)
