"""Element laws of the cable, FEniCS-style: write an energy density, get a compiled kernel
and scikit-fem forms (``docs/extending.md``, "Write your own law").

>>> import skfem_cable as sc
>>> from skfem_cable import laws
>>> @sc.cable_law
... def biot(a, b, EA, EI):            # a = r_x, b = r_xx
...     e = laws.norm(a) - 1
...     return EA * e**2 / 2 + EI * laws.kappa2(a, b) / 2

The vocabulary (``norm``, ``dot``, ``cross``, ``kappa2``, ``green_strain``, ``rate``,
``curvature_rate``, ``ramp``, ``where``, ``sqrt``, ``exp``, ``log``, ``tanh``, ``atan``,
``Abs``) is in ``laws.symbolic``; ``CableLaw`` and ``cable_law`` in ``laws.law``; the
derivation and compilation in ``laws.codegen``; the built-in laws ``green`` (the paper's
cable, name ``"cable"``), ``truss``, Exudyn's ``exudyn`` (with ``curvature_vector``) and
their damping ``kelvin_voigt``, ``exudyn_damping`` in ``laws.builtin``.
"""

from .builtin import (
    BUILTIN,
    axial_kelvin_voigt,
    curvature_vector,
    exudyn,
    exudyn_damping,
    green,
    kelvin_voigt,
    truss,
)
from .law import CableLaw, cable_law
from .symbolic import (
    CURVATURE_RATE_DELTA,
    SLOPE_FLOOR,
    Abs,
    atan,
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

__all__ = ["BUILTIN", "CURVATURE_RATE_DELTA", "SLOPE_FLOOR", "Abs", "CableLaw", "atan",
           "axial_kelvin_voigt", "cable_law", "cross", "curvature_rate", "curvature_vector", "dot",
           "exp", "exudyn", "exudyn_damping", "green", "green_strain", "kappa2", "kelvin_voigt",
           "log", "norm", "ramp", "rate", "sqrt", "tanh", "truss", "where"]
