"""Contact between line bodies (two cables or rods, many: the tethers of a sail) or of one
with itself, with Coulomb friction: a penalty on the gap between the closest points of
segments of their sampled centrelines (``kernels.contact_lines``: the narrow phase, with
exact tangents), over the candidate pairs of a broad phase refreshed once per time step
(``BroadPhase``: a compiled grid of the segments' bounding boxes,
``kernels.line_broad_phase``); ``docs/contact.md`` states the method and its tolerances.

* Segments: the lines' quadrature points (``lines.LinePoints``), joined in order along
  each line; a contact at a line's stubs before its first and after its last point is not
  seen.
* Gap: ``d - (r_a + r_b)``, ``d`` the distance of the closest points, ``r`` the
  cross-section radii (default: the radius of the circle of the area of ``section``).
* Normal force: the penalty of ``loads.contact`` (a force here: N per m of penetration),
  default ``k = REFERENCE_FORCE EA / (tolerance d)`` with ``d = r_a + r_b`` and the
  smaller ``EA``: the penetration is ``tolerance d`` under the crossing force of a line at
  1 % strain deflected by 0.1 rad, ``1e-3 EA``; an internal force of the lines, its
  potential booked as stored energy.
* Friction: regularised Coulomb, ``-mu N v_t / sqrt(|v_t|^2 + eps^2)`` on the slip of the
  closest points, booked as dissipation.
* Self-contact (``system.contact(cable, cable)``): segments of one line closer along its
  reference arc length than ``exclusion`` (default ``pi (r_a + r_b)``: the half turn of a
  line folded onto itself) are never a pair; neighbours are therefore excluded.
* Joints: pairs of segments of two lines next to a joint they share (the tethers' roots on
  a hub) are never pairs (``loads.contact_joints``, within ``exclusion``).
* Tangent pattern (``tangent``): ``"full"``, the dense block over the lines' coordinates
  (the exact tangent: contact may couple any element of one with any of the other), the
  default for two lines or one; ``"own"``, each element's own block (the entries that
  couple different elements, of one line or two, left out: the residual stays exact,
  Newton converges linearly while lines touch, and only at steps where the penalty is
  below the touching points' mass term, ``docs/contact.md``), which keeps the pattern of
  a system such as the E-sail whose solver factors each cable apart; ``"woodbury"``,
  the default for more lines, the own pattern with the entries it leaves out added back
  to the factored matrix by the compiled step, pair by pair in contact, as a low-rank
  correction (``kernels.woodbury``): the exact Newton step on the own pattern, for up to
  ``active_pairs`` pairs in contact (beyond that, the rest's coupling is left out as
  with ``"own"``, and the run warns once, naming the contact).
* Crossings: a step whose converged state has carried two lines (or two parts of one)
  through each other is refused, naming them (``contact_crossing``: the term's
  ``check``, once per attempted step over the step's candidate pairs).
* Run store: the per-step outputs ``<name>_<key>`` (``OUTPUTS``, ``summary``) and the
  pairs in contact (``ARRAYS``, ``step_arrays``: at most ``active_pairs`` of them, NaN
  after the last; ``<name>_contacts`` counts them all), evaluated once per saved step
  from the step's converged state (the one its broad phase keeps).
"""

import warnings

import numpy as np

from ..core.contract import Term
from ..core.lines import check_line_body, joined, line_points
from ..kernels import contact_lines as kernel
from ..kernels import line_broad_phase, woodbury
from ..kernels.line import points as line_points_kernel
from .accepted import AcceptedState
from .contact import ONSET, ContactToleranceWarning, nonnegative, positive
from .contact_crossing import crossing_check
from .contact_joints import excluded_pairs

#: The crossing force (in units of ``EA``) that penetrates ``tolerance d`` with the
#: default stiffness: a line at 1 % strain deflected by 0.1 rad.
REFERENCE_FORCE = 1e-3

#: Candidate pairs held per segment (``capacity`` default).
PAIRS_PER_SEGMENT = 8

#: The patterns of the tangent (``LineLineContact(tangent=...)``, module notes).
TANGENTS = ("full", "own", "woodbury")

#: Pairs in contact whose coupling the ``"woodbury"`` tangent adds back (``active_pairs``
#: default).
ACTIVE_PAIRS = 8

#: The per-step outputs of a contact (``summary``), recorded as ``<name>_<key>``.
OUTPUTS = ("contacts", "normal", "max_penetration", "friction_power")

#: The per-step arrays of a contact (``step_arrays``), recorded as ``<name>_pair_<key>``,
#: a row per pair in contact (``active_pairs`` rows, NaN after the last; ``contacts``):
#: the two lines' positions in ``lines``, the reference arc lengths (m) of the contact
#: along each, its normal force (N).
ARRAYS = ("lines", "arc", "normal")


def summary(out):
    """The per-step outputs (``OUTPUTS``) of the contacts ``out``
    (``LineLineContact.contacts``): ``contacts`` their number, ``normal`` the total normal
    force (N), ``max_penetration`` (m) and ``friction_power`` (W, <= 0)."""
    return {"contacts": float(len(out["normal"])), "normal": float(out["normal"].sum()),
            "max_penetration": out["max_penetration"],
            "friction_power": out["friction_power"]}


def _radius(line, radius):
    """The cross-section radius of ``line``: ``radius``, else that of the circle of the
    area of its ``section`` (``ValueError`` naming ``radius`` if it has none)."""
    section = getattr(line, "section", None)
    if radius is None and section is None:
        raise ValueError(f"radius must be given for {line!r}, a line body without a section")
    return positive("radius", np.sqrt(section.A / np.pi) if radius is None else radius)


def segments(points, ends):
    """The segments of one line's points ``points`` (``LinePoints``) in order: rows
    ``[e0, g0, e1, g1, end0, end1]`` (``kernels.contact_lines``) and the reference arc
    positions (nseg, 2) of their ends (the weights' running sums); the rows' element
    indices are shifted by ``ends`` (the lines' points are joined)."""
    ne, nq = points.shape
    e, g = np.divmod(np.arange(ne * nq), nq)
    e = e + ends
    rows = np.column_stack([e[:-1], g[:-1], e[1:], g[1:], np.zeros(ne * nq - 1, int),
                            np.zeros(ne * nq - 1, int)])
    rows[0, 4] = rows[-1, 5] = 1
    w = points.w.ravel()
    arc = np.cumsum(w) - 0.5 * w
    return rows, np.column_stack([arc[:-1], arc[1:]])


class BroadPhase(AcceptedState):
    """The candidate pairs of segments, refreshed once per time step: a step hook of the
    run (``protocols.StepHook``: it keeps the last accepted state) and the term's
    ``prepare(t)``.  Each segment's box is inflated by ``margin / 2`` (``r_a + r_b`` and
    the stated tolerance) and twice the distance its faster end travels to ``t`` at the
    last state's speed; a compiled pass on a grid of the boxes
    (``kernels.line_broad_phase.candidates``) gives the pairs whose boxes overlap, and
    keeps those whose segments are within ``margin`` and both reaches of each other.
    Pairs of one line closer than ``exclusion`` along it are dropped; ``exclusion``
    None (no self-contact): every pair within one line; so are the pairs ``excluded``.

    Parameters
    ----------
    points : LinePoints
        The joined points of the lines.
    rows, arc, line : ndarray
        The segments' rows and arc positions (``segments``) and their line's number.
    exclusion : float or None
        Self-contact's exclusion along the line (m), or None.
    excluded : int64 ndarray
        The sorted keys ``i nseg + j`` of pairs left out (``contact_joints``).
    margin : float
        The distance (m) below which two segments are candidates at rest.
    pairs, count : int64 ndarray (capacity, 2), (1,)
        Where the pairs go (the term's pack holds the same arrays).
    q0 : ndarray
        The coordinates before a run's first step.
    """

    def __init__(self, points, rows, arc, line, exclusion, excluded, margin, pairs, count,
                 q0):
        self.points, self.arc, self.line = points, np.ascontiguousarray(arc), line
        self.excluded = np.ascontiguousarray(excluded, dtype=np.int64)
        nq = points.shape[1]
        self.ends = np.column_stack([rows[:, 0] * nq + rows[:, 1], rows[:, 2] * nq + rows[:, 3]])
        self.exclusion = -1.0 if exclusion is None else float(exclusion)
        self.margin, self.box = float(margin), np.empty((len(rows), 7))
        self.scratch = tuple(np.empty(points.shape + (3,)) for _ in range(3))
        self.pairs, self.count = pairs, count
        self.accept(q0, np.zeros_like(q0), 0.0)

    def prepare(self, t):
        """The candidate pairs for the step to ``t`` into ``pairs[:count[0]]`` (once per
        time; ``kernels.line_broad_phase.candidates``).  A time before the kept state's
        (a new run's first evaluation, before its hooks start) reaches nothing."""
        t = float(t)
        if t == self.done:
            return
        X, A, V = self.scratch
        points = self.points
        line_points_kernel(points.edofs, points.S, points.Sx, self.q, self.v, X, A, V)
        found = line_broad_phase.candidates(X.reshape(-1, 3), V.reshape(-1, 3), self.ends,
                                            self.line, self.arc, self.exclusion,
                                            self.excluded, self.margin, max(t - self.t, 0.0),
                                            self.box, self.pairs)
        if found > len(self.pairs):
            raise RuntimeError(f"line contact: {found} candidate pairs exceed the "
                               f"capacity {len(self.pairs)}: give capacity= larger")
        self.count[0] = found
        self.done = t


class LineLineContact:
    """Contact of the line bodies ``lines`` with each other (or of one with itself: the same
    body twice), with Coulomb friction (module notes).

    Parameters
    ----------
    *lines : Cable or line body
        The lines (bodies with the hook ``line_points``), at least two, distinct; or one
        body twice for self-contact.
    friction : float
        Coulomb's coefficient ``mu`` >= 0 (default 0).
    radius : float or sequence of float, optional
        The cross-section radii (m, > 0), one for all or one per line; default from each
        ``section``.  More than two lines must have one radius.
    stiffness : float, optional
        Penalty ``k`` (N/m, > 0); default ``REFERENCE_FORCE EA / (tolerance d)``.
    tolerance : float
        The stated penetration relative to ``d``, the sum of two radii (default 1e-2, > 0).
    slip_velocity : float
        The friction's regularisation ``eps`` (m/s, > 0; default 1e-3).
    exclusion : float, optional
        The reference arc length (m, >= 0) within which segments of one line are no pair
        (self-contact), and within which segments next to a joint two lines share are no
        pair (``contact_joints``); default ``pi d``.
    capacity : int, optional
        Candidate pairs held (default ``PAIRS_PER_SEGMENT`` per segment).
    tangent : {"full", "own", "woodbury"}, optional
        The tangent's pattern (module notes); default ``"full"`` for two lines or one,
        ``"woodbury"`` for more.
    active_pairs : int, optional
        The pairs in contact at one time (>= 1, default ``ACTIVE_PAIRS``) whose coupling
        the step adds back with ``tangent="woodbury"`` (12 solves with the band factor
        per pair at every factorization), and the rows of the pairs recorded per saved
        step (``step_arrays``).
    name : str, optional
        The prefix of its per-step outputs (``step_outputs``) and its name in messages;
        default ``contact_<first>_<second>`` (``contact_<line>`` for self-contact,
        ``contact_lines`` for more than two lines).
    """

    def __init__(self, *lines, friction=0.0, radius=None, stiffness=None, tolerance=1e-2,
                 slip_velocity=1e-3, exclusion=None, capacity=None, tangent=None,
                 active_pairs=ACTIVE_PAIRS, name=None):
        if len(lines) < 2:
            raise ValueError(f"lines must be at least two line bodies (one twice for "
                             f"self-contact), got {len(lines)}")
        checked = [check_line_body(body, f"lines[{k}]") for k, body in enumerate(lines)]
        distinct = list({id(body): body for body in checked}.values())
        self.self_contact = len(distinct) == 1
        if len(distinct) != len(lines) and not (self.self_contact and len(lines) == 2):
            raise ValueError("lines must be distinct (one body twice only for self-contact)")
        self.lines = tuple(distinct)
        radii = np.asarray(radius, dtype=object)
        if radii.ndim and radii.shape != (len(lines),):
            raise ValueError(f"radius must be one value or one per line ({len(lines)}), "
                             f"got {radius!r}")
        radii = np.broadcast_to(radii, (len(lines),))
        self.radii = tuple(_radius(body, r) for body, r in zip(checked, radii))
        if len(lines) > 2 and max(self.radii) > min(self.radii):
            raise ValueError(f"radius: more than two lines must have one radius, got "
                             f"{min(self.radii):.3g} to {max(self.radii):.3g} m")
        self.sum_radii = d = self.radii[0] + self.radii[-1]
        self.tolerance = positive("tolerance", tolerance)
        if stiffness is None:
            sections = [getattr(body, "section", None) for body in self.lines]
            if None in sections:
                raise ValueError("stiffness must be given for line bodies without a section")
            stiffness = REFERENCE_FORCE * min(s.EA for s in sections) / (self.tolerance * d)
        self.stiffness = positive("stiffness", stiffness)
        self.friction = nonnegative("friction", friction)
        self.slip_velocity = positive("slip_velocity", slip_velocity)
        self.exclusion = nonnegative("exclusion", np.pi * d if exclusion is None
                                     else exclusion)
        self.capacity = capacity if capacity is None else int(positive("capacity", capacity))
        self.tangent = ("full" if len(lines) <= 2 else "woodbury") if tangent is None \
            else tangent
        if self.tangent not in TANGENTS:
            raise ValueError(f"tangent must be one of {TANGENTS}, got {tangent!r}")
        self.active_pairs = int(positive("active_pairs", active_pairs))
        if self.active_pairs != active_pairs:
            raise ValueError(f"active_pairs must be a whole number >= 1, got {active_pairs!r}")
        default = ("contact_" + "_".join(body.name for body in self.lines)
                   if len(self.lines) <= 2 else "contact_lines")
        self.name = default if name is None else str(name)

    step_outputs = property(lambda self: tuple(f"{self.name}_{key}" for key in OUTPUTS),
                            doc="Recorded per saved step (protocols.Load): ``summary``.")

    def step_arrays(self, system):
        """The per-step arrays (``protocols.Load``): ``{<name>_pair_<key>: shape}`` of
        ``ARRAYS``, ``(active_pairs, 2)``, ``(active_pairs, 2)``, ``(active_pairs,)``."""
        rows = self.active_pairs
        return dict(zip((f"{self.name}_pair_{key}" for key in ARRAYS),
                        ((rows, 2), (rows, 2), (rows,))))

    def __repr__(self):
        names = ", ".join(repr(body.name) for body in self.lines)
        return f"{type(self).__name__}({names}, friction={self.friction})"

    @property
    def coefficients(self):
        """``coef`` of ``kernels.contact_lines``."""
        d = self.sum_radii
        return np.array([self.stiffness, self.friction, self.slip_velocity, d,
                         ONSET * self.tolerance * d])

    def tables(self, system):
        """``(points, rows, arc, line, excluded)``: the joined points of the line(s), the
        segments' rows, their arc positions, their line's number and the keys of the pairs
        next to a joint two lines share (``contact_joints.excluded_pairs``)."""
        bodies = self.lines[:1] if self.self_contact else self.lines
        points = [line_points(body, system) for body in bodies]
        offsets = np.cumsum([0] + [p.shape[0] for p in points])
        parts = [segments(p, o) for p, o in zip(points, offsets)]
        line = np.concatenate([np.full(len(r), k) for k, (r, _) in enumerate(parts)])
        arc = np.vstack([a for _, a in parts])
        excluded = excluded_pairs(system, bodies, points, arc, line, self.exclusion)
        return (joined(points), np.ascontiguousarray(np.vstack([r for r, _ in parts])), arc,
                line, excluded)

    def broad_phase(self, system, tables, q0):
        """The ``BroadPhase`` of the lines' ``tables`` (``tables``) from the state ``q0``."""
        points, rows, arc, line, excluded = tables
        capacity = self.capacity or PAIRS_PER_SEGMENT * len(rows)
        return BroadPhase(points, rows, arc, line,
                          self.exclusion if self.self_contact else None, excluded,
                          self.sum_radii * (1.0 + self.tolerance),
                          np.zeros((capacity, 2), dtype=np.int64),
                          np.zeros(1, dtype=np.int64), q0)

    def bind(self, system):
        """The compiled term (``kernels.contact_lines.kernel``) over the pairs of its
        ``BroadPhase`` (its ``prepare`` and step hook), on the tangent pattern of
        ``tangent``: the dense block over the lines' coordinates, or each element's own;
        its ``check`` refuses a step that carried two lines through each other
        (``contact_crossing``)."""
        tables = self.tables(system)
        points, rows = tables[:2]
        broad = self.broad_phase(system, tables, system.q0)
        dofs = np.unique(points.edofs)
        local = np.full(system.n_dofs, -1, dtype=np.int64)
        local[dofs] = np.arange(len(dofs))
        own = self.tangent != "full"
        nde = points.edofs.shape[1]     # own: each element's block, flat per element
        block = (np.repeat(points.edofs, nde, axis=1), np.tile(points.edofs, (1, nde))) \
            if own else (dofs[:, None], dofs[None, :])
        exact = self.tangent == "woodbury"
        record = woodbury.new_record(self.active_pairs if exact else 0)
        pack = (points.edofs, points.S, rows, broad.pairs, broad.count, self.coefficients,
                local, int(own), record)
        return Term(kernels=((kernel.kernel, pack),), rows=block[0], cols=block[1],
                    prepare=self._watching(broad.prepare, record[0]) if exact
                    else broad.prepare, hooks=(broad,), name=self.name,
                    outputs=lambda: self.step_values(system, tables, broad),
                    check=crossing_check(self, tables, broad),
                    correction=(points.edofs, points.S, *record) if exact else None)

    def _watching(self, prepare, count):
        """``prepare``, then a warning, once, where more pairs were in contact at one
        evaluation than the ``"woodbury"`` tangent holds (``count`` of its record)."""
        warned = []

        def watched(t):
            prepare(t)
            if count[1] > self.active_pairs and not warned:
                warned.append(t)
                warnings.warn(f"{self.name}: {count[1]} pairs in contact, more than "
                              f"active_pairs={self.active_pairs}: the coupling of the rest "
                              "is left out of Newton's matrix (as tangent='own'; it may "
                              "converge slowly): give active_pairs= larger",
                              RuntimeWarning, stacklevel=2)
        return watched

    def step_values(self, system, tables, broad):
        """The per-step outputs ``{step_outputs: summary}`` and arrays (``step_arrays``:
        the pairs in contact, NaN-padded) of the lines' ``tables`` at the converged state
        the term's ``broad`` phase keeps, over its pairs (those of the step that ended
        there)."""
        out = self.evaluate(system, tables, broad.q, broad.v, broad)
        arrays = {}
        for (name, shape), key in zip(self.step_arrays(system).items(), ARRAYS):
            padded = np.full(shape, np.nan)
            kept = out[key][:shape[0]]
            padded[:len(kept)] = kept
            arrays[name] = padded
        return {**dict(zip(self.step_outputs, summary(out).values())), **arrays}

    def contacts(self, system, q, v=None):
        """The active contacts at ``q``, ``v`` (zero if None) of ``system`` (a broad phase
        of their own at ``q``): a dict of ``normal`` (n,) the normal forces (N), ``penetration``
        (n,) (m), ``first``, ``second`` (n, 3) the closest points on each line,
        ``tangential`` (n, 3) the friction on the first line (the second gets the
        opposite), ``lines`` (n, 2) the two lines' positions in ``lines``, ``arc`` (n, 2)
        the reference arc lengths (m) of the contact along each, ``friction_power`` (W,
        <= 0) and ``max_penetration`` (m).  Warns
        (``ContactToleranceWarning``) where the penetration exceeds ``tolerance d``."""
        out = self.evaluate(system, self.tables(system), q, v)
        depth, limit = out["max_penetration"], self.tolerance * self.sum_radii
        if depth > limit:
            warnings.warn(f"{self.name}: penetration {depth:.3g} m exceeds the stated "
                          f"tolerance {limit:.3g} m: raise the stiffness",
                          ContactToleranceWarning, stacklevel=2)
        return out

    def evaluate(self, system, tables, q, v=None, broad=None):
        """``contacts`` over the lines' ``tables`` (``tables``), unchecked, over the pairs
        of ``broad`` (default: a broad phase of their own at ``q``)."""
        points, rows, arc, line = tables[:4]
        v = np.zeros_like(q) if v is None else v
        if broad is None:
            broad = self.broad_phase(system, tables, q)
            broad.prepare(0.0)
        out = np.empty((broad.count[0], 17))
        n = 0 if broad.count[0] == 0 else kernel.resolve(
            points.edofs, points.S, rows, broad.pairs, broad.count, self.coefficients,
            np.ascontiguousarray(q, float), np.ascontiguousarray(v, float), out)
        out = out[:n]
        depth = float(out[:, 2].max(initial=0.0))
        power = float(np.einsum("mi,mi->", out[:, 9:12], out[:, 12:15]))
        pairs = broad.pairs[out[:, 0].astype(np.int64)]
        ends = arc[pairs]                               # (n, 2 segments, 2 ends)
        along = ends[:, :, 0] + out[:, 15:17] * (ends[:, :, 1] - ends[:, :, 0])
        return {"normal": out[:, 1], "penetration": out[:, 2], "first": out[:, 3:6],
                "second": out[:, 6:9], "tangential": out[:, 9:12], "lines": line[pairs],
                "arc": along, "friction_power": power, "max_penetration": depth}
