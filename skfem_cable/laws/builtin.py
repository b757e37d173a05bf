"""The built-in element laws: the paper's ANCF cable (Green strain and squared curvature,
Eqs. 23-26, with the Kelvin-Voigt damping of Eqs. 36-38) and its truss (no bending)."""

from .law import cable_law
from .symbolic import curvature_rate, dot, green_strain, kappa2


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


#: Built-in laws by name (``Cable(..., law="truss")``).
BUILTIN = {"cable": green, "truss": truss}
