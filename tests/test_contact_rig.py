"""Contact, third step (issue 49; ``docs/contact.md``): a rope draped over a table's
rounded edge (``sc.Edge``) carries the weight of its hanging part (item 3, second half).

The rig: a rope (EA = 1e5 N, 0.1 kg/m, d = 1 cm, the capstan's, with the bending
stiffness of a braided rope, ``EI = 1e-5 N m^2``: a bending length ``sqrt(EI / T)`` of
4 mm, small against the edge's radius) lies 0.5 m on a frictionless table, goes over
its edge (rounded, R = 5 cm) and hangs 0.6 m; the end on the table is pinned (what
holds the hanging weight: without friction the table cannot), gravity 9.81 m/s^2.
"""

import numpy as np
import pytest
from skfem import MeshLine

import skfem_cable as sc
from skfem_cable.loads.contact import ContactToleranceWarning
from skfem_cable.scenes.capstan import ROPE as CAPSTAN_ROPE

R, LIE, HANG, G = 0.05, 0.5, 0.6, 9.81
ROPE = sc.Section(E=CAPSTAN_ROPE.E, A=CAPSTAN_ROPE.A, I=1e-5 / CAPSTAN_ROPE.E,
                  rho=CAPSTAN_ROPE.rho, gamma_axial=1e-4)
RC = np.sqrt(ROPE.A / np.pi)                  # the rope's cross-section radius (5 mm)
#: No pair excluded next to a joint (``candidates``' ``excluded``).
NONE = np.zeros(0, dtype=np.int64)
EDGE = sc.Edge([0, 0, 0], [0, 1, 0], [1, 0, 0], R)


def draped(depth=5e-6, n_lie=4, n_arc=6, n_hang=6):
    """The rope of the module notes along the table (x < 0), a quarter circle over the
    edge and down (x = R + r_c), its axis ``depth`` into the surfaces; nodes at the
    tangent points: ``(cable, arc)``, ``arc`` the length over the edge."""
    rr = R + RC - depth
    arc = 0.5 * np.pi * rr
    s = np.concatenate([np.linspace(0, LIE, n_lie + 1)[:-1],
                        LIE + np.linspace(0, arc, n_arc + 1)[:-1],
                        LIE + arc + np.linspace(0, HANG, n_hang + 1)])
    phi = np.clip((s - LIE) / rr, 0, np.pi / 2)
    lie, hang = s < LIE, s > LIE + arc
    x = np.where(lie, s - LIE, np.where(hang, rr, rr * np.sin(phi)))
    y = np.where(lie, rr - R, np.where(hang, -R - (s - LIE - arc), rr * np.cos(phi) - R))
    tx = np.where(lie, 1.0, np.where(hang, 0.0, np.cos(phi)))
    ty = np.where(lie, 0.0, np.where(hang, -1.0, -np.sin(phi)))
    cable = sc.Cable(MeshLine(s), ROPE, np.stack([x, y, 0 * x], 1),
                     np.stack([tx, ty, 0 * x], 1))
    return cable, arc


@pytest.fixture(scope="module")
def settled():
    """The draped rope at rest (a static solve): ``(state, system, cable, arc)``."""
    cable, arc = draped()
    system = (sc.System([cable]).add_gravity([0, -G, 0]).pin(cable.node(0))
              .contact(cable, EDGE))
    return sc.solve_static(system), system, cable, arc


def test_the_hanging_part_carries_its_own_weight(settled):
    """Where the rope leaves the edge, its tension is the weight ``rho A g L_hang`` of the
    part hanging below, within 1 % (measured -2.7e-3: the bending near the tangent
    point); down the hanging part ``T(s) = rho A g (L - s)`` within 1e-4 from a
    bending length below the edge (measured 2e-6)."""
    state, system, cable, arc = settled
    w = ROPE.mass_per_length * G
    leaves = LIE + arc
    assert state.tension(cable, leaves) == pytest.approx(w * HANG, rel=1e-2)
    s = np.linspace(leaves + 0.2, cable.length - 0.05, 8)
    assert state.tension(cable, s) == pytest.approx(w * (cable.length - s), rel=1e-4)


def test_on_a_frictionless_table_the_tension_is_the_weight_below(settled):
    """Frictionless, the tension anywhere is the weight of rope of the height above the
    free end, ``rho A g (y - y_end)`` (the tangential balance on a smooth surface,
    ``dT/ds = rho A g dy/ds``): the lying part carries the hanging weight and the drop
    over the edge, what the pin holds (a table with friction would hold it instead, and
    its lying part carry less); within 1 % along the whole rope (measured 4.4e-3, the
    bending over the edge); the penetration is below the stated tolerance d."""
    state, system, cable, _ = settled
    w = ROPE.mass_per_length * G
    s = np.linspace(0, cable.length - 0.05, 30)
    x = cable.interpolate(state.q[system.dofs(cable)], np.r_[s, cable.length])[0]
    height = x[:-1, 1] - x[-1, 1]
    assert state.tension(cable, s) == pytest.approx(w * height, rel=1e-2)
    contact = system.loads[-1]
    out = contact.forces(state)
    assert out["max_penetration"] < contact.tolerance * 2 * RC


def test_the_edge_tangent_against_central_differences():
    """The contact's tangent in q and v (penalty, damping, friction) on the edge, at a
    perturbed state of the draped rope touching both the flat and the rounded part:
    relative error below 1e-6."""
    cable, _ = draped(depth=2e-3)
    rng = np.random.default_rng(2)
    q = cable.q0 + 1e-3 * rng.standard_normal(cable.n_dofs)
    v = 0.02 * rng.standard_normal(cable.n_dofs)
    system = sc.System([cable]).contact(cable, EDGE, friction=0.3, slip_velocity=0.01)
    with pytest.warns(ContactToleranceWarning):            # pressed in on purpose
        gap = system.loads[-1].forces(sc.State(system, q, v))["gap"]
    assert (gap < 0).sum() >= 6
    parts = [p for p in sc.check_tangent(system, q, v).parts if p.name.startswith("contact")]
    assert {p.wrt for p in parts} == {"q", "v"}
    assert max(p.error for p in parts) < 1e-6


def test_an_edge_is_the_plane_behind_and_the_cylinder_beyond():
    """The edge's distance: the table's plane behind the edge, the rounding cylinder
    beyond it, the same on the line where they meet; ``outward`` must lie in the plane."""
    d = EDGE.distance([[-1.0, 0.3, 2.0], [2 * R, -R, 0.0], [0.0, 0.1, 0.0],
                       [R * np.sqrt(0.5), -R * (1 - np.sqrt(0.5)), 0.0]])
    assert d == pytest.approx([0.3, R, 0.1, 0.0], abs=1e-15)
    with pytest.raises(ValueError, match="outward must be perpendicular to normal"):
        sc.Edge([0, 0, 0], [0, 1, 0], [1, 1, 0], R)


def test_the_line_broad_phase_keeps_only_near_pairs():
    """Tether-tether contact's broad phase (``kernels.line_broad_phase.candidates``): of two
    segments whose boxes overlap (a diagonal and a short segment in its box, 0.46 m
    from it), the pair is a candidate only if their distance is within the margin and
    the reach of their motion over the step (``2 dt v`` each), not otherwise: the radial
    sail's boxes overlap pairwise, its segments do not (4034 candidate pairs of the
    100-tether sail at rest become 100, ``benchmarks/contact_cost.py``)."""
    from skfem_cable.kernels.line_broad_phase import candidates

    X = np.array([[0.0, 0, 0], [1, 1, 0], [0.8, 0.1, 0], [0.85, 0.2, 0]])
    ends, line, arc = np.array([[0, 1], [2, 3]]), np.array([0, 1]), np.zeros((2, 2))
    gap = 0.65 / np.sqrt(2)                 # the distance of the segments, at (0.85, 0.2)

    def found(margin, dt, speed):
        V = np.zeros_like(X)
        V[2:, 1] = speed
        return candidates(X, V, ends, line, arc, -1.0, NONE, margin, dt, np.empty((2, 7)),
                          np.zeros((4, 2), dtype=np.int64))

    assert found(0.01, 0.0, 0.0) == 0                  # boxes overlap, segments apart
    assert found(gap + 1e-9, 0.0, 0.0) == 1            # within the margin
    assert found(0.01, 1.0, 0.5 * (gap - 0.01) + 1e-9) == 1   # within reach in the step
    assert found(0.01, 1.0, 0.5 * (gap - 0.01) - 1e-6) == 0


def test_the_grid_finds_what_all_pairs_find():
    """The grid of the broad phase finds the same pairs as a test of every pair (boxes
    overlapping and segments within the margin and their reaches), on 400 random
    segments of 40 lines of assorted lengths and speeds, none twice."""
    from skfem_cable.kernels.line_broad_phase import candidates, distance

    rng = np.random.default_rng(3)
    start = rng.uniform(0, 10, (400, 3))
    X = np.vstack([start, start + rng.normal(0, 1, (400, 3)) * rng.uniform(0.1, 2, (400, 1))])
    V = rng.normal(0, 0.5, X.shape)
    ends = np.column_stack([np.arange(400), np.arange(400) + 400])
    line, arc = np.arange(400) // 10, np.zeros((400, 2))
    margin, dt, box = 0.2, 0.3, np.empty((400, 7))
    pairs = np.zeros((4000, 2), dtype=np.int64)
    n = candidates(X, V, ends, line, arc, -1.0, NONE, margin, dt, box, pairs)
    reach = 2 * dt * np.linalg.norm(V, axis=1).reshape(2, 400).max(axis=0)
    P = np.empty((4, 3))
    expected = {(i, j) for i in range(400) for j in range(i + 1, 400)
                if line[i] != line[j] and np.all(box[i, :3] <= box[j, 3:6])
                and np.all(box[j, :3] <= box[i, 3:6])
                and distance(X, ends, i, j, P) <= margin + reach[i] + reach[j]}
    found = [tuple(p) for p in pairs[:n]]
    assert len(found) == len(set(found)) == n > 50
    assert set(found) == expected


def test_a_scene_file_names_an_edge():
    """``[[contacts]]`` with ``edge = { point, normal, outward, radius }``: the contact's
    surface is that ``sc.Edge``; an ``outward`` out of the plane is refused, naming it."""
    scene = """
[solver]
t_end = 1.0
dt = 1e-3
[sections.rope]
radius = 5e-3
E = 1.27e9
rho = 1273.0
[[cables]]
name = "rope"
section = "rope"
start = [-1, 0.005, 0]
end = [0, 0.005, 0]
elements = 2
[[contacts]]
cable = "rope"
edge = { point = [0, 0, 0], normal = [0, 1, 0], outward = [OUT], radius = 0.05 }
"""
    contact = sc.scene_file.loads_text(scene.replace("OUT", "1, 0, 0")).system.loads[-1]
    assert contact.surface.surface_array() == pytest.approx(EDGE.surface_array())
    with pytest.raises(sc.scene_file.SceneFileError, match="outward must be perpendicular"):
        sc.scene_file.loads_text(scene.replace("OUT", "1, 1, 0"))
