"""Cross-section and material of a cable (paper Table 1 symbols ``E_t, A_t, I_t, rho_t``)
and of a rod (``Rod``: also its torsion and its two principal bending stiffnesses).

Examples
--------
>>> from skfem_cable import Section
>>> steel = Section.circular(radius=1e-3, E=2e11, rho=7850.0)
>>> round(steel.EA), round(steel.mass_per_length, 5)
(628319, 0.02466)
"""

import math
import numbers
from dataclasses import dataclass

import numpy as np


def check_positive(name, value, allow_zero=False):
    """Return ``float(value)``; raise ``ValueError`` naming ``name`` unless it is finite and
    positive (or non-negative with ``allow_zero``)."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a real number, got {value!r}") from None
    ok = math.isfinite(v) and (v >= 0 if allow_zero else v > 0)
    if not ok:
        bound = ">= 0" if allow_zero else "> 0"
        raise ValueError(f"{name} must be finite and {bound}, got {value!r}")
    return v


def vector3(v, name):
    """``v`` as a finite 3-vector, or ``ValueError`` naming ``name``."""
    v = np.asarray(v, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be a finite 3-vector, got {v!r}")
    return v


def unit(v, name):
    """``v`` (a nonzero finite 3-vector) normalised, or ``ValueError`` naming ``name``."""
    v = vector3(v, name)
    norm = float(np.linalg.norm(v))
    if norm == 0.0:
        raise ValueError(f"{name} must be a nonzero 3-vector, got {v!r}")
    return v / norm


def real_number(name, value, allow_zero=False, hint=""):
    """Return ``float(value)``; raise ``ValueError`` naming ``name`` (and ``hint``, what
    the value means) unless it is a finite real number > 0 (>= 0 with ``allow_zero``),
    given as a number: not a bool and not a string, which ``check_positive`` would take
    (``True`` or ``"1e-4"`` read as numbers would be values nobody asked for)."""
    bound = ">= 0" if allow_zero else "> 0"
    if isinstance(value, bool) or not isinstance(value, numbers.Real) \
            or not math.isfinite(value) or not (value >= 0 if allow_zero else value > 0):
        raise ValueError(f"{name} must be a finite number {bound}{hint}, got {value!r}")
    return float(value)


def positive_int(name, value):
    """Return ``int(value)``; raise ``ValueError`` naming ``name`` unless it is an integer
    >= 1 (not a bool: ``True`` is no count)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1:
        raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class Section:
    """Homogeneous cable section (frozen: change one with ``dataclasses.replace``).

    Parameters
    ----------
    E : float
        Young's modulus (Pa), > 0.
    A : float
        Cross-section area (m^2), > 0.
    I : float
        Second moment of area (m^4), > 0.
    rho : float
        Density (kg/m^3), > 0.
    gamma_axial, gamma_bending : float
        Internal (Kelvin-Voigt) damping coefficients ``gamma_x, gamma_b`` of Eq. 36 in
        seconds, >= 0: ``N = EA (eps + gamma_x eps_dot)``, ``M = EI (kappa + gamma_b kappa_dot)``.
    G : float, optional
        Shear modulus (Pa), > 0; default ``E / (2 (1 + nu))``, which follows ``E`` when a
        section is replaced with another ``E``.  Read by a ``Rod`` only.
    nu : float
        Poisson's ratio in ``(-1, 0.5]`` for the default ``G``; 0.3.
    J : float, optional
        Saint-Venant torsion constant (m^4), > 0; default ``2 I`` (a round section).
    I_edge : float, optional
        Second moment of area about the section's ``normal`` axis (m^4), > 0: the
        edgewise bending of a tape; default ``I`` (isotropic).

    The principal axes of a section (``principal_axes``) are its ``normal`` (the
    thickness direction of a tape, the director ``d1`` of a ``Rod``), about which the
    bending stiffness is ``EI_edge``, and its ``width`` (``d2 = t x d1``), about which it
    is ``EI_flat = EI``.  A cable sees ``EI`` only.

    Attributes
    ----------
    EA, EI : float
        Axial (N) and bending (N m^2) stiffness.
    EI_flat, EI_edge : float
        Bending stiffnesses about the width and the normal axis (N m^2).
    GJ : float
        Torsional stiffness (N m^2).
    mass_per_length : float
        ``rho A`` (kg/m).
    polar_mass_moment : float
        ``rho I_p`` (kg m), ``I_p = I + I_edge``: the rotary inertia per length about the
        centreline.

    Raises
    ------
    ValueError
        A parameter that is not finite and positive (the damping: non-negative).

    See Also
    --------
    Cable : the cable that carries the section.

    Examples
    --------
    >>> from skfem_cable import Section
    >>> s = Section(E=7e10, A=1e-6, I=1e-13, rho=2700.0, gamma_axial=0.01)
    >>> s.EA, s.EI
    (70000.0, 0.007)
    >>> Section(E=-1.0, A=1e-6, I=1e-13, rho=2700.0)
    Traceback (most recent call last):
        ...
    ValueError: E must be finite and > 0, got -1.0
    """

    E: float
    A: float
    I: float
    rho: float
    gamma_axial: float = 0.0
    gamma_bending: float = 0.0
    G: float | None = None
    J: float | None = None
    I_edge: float | None = None
    nu: float = 0.3

    #: The principal axes of the section: the rod's directors ``d1`` and ``d2``.
    principal_axes = ("normal", "width")

    def __post_init__(self):
        for name in ("E", "A", "I", "rho"):
            object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        shear_modulus(self.E, self.G, self.nu)  # checks G or nu
        for name in ("G", "J", "I_edge"):
            if getattr(self, name) is not None:
                object.__setattr__(self, name, check_positive(name, getattr(self, name)))
        for name in ("gamma_axial", "gamma_bending"):
            value = check_positive(name, getattr(self, name), allow_zero=True)
            object.__setattr__(self, name, value)

    @classmethod
    def circular(cls, radius, E, rho, G=None, nu=0.3, **damping):
        """Solid circular section of the given ``radius`` (m), ``A = pi r^2``, ``I = pi r^4/4``,
        ``J = pi r^4 / 2``.

        Parameters
        ----------
        radius : float
            Radius (m), > 0.
        E, rho : float
            Young's modulus (Pa) and density (kg/m^3).
        G : float, optional
            Shear modulus (Pa); default ``E / (2 (1 + nu))``.
        nu : float
            Poisson's ratio in ``(-1, 0.5]``, for the default ``G``.
        **damping
            ``gamma_axial``, ``gamma_bending`` (s).

        Examples
        --------
        >>> from skfem_cable import Section
        >>> s = Section.circular(radius=0.01, E=7e10, rho=7800.0)
        >>> round(s.EA / 1e6, 3), round(s.EI, 3)
        (21.991, 549.779)
        """
        r = check_positive("radius", radius)
        return cls(E=E, A=math.pi * r**2, I=math.pi * r**4 / 4, rho=rho,
                   G=G, nu=nu, J=math.pi * r**4 / 2, **damping)

    @classmethod
    def tape(cls, width, thickness, E, rho, G=None, nu=0.3, **damping):
        """Thin rectangular tape ``width`` x ``thickness`` (m): ``A = w t``, ``I = w t^3 / 12``
        (flatwise, about the width), ``I_edge = t w^3 / 12`` (edgewise, about the normal)
        and the Saint-Venant ``J = w t^3 / 3 (1 - 0.63 t / w)`` (Roark's formula for a
        thin rectangle, ``t <= w``).

        Parameters
        ----------
        width, thickness : float
            Width and thickness (m), ``0 < thickness <= width``.
        E, rho, G, nu, **damping
            As for ``circular``.

        Examples
        --------
        >>> from skfem_cable import Section
        >>> s = Section.tape(0.02, 50e-6, E=7e10, rho=2700.0)
        >>> round(s.EI_edge / s.EI_flat)
        160000
        """
        w, t = check_positive("width", width), check_positive("thickness", thickness)
        if t > w:
            raise ValueError(f"thickness must be <= width (a tape), got thickness {t!r} "
                             f"and width {w!r}")
        return cls(E=E, A=w * t, I=w * t**3 / 12, rho=rho, G=G, nu=nu,
                   J=w * t**3 / 3 * (1 - 0.63 * t / w), I_edge=t * w**3 / 12, **damping)

    @property
    def EA(self):
        """Axial stiffness ``E A`` (N)."""
        return self.E * self.A

    @property
    def EI(self):
        """Bending stiffness ``E I`` (N m^2)."""
        return self.E * self.I

    @property
    def mass_per_length(self):
        """Mass per unit length ``rho A`` (kg/m)."""
        return self.rho * self.A

    @property
    def EI_flat(self):
        """Bending stiffness about the width axis, ``E I`` (N m^2)."""
        return self.E * self.I

    @property
    def EI_edge(self):
        """Bending stiffness about the normal axis, ``E I_edge`` (N m^2)."""
        return self.E * (self.I if self.I_edge is None else self.I_edge)

    @property
    def GJ(self):
        """Torsional stiffness ``G J`` (N m^2)."""
        G = shear_modulus(self.E, self.G, self.nu)
        return G * (2 * self.I if self.J is None else self.J)

    @property
    def polar_mass_moment(self):
        """Rotary inertia per length about the centreline, ``rho (I + I_edge)`` (kg m)."""
        return self.rho * (self.I + (self.I if self.I_edge is None else self.I_edge))


def shear_modulus(E, G, nu):
    """``G``, or ``E / (2 (1 + nu))`` when None; ``ValueError`` naming ``nu`` outside
    ``(-1, 0.5]``."""
    if G is not None:
        return check_positive("G", G)
    nu = float(nu)
    if not -1.0 < nu <= 0.5:
        raise ValueError(f"nu must be in (-1, 0.5], got {nu!r}")
    return float(E) / (2 * (1 + nu))
