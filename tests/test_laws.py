"""Element laws: generated kernels against scikit-fem forms and finite differences, errors
that name the parameter, the on-disk cache, and batching by law."""

import importlib.util
from pathlib import Path

import numpy as np
import pytest
import skfem
from scipy.sparse import issparse

import skfem_cable as sc
from skfem_cable import laws
from skfem_cable.elements import ELEMENTS
from skfem_cable.laws import codegen

DEMOS = Path(__file__).resolve().parents[1] / "demos"
DAMPED = sc.Section(E=7e10, A=3e-6, I=1e-12, rho=2700.0, gamma_axial=0.02,
                    gamma_bending=0.05)


def gallery():
    spec = importlib.util.spec_from_file_location("law_gallery", DEMOS / "law_gallery.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


GALLERY = gallery()
LAWS = {"green": "cable", "truss": "truss", "biot": GALLERY.biot,
        "polymer": GALLERY.polymer, "power-law": GALLERY.damped_biot}


def deformed(cable, seed, size=0.05):
    """A random deformed state of a cable of length 2 and velocities of order 1."""
    rng = np.random.default_rng(seed)
    q = cable.q0 * 1.01 + size * rng.standard_normal(cable.n_dofs) * cable.length / max(
        cable.n_elements, 4)
    return q, rng.standard_normal(cable.n_dofs)


def make(law, n, formulation=None, element="hermite3"):
    return sc.Cable.straight([0, 0, 0], [2, 0, 0], n, DAMPED, law=law, formulation=formulation,
                             element=element)


#: Every element with every formulation it supports.
ELEMENT_FORMULATIONS = [(e, f) for e, element in ELEMENTS.items() for f in element.formulations]


def relative(a, b):
    """``max |a - b| / max |b|`` of arrays, or of sparse matrices as they are (not made
    dense: those of 1000 elements are 6006 x 6006, 0.3 GB each)."""
    if not (issparse(a) and issparse(b)):
        a, b = np.asarray(a), np.asarray(b)
    return abs(a - b).max() / abs(b).max()


@pytest.mark.parametrize(("element", "n"), [("hermite3", 1), ("hermite3", 16),
                                            ("hermite3", 1000), ("hermite5", 1),
                                            ("hermite5", 16)])
@pytest.mark.parametrize("name", LAWS)
def test_forms_equal_kernel(name, element, n):
    """skfem.asm of the law's forms on the element's scikit-fem basis = the compiled kernel
    of the paper's formulation (force, df/dq, df/dv) to 1e-12, damping included, on the
    cubic and the quintic element."""
    cable = make(LAWS[name], n, "paper", element)
    q, v = deformed(cable, n)
    w = sc.forms.state(cable, q, v)
    L, a = sc.forms.internal(cable)
    f, K = sc.System([cable]).assemble(q, v)
    assert relative(skfem.asm(L, cable.basis, **w), f) < 1e-12
    assert relative(skfem.asm(a, cable.basis, **w), K) < 1e-12
    _, C = sc.System([cable]).assemble(q, v, cK=0.0, cC=1.0)
    if cable.law.damped:
        assert relative(skfem.asm(sc.forms.damping(cable), cable.basis, **w), C) < 1e-12
    else:
        assert C.nnz == 0 or abs(C).max() == 0


def energy(system, q):
    """The elastic energy of ``system`` at ``q``."""
    _, info = system.evaluate(q, None, 0.0, np.zeros(0), layout=system.layout)
    return info["energy"].sum()


@pytest.mark.parametrize("formulation", ELEMENTS["hermite3"].formulations)
def test_forms_refuse_the_locking_free_formulations(formulation):
    """The forms express one rule on cable.basis: the other formulations are refused with
    the formulation named and the one that works."""
    cable = make("cable", 2, formulation)
    if formulation == "paper":
        sc.forms.internal(cable)
        return
    with pytest.raises(NotImplementedError, match=f"'{formulation}'.*formulation='paper'"):
        sc.forms.internal(cable)


@pytest.mark.parametrize(("element", "formulation"), ELEMENT_FORMULATIONS)
@pytest.mark.parametrize("name", LAWS)
def test_generated_tangents_match_finite_differences(name, element, formulation):
    """Every law on every element in every formulation (the laws with bending on the
    elements with ``r_xx``): f = dU/dq, K = df/dq and C = df/dv of the generated kernels
    against central differences (relative 1e-6)."""
    law = LAWS[name]
    if not ELEMENTS[element].bending and (law if isinstance(law, sc.CableLaw)
                                          else laws.BUILTIN[law]).bending:
        with pytest.raises(ValueError, match="has bending"):
            make(law, 3, formulation, element)
        return
    cable = make(law, 3, formulation, element)
    q, v = deformed(cable, 7)
    system = sc.System([cable])
    f_static, K_static = system.assemble(q)
    f, K = system.assemble(q, v)
    _, C = system.assemble(q, v, cK=0.0, cC=1.0)
    h = 1e-6
    E = np.eye(cable.n_dofs)
    fd_f = np.array([(energy(system, q + h * e) - energy(system, q - h * e)) / (2 * h)
                     for e in E])

    def force(x, y):  # the unedited system's layout, held (no description per call)
        return system.assemble(x, y, layout=system.layout)[0]

    fd_K = np.array([(force(q + h * e, v) - force(q - h * e, v)) / (2 * h) for e in E]).T
    fd_C = np.array([(force(q, v + h * e) - force(q, v - h * e)) / (2 * h) for e in E]).T
    assert relative(fd_f, f_static) < 1e-6
    assert relative(fd_K, K.toarray()) < 1e-6
    if cable.law.damped:
        assert relative(fd_C, C.toarray()) < 1e-6
    assert relative(f_static, f) > 0 if cable.law.damped else np.allclose(f_static, f)


def test_builtin_tension_is_the_explicit_formula():
    """Cable.tension of the generated law where it is asked (the paper's formulation): EA
    eps |r_x| - EI kappa^2 / |r_x| (the previous hand-written formula) on a curved,
    stretched state."""
    cable = make("cable", 8, "paper")
    q, _ = deformed(cable, 3, size=0.3)
    s = np.linspace(0, cable.length, 23)
    _, a, b = cable.interpolate(q, s)
    p = np.einsum("...i,...i", a, a)
    k2 = np.einsum("...i,...i", np.cross(a, b), np.cross(a, b)) / p**3
    sec = cable.section
    explicit = sec.EA * 0.5 * (p - 1) * np.sqrt(p) - sec.EI * k2 / np.sqrt(p)
    assert np.allclose(cable.tension(q, s), explicit, rtol=1e-12, atol=1e-12 * sec.EA)


def test_biot_tension_is_linear_in_the_stretch():
    bar = make(GALLERY.biot, 2)
    q = bar.q0 * 1.25
    q[3::6] = 1.25
    assert np.allclose(bar.tension(q, [0.3, 1.7]), 0.25 * DAMPED.EA, rtol=1e-12)


def test_law_errors_name_the_problem():
    with pytest.raises(TypeError, match="field arguments"):
        sc.cable_law(lambda a: a[0])
    with pytest.raises(ValueError, match="'stiffness'"):
        @sc.cable_law
        def unknown(a, b, stiffness):
            return stiffness * laws.green_strain(a) ** 2
        make(unknown, 2)
    with pytest.raises(TypeError, match="scalar expression"):
        @sc.cable_law
        def vector(a, b, EA):
            return EA * a
        make(vector, 2)
    with pytest.raises(ValueError, match="law must be"):
        make("rope", 2)
    with pytest.raises(ValueError, match="no parameter 'EB'"):
        laws.green.with_parameters(EB=1.0)
    with pytest.raises(ValueError, match="finite"):
        make(laws.green.with_parameters(EA=np.nan), 2)


def test_parameters_from_the_law_override_the_section():
    """with_parameters fixes EA whatever the section: twice the stiffness, twice the force."""
    stiff = laws.green.with_parameters(EA=2 * DAMPED.EA)
    q = make("cable", 2).q0 * 1.01
    f1, _ = sc.System([make("cable", 2)]).assemble(q)
    f2, _ = sc.System([make(stiff, 2)]).assemble(q)
    assert np.allclose(f2, 2 * f1, rtol=1e-12)


def test_generated_module_is_cached_on_disk(tmp_path, monkeypatch):
    """A law is derived once per machine: a new process (here a new CableLaw of the same
    function) imports the module from the cache folder without deriving it again."""
    monkeypatch.setenv("SKFEM_CABLE_CACHE", str(tmp_path))

    def quartic(a, b, EA, k4=3.0):
        e = laws.green_strain(a)
        return EA * (e**2 / 2 + k4 * e**4)

    first = sc.CableLaw(quartic)
    module = first.compiled()
    assert Path(module.__file__).parent == tmp_path / "laws"
    monkeypatch.setattr(codegen, "source", lambda law: pytest.fail("derived again"))
    monkeypatch.delitem(__import__("sys").modules, module.__name__)
    again = sc.CableLaw(quartic).compiled()
    assert again.__file__ == module.__file__
    changed = sc.CableLaw(quartic).with_parameters(k4=4.0)
    assert codegen.module_name(changed) == codegen.module_name(first)  # values are data
    monkeypatch.undo()


def test_cables_with_the_same_law_and_values_share_one_kernel_call():
    c1, c2, c3 = make("cable", 2), make("cable", 3), make(GALLERY.biot, 2)
    system = sc.System([c1, c2, c3])
    names = sorted(t.name for t, _ in system.layout.body_terms)
    assert names == sorted([f"{c1.name} + {c2.name}", c3.name])
