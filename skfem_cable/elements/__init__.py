"""Element types of the cable (``base.CableElement``): the cubic Hermite (the paper's, the
default), the quintic Hermite and the two-node linear element.

``Cable(..., element=...)`` takes a name of ``ELEMENTS`` or an instance of a user's own
``CableElement`` subclass (``docs/extending.md``, "Write your own element").
"""

from .base import CableElement
from .hermite3 import ElementLineCableHermite
from .hermite5 import ElementLineCableHermite5
from .linear import ElementLineCableLinear

#: The built-in element types by name; the first is the default.
ELEMENTS = {e.name: e for e in (ElementLineCableHermite(), ElementLineCableHermite5(),
                                ElementLineCableLinear())}
DEFAULT_ELEMENT = next(iter(ELEMENTS))


def element_type(element):
    """The element type named ``element`` (a key of ``ELEMENTS``), or ``element`` itself if
    it is a ``CableElement``; a clear ``ValueError`` otherwise."""
    if isinstance(element, CableElement):
        return element
    if isinstance(element, str) and element in ELEMENTS:
        return ELEMENTS[element]
    raise ValueError(f"element must be one of {tuple(ELEMENTS)} or a CableElement "
                     f"(skfem_cable.elements.CableElement), got {element!r}")


__all__ = ["ELEMENTS", "DEFAULT_ELEMENT", "CableElement", "ElementLineCableHermite",
           "ElementLineCableHermite5", "ElementLineCableLinear", "element_type"]
