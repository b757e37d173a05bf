"""The built-in element laws: the paper's ANCF cable (Green strain and squared curvature,
Eqs. 23-26, with the Kelvin-Voigt damping of Eqs. 36-38), its truss (no bending), the truss
that goes slack (``"tension-only"``), and
Exudyn's cable (engineering strain, curvature per reference length), to reproduce that
code's numbers (``docs/peers.md``)."""

from .law import cable_law
from .symbolic import (
    cross,
    curvature_rate,
    dot,
    floored,
    green_strain,
    kappa2,
    norm,
    ramp,
    rate,
    where,
)


# --8<-- [start:green]
def kelvin_voigt(a, b, ad, bd, EA, EI, gamma_axial, gamma_bending, h):
    """Rayleigh dissipation of the Kelvin-Voigt section (Eq. 36): ``N = EA (eps + gamma_x
    eps_dot)``, ``M = EI (kappa + gamma_b kappa_dot)``, i.e. ``D = gamma_x EA eps_dot^2 / 2
    + gamma_b EI kappa_dot^2 / 2`` with the regularised ``curvature_rate``."""
    eps_dot = dot(a, ad)
    kappa_dot = curvature_rate(a, b, ad, bd, h)
    return gamma_axial * EA * eps_dot**2 / 2 + gamma_bending * EI * kappa_dot**2 / 2


@cable_law(dissipation=kelvin_voigt, name="cable")
def green(a, b, EA, EI):
    """The paper's cable: ``W = EA eps^2 / 2 + EI kappa^2 / 2`` (Eqs. 23-26)."""
    return EA * green_strain(a) ** 2 / 2 + EI * kappa2(a, b) / 2
# --8<-- [end:green]


# --8<-- [start:truss]
def axial_kelvin_voigt(a, b, ad, bd, EA, gamma_axial):
    """The axial part of ``kelvin_voigt`` (a truss has no curvature)."""
    return gamma_axial * EA * dot(a, ad) ** 2 / 2


@cable_law(dissipation=axial_kelvin_voigt, name="truss")
def truss(a, b, EA):
    """The paper's comparison model: ``W = EA eps^2 / 2``, no bending stiffness."""
    return EA * green_strain(a) ** 2 / 2
# --8<-- [end:truss]


# --8<-- [start:tension_only]
def slack_kelvin_voigt(a, b, ad, bd, EA, gamma_axial, onset_strain=1e-5):
    """``axial_kelvin_voigt`` that comes on over the strain ``onset_strain`` (``eps_o``):
    ``D = s(eps) gamma_x EA eps_dot^2 / 2`` with ``s = min(max(eps, 0) / eps_o, 1)``, so
    the damping force ``s gamma_x EA eps_dot`` is continuous where the tether goes slack
    or taut (switched on at ``eps = 0`` it jumps by ``gamma_x EA eps_dot``: Newton cycles
    across the jump, and the tether pushes while it slackens).  Stretched beyond
    ``eps_o`` the section is the truss's; within it the damping is ``s`` of that and the
    tether can push only by ``s gamma_x EA |eps_dot|`` less its elastic tension."""
    e = green_strain(a)
    onset = where(e >= onset_strain, 1, ramp(e) / onset_strain)
    return onset * axial_kelvin_voigt(a, b, ad, bd, EA, gamma_axial)


@cable_law(dissipation=slack_kelvin_voigt, name="tension-only")
def tension_only(a, b, EA):
    """The truss that goes slack: ``W = EA max(eps, 0)^2 / 2``, no force in compression
    (an auxiliary tether of an E-sail's ring, a mooring line that may slacken)."""
    return EA * ramp(green_strain(a)) ** 2 / 2
# --8<-- [end:tension_only]


# --8<-- [start:exudyn]
def curvature_vector(a, b):
    """Exudyn's curvature as a vector, ``k = (a x b) / |a|^2`` (its 2-D cable's signed
    curvature ``(a x b)_z / |a|^2`` times the plane's normal): curvature per reference
    length, where ``kappa2`` is per current length (``|k| = |a| kappa``)."""
    return cross(a, b) / floored(dot(a, a))


def exudyn_damping(a, b, ad, bd, EA, EI, gamma_axial, gamma_bending):
    """Exudyn's cable damping: ``N = gamma_x EA eps_dot`` and ``M = gamma_b EI k_dot``
    (its ``physicsAxialDamping``, ``physicsBendingDamping``), i.e. ``D = gamma_x EA
    eps_dot^2 / 2 + gamma_b EI |k_dot|^2 / 2`` with ``eps_dot = a . ad / |a|``; smooth at
    zero curvature, where the rate of ``|k|`` is not."""
    eps_dot = dot(a, ad) / floored(dot(a, a)) ** 0.5
    k = curvature_vector(a, b)
    k_dot2 = sum(rate(k[i], a, b, ad, bd) ** 2 for i in range(3))
    return gamma_axial * EA * eps_dot**2 / 2 + gamma_bending * EI * k_dot2 / 2


@cable_law(dissipation=exudyn_damping, name="exudyn")
def exudyn(a, b, EA, EI):
    """Exudyn's cable (``ObjectANCFCable2D``, ``ObjectANCFCable``): engineering strain
    ``eps = |a| - 1`` and curvature ``|a x b| / |a|^2``, ``W = EA eps^2 / 2 + EI |k|^2 /
    2``.  The same stiffness as ``green`` about a straight unstretched cable; in bending
    its curvature has no ``1/|a|`` (bending stiffness ``EI`` where ``green`` has ``EI /
    |a|^2``, about twice the axial strain apart)."""
    k = curvature_vector(a, b)
    return EA * (norm(a) - 1) ** 2 / 2 + EI * dot(k, k) / 2
# --8<-- [end:exudyn]


#: Built-in laws by name (``Cable(..., law="truss")``).
BUILTIN = {"cable": green, "truss": truss, "exudyn": exudyn, "tension-only": tension_only}
