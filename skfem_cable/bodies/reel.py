"""A reel with inertia whose coordinate is the free length of the tether it pays out
(``System.deploy(cable, anchor, reel=Reel(...))``), and the drives of its torque.

The reel is a body with one coordinate, the free (unstretched) length ``l`` of its tether
(m), and the kinetic energy ``1/2 (J / R^2) l'^2`` of a drum of inertia ``J`` and radius
``R`` (the tether leaves it at the rim speed ``l'``).  Its drive gives the torque on the drum,
positive when it pays out; the generalized force on ``l`` is ``torque / R``.  Everything
the tether adds to the equation of ``l`` (its inertia, the tension at the exit, the material
still wound on the drum) comes from the deployment (``deploy``).

The drives are small classes with one hook, ``torque(t, length, rate)``, returning the
torque (N m) and its derivatives in the length and the rate (the Newton tangent):

* ``Brake(damping)``: a viscous brake, ``-c l'`` (N m s/m);
* ``Motor(torque)``: a prescribed torque ``torque(t)``;
* ``Servo(length, stiffness, damping)``: a motor and brake holding the length on a
  reference ``length(t)`` (a deployment controller).

A user's drive is any object with that hook.
"""

import copy

import numpy as np
import scipy.sparse as sp

from ..core.contract import Term
from ..core.inputs import declared, reader
from ..kernels import drives
from .section import check_positive


class Reel:
    """A reel (drum) paying out a tether: one coordinate, the free length ``l`` (m).

    Parameters
    ----------
    length : float
        Free length at the start (m), > 0: the tether's length as built.
    radius : float
        Drum radius ``R`` (m), > 0.
    inertia : float
        Moment of inertia of the empty drum about its axle ``J`` (kg m^2), >= 0; the wound
        tether's share is added by the deployment (``capacity``).
    drive : object, optional
        The law of the torque on the drum, with ``torque(t, length, rate) -> (torque,
        d/dlength, d/drate)`` (``Brake``, ``Motor``, ``Servo``); None: a free reel.
    name : str

    Attributes
    ----------
    n_dofs : int
        1.
    q0 : ndarray (1,)
        ``[length]``.
    position_mask : bool ndarray (1,)
        True: the coordinate is a length (a scale for convergence tests).
    vector_mask : bool ndarray (1,)
        False: the coordinate is a scalar, not part of a 3-vector in space (rigid motions
        leave it alone).

    Examples
    --------
    >>> import skfem_cable as sc
    >>> reel = sc.Reel(10.0, radius=0.1, inertia=0.02, drive=sc.Brake(5.0))
    >>> reel.n_dofs, float(reel.mass_matrix()[0, 0]), reel.drive.torque(0.0, 10.0, 2.0)
    (1, 2.0, (-10.0, 0.0, -5.0))
    """

    n_dofs = 1
    position_mask = np.array([True])
    vector_mask = np.array([False])

    #: ``contract.Body.energy_parts``: none (its drive's work is external).
    energy_parts = ()

    def __init__(self, length, radius, inertia=0.0, drive=None, name="reel"):
        self.q0 = np.array([check_positive("length", length)])
        self.radius = check_positive("radius", radius)
        if not (np.isfinite(inertia) and inertia >= 0):
            raise ValueError(f"inertia must be >= 0 (kg m^2), got {inertia!r}")
        self.inertia = float(inertia)
        if drive is not None and not callable(getattr(drive, "torque", None)):
            raise TypeError(f"drive must have torque(t, length, rate), got {drive!r}")
        self.drive = drive
        self.name = name

    def describe_dof(self, index):
        return "free length"

    def internal_constraints(self):
        return []

    def mass_matrix(self):
        """``[[J / R^2]]`` (kg): the drum's inertia seen by the length."""
        return sp.csr_matrix([[self.inertia / self.radius**2]])

    def mass_points(self):
        """No mass in space (``Body.mass_points``): the drum's inertia is the length's."""
        return np.zeros((0, 1), np.int64), np.zeros((0, 1)), np.zeros(0)

    def show(self, system, q, v, t, **detail):
        """Nothing to draw (``Body.show``): the drum is not placed in space."""
        return None

    def outputs(self, system, q, t):
        """``Body.outputs``: the free length (m)."""
        return {"length": q[system.dofs(self)][0]}

    def inputs(self):
        """The inputs the drive reads (``inputs.declared``)."""
        return declared(self.drive)

    def bind(self, system, inputs=None):
        """The term of the drive's torque on the length, ``torque / R``, booked as
        external work (a brake's is negative); None for a free reel.  The drive reads the
        run's values of its inputs (``inputs``: the run's ``InputTable``)."""
        if self.drive is None:
            return None
        dof = np.ascontiguousarray(system.dofs(self), dtype=np.int64)
        drive = reader(self.drive, inputs)
        c = np.array(drive.coefficients(0.0), dtype=float)

        def prepare(t):
            c[:] = drive.coefficients(t)

        pack = (dof, c, np.array([1.0 / self.radius]))
        return Term(kernels=((drives.reel_torque, pack),), prepare=prepare,
                    rows=dof[:, None], cols=dof[None, :], name=f"{self.name} torque",
                    writes=("f_ext",))


class Drive:
    """A reel's drive: a torque ``c0(t) + c1 l + c2 l'`` (N m) linear in the free length
    ``l`` and its rate, given by ``coefficients(t) -> (c0, c1, c2)`` (its one hook; the
    reel's compiled term refreshes them once per step).  Any of its functions of time
    may be an ``Input`` that a controller sets: a drive names the attributes holding its
    functions of time in ``functions``, which declares their inputs (``inputs``) and
    gives the run's drive (``reading``)."""

    #: The names of the attributes holding the drive's functions of time.
    functions = ()

    def coefficients(self, t):
        raise NotImplementedError

    def inputs(self):
        """The inputs the drive's functions of time read (``inputs.declared``)."""
        return declared(*(getattr(self, name) for name in self.functions))

    def reading(self, table):
        """The drive as a run reads it: a copy whose functions of time read the run's
        ``table`` (``inputs.InputTable``); this one when it reads none."""
        if not self.inputs():
            return self
        out = copy.copy(self)
        for name in self.functions:
            setattr(out, name, reader(getattr(self, name), table))
        return out

    def torque(self, t, length, rate):
        """``(torque, d torque / d l, d torque / d l')`` at time ``t``."""
        c0, c1, c2 = self.coefficients(t)
        return c0 + c1 * length + c2 * rate, c1, c2


class Brake(Drive):
    """A viscous brake: torque ``-damping l'`` (N m), ``damping`` in N m s/m, >= 0."""

    def __init__(self, damping):
        if not (np.isfinite(damping) and damping >= 0):
            raise ValueError(f"damping must be >= 0 (N m s/m), got {damping!r}")
        self.damping = float(damping)

    def coefficients(self, t):
        return 0.0, 0.0, -self.damping


class Motor(Drive):
    """A prescribed torque ``torque(t)`` (N m; a number for a constant one, or an
    ``Input``)."""

    functions = ("value",)

    def __init__(self, torque):
        self.value = torque if callable(torque) else (lambda t, c=float(torque): c)

    def coefficients(self, t):
        return float(self.value(t)), 0.0, 0.0


class Servo(Drive):
    """A motor and brake holding the free length on a reference:
    ``torque = -stiffness (l - length(t)) - damping (l' - rate(t))``.

    Parameters
    ----------
    length : callable
        Reference length ``length(t)`` (m), e.g. ``deploy.smooth_profile``'s first item.
    stiffness : float
        N m / m, > 0.
    damping : float
        N m s / m, >= 0.
    rate : callable, optional
        ``length'(t)`` (m/s); None: the reference rate is not fed forward.
    """

    functions = ("length", "rate")

    def __init__(self, length, stiffness, damping, rate=None):
        self.length, self.rate = length, rate
        self.stiffness = check_positive("stiffness", stiffness)
        if not (np.isfinite(damping) and damping >= 0):
            raise ValueError(f"damping must be >= 0 (N m s/m), got {damping!r}")
        self.damping = float(damping)

    def coefficients(self, t):
        target_rate = 0.0 if self.rate is None else float(self.rate(t))
        return (self.stiffness * float(self.length(t)) + self.damping * target_rate,
                -self.stiffness, -self.damping)
