"""Quadratic drag of a surrounding flow on cables and other line bodies: Morison drag in
water (with buoyancy and added mass) and free-molecular drag of a rarefied atmosphere on
low-orbit tethers.

Both are compiled loads: their force at a point (``kernels.drag.point``) in the one loop
of the line loads (``kernels.line.module``) over the body's points (``lines``, the
line-body hook), the generalized force ``int S^T f dx`` with its exact tangent in the
coordinates and the velocities, evaluated inside the compiled Newton step; a current that
changes in time is refreshed once per step (``Term.prepare``).

The force is per unit *reference* length by default, as in MoorDyn (its drag uses the
unstretched segment lengths): the diameter and the drag coefficients are nominal values
of the unstretched line, and the difference from the deformed length is of the order of
the strain.  ``deformed_length=True`` multiplies by the stretch ``|r_x|`` instead.

References
----------
1. J. R. Morison, M. P. O'Brien, J. W. Johnson and S. A. Schaaf, "The force exerted by
   surface waves on piles", Petroleum Transactions AIME 189 (1950) 149-154.
2. M. Hall and A. Goupee, "Validation of a lumped-mass mooring line model with DeepCwind
   semisubmersible model test data", Ocean Engineering 104 (2015) 590-603 (MoorDyn: normal
   drag on ``d``, tangential drag on ``pi d``, added mass ``C_a rho pi d^2 / 4``).
3. M. L. Cosmo and E. C. Lorenzini (eds.), "Tethers in Space Handbook", 3rd ed., NASA
   Marshall Space Flight Center, 1997 (aerodynamic drag on tethers: the projected area of
   the tether normal to the flow, ``C_D`` about 2.2 in free-molecular flow).

Examples
--------
>>> import skfem_cable as sc
>>> sec = sc.Section.circular(0.02, 1e11, 7800.0)
>>> line = sc.Cable.straight([0, 0, -20], [100, 0, -20], 10, sec)
>>> drag = sc.MorisonDrag(line, rho=1025.0, diameter=0.04, cd_normal=1.2,
...                       cd_tangential=0.008, current=[1.0, 0, 0])
>>> system = sc.System([line]).add_load(drag).add_load(
...     sc.Buoyancy(line, rho=1025.0, diameter=0.04, g=[0, 0, -9.81]))
"""

import numpy as np

from ..bodies.section import check_positive
from ..core.contract import Term
from ..core.lines import check_line_body, line_points
from ..kernels import drag as kernel
from ..space.orbit import co_rotation
from .knots import spacing_or_none
from .line import AlongCable, UniformLineLoad
from .point import vector3
from .sampling import density_model, is_model, line_sampler


class CurrentProfile:
    """A current varying with the elevation ``z = vertical . r``: piecewise linear through
    the table ``(elevations, velocities)``, constant beyond its ends, optionally scaled in
    time by ``ramp(t)`` (e.g. switched on).

    Parameters
    ----------
    elevations : array_like (n,)
        Strictly increasing elevations (m), n >= 1.
    velocities : array_like (n, 3)
        Current velocity (m/s) at each elevation.
    vertical : array_like (3,)
        Unit vector along which the elevation is measured (default ``z``).
    ramp : callable, optional
        ``ramp(t) -> float``: a factor on the whole profile (default 1).

    Examples
    --------
    A current of 1 m/s at the surface decreasing linearly to 0.2 m/s at 100 m depth,
    switched on over 10 s:

    >>> import skfem_cable as sc
    >>> profile = sc.CurrentProfile([-100.0, 0.0], [[0.2, 0, 0], [1.0, 0, 0]],
    ...                             ramp=lambda t: min(t / 10.0, 1.0))
    >>> profile.velocity([0, 0, -50.0], t=5.0).round(12).tolist()
    [0.3, 0.0, 0.0]
    """

    def __init__(self, elevations, velocities, vertical=(0.0, 0.0, 1.0), ramp=None):
        z = np.asarray(elevations, dtype=float).ravel()
        u = np.asarray(velocities, dtype=float)
        if z.size < 1 or not np.all(np.isfinite(z)) or np.any(np.diff(z) <= 0):
            raise ValueError("elevations must be finite and strictly increasing, "
                             f"got {elevations!r}")
        if u.shape != (z.size, 3) or not np.all(np.isfinite(u)):
            raise ValueError(f"velocities must be a finite ({z.size}, 3) array (one "
                             f"3-vector per elevation), got shape {u.shape}")
        e = vector3(vertical, "vertical")
        if not abs(np.linalg.norm(e) - 1.0) < 1e-12:
            raise ValueError(f"vertical must be a unit vector, got {vertical!r}")
        if ramp is not None and not callable(ramp):
            raise TypeError(f"ramp must be a callable t -> float, got {ramp!r}")
        self.elevations, self.velocities, self.vertical, self.ramp = z, u, e, ramp
        self.factor(0.0)  # a bad ramp fails now, not in the middle of a run

    def factor(self, t):
        """``ramp(t)`` (1 without a ramp)."""
        if self.ramp is None:
            return 1.0
        value = float(self.ramp(t))
        if not np.isfinite(value):
            raise ValueError(f"ramp({t!r}) must be finite, got {value!r}")
        return value

    def velocity(self, x, t=0.0):
        """The current (m/s) at the point ``x`` and time ``t``."""
        z = float(np.dot(self.vertical, x))
        return self.factor(t) * np.array([np.interp(z, self.elevations, self.velocities[:, i])
                                          for i in range(3)])


class Flow:
    """The flow of a drag load, ``c(r, t) = c_0(t) + W r + sigma(t) U(e . r)``, as the
    arrays of the compiled kernel (``kernels.drag``).

    Parameters
    ----------
    current : None, array_like (3,), callable or CurrentProfile
        None: still fluid; a 3-vector: uniform and steady; ``current(t) -> (3,)``:
        uniform, time-dependent; a ``CurrentProfile``: varying with elevation.
    omega : array_like (3,) or None
        Rotation rate of the fluid about the origin (rad/s): ``W r = omega x r``; None:
        the rotation of the central body of the system's orbit (``orbit.co_rotation``).

    Notes
    -----
    In a system in orbit (``System.add_orbit``) the coordinates are offsets ``x`` from
    the reference point ``R(t)``, moving at ``V(t)``, in axes parallel to the inertial
    ones: the flow is taken at the absolute position ``R + x`` and relative to the
    frame's motion, ``c(R + x, t) - V``, so that the kernel's ``c - v`` is the flow
    relative to the absolute velocity ``V + v`` (``refresh``).  ``R`` and ``V`` depend
    on time only: the kernel's tangent keeps its form.
    """

    def __init__(self, current=None, omega=(0.0, 0.0, 0.0)):
        self.omega = None if omega is None else vector3(omega, "omega")
        self.profile = current if isinstance(current, CurrentProfile) else None
        self.fn = current if callable(current) else None
        self.constant = (np.zeros(3) if current is None or self.profile is not None
                         or self.fn is not None else vector3(current, "current"))
        self.uniform(0.0)  # a bad current callable fails now

    @property
    def steady(self):
        """True when the flow does not depend on time (in a fixed frame)."""
        return self.fn is None and (self.profile is None or self.profile.ramp is None)

    def uniform(self, t):
        """The uniform part ``c_0(t)`` (m/s)."""
        if self.fn is None:
            return self.constant
        return vector3(self.fn(t), f"current({t!r})")

    def arrays(self, orbit=None):
        """``(uniform, W, vertical, heights, velocities, sigma)`` for the kernel in a
        system of reference orbit ``orbit`` (None: not in orbit), set for its start
        (fresh arrays: ``refresh`` updates ``uniform``, ``heights`` and ``sigma`` in
        place)."""
        p = self.profile
        if p is None:
            vertical, z, u = np.array([0.0, 0.0, 1.0]), np.zeros(0), np.zeros((0, 3))
        else:
            vertical, z, u = p.vertical, p.elevations, p.velocities
        W = np.cross(co_rotation(self.omega, orbit), np.eye(3)).T  # W @ r = omega x r
        out = (np.zeros(3), np.ascontiguousarray(W), vertical.copy(), z.copy(),
               np.ascontiguousarray(u), np.ones(1))
        self.refresh(out, 0.0 if orbit is None else orbit.t0, orbit)
        return out

    def refresh(self, arrays, t, orbit=None):
        """Set the time-dependent parts of ``arrays`` for time ``t``; in orbit, the flow
        at ``R(t) + x`` relative to the frame moving at ``V(t)``: ``c_0 + W R - V`` and
        the profile's elevations shifted by ``-e . R`` (class notes)."""
        uniform = self.uniform(t)
        if orbit is not None:
            R = orbit.position(float(t))
            uniform = uniform + arrays[1] @ R - orbit.velocity(float(t))
            if self.profile is not None:
                arrays[3][:] = self.profile.elevations - arrays[2] @ R
        arrays[0][:] = uniform
        arrays[5][0] = 1.0 if self.profile is None else self.profile.factor(t)


class QuadraticDrag(AlongCable):
    """Drag ``lam (k_n |u_n| u_n + k_t |s| s t + k_x |u_n| s t)`` per unit length of one
    line body (a cable), with ``u`` the flow velocity relative to the cable, ``t`` its tangent,
    ``s = u . t`` and ``u_n = u - s t`` (the model of ``kernels.drag``); the common base
    of ``MorisonDrag`` and ``FreeMolecularDrag``, which set the coefficients.  In a
    system in orbit ``u`` is relative to the cable's absolute velocity ``V(t) + v``
    (the reference point's and the offsets'), at the absolute position ``R(t) + x``
    (``Flow``).

    Parameters
    ----------
    cable : Cable or line body
        The line (any body with the hook ``line_points``, ``lines``).
    coefficients : (k_n, k_t, k_x)
        In kg/m^2 (N per metre per (m/s)^2), each >= 0.
    flow : Flow
    deformed_length : bool
        False: per unit reference length (``lam = 1``); True: per unit deformed length
        (``lam = |r_x|``).
    """

    def __init__(self, cable, coefficients, flow, deformed_length=False):
        if not isinstance(deformed_length, bool):
            raise TypeError(f"deformed_length must be True or False, got {deformed_length!r}")
        self.cable, self.flow = check_line_body(cable, "cable"), flow
        self.coef = np.array([*coefficients, float(deformed_length)])

    def line_force(self, slope, relative_velocity):
        """Force per unit length (N/m) at one point with slope ``r_x`` (3,) in a flow of
        velocity ``relative_velocity`` (3,) relative to the cable (the kernel's model,
        for checks and plots)."""
        h, scratch = np.empty(3), np.empty((4, 3, 3))
        kernel.point_force(np.asarray(slope, float), np.asarray(relative_velocity, float),
                           self.coef, False, h, scratch[0], scratch[1], scratch[2, 0],
                           scratch[3, 0])
        return h

    #: Bound with the run's reference in orbit (``bind(system, reference)``).
    reads_reference = True

    def bind(self, system, reference=None):
        """The compiled term: the loop of ``kernels.line`` with the point function
        ``kernels.drag.point`` over the body's points (``lines.line_points``); a
        time-dependent current, or the reference point of a system in orbit (``Flow``: of
        ``reference``, the run's ``Reference``; None: the orbit as given), refreshes its
        arrays once per time step (``Term.prepare``)."""
        points = line_points(self.cable, system)
        orbit = system.orbit if reference is None else reference
        arrays = self.flow.arrays(orbit)
        hook = points.hook(kernel.point)
        rows, cols = points.tangent_pattern()
        hooks = self.samplers(system, points, orbit)

        def prepare(t):
            self.flow.refresh(arrays, t, orbit)
            for sampled in hooks:
                sampled.prepare(t)

        scale = hooks[0].out if hooks else None
        return Term(kernels=((hook, points.pack((self.coef.copy(), *arrays), scale)),),
                    rows=rows, cols=cols, mass=self.added_mass(system),
                    prepare=None if self.flow.steady and orbit is None and not hooks
                    else prepare, hooks=hooks,
                    name=f"{type(self).__name__} {self.cable.name}")

    def samplers(self, system, points, orbit):
        """The step hooks that refresh a per-element factor of the force once per step
        (``sampling.DensitySampler``: its ``out`` is the elements' ``scale``), at most
        one: none for a drag of constant coefficients."""
        return ()

    def added_mass(self, system):
        """``(rows, cols, values)`` of a constant added mass in ``system``, or None (no
        added mass)."""
        return None


class MorisonDrag(QuadraticDrag):
    """Morison drag of a current on a cable in water, with an optional added mass.

    Per unit length, with ``u = c(r, t) - r_dot`` the flow relative to the cable, ``t``
    the tangent, ``u_t = (u . t) t`` and ``u_n = u - u_t``:

        f = rho d C_dn |u_n| u_n / 2 + rho pi d C_dt |u_t| u_t / 2

    (the normal drag on the projected diameter ``d``, the tangential drag on the
    perimeter ``pi d``: MoorDyn's convention), per unit reference length by default.  In
    statics the cable is at rest, so a current is a real load: ``solve_static`` finds the
    settled shape in a current; in dynamics the drag also damps the motion.

    Parameters
    ----------
    cable : Cable or line body
        The line (any body with the hook ``line_points``, ``lines``).
    rho : float
        Density of the water (kg/m^3), > 0.
    diameter : float
        Hydrodynamic (volume-equivalent) diameter ``d`` (m), > 0.
    cd_normal, cd_tangential : float
        Drag coefficients ``C_dn`` and ``C_dt`` (>= 0).
    current : None, array_like (3,), callable or CurrentProfile
        Still water (None, default); a uniform steady current (m/s); ``current(t)``, a
        uniform current changing in time; a ``CurrentProfile`` (elevation-dependent,
        optionally ramped).  A general field ``current(x, t)`` is not compiled: use
        ``LineLoad`` with this force (Python path).
    added_mass : float
        Added-mass coefficient ``C_a`` >= 0 (default 0): a constant, *isotropic* added mass
        ``C_a rho pi d^2 / 4`` per unit reference length, the consistent mass
        ``int S^T S dx`` times it.  Exact for motions normal to the cable, too large by
        ``C_a - C_at`` for motions along it (``C_at`` is 0 for a smooth line, so axial
        vibrations are slowed; the normal, dominant ones are right).  No Froude-Krylov
        force from a time-dependent current is included (the water's acceleration is
        assumed zero).  It enters the integrator's mass matrix (``Term.mass``; gravity
        does not weigh it).
    deformed_length : bool
        True: per unit deformed length (the drag times the stretch ``|r_x|``).

    Notes
    -----
    The weight of the displaced water is ``Buoyancy``.  The tangent (``kernels.drag``)
    is exact in the coordinates (positions through the profile, slopes through the
    tangent) and in the velocities.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> line = sc.Cable.straight([0, 0, 0], [10, 0, 0], 4, sc.Section.circular(0.01, 1e11, 7800.0))
    >>> drag = sc.MorisonDrag(line, rho=1000.0, diameter=0.02, cd_normal=1.0,
    ...                       cd_tangential=0.0, current=[0, 2.0, 0])
    >>> drag.line_force([1.0, 0, 0], [0, 2.0, 0]).tolist()   # rho d Cd u^2 / 2
    [0.0, 40.0, 0.0]
    """

    def __init__(self, cable, rho, diameter, cd_normal, cd_tangential, current=None,
                 added_mass=0.0, deformed_length=False):
        self.rho = check_positive("rho", rho)
        self.diameter = check_positive("diameter", diameter)
        self.cd_normal = check_positive("cd_normal", cd_normal, allow_zero=True)
        self.cd_tangential = check_positive("cd_tangential", cd_tangential, allow_zero=True)
        self.ca = check_positive("added_mass", added_mass, allow_zero=True)
        k = 0.5 * self.rho * self.diameter
        super().__init__(cable, (k * self.cd_normal, np.pi * k * self.cd_tangential, 0.0),
                         Flow(current), deformed_length)

    def added_mass(self, system):
        """The isotropic added mass ``C_a rho pi d^2 / 4 int S^T S dx`` on the line's
        points (``lines.LinePoints.mass``: global ``(rows, cols, values)``), or None when
        ``C_a = 0``."""
        if self.ca == 0.0:
            return None
        mass_per_length = self.ca * self.rho * np.pi * self.diameter**2 / 4
        return line_points(self.cable, system).mass(mass_per_length)


class FreeMolecularDrag(QuadraticDrag):
    """Free-molecular (rarefied) drag of the upper atmosphere on a tether.

    Per unit length, with ``v_r = r_dot - v_atm`` the velocity relative to the atmosphere
    and ``t`` the tether's tangent:

        f = -C_D rho d |v_r x t| v_r / 2

    the dynamic pressure on the projected area ``d |sin theta|`` per unit length, along
    the relative velocity (hypersonic free-molecular flow: the momentum of the molecules
    that hit the tether is absorbed; Cosmo & Lorenzini, Tethers in Space Handbook).  The
    atmosphere moves with ``v_atm = velocity + omega x r`` (``omega``: Earth's rotation
    for a co-rotating atmosphere in an Earth-centred inertial frame), with a uniform,
    constant density or a density model.

    In a system in orbit (``System.add_orbit``) ``r`` is the absolute position
    ``R(t) + x`` and ``r_dot`` the absolute velocity ``V(t) + v`` (the reference point's
    orbital motion plus the offsets'), so the orbital velocity is the flow a tether
    meets: ``v_r = V + v - velocity - omega x (R + x)``, with ``omega`` by default the
    central body's rotation about the inertial ``z`` axis (``Orbit.central_body``: the
    Earth's ``OMEGA_EARTH`` = 7.292115e-5 rad/s for an orbit of ``MU_EARTH``).

    Parameters
    ----------
    cable : Cable or line body
        The line (any body with the hook ``line_points``, ``lines``).
    density : float or model
        Atmospheric density ``rho`` (kg/m^3), > 0; or a density model, an object with
        ``density(x, t)`` at absolute positions ``x`` (..., 3) ``t`` s after the epoch
        (``environment.MSIS``; made without an epoch it takes the system's,
        ``System.add_orbit(orbit, epoch=...)``), evaluated once per time step at every
        point and frozen over the step (the weighted mean over each element's points:
        the tangent is exact in the velocities, without ``d rho / dx``;
        ``loads.atmosphere``); ``line_force`` is then per unit density.
    diameter : float
        Tether diameter ``d`` (m), > 0 (a tape: its width across the flow).
    cd : float
        Drag coefficient ``C_D`` >= 0 (default 2.2).
    velocity : array_like (3,) or callable
        Uniform velocity of the atmosphere (m/s, in the inertial axes; a wind), or
        ``velocity(t)``.
    omega : array_like (3,) or None
        Rotation rate of the atmosphere about the origin (rad/s, the central body's
        centre in orbit); None (default): the central body's rotation in a system in
        orbit (``[0, 0, OMEGA_EARTH]`` about the Earth; zero for a ``mu`` of no known
        body), zero otherwise.
    deformed_length : bool
        True: per unit deformed length.
    sample_every : float or None
        With a density model: None (default), the model at the points once per time
        step; ``h`` (s, > 0), the model at knots every ``h`` seconds along the reference
        point, interpolated (``sampling``, ``loads.knots``).

    Examples
    --------
    A tether across a 7.5 km/s flow at 300 km (rho about 2e-11 kg/m^3):

    >>> import skfem_cable as sc
    >>> t = sc.Cable.straight([0, 0, 0], [0, 0, 1e3], 4, sc.Section.circular(5e-4, 1e11, 1500.0))
    >>> drag = sc.FreeMolecularDrag(t, density=2e-11, diameter=1e-3, velocity=[-7.5e3, 0, 0])
    >>> f"{drag.line_force([0, 0, 1.0], [-7.5e3, 0, 0])[0]:.4e} N/m"   # C_D rho d U^2 / 2
    '-1.2375e-06 N/m'
    """

    def __init__(self, cable, density, diameter, cd=2.2, velocity=(0.0, 0.0, 0.0),
                 omega=None, deformed_length=False, sample_every=None):
        self.density = density_model(density)
        self.sample_every = spacing_or_none(sample_every)
        self.diameter = check_positive("diameter", diameter)
        self.cd = check_positive("cd", cd, allow_zero=True)
        rho = 1.0 if is_model(self.density) else self.density  # a model: the elements' scale
        k = 0.5 * self.cd * rho * self.diameter
        super().__init__(cable, (k, 0.0, k), Flow(velocity, omega), deformed_length)

    def samplers(self, system, points, orbit):
        """A density model's ``DensitySampler`` (the per-element density, the kernel's
        ``scale``: the coefficients are per unit density), none for a number."""
        if not is_model(self.density):
            return ()
        return (line_sampler(self.density, points, system, orbit, self.sample_every),)


class Buoyancy(UniformLineLoad):
    """The weight of the water displaced by a cable, ``-rho (pi d^2 / 4) g`` per unit
    reference length: a constant generalized force (like ``Gravity``), the consistent
    ``int S^T f dx``.

    Parameters
    ----------
    cable : Cable or line body
        The line (any body with the hook ``line_points``, ``lines``).
    rho : float
        Density of the water (kg/m^3), > 0.
    diameter : float
        Volume-equivalent diameter (m), > 0.
    g : array_like (3,)
        Gravitational acceleration (m/s^2), the one given to ``add_gravity``.

    Examples
    --------
    >>> import skfem_cable as sc
    >>> line = sc.Cable.straight([0, 0, 0], [2, 0, 0], 2, sc.Section.circular(0.01, 1e11, 7800.0))
    >>> b = sc.Buoyancy(line, rho=1000.0, diameter=0.02, g=[0, 0, -10.0])
    >>> round(float(b.value[2]), 4)      # rho pi d^2 / 4 g
    3.1416
    """

    label = "buoyancy"

    def __init__(self, cable, rho, diameter, g):
        area = np.pi * check_positive("diameter", diameter) ** 2 / 4
        super().__init__(cable, -check_positive("rho", rho) * area * vector3(g, "g"))
