"""Faults, round two: never a silent wrong answer.

Each test reproduces one fault of the issue and asserts what the user gets now.

* a system edited after it was simulated (a load's attribute, a cable's section) is
  simulated as edited, and its run store's fingerprint is that of what was simulated; an
  edit while a run is under way (an observer) is refused, naming what changed;
* degenerate constraints (a node pinned to itself, the same node pinned or clamped twice)
  are refused when added, naming them, in the API and in scene files.
"""

import dataclasses
import json
import re
from pathlib import Path

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable import constraints, scene_file
from skfem_cable.io import RunStore, StoreMismatch, run_observers
from skfem_cable.loads.coulomb import SolarWindForce
from skfem_cable.model.system import SystemChanged
from skfem_cable.scenes import classics

#: The pendulum of the issue: 0.2 s in steps of 1 ms.
RUN = dict(t_end=0.2, dt=1e-3)
#: The tip's vertical coordinate (the last node's y).
TIP_Y = -5


def pendulum(g=9.81, **kwargs):
    return classics.pendulum(n_elements=4, g=g, **kwargs)


def tip_y(result):
    return float(result.q[-1, TIP_Y])


# ===========================================================================================
# A system edited after it was simulated
# ===========================================================================================
def test_load_edited_after_a_simulate_is_simulated_as_edited(tmp_path):
    """Before: the second run repeated the 1 g trajectory exactly (tip y -0.291 instead of
    -1.053): the layout, which holds the constant gravity force, was built by the first
    run and kept.  Now every solve starts from the system as it is (the layout is rebuilt
    when the system's description changed)."""
    system = pendulum().system
    first = sc.simulate(system, **RUN)
    assert tip_y(first) == pytest.approx(-0.291, abs=1e-3)
    system.loads[0].g = 10 * system.loads[0].g
    edited = sc.simulate(system, **RUN, observers=run_observers(tmp_path / "stale"))
    fresh = sc.simulate(pendulum(g=10 * 9.81).system, **RUN)
    assert tip_y(edited) == pytest.approx(-1.053, abs=1e-3)
    np.testing.assert_allclose(edited.q, fresh.q, rtol=0, atol=1e-12)


def test_run_store_fingerprint_is_that_of_what_was_simulated(tmp_path):
    """Before: the store of the edited system's run carried the fingerprint of the edited
    attributes over the 1 g data, so ``Result.load`` with a fresh 10 g system passed the
    check and returned the 1 g trajectory.  Now the data are the 10 g system's, which
    loads them, and the 1 g system is refused."""
    system = pendulum().system
    sc.simulate(system, **RUN)
    system.loads[0].g = 10 * system.loads[0].g
    sc.simulate(system, **RUN, observers=run_observers(tmp_path / "stale"))
    ten_g = pendulum(g=10 * 9.81).system
    loaded = sc.Result.load(tmp_path / "stale", ten_g)
    np.testing.assert_allclose(loaded.q, sc.simulate(ten_g, **RUN).q, rtol=0, atol=1e-12)
    with pytest.raises(StoreMismatch, match="same bodies and sizes"):
        sc.Result.load(tmp_path / "stale", pendulum().system)


def test_section_replaced_after_a_simulate_is_simulated_as_replaced(tmp_path):
    """Before: replacing ``cable.section`` kept the old stiffness (the layout's kernels)
    and the old mass (the cable's cached mass matrix).  Now the run and its store are
    those of the new section, as a system built with it."""
    scene = pendulum()
    sc.simulate(scene.system, **RUN)
    new = dict(E=7e8, rho=2 * 7800.0)
    scene.cable.section = dataclasses.replace(scene.cable.section, **new)
    edited = sc.simulate(scene.system, **RUN, observers=[RunStore(tmp_path / "run")])
    built = pendulum(**new).system
    fresh = sc.simulate(built, **RUN)
    assert np.abs(fresh.q - sc.simulate(pendulum().system, **RUN).q).max() > 1e-3
    np.testing.assert_allclose(edited.q, fresh.q, rtol=0, atol=1e-12)
    assert len(sc.Result.load(tmp_path / "run", built)) == len(fresh)


def test_static_solve_and_modes_take_the_edited_system():
    """``solve_static`` and ``modes`` start from the system as it is too: a tip load
    doubled after a first solve doubles the deflection of a cantilever."""
    scene = classics.cantilever(n_elements=8, k=0.01)
    first = sc.solve_static(scene.system)
    f0 = sc.modes(scene.system, first, k=1)[0]
    scene.system.loads[0].value = 2 * scene.system.loads[0].value
    second = sc.solve_static(scene.system)
    assert second.q[TIP_Y] == pytest.approx(2 * first.q[TIP_Y], rel=1e-3)
    scene.cable.section = dataclasses.replace(scene.cable.section, rho=4 * 7850.0)
    assert sc.modes(scene.system, second, k=1)[0] == pytest.approx(f0[0] / 2, rel=1e-3)


def test_solar_wind_voltage_edited_after_a_simulate_is_simulated_as_edited():
    """A load that precomputed its constant coefficients when built: rebinding it must
    see the edit too (before: the tether kept being pushed at 20 kV)."""

    def tether(voltage):
        cable = sc.Cable.straight([0, 0, 0], [0, 100, 0], 4,
                                  sc.Section.circular(1e-4, 2e11, 7850.0))
        return sc.System([cable]).pin(cable.node(0)).add_load(SolarWindForce([cable],
                                                                             voltage))

    system = tether(20e3)
    sc.simulate(system, t_end=1.0, dt=0.1)
    system.loads[0].voltage = [40e3]
    edited = sc.simulate(system, t_end=1.0, dt=0.1)
    np.testing.assert_allclose(edited.q, sc.simulate(tether(40e3), t_end=1.0, dt=0.1).q,
                               rtol=0, atol=1e-12)


def test_observer_editing_a_load_mid_run_is_refused_naming_it(tmp_path):
    """Before: an observer that multiplied g by 10 halfway had no effect (the layout held
    the 1 g force) and the run ended normally (exit 0), with no word that the system now
    said 10 g.  Now the run is refused at its end, naming what changed; its steps, in the
    error's result and in the store (marked failed), are all those of the system as it
    was at the start, the system its fingerprint names: not a mix of the two."""

    class Editor(sc.Observer):  # a control law, as a user might try to write it
        def saved(self, run, step):
            if step.index == 100:
                run.system.loads[0].g = 10 * run.system.loads[0].g

    run = tmp_path / "run"
    with pytest.raises(SystemChanged, match=r"during the run: loads\[0\] \(Gravity\): g\.") \
            as info:
        sc.simulate(pendulum().system, **RUN, observers=[Editor(), RunStore(run)])
    reference = sc.simulate(pendulum().system, **RUN)
    np.testing.assert_array_equal(info.value.result.q, reference.q)
    stored = sc.Result.load(run, pendulum().system)
    np.testing.assert_array_equal(stored.q, reference.q)
    manifest = json.loads(Path(run, "manifest.json").read_text())
    assert manifest["status"] == "failed"
    assert "SystemChanged" in manifest["message"]
    assert "loads[0] (Gravity): g" in manifest["message"]


def _replace_section(scene):
    scene.cable.section = dataclasses.replace(scene.cable.section, E=7e8)


def _add_tip_load(scene):
    scene.system.add_point_load(scene.cable.node(-1), [0.0, -10.0, 0.0])


@pytest.mark.parametrize("edit, named", [
    (_replace_section, r"bodies\[0\] \(cable\): section\.E"),
    (_add_tip_load, r"loads: 2 now, 1 before"),
])
def test_other_edits_mid_run_are_refused_naming_them(edit, named):
    """A section replaced, or a load added (which rebuilds the system's layout under the
    running integrator), by an observer: refused too, naming the change."""
    scene = pendulum()

    class Editor(sc.Observer):
        def saved(self, run, step):
            if step.index == 10:
                edit(scene)

    with pytest.raises(SystemChanged, match=f"the system changed during the run: {named}"):
        sc.simulate(scene.system, **RUN, observers=[Editor()])


def deploying():
    tether = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, sc.Section.circular(1e-3, 1e9, 1e3))
    system = sc.System([tether]).deploy(tether, length=lambda t: 1 + 2 * t,
                                        rate=lambda t: 2.0, acceleration=lambda t: 0.0)
    return system.add_gravity([0, -9.81, 0])


def test_a_system_solved_twice_unchanged_keeps_its_layout():
    """The check costs a description per solve, not a rebuild: an unchanged system keeps
    its layout, and a run ends without a false alarm (a deploying cable, whose deployment
    memoizes its last time and its matrices, included)."""
    system = deploying()
    sc.simulate(system, t_end=0.01, dt=1e-3)
    layout = system.layout
    sc.simulate(system, t_end=0.01, dt=1e-3)
    assert system.layout is layout


def test_deploying_run_store_loads_with_the_system_built_again(tmp_path):
    """Before: the fingerprint of a deploying system described the deployment's memos
    (its matrices once bound, its last time), so the store of its run was refused by the
    same system built again (``StoreMismatch``).  Now the fingerprint is that of the
    system, whatever it evaluated."""
    written = sc.simulate(deploying(), t_end=0.01, dt=1e-3, observers=[RunStore(tmp_path)])
    np.testing.assert_array_equal(sc.Result.load(tmp_path, deploying()).q, written.q)


# ===========================================================================================
# Degenerate constraints
# ===========================================================================================
SECTION = sc.Section.circular(1e-3, 2e11, 7850.0)


def two_cables():
    a = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4, SECTION, name="a")
    b = sc.Cable.straight([0, 0, 1], [1, 0, 1], 4, SECTION, name="b")
    return a, b, sc.System([a, b])


def test_node_pinned_to_itself_is_refused():
    """Before: ``system.pin(c.node(2), c.node(2))`` (a typo for another cable's node) ran
    with exit 0, almost every step rejected and a tip 0.05 m off: its equations vanish.
    Now it is refused when added, naming the parameter and what it accepts."""
    a, b, system = two_cables()
    with pytest.raises(ValueError, match=r"pin Node\(a, 2\): target is the node itself; it "
                                         r"must be another node .* a rigid-body point"):
        system.pin(a.node(2), a.node(-3))
    assert system.constraints == []
    system.pin(a.node(2), b.node(2))  # what was meant


def test_degenerate_constraint_of_the_user_is_refused():
    """The same through ``add_constraint`` and a hand-made joint: equations with a rank
    below their number are refused, naming the constraint."""
    a, _, system = two_cables()
    weld = constraints.LinearConstraint(
        lambda s: np.concatenate([s.dofs(a.node(1))[:3], s.dofs(a.node(1))[:3]]),
        np.hstack([np.eye(3), -np.eye(3)]), np.zeros(3), "weld", ["Fx", "Fy", "Fz"])
    with pytest.raises(ValueError, match="constraint 'weld' is degenerate: its 3 equations "
                                         "have rank 0"):
        system.add_constraint(weld)


@pytest.mark.parametrize("first, second, names", [
    ("pin", "pin", ("pin Node(a, 0)", "pin Node(a, 0)")),
    ("clamp", "clamp", ("clamp Node(a, 0)", "clamp Node(a, 0)")),
    ("pin", "clamp", ("clamp Node(a, 0)", "pin Node(a, 0)")),
    ("clamp", "pin", ("pin Node(a, 0)", "clamp Node(a, 0)")),
])
def test_node_pinned_or_clamped_twice_is_refused(first, second, names):
    """Before: the same node pinned or clamped twice was accepted, and the first solve
    failed with ``singular iteration matrix at unknown 32`` naming neither constraint.
    Now the second is refused when added, naming both."""
    a, _, system = two_cables()
    getattr(system, first)(a.node(0))
    with pytest.raises(ValueError, match=rf"constraint '{re.escape(names[0])}' repeats "
                                         rf"equations of '{re.escape(names[1])}', added "
                                         r"before: .* constrain each coordinate once"):
        getattr(system, second)(a.node(-5))
    assert len(system.constraints) == 1


def test_two_pins_of_one_pair_of_nodes_are_refused():
    a, b, system = two_cables()
    system.pin(a.node(-1), b.node(0))
    with pytest.raises(ValueError, match=r"'pin Node\(b, 0\)-Node\(a, 4\)' repeats"):
        system.pin(b.node(0), a.node(-1))


def test_independent_constraints_on_shared_coordinates_are_accepted():
    """Joints that share coordinates without repeating equations stay accepted: a chain of
    node-to-node pins, a node pinned to the ground and to another node, two tethers pinned
    to one point of a hub and clamped to others."""
    a, b, system = two_cables()
    system.pin(a.node(0)).pin(b.node(0), a.node(0)).pin(b.node(-1), a.node(-1))
    hub = sc.RigidBody.cylinder(radius=1.0, height=0.5, density=100.0)
    t1 = sc.Cable.straight([0, 1, 0], [0, 3, 0], 2, SECTION, name="t1")
    t2 = sc.Cable.straight([0, 1, 0], [0, 3, 0], 2, SECTION, name="t2")
    t3 = sc.Cable.straight([0, -1, 0], [0, -3, 0], 2, SECTION, name="t3")
    spin = sc.System([hub, t1, t2, t3])
    spin.pin(t1.node(0), hub.point([0, 1, 0])).pin(t2.node(0), hub.point([0, 1, 0]))
    spin.clamp(t3.node(0), position=hub.point([0, -1, 0]))
    assert spin.n_constraints == 6 + 3 + 3 + 5


SCENE = """
[solver]
analysis = "dynamic"
t_end = 0.01
dt = 1e-3

[sections.wire]
E = 2e11
rho = 7850.0
radius = 1e-3

[[cables]]
name = "a"
section = "wire"
start = [0, 0, 0]
end = [1, 0, 0]
elements = 4

[[cables]]
name = "b"
section = "wire"
start = [0, 0, 1]
end = [1, 0, 1]
elements = 4

[[constraints]]
type = "pin"
node = {{ cable = "a", index = 0 }}

[[constraints]]
{second}
"""


def test_scene_file_node_pinned_to_itself_is_refused():
    """Before: the same typo in ``[[constraints]]`` ran with exit 0.  Now the file is
    refused, naming the table and the parameter."""
    good = 'type = "pin"\nnode = { cable = "a", index = 2 }\ntarget = { cable = "b", index = 2 }'
    assert scene_file.loads_text(SCENE.format(second=good)).system.n_constraints == 6
    typo = good.replace('"b"', '"a"')
    with pytest.raises(scene_file.SceneFileError,
                       match=r"demo.toml: constraints\[1\]\.target is refused: pin "
                             r"Node\(a, 2\): target is the node itself"):
        scene_file.loads_text(SCENE.format(second=typo), "demo.toml")


@pytest.mark.parametrize("kind", ["pin", "clamp"])
def test_scene_file_node_constrained_twice_is_refused(kind):
    second = f'type = "{kind}"\nnode = {{ cable = "a", index = 0 }}'
    with pytest.raises(scene_file.SceneFileError,
                       match=rf"demo.toml: constraints\[1\]\.node is refused: constraint "
                             rf"'{kind} Node\(a, 0\)' repeats equations of 'pin Node\(a, 0\)'"):
        scene_file.loads_text(SCENE.format(second=second), "demo.toml")


def test_rigid_body_mass_edited_after_a_run_is_simulated_as_edited():
    """A rigid body's mass matrix was cached from its first solve: doubling ``mass`` (and
    ``inertia``) after a run left a constant force accelerating the old mass.  A free
    hub pushed by 1 N at its centre for 0.1 s moves ``F t^2 / 2m``."""
    hub = sc.RigidBody.cylinder(radius=0.5, height=1.0, density=100.0)
    system = sc.System([hub]).add_point_load(hub.point([0.0, 0.0, 0.0]), [1.0, 0.0, 0.0])

    def travel():
        r = sc.simulate(system, t_end=0.1, dt=1e-3)
        return hub.positions(r.q[-1, system.dofs(hub)], np.zeros(3))[0]

    first = travel()
    assert first == pytest.approx(0.5 * 0.1**2 / hub.mass, rel=1e-6)
    hub.mass, hub.inertia = 2 * hub.mass, 2 * hub.inertia
    assert travel() == pytest.approx(first / 2, rel=1e-6)


def test_interrupt_right_after_the_temporary_is_created_leaves_nothing(tmp_path,
                                                                       monkeypatch):
    """A signal turned into an exception between the creation of the temporary file and
    the block that writes it (the window of the SIGTERM test's leftover
    ``series.pvd.tmp-*``) leaves no temporary file and the old content."""
    from skfem_cable.util import atomic

    target = tmp_path / "series.pvd"
    target.write_text("old")
    real_close = atomic.os.close

    def interrupted(fd):
        real_close(fd)
        raise KeyboardInterrupt

    monkeypatch.setattr(atomic.os, "close", interrupted)
    with pytest.raises(KeyboardInterrupt):
        atomic.write_atomic(target, b"new")
    monkeypatch.undo()
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["series.pvd"]
