"""Elastic energy, force and tangent of the cable: numba vs numpy (the paper's equations),
the assumed-strain energy from its definition, analytic vs finite differences in every
formulation, and finite values in degenerate states."""

import ancf_reference
import numpy as np
import pytest

from skfem_cable import Cable, Section, System

SEC = Section(E=7e10, A=3e-6, I=1e-12, rho=2700.0)


def make_cable(kind, n=5, formulation=None):
    return Cable.straight([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], n, SEC, law=kind,
                          formulation=formulation)


def states(cable):
    """Random curved, stretched, compressed and straight configurations."""
    rng = np.random.default_rng(42)
    q0 = cable.q0.reshape(-1, 2, 3)
    s = cable.mesh.p[0]
    R = 1.3
    arc = np.zeros_like(q0)
    arc[:, 0] = np.column_stack([R * np.sin(s / R), R * (1 - np.cos(s / R)), 0.1 * s])
    arc[:, 1] = np.column_stack([np.cos(s / R), np.sin(s / R), 0.1 + 0 * s])
    stretched = q0 * np.array([1.02, 1.0])[None, :, None] * np.array([1.0, 1.02])[None, :, None]
    compressed = q0 * 0.9
    return {
        "curved": arc.ravel() + 0.01 * rng.standard_normal(cable.n_dofs),
        "random": cable.q0 + 0.05 * rng.standard_normal(cable.n_dofs),
        "stretched": stretched.ravel(),
        "compressed": compressed.ravel(),
        "straight": cable.q0.copy(),
    }


def numba_eval(cable, q, system=None):
    """Energy, force and tangent (dense) through the evaluation contract of ``system``
    (default: a new ``System([cable])``; the same numbers, bit for bit)."""
    system = System([cable]) if system is None else system
    lay = system.layout  # held: the system is not edited (no description per call)
    data = np.zeros(lay.nnz)
    f, info = system.evaluate(q, None, 0.0, np.zeros(0), data=data, layout=lay)
    return info["energy"].sum(), f, lay.matrix(data).toarray()


def central(function, x, h=1e-6):
    """Central differences of every output of ``function`` at ``x``: per output, the
    rows ``(out(x + h e_i) - out(x - h e_i)) / (2 h)`` over the unit vectors ``e_i`` (each
    perturbed state evaluated once for all outputs)."""
    pairs = [(function(x + h * e), function(x - h * e)) for e in np.eye(x.size)]
    return [np.array([(plus[k] - minus[k]) / (2 * h) for plus, minus in pairs])
            for k in range(len(pairs[0][0]))]


def numpy_eval(cable, q):
    energy, _, fe, Ke, _ = ancf_reference.cable_forces(cable, q)
    f = np.zeros(cable.n_dofs)
    np.add.at(f, cable.element_dofs, fe.reshape(-1, 12))
    K = np.zeros((cable.n_dofs,) * 2)
    ed = cable.element_dofs
    np.add.at(K, (ed[:, :, None], ed[:, None, :]), Ke.reshape(-1, 12, 12))
    return energy.sum(), f, K


@pytest.mark.parametrize("kind", ["cable", "truss"])
def test_numba_and_numpy_paths_agree(kind):
    """The paper's formulation against the paper's equations written out in numpy."""
    cable = make_cable(kind, formulation="paper")
    for name, q in states(cable).items():
        U1, f1, K1 = numba_eval(cable, q)
        U2, f2, K2 = numpy_eval(cable, q)
        assert U1 == pytest.approx(U2, rel=1e-12, abs=1e-300), name
        assert np.allclose(f1, f2, rtol=0, atol=1e-12 * max(np.abs(f2).max(), 1e-300)), name
        assert np.allclose(K1, K2, rtol=0, atol=1e-12 * np.abs(K2).max()), name


def test_assumed_strain_energy_is_its_definition():
    """The default formulation's axial energy and dissipated power from their definition:
    the assumed strain is the quadratic with the raw strain's nodal values ``e0, e1`` and
    element mean ``M`` (8-point Gauss), ``M + a1 P1 + a2 P2`` in shifted Legendre
    polynomials (``a1 = (e1 - e0)/2``, ``a2 = (e0 + e1)/2 - M``), whose square integrates
    to ``M^2 + a1^2/3 + a2^2/5``; the energy is ``EA/2`` times that, the power of the
    Kelvin-Voigt damping ``gamma EA`` times the same of the strain rate."""
    sec = Section(E=7e10, A=3e-6, I=1e-12, rho=2700.0, gamma_axial=0.3, gamma_bending=0.7)
    truss = Cable.straight([0, 0, 0], [2, 0, 0], 5, sec, law="truss")
    ne = truss.n_elements
    gx, gw = np.polynomial.legendre.leggauss(8)
    rng = np.random.default_rng(11)

    def square_integral(q, v):
        """``int eps_bar^2 dx`` and ``int eps_bar_dot^2 dx`` over the cable."""
        xi = np.concatenate([[0.0, 1.0], 0.5 + 0.5 * gx])
        a, ad = (truss._fields(z, np.arange(ne)[:, None], xi[None, :])[1] for z in (q, v))
        out = []
        for raw in (0.5 * ((a * a).sum(-1) - 1), (a * ad).sum(-1)):
            e0, e1, M = raw[:, 0], raw[:, 1], raw[:, 2:] @ gw / 2
            a1, a2 = (e1 - e0) / 2, (e0 + e1) / 2 - M
            out.append(truss.h @ (M**2 + a1**2 / 3 + a2**2 / 5))
        return out

    for name, q in states(truss).items():
        v = rng.standard_normal(truss.n_dofs)
        energy, power = square_integral(q, v)
        _, info = System([truss]).evaluate(q, v, 0.0, np.zeros(0))
        assert info["energy"][0] == pytest.approx(sec.EA * energy / 2, rel=1e-12), name
        assert info["power"][0] == pytest.approx(sec.gamma_axial * sec.EA * power,
                                                 rel=1e-12), name


@pytest.mark.parametrize("formulation", ["assumed-strain", "paper", "lobatto"])
@pytest.mark.parametrize("kind", ["cable", "truss"])
def test_force_and_tangent_match_finite_differences(kind, formulation):
    cable = make_cable(kind, formulation=formulation)
    system = System([cable])
    for name, q in states(cable).items():
        U, f, K = numba_eval(cable, q)
        h = 1e-6
        fd_f, fd_K, _ = central(lambda x: numba_eval(cable, x, system), q, h)
        fd_K = fd_K.T
        fscale = max(np.abs(f).max(), h * np.abs(K).max())  # f = 0 when unstressed
        assert np.abs(fd_f - f).max() <= 1e-6 * fscale, name
        assert np.abs(fd_K - K).max() <= 1e-6 * np.abs(K).max(), name


@pytest.mark.parametrize("formulation", ["assumed-strain", "paper"])
def test_bending_force_and_tangent_alone_match_finite_differences(formulation):
    """The bending part is many orders smaller than the axial part: check it separately."""
    cable = make_cable("cable", formulation=formulation)
    truss = make_cable("truss", formulation=formulation)
    systems = System([cable]), System([truss])
    for name, q in states(cable).items():
        def bending(q):
            U1, f1, K1 = numba_eval(cable, q, systems[0])
            U2, f2, K2 = numba_eval(truss, q, systems[1])
            return U1 - U2, f1 - f2, K1 - K2
        U, f, K = bending(q)
        h = 1e-6
        fd_f, fd_K, _ = central(bending, q, h)
        fd_K = fd_K.T
        if name in ("straight", "compressed"):  # straight: no bending
            assert U == 0 and np.abs(f).max() < 1e-20
            assert np.all(np.isfinite(K)) and np.abs(K).max() > 0
            continue
        assert np.abs(fd_f - f).max() <= 1e-5 * np.abs(f).max(), name
        assert np.abs(fd_K - K).max() <= 1e-5 * np.abs(K).max(), name


def test_degenerate_states_are_finite():
    cable = make_cable("cable", n=6)
    s = cable.mesh.p[0]
    L = cable.length
    folded = np.zeros((len(s), 2, 3))
    folded[:, 0, 0] = np.minimum(s, L - s)
    folded[:, 1, 0] = np.where(s < L / 2, 1.0, -1.0)
    folded[np.isclose(s, L / 2), 1, 0] = 0.0
    collapsed = np.zeros(cable.n_dofs)
    for q in (folded.ravel(), collapsed, 0.2 * cable.q0):
        U, f, K = numba_eval(cable, q)
        assert np.isfinite(U) and np.all(np.isfinite(f)) and np.all(np.isfinite(K))


def test_section_validation_names_parameter():
    with pytest.raises(ValueError, match="E must be finite and > 0"):
        Section(E=-1.0, A=1.0, I=1.0, rho=1.0)
    with pytest.raises(ValueError, match="rho"):
        Section(E=1.0, A=1.0, I=1.0, rho=float("nan"))
    with pytest.raises(ValueError, match="gamma_axial must be finite and >= 0"):
        Section(E=1.0, A=1.0, I=1.0, rho=1.0, gamma_axial=-0.1)
    with pytest.raises(ValueError, match="radius"):
        Section.circular(radius=0.0, E=1.0, rho=1.0)
    circ = Section.circular(radius=0.01, E=7e10, rho=7800.0)
    assert circ.A == pytest.approx(np.pi * 1e-4) and circ.I == pytest.approx(np.pi * 1e-8 / 4)


def test_cable_input_validation():
    with pytest.raises(ValueError, match="law"):
        Cable.straight([0, 0, 0], [1, 0, 0], 2, SEC, law="rope")
    with pytest.raises(ValueError, match="n_elements"):
        Cable.straight([0, 0, 0], [1, 0, 0], 0, SEC)
    with pytest.raises(ValueError, match="start and end"):
        Cable.straight([0, 0, 0], [0, 0, 0], 2, SEC)


DAMPED = Section(E=7e10, A=3e-6, I=1e-12, rho=2700.0, gamma_axial=0.3, gamma_bending=0.7)


def damped_eval(cable, q, v, system=None):
    """Force, dF/dq and dF/dv (global dense), dissipated power and damping force, through
    ``system`` (default: a new ``System([cable])``; the same numbers, bit for bit)."""
    system = System([cable]) if system is None else system
    lay = system.layout  # held: the system is not edited (no description per call)
    dK, dC = np.zeros(lay.nnz), np.zeros(lay.nnz)
    f, info = system.evaluate(q, v, 0.0, np.zeros(0), cK=1.0, cC=0.0, data=dK, layout=lay)
    system.evaluate(q, v, 0.0, np.zeros(0), cK=0.0, cC=1.0, data=dC, layout=lay)
    return (f, lay.matrix(dK).toarray(), lay.matrix(dC).toarray(), info["power"],
            info["f_damping"])


@pytest.mark.parametrize("formulation", ["assumed-strain", "paper", "lobatto"])
@pytest.mark.parametrize("kind", ["cable", "truss"])
def test_damping_force_and_tangents_match_finite_differences(kind, formulation):
    """For the cable, curved states only: at zero curvature the curvature rate is
    regularised over ``delta = 1e-6/h`` and varies faster than any usable FD step."""
    cable = Cable.straight([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], 4, DAMPED, law=kind,
                           formulation=formulation)
    rng = np.random.default_rng(7)
    system = System([cable])
    for name, q in states(cable).items():
        if kind == "cable" and name not in ("curved", "random"):
            continue
        v = rng.standard_normal(cable.n_dofs)
        f, K, C, power, fd = damped_eval(cable, q, v)
        h = 1e-6
        fd_K = central(lambda x, v=v: damped_eval(cable, x, v, system)[:1], q, h)[0].T
        fd_C = central(lambda x, q=q: damped_eval(cable, q, x, system)[:1], v, h)[0].T
        assert np.abs(fd_K - K).max() <= 1e-6 * np.abs(K).max(), name
        assert np.abs(fd_C - C).max() <= 1e-6 * np.abs(C).max(), name
        # the damping force is the derivative of the Rayleigh function D with P = 2 D:
        # f_d . v = P (homogeneous of degree 2 in v)
        assert fd @ v == pytest.approx(power.sum(), rel=1e-10), name
        assert power.min() >= 0.0


def test_damping_numba_matches_numpy_reference():
    cable = Cable.straight([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], 4, DAMPED, formulation="paper")
    rng = np.random.default_rng(3)
    for name, q in states(cable).items():
        v = rng.standard_normal(cable.n_dofs)
        f, K, C, power, _ = damped_eval(cable, q, v)
        energy_r, power_r, fe, Ke, Ce = ancf_reference.cable_forces(cable, q, v)
        ed = cable.element_dofs
        fr = np.zeros(cable.n_dofs)
        np.add.at(fr, ed, fe)
        Kr = np.zeros_like(K)
        np.add.at(Kr, (ed[:, :, None], ed[:, None, :]), Ke)
        Cr = np.zeros_like(C)
        np.add.at(Cr, (ed[:, :, None], ed[:, None, :]), Ce)
        assert np.allclose(f, fr, rtol=0, atol=1e-12 * np.abs(fr).max()), name
        assert np.allclose(K, Kr, rtol=0, atol=1e-12 * np.abs(Kr).max()), name
        assert np.allclose(C, Cr, rtol=0, atol=1e-12 * np.abs(Cr).max()), name
        assert np.allclose(power, power_r.sum(axis=0), rtol=1e-12), name


def test_rigid_motion_is_not_damped():
    """Rigid rotation and translation of a curved cable dissipate nothing (objectivity)."""
    cable = Cable.straight([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], 4, DAMPED)
    q = states(cable)["curved"]
    Omega = np.array([0.3, -1.1, 0.7])
    nodes = q.reshape(-1, 2, 3)
    v = np.stack([np.cross(Omega, nodes[:, 0]) + [0.2, 0.1, -0.4],
                  np.cross(Omega, nodes[:, 1])], axis=1).ravel()
    f, _, _, power, fd = damped_eval(cable, q, v)
    assert power.sum() < 1e-20 * DAMPED.EA
    assert np.abs(fd).max() < 1e-9 * np.abs(f).max()


def test_straight_cable_bending_damping_is_finite():
    cable = Cable.straight([0.0, 0.0, 0.0], [2.0, 0.0, 0.0], 4, DAMPED)
    v = np.random.default_rng(0).standard_normal(cable.n_dofs)
    out = damped_eval(cable, cable.q0, v)
    assert all(np.all(np.isfinite(x)) for x in out)
