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
