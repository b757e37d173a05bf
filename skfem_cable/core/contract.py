"""The evaluation contract: what the solvers hand to bodies, loads, constraints and
observers, and what those give back (``docs/extending.md`` explains it with examples).

A *contributor* (a body's internal forces, a load, a point mass, gravity) is turned into a
``Term`` by ``bind(system)`` once, when the system's layout is built; binding returns a new
object and never changes the contributor.  A term declares the global coordinates of its
tangent entries (``rows``, ``cols``), any constant mass and constant generalized force, and
its forces through one of two hooks, called once per Newton iteration with the positions
``index`` of its tangent entries in the matrix values (same shape as ``rows``):

* ``add(ev, index)``, a Python callable receiving an ``Evaluation``;
* ``kernels``, a sequence of compiled ``(function, pack)`` pairs: ``function(pack, index,
  ev)`` is a numba ``njit`` function receiving the term's own packed data ``pack`` (a
  tuple of arrays and scalars fixed at binding) and the *packed evaluation*
  ``ev = (q, v, s, f, f_ext, f_damping, data, energy, power)`` (see ``Evaluation.packed``).
  Terms with kernels are evaluated inside the compiled Newton step of the
  generalized-alpha integrator (``solvers.compiled``); a term with a Python ``add`` is
  called back from it (``numba.objmode``), the rest of the step staying compiled.

Sign conventions (residual ``r = f_int - f_ext + C_q^T lambda``):

* internal forces (elastic, damping) go into ``ev.f`` and ``cK dF/dq + cC dF/dv`` into
  ``ev.data``;
* external forces go into ``ev.f_ext`` and ``-(cK dF/dq + cC dF/dv)`` into ``ev.data``
  (``Evaluation.add_tangent`` with ``sign=-1`` does the bookkeeping);
* their work is booked by the integrator as external work; the damping part of the
  internal force, ``ev.f_damping``, as dissipation.

Inertia that the constant mass matrix cannot express (a body whose mass changes in time,
such as a deploying tether, ``deploy``) is added like an external force: ``-(F_in - M a)``
into ``ev.f_ext``, with ``F_in`` the body's inertial force ``d/dt dT/dv - dT/dq`` and ``M``
the constant mass it declared, evaluated at the accelerations ``ev.a``; its tangent
carries ``ev.cM`` times the derivative in ``a`` (``add_tangent(..., da=...)``).  Such a
term has a Python ``add`` (called back from the compiled step).

A term evaluated outside its domain raises ``OutOfDomain`` (a Newton iterate may leave
it where the converged state would not).

Terms with equal, non-None ``key`` are merged with ``merge`` into one term before the
pattern is built, so that many bodies of one kind are evaluated by one compiled call.

A *constraint* ``C(q, t) = 0`` provides ``n_eq``, ``labels``, ``name``, ``linear``,
``dofs(system)`` and ``value``, ``jacobian``, ``hessian``, ``velocity_term``
(``C_t``), ``accel_term`` (``(C_q v)_q v + 2 C_qt v + C_tt``); see ``constraints``.  A
nonlinear constraint may also provide ``kernel = (function, pack)``, a compiled hook
``function(pack, index, cev)`` that replaces ``value``, ``jacobian`` and ``hessian`` in the
Newton iterations: with ``index = (dofs, rows, jac, jacT, hess)`` (its coordinates, its
multiplier rows and the positions of ``C_q``, ``C_q^T`` and ``d(C_q^T lam)/dq`` in the
matrix values, row-major) and ``cev = (q, lam, s, r_c, f_con, data)`` with
``s = [t, cK, scale]``, it writes ``scale C`` into ``r_c[rows]``, adds ``C_q^T lam`` to
``f_con`` and, if ``data`` is not empty, ``scale C_q``, ``scale C_q^T`` and ``cK`` times
the Hessian term (``kernels.rigid`` does it for the rigid body).

An *observer* receives the state at the start, at every saved step and at the end of a
time integration; see ``Observer``.

What plugs in is stated as ``typing.Protocol``s in ``protocols``: ``Body``, ``Line``,
``Load``, ``Constraint``, ``Observer``, with what the solvers and ``io`` read of a system
and the step hooks.
"""

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numba import njit

# The protocols moved to ``protocols``; their old names here stay for one release.
from .protocols import Body, Constraint, Line, Load, Observer, check_body  # noqa: F401

#: Indices of ``Evaluation.energy`` and ``Evaluation.power``: the stretching (axial) and
#: bending parts of the stored elastic energy and of the dissipated power.  A body with
#: another kind of stored energy adds it to ``AXIAL``.
AXIAL, BENDING = 0, 1

#: The force accumulators of an ``Evaluation`` a term may write (``Term.writes``).
WRITTEN = ("f", "f_damping", "f_ext")

#: What compiled hooks receive for "no matrix values" (no tangent wanted) and for "no
#: tangent entries": empty arrays of the right types.
NO_DATA = np.zeros(0)
NO_INDEX = np.zeros(0, dtype=np.int64)


class OutOfDomain(ValueError):
    """Raised by a term evaluated at coordinates outside the domain where it is defined
    (a reel's free length outside ``(0, capacity]``).  The time integrator rejects the
    step and retries it smaller; if it happens at the smallest step, the run stops with
    this message."""


@njit(cache=True)
def scatter_add(data, index, values):
    """``data[index.flat[k]] += values.flat[k]`` for all ``k`` (repeated indices add)."""
    idx = index.ravel()
    val = values.ravel()
    for k in range(idx.size):
        data[idx[k]] += val[k]


def static_evaluation(calls, q, index):
    """The stored energy (J, both parts) and the internal force (n,) of compiled kernel
    calls ``[(function, pack), ...]`` at the coordinates ``q``, at rest and without
    tangent (``index``: the empty tangent index the kernels take), as a deploying cable
    and a law that varies in time evaluate their own kernels with other tables or
    values."""
    energy, f, zeros = np.zeros(2), np.zeros_like(q), np.zeros_like(q)
    ev = (q, zeros, np.zeros(4), f, zeros.copy(), zeros.copy(), NO_DATA, energy, np.zeros(2))
    for function, pack in calls:
        function(pack, index, ev)
    return energy.sum(), f


class Evaluation:
    """The state and the accumulators of one evaluation of the system.

    Attributes
    ----------
    system : System
    t : float
        Time (s).
    q, v : ndarray (n_dofs,)
        Coordinates and velocities (``v`` is zero in statics and modal analysis).
    lam : ndarray (n_constraints,)
        Lagrange multipliers.
    cK, cC : float
        Coefficients of the tangent: the matrix receives ``cK dr/dq + cC dr/dv``.
    dynamic : bool
        True when ``v`` is meaningful (dynamics): damping and velocity-dependent forces
        are on.  False in statics and modal analysis (``v`` is then zero).
    f : ndarray (n_dofs,)
        Internal forces (elastic plus damping).
    f_ext : ndarray (n_dofs,)
        External forces that are not constant (constant ones are ``Layout.f_const``).
    f_damping : ndarray (n_dofs,)
        The damping part of ``f`` (for the dissipation bookkeeping).
    data : ndarray (nnz,) or None
        Values of the iteration matrix in the fixed pattern; None when no tangent is
        wanted (``want_tangent``).
    energy, power : ndarray (2,)
        Stored elastic energy and dissipated power, split ``[AXIAL, BENDING]``.
    a : ndarray (n_dofs,)
        Accelerations (zero in statics and where the integrator solves for them).
    cM : float
        Coefficient of the derivatives in ``a`` in the tangent (1 in dynamics, where the
        iteration matrix is ``M + cC dr/dv + cK dr/dq``; 0 in statics).
    """

    __slots__ = ("system", "t", "q", "v", "lam", "cK", "cC", "dynamic", "f", "f_ext",
                 "f_damping", "data", "energy", "power", "a", "cM")

    def __init__(self, system, t, q, v, lam, cK=1.0, cC=0.0, data=None, a=None, cM=0.0):
        n = system.n_dofs
        self.system = system
        self.t = float(t)
        self.q = q
        self.dynamic = v is not None
        self.v = v if v is not None else np.zeros(n)
        self.a = a if a is not None else np.zeros(n)
        self.lam = lam
        self.cK, self.cC, self.cM = float(cK), float(cC), float(cM)
        self.data = data
        self.f = np.zeros(n)
        self.f_ext = np.zeros(n)
        self.f_damping = np.zeros(n)
        self.energy = np.zeros(2)
        self.power = np.zeros(2)

    @property
    def want_tangent(self):
        return self.data is not None

    def packed(self):
        """The evaluation as compiled kernels receive it: the tuple
        ``(q, v, s, f, f_ext, f_damping, data, energy, power)`` with
        ``s = [t, cK, cC, dynamic]`` (float64) and ``data`` of size 0 when no tangent is
        wanted; the arrays are this evaluation's own (kernels add into them)."""
        s = np.array([self.t, self.cK, self.cC, float(self.dynamic)])
        data = NO_DATA if self.data is None else self.data
        return (self.q, self.v, s, self.f, self.f_ext, self.f_damping, data, self.energy,
                self.power)

    def add_tangent(self, index, dq=None, dv=None, sign=1.0, da=None):
        """Add ``sign (cK dq + cC dv + cM da)`` at the matrix positions ``index`` (``dq``,
        ``dv``, ``da`` of the shape of ``index`` or broadcastable; None for a zero block).
        Use ``sign=-1`` for the derivatives of an external force."""
        if self.data is None:
            return
        for block, c in ((dq, self.cK), (dv, self.cC), (da, self.cM)):
            if block is not None and c != 0.0:
                scatter_add(self.data, index, np.broadcast_to(sign * c * block, index.shape))


@dataclass(frozen=True)
class Term:
    """A contributor bound to a system (returned by ``bind(system)``).

    Attributes
    ----------
    add : callable or None
        ``add(ev, index)``: add forces (and, if ``ev.want_tangent``, tangents at
        ``index``) for the ``Evaluation`` ``ev``.
    kernels : tuple of ``(function, pack)``
        The same as compiled calls ``function(pack, index, ev)`` on the packed
        evaluation (``Evaluation.packed``); ``index`` is an empty int64 array for a term
        without tangent.  A term gives ``add`` or ``kernels``, not both.
    prepare : callable or None
        ``prepare(t)``: refresh, in place, the arrays of the packs that depend on time
        only (e.g. a modulated voltage), before the kernels are evaluated at time ``t``;
        the compiled step calls it once per time step (its equations hold at one time).
    rows, cols : int ndarray or None
        Global coordinates of the tangent entries (broadcast against each other); None
        for a term without tangent.
    mass : tuple or None
        ``(rows, cols, values)`` of a constant mass contribution (e.g. a point mass).
    force : tuple or None
        ``(dofs, values)`` of a constant generalized force (gravity, fixed point and line
        loads); its potential ``-f . q`` is booked as potential energy.
    key : hashable or None
        Terms with equal keys are merged by ``merge`` (a callable taking the list of terms
        and returning one term): the compiled path batches all cables of one law.
    name : str
        Label used in diagnostics.
    energy_rate : callable or None
        ``energy_rate(q, t)``: the explicit time derivative (W) of the term's stored
        energy at fixed coordinates, for energies that depend on time (a deploying
        cable's elastic energy: the work of its reel); the integrator books its time
        integral as external work.
    energy_change : callable or None
        ``energy_change(q0, q1, t0, t1)``: the work done on the term over a step from
        ``(q0, t0)`` to ``(q1, t1)`` by the change of its data in time (what
        ``prepare(t1)`` does at the start of the step: a law parameter that varies in
        time), the change of its stored energy at fixed coordinates, averaged over the
        step's ends; the integrator books it as external work at every step.
    hooks : tuple
        Step hooks (``protocols.StepHook``) the term needs between the steps of a run;
        ``simulate`` calls them after its own (the rectification's, the controllers'), and
        ``solve_static`` calls a body term's after every converged load step.  E.g. a rod's
        reference frames, re-based on the current tangents after every step
        (``bodies.rod_frames``), or an environment model sampled at the bodies' positions
        once per step (``loads.sampling.DensitySampler``: the hook keeps the state of the
        last accepted step, ``prepare`` evaluates the model from it).  What a hook's
        ``snapshot`` returns goes into every checkpoint.
    outputs : callable or None
        ``outputs()``: the term's numbers at its last evaluation, ``{name: float}`` with
        the names its load declares (``protocols.Load``'s ``step_outputs``); ``simulate``
        records them at every saved step (``Step.outputs``: the store's ``output_<name>``,
        ``Result.outputs``), from the step's last Newton iterate.
    check : callable or None
        ``check(q0, q1)``: None, or the reason (a str naming the term and what it saw)
        the step from the accepted coordinates ``q0`` to the converged candidate ``q1``
        must be refused; the integrator calls it once per attempted step, before its
        instability guard (``solvers.guard.refusal``), and a refused step is retried
        smaller like one that failed to converge.  E.g. line-to-line contact refuses a
        step that carried two lines through each other (``loads.contact_crossing``).
    correction : tuple or None
        ``(edofs, S, count, points, values)``: entries of the term's exact tangent that its
        pattern (``rows``, ``cols``) leaves out, which its kernels write at every
        evaluation with the tangent as records of ``kernels.woodbury`` (four points
        ``S[e, g] x[edofs[e]]`` and a 12 x 12 block each); the compiled Newton step adds
        them back to its factored matrix (the Woodbury identity), so that Newton is exact
        on the pattern.  E.g. line-to-line contact with ``tangent="woodbury"``.  At most
        one term of a system.
    writes : tuple of str
        The accumulators of the evaluation its forces go into, of ``WRITTEN``: ``"f"``,
        ``"f_damping"`` (the damping part of ``f``) and ``"f_ext"`` (all three unless
        said).  The compiled step clears, reads, books and keeps an accumulator only if a
        term of the system writes it: an undamped cable declares ``("f",)``, and its
        step makes no pass over the other two (``kernels.step._residual``).
    """

    add: Callable[..., None] | None = None
    kernels: tuple = ()
    rows: np.ndarray | None = None
    cols: np.ndarray | None = None
    mass: tuple | None = None
    force: tuple | None = None
    key: Any = None
    merge: Callable[[list], "Term"] | None = None
    name: str = ""
    prepare: Callable[[float], None] | None = None
    energy_rate: Callable[[Any, float], float] | None = None
    energy_change: Callable[[Any, Any, float, float], float] | None = None
    hooks: tuple = ()
    outputs: Callable[[], dict] | None = None
    check: Callable[[Any, Any], str | None] | None = None
    correction: tuple | None = None
    writes: tuple = ("f", "f_damping", "f_ext")

    def __post_init__(self):
        if self.add is not None and self.kernels:
            raise ValueError(f"term {self.name!r}: give add or kernels, not both")
        if not set(self.writes) <= set(WRITTEN):
            raise ValueError(f"term {self.name!r}: writes must name accumulators of "
                             f"{WRITTEN}, got {self.writes!r}")

    @property
    def has_tangent(self):
        return self.rows is not None

    @property
    def evaluates(self):
        """True when the term adds forces at every evaluation."""
        return self.add is not None or bool(self.kernels)

    def no_index(self):
        """An empty index of the dimensions of the term's own (``rows`` and ``cols``
        broadcast): its kernels, compiled for that index, are not compiled again for a
        call without the tangent."""
        if self.rows is None:
            return NO_INDEX
        shape = np.broadcast_shapes(np.shape(self.rows), np.shape(self.cols))
        return NO_INDEX.reshape((0,) + shape[1:])

    def evaluate(self, ev, index):
        """Add this term's forces (and tangents) to the ``Evaluation`` ``ev``."""
        if self.add is not None:
            self.add(ev, index)
            return
        if self.prepare is not None:
            self.prepare(ev.t)
        packed = ev.packed()
        index = self.no_index() if index is None else index
        for function, pack in self.kernels:
            function(pack, index, packed)


def combined(terms, name):
    """One term with Python ``add`` evaluating ``terms`` (terms with ``add``) in turn,
    each with its own part of the tangent entries (for a contributor made of several,
    such as gravity with the weight of every deploying cable)."""
    parts = [t for t in terms if t.has_tangent]
    entries = [np.broadcast_arrays(t.rows, t.cols) for t in parts]
    ends = np.cumsum([r.size for r, _ in entries])
    spans = {id(t): (end - r.size, end, r.shape) for t, (r, _), end in zip(parts, entries, ends)}

    def add(ev, index):
        for term in terms:
            span = spans.get(id(term))
            term.add(ev, None if span is None else index[span[0]:span[1]].reshape(span[2]))

    if not parts:
        return Term(add=add, name=name)
    return Term(add=add, rows=np.concatenate([r.ravel() for r, _ in entries]),
                cols=np.concatenate([c.ravel() for _, c in entries]), name=name)


def merge_terms(terms):
    """Merge terms with equal keys (keeping the first occurrence's position)."""
    groups, order = {}, []
    for term in terms:
        if term.key is None:
            order.append([term])
            continue
        if term.key not in groups:
            groups[term.key] = []
            order.append(groups[term.key])
        groups[term.key].append(term)
    return [g[0] if len(g) == 1 else g[0].merge(g) for g in order]


@dataclass
class Step:
    """A saved step, as observers see it (arrays are the integrator's own: copy what you
    keep).

    Attributes
    ----------
    index : int
        Step number (0: the initial state).
    t : float
    q, v, a, lam : ndarray
        Coordinates, velocities, accelerations and multipliers.
    iterations : int
        Newton iterations of this step.
    energies : dict
        ``kinetic``, ``axial``, ``bending``, ``potential``, ``dissipated``,
        ``external_work`` (J).
    inputs : dict
        The values the system's inputs hold (``inputs.Input``, by name) for the steps
        after this one: what a controller set (empty without inputs).
    outputs : dict
        The loads' numbers at the step (``Term.outputs``, by the names the loads declare
        in ``step_outputs``; empty when none does).
    """

    index: int
    t: float
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    lam: np.ndarray
    iterations: int
    energies: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    outputs: dict = field(default_factory=dict)


#: Values of a ``Shape``'s ``part`` (the cell data ``part`` of the ParaView output).
PART_CABLE, PART_RIGID, PART_POINT_MASS = 0, 1, 2
#: The ``part`` of a ribbon (``io.export.ribbon``): a rod's section drawn along its line.
PART_RIBBON = 3
#: The part of what a load shows (``show``, e.g. the contact forces of ``loads.contact``).
PART_LOAD = 4


@dataclass
class Shape:
    """What a body shows in ParaView (``Body.show``): ``points`` (n, 3) and their
    ``velocity`` (n, 3); cells of one meshio ``cell_type`` (``"line"``, ``"triangle"``,
    ``"vertex"``, ...) with ``cells`` (m, k), indices into ``points``; a ``part`` number
    (``PART_CABLE``, ...); point ``data``, name -> array (n,) or (n, 3) (fields that
    other bodies lack are NaN there)."""

    points: np.ndarray
    velocity: np.ndarray
    cell_type: str
    cells: np.ndarray
    part: int
    data: dict = field(default_factory=dict)


@dataclass
class Run:
    """A time integration as observers see it.

    Attributes
    ----------
    system : System
    integrator : object
        The stepper (``GeneralizedAlpha``); ``integrator.snapshot()`` holds everything a
        bit-for-bit continuation needs.
    settings : dict
        The run's settings (``t_start``, ``t_end``, ``dt``, ``rho_inf``, ``every``, ...).
    stats : dict
        Counters updated as the run goes (steps, rejected, newton, factorizations).
    resumed : bool
        True when the run continues an interrupted one.
    stop_reason : str or None
        Set when an observer stopped the run.
    make_result : callable
        ``make_result(records, stats)``: the run's result of saved steps ``records`` (the
        arrays of ``io.schema``) and counters ``stats`` (a ``Result``), which an observer
        that holds steps hands back with an error (``err.result``) without knowing the
        result's class.
    """

    system: Any
    integrator: Any
    settings: dict
    stats: dict
    resumed: bool = False
    stop_reason: str | None = None
    make_result: Any = None
