"""The evaluation contract from a user's side: velocity-dependent line loads, driven
constraints, user bodies and Cable subclasses on the compiled path; every analytic Jacobian
against finite differences."""


import numpy as np
import pytest
from demo_modules import load_demo
from node_spring import CompiledNodeSpring, NodeSpring

import skfem_cable as sc
from skfem_cable.constraints.joints import pin
from skfem_cable.constraints.linear import SlopeDirection
from skfem_cable.constraints.prescribed import time_derivatives

SECTION = sc.Section(E=2e9, A=1e-4, I=1e-9, rho=1000.0, gamma_axial=0.01,
                     gamma_bending=0.02)


def curved_state(cable, seed=3):
    rng = np.random.default_rng(seed)
    return (cable.q0 + 0.05 * rng.standard_normal(cable.n_dofs),
            rng.standard_normal(cable.n_dofs))


def nonlinear_load():
    """A force depending nonlinearly on position, velocity and time, with exact
    Jacobians: ``f = -c |v| v + k sin(x) cos(t)`` (componentwise sine)."""
    c, k = 0.7, 2.0

    def force(x, v, t):
        return -c * np.linalg.norm(v, axis=1)[:, None] * v + k * np.sin(x) * np.cos(t)

    def dq(x, v, t):
        return k * np.cos(t) * np.cos(x)[:, :, None] * np.eye(3)

    def dv(x, v, t):
        s = np.linalg.norm(v, axis=1)[:, None, None]
        return -c * (s * np.eye(3) + v[:, :, None] * v[:, None, :] / s)

    return force, dq, dv


@pytest.mark.parametrize("exact", [True, False])
def test_line_load_jacobians_match_finite_differences(exact):
    """The dynamic tangents (cable with damping, the load): ``dF/dq`` and ``dF/dv`` of
    each term (``sc.check_tangent``), with the exact Jacobians (1e-6) and with the
    finite-difference fallback (1e-5)."""
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0.2, 0.1], 3, SECTION)
    force, dq, dv = nonlinear_load()
    load = sc.LineLoad(cable, force, dq if exact else None, dv if exact else None)
    system = sc.System([cable]).add_load(load)
    check = sc.check_tangent(system, *curved_state(cable), t=0.3)
    assert sum(p.name.startswith("line load") for p in check.parts) == 2   # q and v
    assert check.error < (1e-6 if exact else 1e-5), str(check)


def test_line_load_force_is_consistent():
    """A uniform field through ``LineLoad`` gives the consistent force of
    ``add_line_load`` (scikit-fem assembly), and a wrong shape is named."""
    cable = sc.Cable.straight([0, 0, 0], [2.0, 0, 0], 4, SECTION)
    w = np.array([0.3, -1.2, 0.5])
    a = sc.System([cable]).add_load(sc.LineLoad(cable, lambda x, v, t: np.tile(w, (len(x), 1))))
    b = sc.System([cable]).add_line_load(cable, w)
    ra = a.evaluate(cable.q0, None, 0.0, np.zeros(0))[0]
    rb = b.evaluate(cable.q0, None, 0.0, np.zeros(0))[0]
    assert np.allclose(ra, rb, rtol=1e-13, atol=1e-15)
    bad = sc.System([cable]).add_load(sc.LineLoad(cable, lambda x, v, t: w))
    with pytest.raises(ValueError, match=r"LineLoad force\(x, v, t\) must return shape"):
        bad.evaluate(cable.q0, None, 0.0, np.zeros(0))
    with pytest.raises(TypeError, match="force must be a callable"):
        sc.LineLoad(cable, w)


def test_point_moment_and_centrifugal_tangents():
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0.0, 0.0], 2, SECTION)
    system = sc.System([cable]).add_point_moment(cable.node(-1), [0.1, -0.3, 0.2])
    system.add_centrifugal([0.0, 0.4, 1.1])
    check = sc.check_tangent(system, curved_state(cable)[0], t=0.3)
    assert {"centrifugal"} <= {p.name for p in check.parts}
    assert check.error < 1e-6, str(check)


def test_drag_demo_reaches_terminal_speed():
    """``rho A g / c`` to 1e-8 relative, with the exact and with the FD Jacobian."""
    demo = load_demo("drag_terminal_speed")
    for exact in (True, False):
        out = demo.main(exact_jacobian=exact)
        assert out["fall_speed"] == pytest.approx(out["terminal_speed"], rel=1e-8)
        assert out["drag_work"] < 0
        assert abs(out["energy_balance"]) < 1e-5 * abs(out["drag_work"])


def test_kapitza_demo_threshold_both_sides():
    """5 % above the Floquet threshold the rod stays up; 5 % below it falls."""
    demo = load_demo("kapitza")
    out = demo.main(margin=0.05, t_end=5.0)
    assert out["threshold_amplitude"] == pytest.approx(out["kapitza_estimate"], rel=5e-3)
    assert out["max_tilt_above"] < 0.15
    assert out["max_tilt_below"] > 1.0


def test_time_derivatives_are_accurate():
    w = 80.0
    for order, exact in ((1, -w * np.sin(w * 0.7)), (2, -w**2 * np.cos(w * 0.7))):
        assert time_derivatives(lambda t: np.cos(w * t), 0.7, order) == pytest.approx(
            exact, rel=1e-6)


def driven_constraint_terms(constraint, system, q, v, t):
    """``C_t`` and ``(C_q v)_q v + 2 C_qt v + C_tt`` by differences along ``q + s v``."""
    d = constraint.dofs(system)

    def C(s):
        return constraint.value(q[d] + s * v[d], t + s)

    h = 1e-4
    return ((C(h) - C(-h)) / (2 * h) - constraint.jacobian(q[d], t) @ v[d],
            (C(h) - 2 * C(0.0) + C(-h)) / h**2)


def test_driven_pin_and_clamp_terms_match_differences():
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0, 0], 2, SECTION)
    system = sc.System([cable])
    w = 3.0
    driven_pin = pin(cable.node(0), lambda t: np.array([np.cos(w * t), np.sin(t), t**3]))
    turning = SlopeDirection(cable.node(-1),
                             lambda t: np.array([np.cos(w * t), np.sin(w * t), 0.2 * t]))
    q, v = curved_state(cable)
    t = 0.4
    for c in (driven_pin, turning):
        d = c.dofs(system)
        ct, accel = driven_constraint_terms(c, system, q, v, t)
        assert c.velocity_term(q[d], t) == pytest.approx(ct, rel=1e-5, abs=1e-7)
        assert c.accel_term(q[d], v[d], t) == pytest.approx(accel, rel=1e-5, abs=1e-6)
    # the driven clamp follows its direction exactly and stays orthogonal to it
    n = turning.normals(t)
    assert n @ n.T == pytest.approx(np.eye(2), abs=1e-14)
    assert n @ np.array([np.cos(w * t), np.sin(w * t), 0.2 * t]) == pytest.approx(0, abs=1e-14)


def test_driven_clamp_turns_a_stiff_cable():
    """A short stiff cable clamped with a direction turning at ``W`` about z, started in
    the rigid rotation, turns with it: after 0.5 s its tip is at ``L (cos W t, sin W t)``
    within the centrifugal stretch (2e-7 L) and moves at ``W L``, and the clamp holds."""
    W = 2.0
    section = sc.Section.circular(radius=0.01, E=2e11, rho=7850.0)
    cable = sc.Cable.straight([0, 0, 0], [0.5, 0, 0], 2, section)
    system = sc.System([cable]).clamp(
        cable.node(0), direction=lambda t: np.array([np.cos(W * t), np.sin(W * t), 0.0]))
    q0 = system.q0
    initial = sc.State(system, q0, v=system.rigid_motion_velocity(q0, [0, 0, W]))
    r = sc.simulate(system, t_end=0.5, dt=5e-3, rho_inf=0.8, initial=initial)
    e = np.array([np.cos(W * 0.5), np.sin(W * 0.5), 0.0])
    assert r.position(cable, 0.5)[-1] == pytest.approx(0.5 * e, abs=1e-7)
    # index-3 velocities carry an O(h^2) error: 1.4e-5 relative here
    assert r.velocity(cable, 0.5)[-1] == pytest.approx(0.5 * W * np.cross([0, 0, 1], e),
                                                       abs=1e-4 * W * 0.5)
    assert np.abs(system.constraint_values(r.q[-1], r.t[-1])).max() < 1e-12


def test_cable_subclass_keeps_the_compiled_path():
    """A subclass that adds no physics is merged with plain cables of the same law into
    one compiled kernel call."""

    class TaggedCable(sc.Cable):
        colour = "red"

    a = sc.Cable.straight([0, 0, 0], [1, 0, 0], 3, SECTION, name="a")
    b = TaggedCable.straight([0, 1, 0], [1, 1, 0], 4, SECTION, name="b")
    system = sc.System([a, b])
    (term, index), = system.layout.body_terms
    assert term.add is None and index.shape == (7, 12, 12)
    (function, pack), = term.kernels
    assert pack[0].shape == (7, 12)
    r = system.evaluate(system.q0 * 1.01, None, 0.0, np.zeros(0))[0]
    alone = sc.System([b]).evaluate(b.q0 * 1.01, None, 0.0, np.zeros(0))[0]
    assert r[a.n_dofs:] == pytest.approx(alone, rel=1e-14, abs=1e-12)


class Bead:
    """A user body: a point of mass ``m`` held by a linear spring ``k`` to ``anchor``
    (3 coordinates), with its own force hook."""

    name = "bead"
    n_dofs = 3
    position_mask = np.ones(3, dtype=bool)
    energy_parts = ("spring",)

    def __init__(self, m, k, anchor):
        self.m, self.k, self.anchor = m, k, np.asarray(anchor, dtype=float)
        self.q0 = self.anchor.copy()
        self.calls = 0

    def mass_matrix(self):
        import scipy.sparse as sps
        return sps.identity(3, format="csr") * self.m

    def internal_constraints(self):
        return []

    def describe_dof(self, i):
        return "xyz"[i]

    def mass_points(self):
        return np.zeros((1, 1), np.int64), np.ones((1, 1)), np.array([self.m])

    def show(self, system, q, v, t, **detail):
        d = system.dofs(self)
        return sc.core.contract.Shape(q[d][None], v[d][None], "vertex", [[0]], part=3,
                                 data={"stretch": [np.linalg.norm(q[d] - self.anchor)]})

    def outputs(self, system, q, t):
        return {"stretch": np.linalg.norm(q[system.dofs(self)] - self.anchor)}

    def bind(self, system):
        d = system.dofs(self)
        K = self.k * np.eye(3)

        def add(ev, index):
            self.calls += 1
            u = ev.q[d] - self.anchor
            ev.f[d] += self.k * u
            ev.energy[0] += 0.5 * self.k * u @ u
            ev.add_tangent(index, K)

        return sc.Term(add=add, rows=d[:, None], cols=d[None, :], name=self.name)


def test_user_body_is_called_through_its_own_hook():
    """The user's hook is called once per evaluation (no wrapper, no fallback), and the
    bead oscillates at ``sqrt(k/m)`` under ``simulate``."""
    bead = Bead(m=2.0, k=50.0, anchor=[0, 0, 0])
    system = sc.System([bead])
    (term, _), = system.layout.body_terms
    system.evaluate(system.q0, None, 0.0, np.zeros(0))
    assert bead.calls == 1
    w = np.sqrt(bead.k / bead.m)
    initial = sc.State(system, np.zeros(3), v=np.array([1.0, 0.0, 0.0]))
    r = sc.simulate(system, t_end=1.0, dt=1e-3, rho_inf=1.0, initial=initial)
    assert r.q[-1, 0] == pytest.approx(np.sin(w * r.t[-1]) / w, abs=2e-5)


def test_a_one_point_system_is_one_metre_long_for_newtons_test():
    """A system whose position points coincide (a bead) has no size of its own: its
    length scale is 1 m, not the 1e-300 it was, which scaled its residual by 1e300 and
    left Newton a tolerance of exact zeros (2.3 corrections a step instead of 1.25)."""
    bead = Bead(m=2.0, k=50.0, anchor=[0, 0, 0])
    system = sc.System([bead])
    assert system.current_layout().length_scale == 1.0
    initial = sc.State(system, np.zeros(3), v=np.array([1.0, 0.0, 0.0]))
    r = sc.simulate(system, t_end=0.2, dt=1e-3, rho_inf=1.0, initial=initial)
    assert r.stats["newton"] <= 1.5 * r.stats["steps"]


def test_user_body_appears_in_paraview_and_the_summary(tmp_path):
    """A user body with the hooks of ``contract.Body`` is drawn by the ParaView export as
    it says (a vertex with its own point data, NaN on the cable's points, the cable's
    fields NaN on it) and reports its numbers in a run's summary; one without them is
    refused, the missing hooks named."""
    from skfem_cable import runner
    from skfem_cable.io import export

    bead = Bead(m=2.0, k=50.0, anchor=[0, 0, -1])
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, sc.Section(E=1e9, A=1e-6, I=1e-12,
                                                                 rho=1e3))
    system = sc.System([cable, bead])
    q = system.q0.copy()
    q[-3:] += [0.0, 0.3, 0.4]
    mesh = export.system_mesh(system, q)
    vertex = mesh.cells_dict["vertex"]
    assert mesh.points[vertex[0, 0]] == pytest.approx([0.0, 0.3, -0.6])
    stretch = mesh.point_data["stretch"]
    assert stretch[vertex[0, 0]] == pytest.approx(0.5)
    assert np.isnan(stretch).sum() == len(mesh.points) - 1
    assert np.isnan(mesh.point_data["tension"][vertex[0, 0]])
    result = sc.simulate(system, t_end=0.02, dt=0.01, initial=sc.State(system, q))
    summary = runner.run_outputs(result)
    assert summary["bodies"]["bead"]["stretch"] == pytest.approx(
        np.linalg.norm(result.q[-1, -3:] - bead.anchor))
    assert set(summary["cables"]) == {"cable"}
    # its energy under its own name, beside the cable's; the parts add up to the books
    parts = summary["energy"]["bodies_final"]
    u = result.q[-1, -3:] - bead.anchor
    assert parts["bead"]["spring"] == pytest.approx(0.5 * bead.k * u @ u, rel=1e-12)
    assert set(parts["cable"]) == {"kinetic", "axial", "bending"}
    kinetic = sum(p["kinetic"] for p in parts.values())
    assert kinetic == pytest.approx(result.kinetic[-1], rel=1e-12)
    stored = parts["cable"]["axial"] + parts["bead"]["spring"]  # both in the first slot
    assert stored == pytest.approx(result.axial[-1], rel=1e-12)

    class Lump:
        name, n_dofs, q0, position_mask = "lump", 3, np.zeros(3), np.ones(3, bool)

    with pytest.raises(TypeError, match="lacks bind, describe_dof, energy_parts, "
                                        "internal_constraints, mass_matrix, mass_points, "
                                        "outputs, show"):
        sc.System([Lump()])


def test_user_compiled_load_runs_in_the_compiled_step():
    """A user's load with a compiled kernel takes the compiled Newton step and gives the
    same trajectory as the same load written as a Python hook."""
    runs = []
    for compiled in (True, False):
        cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SECTION)
        system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
        spring = CompiledNodeSpring if compiled else NodeSpring
        system.add_load(spring(cable.node(-1), 50.0, [1.0, 0.2, 0.0], name="spring"))
        runs.append(sc.simulate(system, t_end=0.1, dt=1e-3))
    assert runs[0].stats["path"] == "compiled"
    assert runs[1].stats["path"] == "compiled (Python: term 'spring' has a Python add hook)"
    assert np.abs(runs[0].q - runs[1].q).max() < 1e-12
    assert runs[0].q[-1, -5] > 1e-3  # the spring lifted the tip
