"""What the line loads compile (issue 47, item 5): one module per load and element type
(``kernels.line.module``: the number of functions ``NF`` a constant, its loops unrolled),
all calling the load's one point function, which numba types and lowers once per process
(``line.point_function``) and LLVM inlines into each module's ``span``.  Before, numba
inlined it into every module (``inline="always"``) and typed it there again: ``span`` was
29 s of a clean-clone test run.  Imports only: nothing here compiles."""

import pytest

from skfem_cable.kernels import contact, coulomb, drag, line

#: Every pointwise load's point function.
POINTS = {"drag": drag.point, "solar wind": coulomb.point,
          "uniform solar wind": coulomb.point_uniform, "contact": contact.point}


@pytest.mark.parametrize("name", list(POINTS))
def test_a_point_function_is_compiled_apart_and_inlined_by_llvm(name):
    """Not numba's inlining (typed again in every caller), LLVM's (the same
    instructions in the loop)."""
    options = POINTS[name].targetoptions
    assert options.get("forceinline") is True, name
    assert "inline" not in options, name


def test_the_modules_of_every_element_type_call_the_one_point_function():
    """The Morison drag on the linear, cubic and quintic elements: three modules (their
    ``NF`` fixed), one dispatcher."""
    modules = [line.module(drag.point, nf) for nf in (2, 4, 6)]
    assert len({m.__name__ for m in modules}) == 3
    assert [m.NF for m in modules] == [2, 4, 6]
    for m in modules:
        assert m.point is drag.point
        assert "def point(" not in open(m.__file__).read()
