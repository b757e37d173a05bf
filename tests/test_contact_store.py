"""The contact state in the run store (issue 49, "Outputs"; ``docs/contact.md``): a
line-surface and a line-line contact declare per-step outputs (``step_outputs``,
``Term.outputs``), recorded at every saved step (``Result.outputs``) and in the Zarr
store (``output_<name>``), equal to the ones recomputed from the saved states.

One short scene (one compiled step, shared by the tests): rope ``a`` (0.5 m, 4
elements) starts touching the ground and slides along it under a slanted gravity
(``mu = 0.3`` below the slope's 1), and rope ``b`` starts touching it across, where they
cross (frictionless).
"""

import numpy as np
import pytest

import skfem_cable as sc
from skfem_cable.core.protocols import load_outputs
from skfem_cable.loads import contact as surface_contact
from skfem_cable.loads import contact_lines
from skfem_cable.scenes.capstan import ROPE

#: The rope's cross-section radius (m).
RADIUS = 5e-3

#: Gravity (m/s^2): its slope along x (1) beats the friction (0.3) also under ``b``'s
#: weight, so ``a`` slides.
GRAVITY = [9.81, 0.0, -9.81]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """``(system, result, store)``: 30 ms of the scene (module notes), saved every 5 ms
    into the run store ``store``."""
    a = sc.Cable.straight([-0.25, 0, RADIUS], [0.25, 0, RADIUS], 4, ROPE, name="a")
    b = sc.Cable.straight([0, -0.25, 3 * RADIUS], [0, 0.25, 3 * RADIUS], 4, ROPE, name="b")
    system = (sc.System([a, b]).add_gravity(GRAVITY)
              .contact(a, sc.Plane([0, 0, 0], [0, 0, 1]), friction=0.3)
              .contact(a, b))
    store = tmp_path_factory.mktemp("contact_store")
    result = sc.simulate(system, t_end=0.03, dt=1e-3, every=5, rho_inf=0.0,
                         method="sparse", observers=[sc.io.RunStore(store)])
    return system, result, store


def recomputed(system, result, contact, evaluate, summary):
    """``{name: (n_saved,)}``: ``summary`` of ``evaluate(system, q, v)`` at every saved
    state of ``result``, under the contact's ``step_outputs``."""
    rows = [list(summary(evaluate(system, s.q, s.v)).values())
            for s in map(result.state, range(len(result.t)))]
    return dict(zip(contact.step_outputs, np.array(rows, dtype=float).T))


def assert_recorded(result, expected):
    """The run's recorded outputs equal ``expected`` within 1e-9 of each output's
    largest value."""
    for name, values in expected.items():
        recorded = result.outputs[name]
        assert recorded.shape == result.t.shape
        np.testing.assert_allclose(recorded, values, rtol=1e-9,
                                   atol=1e-9 * np.abs(values).max(), err_msg=name)


def test_the_surface_contact_records_its_state(run):
    """Elements in contact, normal force, friction force, deepest penetration and
    friction power of rope ``a`` on the ground: recorded equal to ``resolve`` of the saved
    states within 1e-9; at the start nothing presses, at the end all elements touch
    within the stated tolerance and the friction works against the sliding rope."""
    system, result, _ = run
    contact = system.loads[1]
    assert contact.step_outputs == tuple(f"contact_a_{key}"
                                         for key in surface_contact.OUTPUTS)
    expected = recomputed(system, result, contact, contact.resolve,
                          surface_contact.summary)
    assert_recorded(result, expected)
    first, out = ({key: expected[f"contact_a_{key}"][i] for key in surface_contact.OUTPUTS}
                  for i in (0, -1))
    assert first["normal"] == first["tangential"] == first["friction_power"] == 0.0
    assert out["elements"] == 4 and out["normal"] > 0.0 and out["tangential"] > 0.0
    assert out["friction_power"] < 0.0
    assert 0.0 < out["max_penetration"] < contact.tolerance * 2 * RADIUS


def test_the_line_contact_records_its_state(run):
    """Number of contacts, normal force and deepest penetration of ``a`` and ``b``:
    recorded equal to ``contacts`` of the saved states within 1e-9; one contact, where
    they cross, pressed and within the stated tolerance."""
    system, result, _ = run
    contact = system.loads[2]
    assert contact.step_outputs == tuple(f"contact_a_b_{key}"
                                         for key in contact_lines.OUTPUTS)
    expected = recomputed(system, result, contact, contact.contacts, contact_lines.summary)
    assert_recorded(result, expected)
    assert expected["contact_a_b_contacts"][-1] == 1
    assert expected["contact_a_b_normal"][-1] > 0.0
    assert 0.0 < expected["contact_a_b_max_penetration"][-1] < contact.tolerance * 2 * RADIUS


def test_the_run_store_reads_the_contact_state_back(run):
    """The store holds every declared output (``output_<name>``) and reads it back as
    the run recorded it."""
    system, result, store = run
    stored = sc.Result.load(store, system).outputs
    assert set(stored) == set(load_outputs(system)) == set(result.outputs)
    for name, values in result.outputs.items():
        np.testing.assert_array_equal(stored[name], values, err_msg=name)


def test_two_contacts_of_a_line_have_their_own_outputs():
    """A line's second contact is numbered (``contact_a_2``) unless named; a given name
    prefixes its outputs (no compiled step: nothing runs)."""
    a = sc.Cable.straight([0, 0, 0], [1, 0, 0], 2, ROPE, name="a")
    system = (sc.System([a]).contact(a, sc.Plane([0, 0, 0], [0, 0, 1]))
              .contact(a, sc.Sphere([0, 0, 1], 0.5))
              .contact(a, sc.Cylinder([0, 0, 2], [0, 1, 0], 0.5), name="drum"))
    assert [load.name for load in system.loads] == ["contact_a", "contact_a_2", "drum"]
    assert len(set(load_outputs(system))) == 3 * (len(surface_contact.OUTPUTS)
                                                  + len(surface_contact.ARRAYS))
    assert "drum_normal" in load_outputs(system)


def test_the_run_summary_takes_a_run_with_contacts(run):
    """The summary of a run (``runner.summary.run_outputs``, the CLI's ``summary.json``)
    takes a run with contacts: their per-step outputs are no ``outputs(result)`` of a
    load's key numbers (no compiled step: the fixture's run)."""
    from skfem_cable.runner.summary import run_outputs

    _, result, _ = run
    assert "loads" not in run_outputs(result)
