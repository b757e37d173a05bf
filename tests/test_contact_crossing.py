"""The crossing guard of line-to-line contact (issue 49, item 4: lines "do not pass through
each other", made safe; ``docs/contact.md``, "Lines that cross"): the swept test
(``kernels.contact_crossing``) fires between two states either side of a crossing and
not in contact or sliding; a step that carries one tether through the other is refused,
and the halved steps hold the contact or the run stops naming the pair.  The tethers are
those of ``test_contact_lines`` (one compiled step for all the runs here)."""

import numpy as np
import pytest
from test_contact_lines import TOLERANCE, D, crossing, loop_cable

import skfem_cable as sc
from skfem_cable.kernels import contact_crossing as kernel
from skfem_cable.loads import contact_lines
from skfem_cable.loads.contact_crossing import crossing_check

#: Tether b's drop of ``crossing`` (m): 3 cm through where tether a is.
DROP = 0.03


def bound(system, contact, q0, v0, h):
    """The term of ``contact`` with its broad phase's pairs for a step ``h`` from
    ``(q0, v0)``."""
    term = contact.bind(system)
    term.hooks[0].accept(q0, v0, 0.0)
    term.prepare(h)
    return term


def heights(system, body):
    """The rows of ``q`` of the z of ``body``'s node positions."""
    return system.dofs(body).reshape(-1, 2, 3)[:, 0, 2]


@pytest.fixture
def reasons(monkeypatch):
    """What every call of the crossing checks bound from here on returned, in order."""
    said = []

    def recorded(*args):
        check = crossing_check(*args)

        def recording(q0, q1):
            said.append(check(q0, q1))
            return said[-1]
        return recording
    monkeypatch.setattr(contact_lines, "crossing_check", recorded)
    return said


@pytest.fixture(scope="module")
def tethers():
    """``(system, a, b, contact, term, q0)``: the crossing tethers at their start (b 0.2
    mm above touching a) and the contact's term with the pairs of a 1 ms step of b
    falling at 30 m/s."""
    system, a, b, contact = crossing()
    q0 = system.q0.copy()
    v0 = np.zeros_like(q0)
    v0[heights(system, b)] = -DROP / 1e-3
    return system, a, b, contact, bound(system, contact, q0, v0, 1e-3), q0


def test_the_swept_test_fires_either_side_of_a_crossing(tethers):
    """b moved 3 cm down, through a (at the middle of both, a third of the way through
    the move): refused, naming the contact, the tethers and where; moved back up too.
    Pressed 5 mm into a (same side), or pressed and slid 1 cm along a: not refused."""
    system, a, b, contact, term, q0 = tethers
    through, pressed = q0.copy(), q0.copy()
    through[heights(system, b)] -= DROP
    pressed[heights(system, b)] -= 0.005
    slid = pressed.copy()
    slid[system.dofs(b).reshape(-1, 2, 3)[:, 0, 0]] += 0.01
    reason = term.check(q0, through)
    assert reason.startswith("contact_a_b: lines 'a' and 'b' pass through each other at 1 m "
                             "along 'a' and 1 m along 'b'"), reason
    assert "0.34 of the way" in reason                      # 10.2 mm of 30 mm
    assert term.check(through, q0) is not None
    assert term.check(q0, pressed) is None
    assert term.check(pressed, slid) is None


def test_the_kernel_on_two_segments():
    """Segment b across a (a along x, b along y), 1 above it, moving to 1 below: the
    crossing at the middle of the move and of both.  None where b moves down beside a's
    end (the lines' intersection off a), where b is parallel to a, 0.5 beside it, and
    moves down past it, or where b slides along a above it."""
    a = np.array([[-1.0, 0, 0], [1, 0, 0]])
    P, c, cuts = np.empty((4, 3)), np.empty(4), np.empty(4)

    def tau(b0, b1):
        return kernel.crossing_time(np.vstack([a, b0]), np.vstack([a, b1]), 1e-5, P, c,
                                    cuts)
    across = np.array([[0.0, -1, 1], [0, 1, 1]])
    assert tau(across, across - [0, 0, 2]) == pytest.approx(0.5, abs=1e-12)
    assert P[2:, 2] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert tau(across + [2, 0, 0], across + [2, 0, -2]) == -1.0      # beside a's end
    along = np.array([[-1.0, 0.5, 1], [1, 0.5, 1]])
    assert tau(along, along - [0, 0, 2]) == -1.0                     # parallel, 0.5 off
    assert tau(across, across + [0.5, 0, 0]) == -1.0                 # slides along a


def test_self_contact_is_checked():
    """The loop of ``test_contact_lines``: its leg 2 moved 3 cm down through its leg 1
    is refused, naming the loop twice and where along it (1 m and 2 + 3 pi / 2 + 1 m)."""
    cable = loop_cable(0.0102)
    system = sc.System([cable]).contact(cable, cable)
    q0 = system.q0.copy()
    z = heights(system, cable)
    leg2 = z[-11:]
    v0 = np.zeros_like(q0)
    v0[leg2] = -DROP / 1e-3
    term = bound(system, system.loads[-1], q0, v0, 1e-3)
    through = q0.copy()
    through[leg2] -= DROP
    reason = term.check(q0, through)
    assert reason.startswith(f"contact_loop: lines 'loop' and 'loop' pass through each "
                             f"other at 1 m along 'loop' and {3 + 1.5 * np.pi:.4g} m"), reason


def test_a_fast_drop_is_held_by_halved_steps(reasons):
    """b dropped on a at 10 ms steps, on the exact tangent: without the guard it
    converged through a (b ended 4.8 cm below a, the penalty released); with it the
    steps that carry it through are refused, and the halved ones hold it above a,
    penetrating less than the stated tolerance d."""
    system, a, b, contact = crossing()
    result = sc.simulate(system, t_end=0.55, dt=1e-2, method="sparse")
    refused = [r for r in reasons if r is not None]
    assert refused and all("'a' and 'b' pass through" in r for r in refused)
    state = result.state(-1)
    out = contact.contacts(system, state.q, state.v)
    assert len(out["normal"]) == 1 and out["first"][0, 2] < out["second"][0, 2]
    assert 0.0 < out["max_penetration"] < TOLERANCE * D


def test_a_soft_penalty_stops_the_run_naming_the_pair():
    """A penalty of 200 N/m cannot stop b (2 N at full depth against some 30 N): on main
    b passed through a silently; with the guard no step can, and the run stops with the
    diagnostic naming the contact, the tethers, where, the time and the step."""
    system, a, b, contact = crossing()
    contact.stiffness = 200.0
    with pytest.raises(sc.SimulationError) as failed:
        sc.simulate(system, t_end=0.55, dt=1e-2, method="sparse")
    message = str(failed.value)
    assert "smallest step size" in message and ", h=9.77e-06: contact_a_b: lines 'a' and " \
        "'b' pass through each other at 1 m along 'a' and 1 m along 'b'" in message, message
    saved = failed.value.result
    q = saved.state(-1).q
    assert q[heights(system, b)[5]] > q[heights(system, a)[5]]    # the last saved: above


def test_sliding_in_contact_is_no_crossing(reasons):
    """b pressed on a and slid 5 cm along it (mu = 0.3): the check, called at every
    converged step, refuses none; the contact held and moved with the slide."""
    system, a, b, contact = crossing(friction=0.3, slide=0.05)
    result = sc.simulate(system, t_end=0.75, dt=2e-3, every=25, method="sparse")
    assert len(reasons) >= result.stats["steps"] and set(reasons) == {None}
    out = contact.contacts(system, result.state(-1).q)
    assert len(out["normal"]) == 1 and out["first"][0, 2] < out["second"][0, 2]
    assert out["first"][0, 0] == pytest.approx(0.05, abs=0.01)
