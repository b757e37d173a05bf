"""Element laws of the cable, FEniCS-style: write an energy density, get a compiled kernel
and scikit-fem forms (``docs/extending.md``, "Write your own law").

>>> import skfem_cable as sc
>>> from skfem_cable import laws
>>> @sc.cable_law
... def biot(a, b, EA, EI):            # a = r_x, b = r_xx
...     e = laws.norm(a) - 1
...     return EA * e**2 / 2 + EI * laws.kappa2(a, b) / 2

The vocabulary (``norm``, ``dot``, ``cross``, ``kappa2``, ``green_strain``, ``rate``,
``curvature_rate``, ``ramp``, ``where``, ``sqrt``, ``exp``, ``log``, ``tanh``, ``Abs``) is
in ``laws.symbolic``; ``CableLaw`` and ``cable_law`` in ``laws.law``; the derivation and
compilation in ``laws.codegen``; the built-in laws ``green`` (the paper's cable, name
``"cable"``), ``truss`` and their damping ``kelvin_voigt`` in ``laws.builtin``.
"""

from .builtin import BUILTIN, axial_kelvin_voigt, green, kelvin_voigt, truss
from .law import CableLaw, cable_law
from .symbolic import (
    CURVATURE_RATE_DELTA,
    SLOPE_FLOOR,
    Abs,
    cross,
    curvature_rate,
    dot,
    exp,
    green_strain,
    kappa2,
    log,
    norm,
    ramp,
    rate,
    sqrt,
    tanh,
    where,
)

__all__ = ["BUILTIN", "CURVATURE_RATE_DELTA", "SLOPE_FLOOR", "Abs", "CableLaw",
           "axial_kelvin_voigt", "cable_law", "cross", "curvature_rate", "dot", "exp",
           "green", "green_strain", "kappa2", "kelvin_voigt", "log", "norm", "ramp", "rate",
           "sqrt", "tanh", "truss", "where"]
