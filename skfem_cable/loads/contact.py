"""Contact of a line body (a cable, a rod) with a fixed surface, with Coulomb friction: a
pointwise line load at the body's points (``lines``, the line-body hook) against a
``protocols.Surface`` (``sc.Plane``, ``sc.Sphere``, ``sc.Cylinder``), compiled in the one
loop of the line loads (``kernels.line.module``; the force and its exact tangents:
``kernels.contact``); ``docs/contact.md`` states the method and its tolerances.

* Normal force: a penalty ``k p`` on the penetration ``p`` of the line's cross-section
  (its radius ``r_c`` counted in the gap), per unit reference length, set in smoothly over
  the onset ``p_0 = 0.1 tolerance d`` (``ONSET``), with a normal damping ``-c v_n``
  (default: critical on the penalty; ``kernels.contact``).  The default stiffness
  ``k = REFERENCE_LOAD EA / (tolerance d^2)`` (``d = 2 r_c``) puts the penetration at
  ``tolerance d`` under the load per length ``T / R = 1e-3 EA / d`` of the line at 1 %
  strain wrapped over a small pulley, ``R = 10 d``; the penetration is proportional to
  the load, and ``forces`` warns (``ContactToleranceWarning``) where a state exceeds
  ``tolerance d``.  Use ``rho_inf = 0`` where a line hits a surface: the penalty is
  stiffer than the step resolves, and with ``rho_inf = 0.8`` an impact gains energy
  (``docs/contact.md``).
* Friction: Coulomb's on the penalty's force ``N``, regularised in the slip velocity,
  ``-mu N v_t / sqrt(|v_t|^2 + eps^2)`` (``eps = slip_velocity``): full Coulomb friction
  where the line slides at ``|v_t| >> eps`` (``1 - eps^2 / (2 v_t^2)`` of it), a
  viscous creep of speed ``eps |f_t| / (mu N)`` where it should stick.
* Energy books: the penalty's work is external work (it is conservative: it closes over
  a cycle); the normal damping and the friction are booked as dissipation
  (``LinePoints.hook(point, dissipative=True)``).
* Run store: the contact declares the per-step outputs ``<name>_<key>`` (``OUTPUTS``,
  ``summary``; ``protocols.Load``'s ``step_outputs``) and the forces per element
  (``ARRAYS``, ``step_arrays``), evaluated once per saved step from the step's converged
  state (the one its broad phase keeps).
"""

import warnings

import numpy as np

from ..core.contract import PART_LOAD, Shape, Term
from ..core.lines import check_line_body, line_points
from ..kernels import contact as kernel
from .line import AlongCable
from .surface_broad_phase import BroadPhase, ContactDampingWarning

#: The load per length ``T / R`` (in units of ``EA / d``) that penetrates ``tolerance d``
#: with the default stiffness: 1 % strain over a radius of ``10 d``.
REFERENCE_LOAD = 1e-2 / 10.0


#: The onset ``p_0`` of the penalty and the damping, in units of ``tolerance d``.
ONSET = 0.1


#: The per-step outputs of a contact (``summary``), recorded as ``<name>_<key>``.
OUTPUTS = ("elements", "normal", "tangential", "max_penetration", "friction_power")

#: The per-step arrays of a contact (``step_arrays``), recorded as ``<name>_<key>``: the
#: normal (ne,) and tangential (ne, 3) forces (N) of the surface on each element.
ARRAYS = ("element_normal", "element_tangential")


class ContactToleranceWarning(UserWarning):
    """A state penetrates a surface deeper than the contact's stated tolerance."""




def nonnegative(name, value):
    """``value`` as a finite float >= 0, or ``ValueError`` naming ``name``."""
    value = float(value)
    if not np.isfinite(value) or value < 0.0:
        raise ValueError(f"{name} must be finite and >= 0, got {value!r}")
    return value


def positive(name, value):
    """``value`` as a finite float > 0, or ``ValueError`` naming ``name``."""
    value = nonnegative(name, value)
    if value == 0.0:
        raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    return value


def summary(out):
    """The per-step outputs (``OUTPUTS``) of the contact forces ``out``
    (``LineSurfaceContact.resolve``): ``elements`` the number of elements pressed on the
    surface (normal force > 0), ``normal`` the total normal force (N), ``tangential`` the
    sum over the elements of the magnitudes of their friction forces (N),
    ``max_penetration`` (m) and ``friction_power`` (W, <= 0)."""
    return {"elements": float(np.count_nonzero(out["normal"] > 0.0)),
            "normal": float(out["normal"].sum()),
            "tangential": float(np.linalg.norm(out["tangential"], axis=1).sum()),
            "max_penetration": out["max_penetration"],
            "friction_power": out["friction_power"]}


class LineSurfaceContact(AlongCable):
    """Contact of the line body ``line`` with the fixed surface ``surface``, with Coulomb
    friction (module notes).

    Parameters
    ----------
    line : Cable or line body
        The line (any body with the hook ``line_points``).
    surface : Surface
        A body with the hooks of ``protocols.Surface`` (``sc.Plane``, ``sc.Sphere``,
        ``sc.Cylinder``).
    friction : float
        Coulomb's coefficient ``mu`` >= 0 (default 0: frictionless).
    radius : float, optional
        The line's cross-section radius ``r_c`` (m, > 0), counted in the gap; default the
        radius of the circle of the area of ``line.section``.
    stiffness : float, optional
        Penalty ``k`` (N/m per m of penetration, > 0); default
        ``REFERENCE_LOAD EA / (tolerance d^2)`` of ``line.section`` (module notes).
    tolerance : float
        The stated penetration, relative to the diameter ``d`` (default 1e-2, > 0).
    damping : float, optional
        Normal damping ``c`` (N s/m^2, >= 0); default ``2 sqrt(k m)``, critical for the
        line's mass per length ``m`` on the penalty (``line.section``), which stops the
        bounces of a penalty stiffer than the time step resolves.
    slip_velocity : float
        The regularisation ``eps`` of the friction (m/s, > 0; default 1e-3).
    broad_phase : bool
        Skip, once per time step, the elements that the step cannot bring within the
        stated tolerance of the surface (``loads.surface_broad_phase``; default True).
        The last bound one is ``broad``; it also checks, once per step, that the contact
        does not work where its damping is below critical (``ContactDampingWarning``).
    name : str, optional
        The prefix of its per-step outputs (``step_outputs``); default ``contact_<line>``
        (``System.contact`` numbers a second contact of a line: ``contact_<line>_2``).
    """

    #: Attributes a run refreshes, not part of the system's fingerprint
    #: (``model.fingerprint``): the broad phase of the last ``bind``.
    caches = ("broad",)

    def __init__(self, line, surface, friction=0.0, radius=None, stiffness=None,
                 tolerance=1e-2, damping=None, slip_velocity=1e-3, broad_phase=True,
                 name=None):
        self.cable = check_line_body(line, "line")
        if not callable(getattr(surface, "surface_array", None)):
            raise TypeError("surface must have the hooks of skfem_cable.core.protocols."
                            f"Surface (surface_array, distance), got {surface!r}")
        self.surface = surface
        section = getattr(line, "section", None)
        if section is None and (radius is None or stiffness is None):
            raise ValueError(f"radius and stiffness must be given for {line!r}, a line body "
                             "without a section")
        self.radius = positive("radius", np.sqrt(section.A / np.pi) if radius is None
                               else radius)
        self.tolerance = positive("tolerance", tolerance)
        d = 2.0 * self.radius
        self.stiffness = positive("stiffness", REFERENCE_LOAD * section.EA
                                  / (self.tolerance * d * d)
                                  if stiffness is None else stiffness)
        self.friction = nonnegative("friction", friction)
        if damping is None and section is None:
            raise ValueError(f"damping must be given for {line!r}, a line body without a "
                             "section")
        self.damping = nonnegative("damping", 2.0 * np.sqrt(self.stiffness
                                                            * section.mass_per_length)
                                   if damping is None else damping)
        self.slip_velocity = positive("slip_velocity", slip_velocity)
        self.check_damping(section)
        self.broad_phase, self.broad = bool(broad_phase), None
        self.name = f"contact_{self.cable.name}" if name is None else str(name)

    step_outputs = property(lambda self: tuple(f"{self.name}_{key}" for key in OUTPUTS),
                            doc="Recorded per saved step (protocols.Load): ``summary``.")

    def step_arrays(self, system):
        """The per-step arrays (``protocols.Load``) in ``system``: ``{<name>_<key>:
        shape}`` of ``ARRAYS``, the normal (ne,) and tangential (ne, 3) forces (N) of the
        surface on each element of the line (``resolve``)."""
        ne = line_points(self.cable, system).shape[0]
        return dict(zip((f"{self.name}_{key}" for key in ARRAYS), ((ne,), (ne, 3))))

    def __repr__(self):
        return (f"{type(self).__name__}({self.cable.name!r}, {self.surface!r}, "
                f"friction={self.friction})")

    def check_damping(self, section):
        """``ContactDampingWarning`` where the damping is below critical on the penalty
        for the line's mass per length (``section``; none: no check)."""
        critical = None if section is None else \
            2.0 * np.sqrt(self.stiffness * section.mass_per_length)
        if critical is not None and self.damping < critical * (1 - 1e-12):
            warnings.warn(f"contact {self.cable.name}: damping {self.damping:.3g} N s/m^2 is "
                          f"below the critical {critical:.3g} of the penalty: its "
                          "oscillation, faster than the step, can gain energy (with none, "
                          "a stiff rope's mass rose on the Atwood machine instead of "
                          "falling); run at rho_inf = 0 or keep the default damping",
                          ContactDampingWarning, stacklevel=3)

    @property
    def onset(self):
        """``p_0``: the penetration over which the penalty and the damping set in
        (``ONSET`` of the stated ``tolerance d``; ``kernels.contact``)."""
        return ONSET * self.tolerance * 2.0 * self.radius

    def coefficients(self, part):
        """``coef`` of ``kernels.contact`` for the part ``part`` of the force."""
        return np.array([self.stiffness, self.damping, self.friction, self.slip_velocity,
                         self.radius, part, self.onset])

    @property
    def dissipative(self):
        """True when the contact has a dissipative part (friction or damping)."""
        return self.friction > 0.0 or self.damping > 0.0

    def bind(self, system):
        """The compiled term: the penalty (external) and, with friction or damping, the
        dissipative part, two calls of the loop of ``kernels.line`` with the point
        ``kernels.contact.point`` over the line's points."""
        points = line_points(self.cable, system)
        surface = self.surface.surface_array()
        parts = [(points.hook(kernel.point, velocity=False), kernel.ELASTIC)]
        if self.dissipative:
            parts.append((points.hook(kernel.point, dissipative=True), kernel.DISSIPATIVE))
        broad = BroadPhase(points, surface, self.radius, self.tolerance * 2.0 * self.radius,
                           self.onset, self.cable.name)
        scale = broad.scale if self.broad_phase else None
        kernels = tuple((hook, points.pack((surface, self.coefficients(part)), scale))
                        for hook, part in parts)
        rows, cols = points.tangent_pattern()
        self.broad = broad
        return Term(kernels=kernels, rows=rows, cols=cols, name=f"contact {self.cable.name}",
                    prepare=broad.prepare, hooks=(broad,),
                    outputs=lambda: self.step_values(system, points, broad.q, broad.v))

    def step_values(self, system, points, q, v):
        """The per-step outputs ``{step_outputs: summary}`` and arrays (``step_arrays``:
        the forces per element) at ``q``, ``v`` of the line's points ``points`` (the
        term's: the converged state its broad phase keeps)."""
        out = self.evaluate(system, points, q, v)
        arrays = (f"{self.name}_{key}" for key in ARRAYS)
        return {**dict(zip(self.step_outputs, summary(out).values())),
                **dict(zip(arrays, (out["normal"], out["tangential"])))}

    def seen(self, system, q, v, X, V):
        """``(surface, V)``: the surface array (``kernels.contact``) at the coordinates
        ``q`` and the velocities ``V`` (m, 3) of the points ``X`` relative to it (a fixed
        surface: ``V``; ``loads.contact_body``: relative to the body)."""
        return self.surface.surface_array(), V

    def forces(self, state):
        """The contact forces of the ``State`` ``state`` (``resolve`` of its ``system``,
        ``q`` and ``v``)."""
        return self.resolve(state.system, state.q, state.v)

    def resolve(self, system, q, v=None):
        """The contact forces at the coordinates ``q`` and velocities ``v`` (zero if None)
        of ``system``, per element of the line: a dict of ``normal`` (ne,) and
        ``tangential`` (ne, 3), the forces (N) of the surface on the element,
        ``friction_power`` (W, the power of the friction and the normal damping, <= 0),
        ``gap`` (ne,) the smallest gap (m; negative: penetration) and
        ``max_penetration`` (m).  Warns (``ContactToleranceWarning``) where the
        penetration exceeds ``tolerance d``."""
        out = self.evaluate(system, line_points(self.cable, system), q, v)
        depth = out["max_penetration"]
        if depth > self.tolerance * 2.0 * self.radius:
            warnings.warn(f"contact {self.cable.name}: penetration {depth:.3g} m exceeds "
                          f"the stated tolerance {self.tolerance:g} d = "
                          f"{self.tolerance * 2 * self.radius:.3g} m: raise the stiffness",
                          ContactToleranceWarning, stacklevel=3)
        return out

    def evaluate(self, system, points, q, v):
        """``resolve`` over the line's points ``points`` (``LinePoints``) of ``system``,
        unchecked."""
        X, _, V = points.at(q, v)
        X, V = X.reshape(-1, 3), V.reshape(-1, 3)
        surface, V = self.seen(system, q, v, X, V)
        ne, nq = points.shape
        normal, gap = np.empty(ne * nq), np.empty(ne * nq)
        tangential, resistance = np.empty((ne * nq, 3)), np.empty((ne * nq, 3))
        kernel.resolve(surface, self.coefficients(kernel.ELASTIC), X,
                       V, normal, tangential, resistance, gap)
        w = points.w.ravel()
        power = float(np.sum(w * np.einsum("mi,mi->m", resistance, V)))
        depth = float(max(0.0, -gap.min()))
        return {"normal": (w * normal).reshape(ne, nq).sum(axis=1),
                "tangential": (w[:, None] * tangential).reshape(ne, nq, 3).sum(axis=1),
                "friction_power": power,
                "gap": gap.reshape(ne, nq).min(axis=1), "max_penetration": depth}

    def show(self, system, q, v, t, **detail):
        """What ParaView draws of the contact (``io.export``): a vertex at the mean of each
        element's points, with the point data ``contact_normal`` (N), ``contact_force``
        (the normal and tangential force, N, a vector), ``contact_tangential`` (the
        tangential force, N, a vector) and ``contact_gap`` (m) of the element
        (``resolve``)."""
        out = self.resolve(system, q, v)
        X, _, V = line_points(self.cable, system).at(q, v)
        centre = X.mean(axis=1)
        normals = np.empty_like(centre)
        kernel.normals(self.seen(system, q, v, X.reshape(-1, 3), V.reshape(-1, 3))[0], centre,
                       normals)
        force = out["normal"][:, None] * normals + out["tangential"]
        return Shape(centre, V.mean(axis=1), "vertex", np.arange(len(centre))[:, None],
                     PART_LOAD, data={"contact_normal": out["normal"],
                                      "contact_force": force,
                                      "contact_tangential": out["tangential"],
                                      "contact_gap": out["gap"]})

    def watch(self):
        """An observer of a run (``simulate(..., observers=[contact.watch()])``) that
        checks the stated tolerance at every saved step (a ``ContactToleranceWarning``
        where it is exceeded) and keeps the contact's history: ``ContactWatch``."""
        return ContactWatch(self)


class ContactWatch:
    """The observer of ``LineSurfaceContact.watch``: at every saved step, ``resolve``
    (which warns beyond the tolerance), and the row ``(t, max_penetration, normal force,
    friction power)`` appended to ``history`` (a list)."""

    def __init__(self, contact):
        self.contact, self.history = contact, []

    def start(self, run):
        self.history = []

    def saved(self, run, step):
        out = self.contact.resolve(run.system, step.q, step.v)
        self.history.append((step.t, out["max_penetration"], float(out["normal"].sum()),
                             out["friction_power"]))

    def finish(self, run, error):
        pass
