"""Tether-tether contact in a sail (issue 49, item 5; ``docs/contact.md``, "Many lines: a
sail's tethers"): a small sail of four tethers on a free hub, one tether lowered across
its neighbour, with the contact over all of them (``system.contact(tethers)``) on each
element's own tangent, the sail still solved as band blocks bordered by the hub; and the
exclusion of the pairs next to the hub."""

import numpy as np
import pytest
from test_contact_lines import resultants

import skfem_cable as sc
from skfem_cable.loads.contact_lines import PAIRS_PER_SEGMENT, BroadPhase
from skfem_cable.scenes import esail
from skfem_cable.scenes.esail_tangle import CrossingRig, crossing_sail

#: The stated tolerance of the default contact (of d = 1 cm), the rig, the run (s) and its
#: step.
TOLERANCE, RIG, D = 1e-2, CrossingRig(), 1e-2
T_END, DT = 0.45, 1e-4


def sail(tangent=None):
    """``crossing_sail``: four tethers, tether 1 lowered across tether 2."""
    return crossing_sail(4, 3, tangent)


@pytest.fixture(scope="module")
def runs():
    """The sail run on each element's own tangent (on the bordered band LU) and on the
    exact tangent (SuperLU)."""
    out = {}
    for tangent, method in (("own", "auto"), ("full", "sparse")):
        system, hub, tethers, contact = sail(tangent)
        result = sc.simulate(system, T_END, DT, every=15, method=method)
        out[tangent] = system, hub, tethers, contact, result
    return out


def test_own_tangent_keeps_the_sails_pattern(runs):
    """Four lines on each element's own tangent: the layout's border is the hub alone, and the
    bordered band LU solves the sail with the contact term in its step (compiled)."""
    system, hub, tethers, contact, result = runs["own"]
    assert contact.tangent == "own" and contact.name == "contact_lines"
    assert result.stats["solver"] == "banded" and result.stats["path"] == "compiled"
    border = system.layout.border
    assert set(border[border < system.n_dofs].tolist()) == set(system.dofs(hub).tolist())


def test_tether_stops_on_its_neighbour(runs):
    """Tether 1, lowered across tether 2, stops on it: one contact, at the crossing
    (``RIG.cross`` from tether 2's root), penetrating less than the stated tolerance d; the
    contact's forces on the two tethers are equal and opposite (1e-9), none on the
    others; the books close to 5e-6 of the work (measured 2.9e-6, as the slide of
    ``tests/test_contact_lines.py``: the contact point crosses the joints of the sampled
    centrelines)."""
    system, hub, tethers, contact, result = runs["own"]
    state = result.state(-1)
    out = contact.contacts(system, state.q, state.v)
    assert len(out["normal"]) == 1 and out["normal"][0] > 10.0
    assert 0.0 < out["max_penetration"] < TOLERANCE * D
    assert out["lines"].tolist() == [[0, 1]]
    assert out["arc"][0, 1] == pytest.approx(RIG.cross, abs=0.05)
    assert out["first"][0, 0] > out["second"][0, 0]              # tether 1 stays above
    forces = resultants(system, contact, state.q, state.v, tethers)
    assert np.abs(forces[0] + forces[1]).max() < 1e-9 * np.abs(forces[0]).max()
    assert np.linalg.norm(forces[0]) == pytest.approx(out["normal"][0], rel=1e-9)
    assert forces[0][0] > 0.0                                   # tether 1 pushed up
    assert np.abs(forces[2:]).max() == 0.0
    assert np.abs(result.energy["balance"]).max() < 5e-6 * result.energy["external_work"][-1]


def test_own_tangent_reaches_the_exact_tangents_states(runs):
    """The residual is the same on both tangents: the runs agree to 1e-6 m; the own
    tangent takes more Newton iterations while the tethers touch (numbers in
    ``docs/contact.md``)."""
    own, full = runs["own"][4], runs["full"][4]
    assert np.abs(own.q[-1] - full.q[-1]).max() < 1e-6
    assert own.stats["newton"] >= full.stats["newton"]


def test_the_hub_exclusion_removes_the_root_pairs():
    """On a sail of six tethers (two elements of 5 km each) at its windless spin, the
    broad phase over a 20 s step finds the pairs of the neighbouring tethers' first
    segments (236 m from the hub, within the reach of their speed), unless the pairs next
    to the hub (the elements holding the pins) are excluded, which leaves none."""
    scene = esail.build(esail.BaselineConfig(n_tethers=6), 10.0, 2)
    system = scene.system
    system.contact(scene.tethers)
    contact = system.loads[-1]
    points, rows, arc, line, excluded = contact.tables(system)
    found = {}
    for name, keys in (("all", np.zeros(0, dtype=np.int64)), ("excluded", excluded)):
        broad = BroadPhase(points, rows, arc, line, None, keys, 2.02 * contact.radii[0],
                           np.zeros((PAIRS_PER_SEGMENT * len(rows), 2), dtype=np.int64),
                           np.zeros(1, dtype=np.int64), scene.initial.q)
        broad.accept(scene.initial.q, scene.initial.v, 0.0)
        broad.prepare(20.0)
        found[name] = broad.pairs[:broad.count[0]]
    roots = arc[found["all"]][:, :, 0].max(axis=1)
    assert len(found["all"]) == 6 and np.all(roots < scene.config.tether_length / 2)
    assert len(found["excluded"]) == 0
    assert np.all(np.isin(found["all"][:, 0] * len(rows) + found["all"][:, 1], excluded))


def test_contact_over_many_lines_names_what_is_wrong():
    """``system.contact(lines)``: a surface among the lines, lines of different radii, a
    radius per line of the wrong length and an unknown tangent each raise an error
    naming the parameter; the defaults: ``"full"`` for two lines, ``"woodbury"`` for more."""
    a, b, c = (sc.Cable.straight([0, k, 0], [1, k, 0], 2, sc.Section.circular(
        0.01 if k < 2 else 0.02, 1e9, 1000.0), name=f"c{k}") for k in range(3))
    system = sc.System([a, b, c])
    with pytest.raises(TypeError, match=r"first\[1\]"):
        system.contact([a, sc.Plane([0, 0, 0], [0, 0, 1])])
    with pytest.raises(ValueError, match="radius"):
        system.contact([a, b, c])
    with pytest.raises(ValueError, match="radius must be one value or one per line"):
        system.contact([a, b], radius=(0.01, 0.01, 0.01))
    with pytest.raises(ValueError, match="tangent must be one of"):
        system.contact([a, b], tangent="dense")
    assert system.contact([a, b]).loads[-1].tangent == "full"
    assert system.contact([a, b, c], radius=0.01).loads[-1].tangent == "woodbury"
