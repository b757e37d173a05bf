"""What the warm test suite spends in the package's Python (issue 47, item 5: the test
command in two minutes warm): a law's strain check runs once per law, not once per
cable (every E-sail scene builds 12 cables of one law: ``esail.build`` 0.21-0.26 ->
0.09-0.12 s of CPU; the full-size sail's ``catalog.esail_full_scene``, 200 cables,
6.7-6.8 -> 4.3-4.5 s)."""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.bodies import cable_options
from skfem_cable.scenes.classics import ELASTICA_SECTION as SEC


def _cable(law):
    return sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, law=law)


def test_a_laws_strain_check_runs_for_its_first_cable_only(monkeypatch):
    """Before: ``CableLaw.check_strain`` (about 0.1 s of sympy) at every assumed-strain
    cable.  Now at the first cable of a law; a law made from it (``with_parameters``)
    is a new law and is checked again."""
    @sc.cable_law
    def stretch_only(a, b, EA):
        return EA * (sc.laws.green_strain(a)) ** 2 / 2

    calls = []
    check = type(stretch_only).check_strain
    monkeypatch.setattr(type(stretch_only), "check_strain",
                        lambda law, *args: calls.append(law) or check(law, *args))
    first, second = _cable(stretch_only), _cable(stretch_only)
    assert calls == [stretch_only] and stretch_only in cable_options._STRAIN_CHECKED
    stiffer = stretch_only.with_parameters(EA=2 * SEC.EA)
    _cable(stiffer)
    assert calls == [stretch_only, stiffer]
    assert np.array_equal(first.q0, second.q0)


def test_a_law_that_fails_the_check_fails_at_every_cable():
    """A refused law is not remembered as checked: its second cable is refused too."""
    @sc.cable_law
    def anisotropic(a, b, EA):
        return EA * (a[0] - 1) ** 2 / 2

    for _ in range(2):
        with pytest.raises(ValueError, match="anisotropic.*formulation='paper' or 'lobatto'"):
            _cable(anisotropic)
    assert anisotropic not in cable_options._STRAIN_CHECKED
