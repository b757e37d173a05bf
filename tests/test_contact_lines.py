"""Line-to-line contact and self-contact (issue 49, item 4; ``docs/contact.md``): the
narrow phase's exact tangents, two taut tethers driven against each other (with and
without friction), and a loop of one cable pressed on itself."""

import numpy as np
import pytest
from skfem import MeshLine

import skfem_cable as sc
from skfem_cable.core.contract import Evaluation
from skfem_cable.loads.contact_lines import LineLineContact
from skfem_cable.scenes.capstan import ROPE

#: The tethers' stretch ramp (s) and their strain (1 %: 1000 N of tension).
RAMP, STRAIN = 0.1, 0.01
#: The rope without its material damping (the books' dissipation is then the friction's).
UNDAMPED = sc.Section.circular(5e-3, 1.27e9, 1273.0)
#: The rope's diameter (m) and the stated tolerance of the default contact (of d).
D, TOLERANCE = 1e-2, 1e-2


def smooth(u):
    """0 before 0, 1 after 1, ``3 u^2 - 2 u^3`` between."""
    u = min(max(u, 0.0), 1.0)
    return u * u * (3.0 - 2.0 * u)


def end(x0, z0, drop=0.0, press=0.4, slide=0.0):
    """A tether end at ``x0`` stretched by ``STRAIN`` over ``RAMP``, then lowered from
    ``z0`` by ``drop`` over ``press`` s, then moved by ``slide`` along x over 0.2 s."""
    x0 = np.asarray(x0, float)

    def target(t):
        x = x0 * (1.0 + STRAIN * smooth(t / RAMP))
        x[0] += slide * smooth((t - RAMP - press) / 0.2)
        x[2] = z0 - drop * smooth((t - RAMP) / press)
        return x
    return target


def crossing(height=0.0102, drop=0.03, slide=0.0, friction=0.0, elements=10, section=ROPE,
             tangent=None):
    """Tether a along x at z = 0 and tether b along y at ``height`` (both 2 m, the rope
    of the capstan by default: EA = 1e5 N, d = 1 cm), stretched by 1 %; b's ends are then
    lowered by ``drop`` (0.4 s) onto a and slid by ``slide`` along x; the contact on the
    tangent pattern ``tangent`` (default: the exact ``"full"``): ``(system, a, b,
    contact)``."""
    a = sc.Cable.straight([-1, 0, 0], [1, 0, 0], elements, section, name="a")
    b = sc.Cable.straight([0, -1, height], [0, 1, height], elements, section, name="b")
    system = (sc.System([a, b]).pin(a.node(0), end([-1, 0, 0], 0.0))
              .pin(a.node(-1), end([1, 0, 0], 0.0))
              .pin(b.node(0), end([0, -1, 0], height, height + drop, slide=slide))
              .pin(b.node(-1), end([0, 1, 0], height, height + drop, slide=slide))
              .contact(a, b, friction=friction, tangent=tangent))
    return system, a, b, system.loads[-1]


def resultants(system, contact, q, v, bodies):
    """The contact's resultant forces (N) on ``bodies`` at ``q``, ``v``: the sums of the
    components of its generalized force on their position coordinates (a translation
    moves those alone)."""
    term = contact.bind(system)
    term.hooks[0].accept(q, v, 0.0)
    ev = Evaluation(system, 0.0, q, v, np.zeros(0))
    term.evaluate(ev, None)
    force = ev.f_ext - ev.f
    return [force[system.dofs(body)].reshape(-1, 2, 3)[:, 0].sum(axis=0) for body in bodies]


def test_tangents_against_central_differences():
    """Penalty and friction in q and v at a perturbed state where the tethers cross and
    penetrate (beyond and within the penalty's onset): relative error below 1e-6."""
    rng = np.random.default_rng(3)
    for height, scale in ((0.008, 1e-4), (D - 2e-6, 1e-7)):
        system, a, b, _ = crossing(height=height, friction=0.3, elements=4)
        q = system.q0 + scale * rng.standard_normal(system.n_dofs)
        v = 0.05 * rng.standard_normal(system.n_dofs)
        parts = [p for p in sc.check_tangent(system, q, v).parts
                 if p.name.startswith("contact")]
        assert {p.wrt for p in parts} == {"q", "v"}
        assert max(p.error for p in parts) < 1e-6, (height, [p.error for p in parts])


def test_taut_tethers_driven_together_do_not_pass():
    """Tether b is lowered 3 cm through where tether a is: it stops on a, penetrating
    less than the stated tolerance d; the contact's forces on the two are equal and
    opposite (to 1e-9 of the force) and push them apart; the energy books close to
    2e-6 of the work (the stretch alone: 7.5e-7)."""
    system, a, b, contact = crossing()
    result = sc.simulate(system, t_end=0.55, dt=1e-3, every=10, method="sparse")
    state = result.state(-1)
    out = contact.contacts(system, state.q, state.v)
    assert len(out["normal"]) == 1 and out["normal"][0] > 10.0
    assert 0.0 < out["max_penetration"] < TOLERANCE * D
    assert out["first"][0, 2] < out["second"][0, 2]          # b stays above a
    on_a, on_b = resultants(system, contact, state.q, state.v, (a, b))
    assert np.abs(on_a + on_b).max() < 1e-9 * np.abs(on_a).max()
    assert on_a[2] == pytest.approx(-out["normal"][0], rel=1e-9) and on_b[2] > 0
    work = result.energy["external_work"][-1]
    assert np.abs(result.energy["balance"]).max() < 2e-6 * work


def test_friction_is_booked_as_dissipation():
    """Pressed together (mu = 0.3, the rope without material damping), b is slid 5 cm
    along a: the friction power of the
    contacts, integrated over the saved steps, is the books' dissipation within 1e-3,
    about mu N times the slide, and the books close to 5e-6 of the work (measured 3.1e-6:
    the contact crosses the joints of the sampled centrelines, where the gap has kinks)."""
    system, a, b, contact = crossing(friction=0.3, slide=0.05, section=UNDAMPED)
    result = sc.simulate(system, t_end=0.75, dt=1e-3, every=1, method="sparse")
    power = [contact.contacts(system, result.state(i).q, result.state(i).v)["friction_power"]
             for i in range(len(result))]
    work = np.trapezoid(-np.asarray(power), result.t)
    assert result.energy["dissipated"][-1] == pytest.approx(work, rel=1e-3)
    normal = contact.contacts(system, result.state(-1).q, result.state(-1).v)["normal"][0]
    assert work == pytest.approx(0.3 * normal * 0.05, rel=0.1)
    assert np.abs(result.energy["balance"]).max() < 5e-6 * result.energy["external_work"][-1]


def loop_cable(height, legs=10, turn=24):
    """One cable that runs along x from (-1, 0, 0) to (1, 0, 0) (leg 1, ``legs``
    elements), turns through 270 degrees on the circle of radius 1 about (1, 1) while
    rising to ``height``, and comes back along y from (0, 1, height) to (0, -1, height)
    (leg 2), across its leg 1 at the origin."""
    rise = height / (1.5 * np.pi)
    s = np.concatenate([np.linspace(0, 2, legs + 1), 2 + np.linspace(0, 1.5 * np.pi,
                                                                      turn + 1)[1:],
                        2 + 1.5 * np.pi + np.linspace(0, 2, legs + 1)[1:]])
    theta = np.clip(s - 2, 0, 1.5 * np.pi) - 0.5 * np.pi
    on_leg1, on_leg2 = s <= 2, s >= 2 + 1.5 * np.pi
    x = np.where(on_leg1, s - 1, np.where(on_leg2, 0.0, 1 + np.cos(theta)))
    y = np.where(on_leg1, 0.0, np.where(on_leg2, 1 - (s - 2 - 1.5 * np.pi),
                                        1 + np.sin(theta)))
    z = np.clip(s - 2, 0, 1.5 * np.pi) * rise
    tangents = np.where(on_leg1[:, None], [1.0, 0.0, 0.0],
                        np.where(on_leg2[:, None], [0.0, -1.0, 0.0],
                                 np.column_stack([-np.sin(theta), np.cos(theta),
                                                  np.full_like(s, rise)])))
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    return sc.Cable(MeshLine(s), ROPE, np.column_stack([x, y, z]), tangents, name="loop")


def test_a_loop_pressed_on_itself():
    """Self-contact: the loop's legs are pinned at their ends and stretched by 1 %, and
    leg 2 is lowered 3 cm onto leg 1, as the tethers of
    ``test_taut_tethers_driven_together_do_not_pass``: the legs do not pass through each
    other (penetration below the stated tolerance d), and the neighbouring segments
    (closer than pi d along the line) never count.  Steps of 2 ms: at 1 / 2 ms the legs
    end 31.65 / 31.54 N apart, 3.67e-3 / 3.66e-3 d deep, one contact all along."""
    height, legs, turn = 0.0102, 10, 24
    cable = loop_cable(height, legs, turn)
    system = sc.System([cable])
    x0 = cable.q0.reshape(-1, 2, 3)[:, 0]
    for k, node in enumerate((0, legs, legs + turn, 2 * legs + turn)):
        system.pin(cable.node(node), end(x0[node] * [1, 1, 0], x0[node, 2],
                                         0.03 if k > 1 else 0.0))
    system.contact(cable, cable)
    contact = system.loads[-1]
    assert contact.exclusion == pytest.approx(np.pi * D)
    result = sc.simulate(system, t_end=0.55, dt=2e-3, every=5, method="sparse")
    out = contact.contacts(system, result.state(-1).q, result.state(-1).v)
    assert len(out["normal"]) == 1 and out["normal"][0] > 10.0
    assert 0.0 < out["max_penetration"] < TOLERANCE * D
    assert out["first"][0, 2] < out["second"][0, 2]          # leg 2 stays above leg 1


def test_the_options_are_checked():
    """Two line bodies give a ``LineLineContact``; bad options name the parameter."""
    system, a, b, contact = crossing()
    assert isinstance(contact, LineLineContact) and not contact.self_contact
    assert sc.System([a]).contact(a, a).loads[-1].self_contact
    with pytest.raises(ValueError, match="friction must be finite and >= 0"):
        system.contact(a, b, friction=-1.0)
    with pytest.raises(ValueError, match="exclusion must be finite and >= 0"):
        system.contact(a, a, exclusion=-1.0)
