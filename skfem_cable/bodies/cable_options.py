"""The options of a ``Cable`` checked and resolved: its law on its element, the Gauss
rules of its parts, its formulation; and the whole-number check its counts share."""

import math
import weakref

from ..laws import BUILTIN, CableLaw
from .formulation import FORMULATIONS

#: The laws whose axial part ``CableLaw.check_strain`` found a function of the strain.
_STRAIN_CHECKED = weakref.WeakSet()


def is_count(value):
    """Whether ``value`` is a whole number >= 1 (an int, or a float without fraction)."""
    try:
        return math.isfinite(value) and int(value) == value and value >= 1
    except (TypeError, ValueError):
        return False


def resolve_law(law, element):
    """The ``CableLaw`` of ``Cable``'s ``law`` on ``element``: a built-in name resolved,
    the default ``"cable"`` (``"truss"`` on an element without ``r_xx``), a law with
    bending refused on such an element."""
    if law is None:
        law = "cable" if element.bending else "truss"
    if isinstance(law, str):
        if law not in BUILTIN:
            raise ValueError(f"law must be a CableLaw or one of {tuple(BUILTIN)}, "
                             f"got {law!r}")
        law = BUILTIN[law]
    if not isinstance(law, CableLaw):
        raise TypeError(f"law must be a CableLaw (see skfem_cable.cable_law) or a name, "
                        f"got {type(law).__name__}")
    if law.bending and not element.bending:
        raise ValueError(f"law {law.name!r} has bending (its energy reads r_xx), which the "
                         f"element {element.name!r} does not have (it sees "
                         f"{', '.join(element.fields)} only): use an axial law such as "
                         "law='truss', or an element with bending, e.g. element='hermite3'")
    return law


def check_strain_once(law):
    """``law.check_strain()`` the first time ``law`` is met: the check is deterministic
    (its own seed) and reads the law's expressions alone, which do not change once the
    law is made (``with_parameters``, ``with_dissipation`` and ``part`` make new laws),
    so every cable of a law after the first would repeat it (about 0.01 s of sympy each:
    a full-size sail's 200 cables, 2.4 s)."""
    if law not in _STRAIN_CHECKED:
        law.check_strain()
        _STRAIN_CHECKED.add(law)


#: Most Gauss points a part of the law may take (``quadrature``).
MAX_GAUSS_POINTS = 20


def gauss_rules(quadrature, formulation, default):
    """``Cable``'s ``quadrature`` checked and completed (``{"axial": na, "bending": nb}``,
    a missing key taking ``default`` points, those of the rule of ``intorder``), or
    None."""
    if quadrature is None:
        return None
    if not isinstance(quadrature, dict) or not quadrature \
            or set(quadrature) - {"axial", "bending"}:
        raise ValueError("quadrature must be a dict with the keys 'axial' and/or 'bending' "
                         f"(Gauss points per element), got {quadrature!r}")
    if formulation != "paper":
        raise ValueError(f"quadrature is for formulation='paper' (Gauss rules for the "
                         f"axial and the bending part); formulation {formulation!r} "
                         "chooses its own rules: leave one of the two out")
    rules = {}
    for part in ("axial", "bending"):
        n = quadrature.get(part, default)
        if not (is_count(n) and n <= MAX_GAUSS_POINTS):
            raise ValueError(f"quadrature[{part!r}] must be a whole number of Gauss points "
                             f"in [1, {MAX_GAUSS_POINTS}], got {n!r}")
        rules[part] = int(n)
    return rules


def formulation_name(formulation, locking_free, element):
    """The formulation's name from ``Cable``'s ``formulation`` and ``locking_free``, one
    that ``element`` supports (its first by default)."""
    if locking_free is not None:
        if not isinstance(locking_free, bool):
            raise TypeError(f"locking_free must be True or False, got {locking_free!r}")
        named = "lobatto" if locking_free else "paper"
        if formulation is not None and formulation != named:
            raise ValueError(f"locking_free={locking_free} means formulation={named!r}, "
                             f"which contradicts formulation={formulation!r}: give one")
        formulation = named
    if formulation is None:
        return element.formulations[0]
    if formulation not in FORMULATIONS:
        raise ValueError(f"formulation must be one of {tuple(FORMULATIONS)}, "
                         f"got {formulation!r}")
    if formulation not in element.formulations:
        raise ValueError(f"formulation {formulation!r} is not available on the element "
                         f"{element.name!r}: it supports {element.formulations}")
    return formulation
