"""Run state is the run's (issue 46, must-show 4): the rectification's arcs live in the
run's ``orbit.Reference`` (the binding's, the checkpoint's, the ``Result``'s), never on
the user's ``Orbit``; reading a run (``Result.load``) leaves the system as it is.

Before: ``Orbit.rebase`` rebased the orbit the user built, so that after a rectified run
``orbit.position(300.0)`` answered the run's last arc, 465.8 m away from the orbit as
given (4 rebases in 300 s here), and ``Result.load(path, system)`` restored the stored
rebases into ``system.orbit`` (a fresh system's orbit moved by the same 465.8 m).  Now
both are 0.0 m; the run's ``Result.reference`` holds the arcs.
"""

import numpy as np
import pytest
from test_rectify import DT, thrusting

import skfem_cable as sc
from skfem_cable import io

TIMES = np.linspace(0.0, 300.0, 31)


@pytest.fixture(scope="module")
def stored(tmp_path_factory):
    """A thrusting tether in orbit run for 300 s with rectification, stored."""
    path = tmp_path_factory.mktemp("rectified")
    system, orbit = thrusting()
    given = orbit.position(TIMES)
    result = sc.simulate(system, 300.0, DT, every=10, observers=[io.RunStore(path)])
    return path, system, orbit, given, result


def test_a_rectified_run_leaves_the_users_orbit_as_given(stored):
    _, _, orbit, given, result = stored
    assert result.stats["rectifications"] > 0 and len(result.reference.rebases) > 0
    np.testing.assert_array_equal(orbit.position(TIMES), given)
    assert not hasattr(orbit, "rebase")
    # the run's reference departs from the orbit at its first rebase
    moved = np.linalg.norm(result.reference.position(TIMES) - given, axis=1)
    first = result.reference.rebases[0, 0]
    assert moved[TIMES < first].max() == 0.0 and moved[-1] > 1.0


def test_loading_a_run_leaves_the_system_unchanged(stored):
    path, _, _, given, result = stored
    system, orbit = thrusting()  # a fresh system
    loaded = sc.Result.load(path, system)
    assert system.orbit is orbit
    np.testing.assert_array_equal(orbit.position(TIMES), given)  # as before the load
    np.testing.assert_array_equal(loaded.reference.rebases, result.reference.rebases)
    np.testing.assert_array_equal(loaded.reference.position(TIMES),
                                  result.reference.position(TIMES))
    np.testing.assert_array_equal(loaded.q, result.q)


def test_a_second_run_and_a_result_keep_their_own_arcs(stored):
    _, system, orbit, given, result = stored
    rebases = result.reference.rebases
    short = sc.simulate(system, 100.0, DT, every=10)
    assert len(short.reference.rebases) < len(rebases)
    np.testing.assert_array_equal(result.reference.rebases, rebases)  # its own copy
    np.testing.assert_array_equal(orbit.position(TIMES), given)


# --- inputs: declared where used, their run values the run's ---------------------------

def test_a_controlled_run_leaves_the_users_input_and_gives_the_same_motion():
    """The pendulum of ``test_control`` pushed by ``Ramp`` with a delay of two steps.
    Before: ``push.value`` held ``[0, 0.04, 0]`` after the run (the controller's last
    output, written on the user's ``Input``).  Now it holds its initial ``[0, 0, 0]``;
    the motion is that of main before the change (the tip's position at 0.05 s: to the
    last bit then; to rounding since ``core.ordering`` puts the pin's multipliers at the
    band's end, where the LU takes other pivots; since the predictor keeps extrapolating
    after a slow step on a kept tangent, ``GeneralizedAlpha.predictor``, within Newton's
    tolerance: its height moved by 1.3e-9 m, to 1.8e-10 m from that at ``tol=1e-13``
    where it was 1.1e-9 m away), and a second run of the same system gives the same
    steps to the last bit."""
    from test_control import DT, SAMPLE, Ramp, pendulum

    system, cable, push = pendulum()
    runs = [sc.simulate(system, 0.05, DT, controllers=[Ramp(SAMPLE, delay=2 * DT)])
            for _ in range(2)]
    assert runs[0].stats["path"] == "compiled"
    assert push.value.tolist() == [0.0, 0.0, 0.0] and push(1.0).tolist() == [0.0, 0.0, 0.0]
    np.testing.assert_array_equal(runs[0].inputs["push"][-1], [0.0, 0.04, 0.0])
    tip = system.dofs(cable)[-12:-9]
    np.testing.assert_allclose(runs[0].q[-1, tip],
                               [0.749795024124857, -0.012575070171914721, 0.0],
                               rtol=0.0, atol=1e-14)
    np.testing.assert_array_equal(runs[1].q, runs[0].q)


class Thruster:
    """A user's load: the force ``throttle(t) direction`` at a node, its throttle an
    ``Input`` that it declares (``inputs()``); its attributes are slots, so nothing can
    find the input by looking through them."""

    __slots__ = ("node", "throttle", "direction")

    def __init__(self, node, throttle, direction):
        self.node, self.throttle = node, throttle
        self.direction = np.asarray(direction, dtype=float)

    def inputs(self):
        return sc.core.inputs.declared(self.throttle)

    def bind(self, system, inputs=None):
        d = system.dofs(self.node)[:3]
        throttle = sc.core.inputs.reader(self.throttle, inputs)  # the run's values

        def add(ev, index):
            ev.f_ext[d] += throttle(ev.t) * self.direction

        return sc.Term(add=add, name="thruster")


class Full(sc.Controller):
    def update(self, t, state):
        return {"throttle": 2.0}


def thruster_run(initial, controllers):
    cable = sc.Cable.straight([0, 0, 0], [1, 0, 0], 4,
                              sc.Section.circular(1e-3, 2e11, 7850.0), name="cable")
    throttle = sc.Input("throttle", initial)
    system = sc.System([cable]).pin(cable.node(0))
    system.add_load(Thruster(cable.node(-1), throttle, [0.0, 1.0, 0.0]))
    return sc.simulate(system, 0.02, 1e-3, controllers=controllers), throttle


def test_a_load_declaring_its_input_gets_the_controllers_values():
    """Before: the controller was refused ("set the input 'throttle' ..., which the
    system does not have (its inputs: none)"): the inputs were found by walking
    attributes, and the slots hid it.  Now the load declares it: the controlled run
    (initial 0, set to 2 N from the start) is the run of the input held at 2 N, to the
    last bit, and the user's input keeps 0."""
    controlled, throttle = thruster_run(0.0, [Full(1e-3)])
    held, _ = thruster_run(2.0, [])
    np.testing.assert_array_equal(controlled.q, held.q)
    assert np.abs(held.q).max() > 0 and throttle.value == 0.0
    np.testing.assert_array_equal(controlled.inputs["throttle"], np.full(len(held.t), 2.0))
