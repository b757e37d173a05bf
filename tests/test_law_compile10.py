"""How many modules a law makes (issue 47, item 5): its point functions in one module per
expressions and damping, which the law's Gauss module, its parts' and the assumed-strain
modules of every element size import, so that a process compiles each point function
once, not once per module that calls it (the green law's bending points were compiled
three times: in its bending part's module and in the assumed-strain modules of the cubic
and the quintic element)."""

import pytest

from skfem_cable import laws
from skfem_cable.laws import codegen

GREEN = laws.BUILTIN["cable"]
TRUSS = laws.BUILTIN["truss"]


@pytest.fixture(scope="module")
def green_modules():
    """The green law's modules of every kind and element size a cable can take (imported,
    not compiled): the whole law's and its two parts' Gauss modules, and its assumed-strain
    modules of the cubic and the quintic element."""
    return {"gauss": GREEN.compiled(), "axial": GREEN.part(0).compiled(),
            "bending": GREEN.part(1).compiled(),
            "assumed-strain 4": GREEN.compiled("assumed-strain", (0, 1)),
            "assumed-strain 6": GREEN.compiled("assumed-strain", (0, 1, 2))}


def _points_module(module):
    return module.point_ghd.py_func.__module__


def test_five_kernel_modules_call_three_points_modules(green_modules):
    assert len({m.__name__ for m in green_modules.values()}) == 5
    assert len({_points_module(m) for m in green_modules.values()}) == 3
    for module in green_modules.values():
        assert _points_module(module) != module.__name__
        assert "def point_g" not in open(module.__file__).read()


def test_the_bending_points_serve_both_element_sizes_and_the_bending_part(green_modules):
    """The same dispatchers (compiled once per process), not copies of the same text."""
    bending = green_modules["bending"]
    for size in ("assumed-strain 4", "assumed-strain 6"):
        for name in codegen.POINTS:
            assert getattr(green_modules[size], name) is getattr(bending, name), (size, name)
    assert green_modules["gauss"].point_gh is not bending.point_gh
    assert green_modules["axial"].point_gh is not bending.point_gh


def test_the_points_module_holds_the_vectorised_point_of_the_gauss_module(green_modules):
    """``numpy_point`` (the scikit-fem forms' and the fields' evaluation) comes with the
    point functions; the strain functions stay in the assumed-strain module of the law."""
    gauss, assumed = green_modules["gauss"], green_modules["assumed-strain 4"]
    assert gauss.numpy_point.__module__ == _points_module(gauss)
    assert assumed.strain_point.py_func.__module__ == assumed.__name__


def test_a_points_module_is_named_by_its_expressions_and_damping():
    """The assumed-strain module takes its bending points with the law's damping (as it
    did when it held them), which names them; a law without bending has empty ones."""
    assert codegen.points_name(GREEN, True) != codegen.points_name(GREEN, False)
    assert codegen.points_name(GREEN.part(1), True) != codegen.points_name(GREEN, True)
    assert codegen.points_name(GREEN.part(1), True).startswith(
        "skfem_cable_law_cable_bending_points_damped_")
    assert TRUSS.part(1).vanishes
    assert codegen.points_name(TRUSS.part(1), True) != codegen.points_name(TRUSS, True)
