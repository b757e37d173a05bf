"""Issue 45, round three of "never a silent wrong answer", the static items: a hanging
cable that settles into a loop (2), modes in a rotating frame without its centrifugal
term (3), and ``solve_steady`` with a load fixed in space across the spin axis (11)."""

import numpy as np
import pytest

import skfem_cable as sc

ORBIT = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3)
N = ORBIT.mean_motion
L = 20e3


def dumbbell():
    """Two 100 kg end bodies on a stiff, light 20 km tether along the local vertical, in
    a circular orbit at 400 km (``test_orbit_system``)."""
    cable = sc.Cable.straight([-L / 2, 0, 0], [L / 2, 0, 0], 8,
                              sc.Section.circular(1e-3, 1e11, 1.0))
    system = sc.System([cable]).add_point_mass(cable.node(0), 100.0)
    return cable, system.add_point_mass(cable.node(-1), 100.0).add_orbit(ORBIT)


def in_plane(shapes):
    """Which complex mode shapes move mostly in the orbit plane (x, y)."""
    return np.array([np.sum(np.abs(s[2::3]) ** 2) / np.sum(np.abs(s) ** 2) < 0.5
                     for s in shapes])


# --- item 3: modes(spin=) without add_centrifugal ----------------------------------------

def test_modes_with_spin_hold_the_centrifugal_term_themselves():
    """``modes(system, state, spin=n)`` on the orbiting dumbbell without
    ``add_centrifugal``: the in-plane libration at ``sqrt(3) n`` and the out-of-plane one
    at ``2 n`` (Beletsky & Levin), within 0.5 %, as with ``add_centrifugal(n)``.  Before:
    the in-plane mode at 1.887 n (the tangent without the centrifugal softening)."""
    _, system = dumbbell()
    state = sc.solve_steady(system, omega=[0, 0, N])
    freqs, shapes = sc.modes(system, state, k=6, spin=[0, 0, N])
    freqs = 2 * np.pi * np.asarray(freqs) / N
    plane = in_plane(shapes)
    pitch = freqs[plane][np.argmin(np.abs(freqs[plane] - np.sqrt(3)))]
    roll = freqs[~plane][np.argmin(np.abs(freqs[~plane] - 2.0))]
    assert pitch == pytest.approx(np.sqrt(3), rel=5e-3)
    assert roll == pytest.approx(2.0, rel=5e-3)
    same = sc.modes(dumbbell()[1].add_centrifugal([0, 0, N]), state, k=6, spin=[0, 0, N])[0]
    np.testing.assert_allclose(2 * np.pi * np.asarray(same) / N, freqs, rtol=1e-9, atol=1e-9)
    assert not any(getattr(load, "frame_rate", None) is not None for load in system.loads)


@pytest.mark.parametrize("spin", [[0, 0, 2 * N], None])
def test_modes_refuse_a_spin_other_than_the_centrifugal_rate(spin):
    """A system with ``add_centrifugal(n)`` and ``spin`` of another rate (or none: the
    Coriolis term left out) is refused, naming ``add_centrifugal``."""
    _, system = dumbbell()
    state = sc.solve_steady(system, omega=[0, 0, N])
    with pytest.raises(ValueError, match="add_centrifugal at"):
        sc.modes(dumbbell()[1].add_centrifugal([0, 0, N]), state, k=6, spin=spin)


# --- item 11: solve_steady with a net force fixed in space --------------------------------

@pytest.mark.parametrize("kind", ["line", "point"])
def test_solve_steady_names_a_load_fixed_in_space_across_the_axis(kind):
    """A constant drag on the orbiting dumbbell (along the flight, fixed in space): no
    relative equilibrium.  ``solve_steady`` raises the ``ValueError`` its docstring
    promises, naming the load.  Before: ``StaticConvergenceError``, "the loads exert a
    net torque of -13.5563 N m" (the line load; -67.6875 N m the point load), after a
    Newton iteration that cannot balance the net force along the flight."""
    cable, system = dumbbell()
    if kind == "line":
        system.add_line_load(cable, [0, -1e-10, 0])
        name = r"UniformLineLoad\('cable', \[0.0, -1e-10, 0.0\]\)"
    else:
        system.add_point_load(cable.node(0), [0, -1e-5, 0])
        name = r"PointLoad\(Node\(cable, 0\), \[0.0, -1e-05, 0.0\]\)"
    with pytest.raises(ValueError, match=name + ".*fixed in space"):
        sc.solve_steady(system, omega=[0, 0, N])


def test_solve_steady_takes_a_load_along_the_axis():
    """A load fixed in space along the spin axis turns with the frame: accepted."""
    cable, system = dumbbell()
    system.add_point_load(cable.node(0), [0, 0, 1e-5]).add_point_load(cable.node(-1),
                                                                       [0, 0, -1e-5])
    state = sc.solve_steady(system, omega=[0, 0, N])
    assert state.stats["converged"]


# --- item 2: a hanging cable that forms a loop --------------------------------------------

WIRE = sc.Section.circular(2e-3, 2.1e11, 7850.0)   # steel wire, radius 2 mm
SPAN, LENGTH = 10.0, 12.0


def hanging_wire(build="straight"):
    """The 12 m wire in 16 elements, built straight from 0 to 12 m (or hanging, with
    ``Cable.between``), pinned at 0 and at 10 m, under gravity."""
    if build == "straight":
        cable = sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], 16, WIRE, name="wire")
    else:
        cable = sc.Cable.between([0, 0, 0], [SPAN, 0, 0], LENGTH, 16, WIRE, name="wire")
    system = sc.System([cable]).pin(cable.node(0)).pin(cable.node(-1), [SPAN, 0, 0])
    return cable, system.add_gravity([0, 0, -9.81])


def inextensible_catenary(w):
    """Sag, mid-span and support tensions (m, N, N) of the inextensible catenary of
    ``LENGTH`` between supports ``SPAN`` apart at one height, weight ``w`` (N/m):
    ``LENGTH = 2 a sinh(SPAN / 2a)``, ``H = w a``."""
    from scipy.optimize import brentq

    a = brentq(lambda a: 2 * a * np.sinh(SPAN / (2 * a)) - LENGTH, 0.1, 100.0)
    sag = a * (np.cosh(SPAN / (2 * a)) - 1)
    return sag, w * a, w * (a + sag)


def measured(cable, state):
    """Sag, mid-span and support tensions of ``state``."""
    s = np.linspace(0.0, LENGTH, 193)
    sag = -cable.interpolate(state.q, s)[0][:, 2].min()
    return sag, float(state.tension(cable, LENGTH / 2)), float(state.tension(cable, 0.0))


@pytest.mark.parametrize("build", ["straight", "between"])
def test_wire_pinned_closer_than_its_length_hangs_as_the_catenary(build):
    """The wire built straight and pinned with its far end at 10 m hangs as it does when
    built hanging: ``solve_static`` starts it from its hanging shape (``Cable.hanging``,
    the catenary ``Cable.between`` builds).  Against the inextensible catenary
    (``inextensible_catenary``: sag 2.923 m, tensions 4.544 N mid-span and 7.373 N at the
    supports) within 0.5 % (sag) and 5 % (tensions: the wire's bending, EI = 2.6 N m^2,
    carries part of the weight near the supports), and against the elastica-catenary
    boundary-value problem (``analytic.elastica_catenary``, bending and stretch: 2.9275 m,
    4.352 N, 7.245 N) within 1e-3.  Measured: 2.9275 m, 4.3520 N, 7.2459 N.  Before,
    built straight: a loop in the middle elements, sag 2.632 m, 1.30 N and 7.73 N."""
    from skfem_cable.analysis.analytic import elastica_catenary
    from skfem_cable.solvers.static_states import folds

    cable, system = hanging_wire(build)
    state = sc.solve_static(system)
    sag, mid, support = measured(cable, state)
    w = WIRE.mass_per_length * 9.81
    ref = inextensible_catenary(w)
    assert ref == pytest.approx((2.9234, 4.5438, 7.3729), abs=1e-4)
    assert sag == pytest.approx(ref[0], rel=5e-3)
    assert mid == pytest.approx(ref[1], rel=5e-2) and support == pytest.approx(ref[2], rel=5e-2)
    xz, N, _, _ = elastica_catenary([0.0, LENGTH / 2], SPAN, LENGTH, w, WIRE.EA, WIRE.EI)
    assert (sag, mid, support) == pytest.approx((-xz[1, 1], N[1], N[0]), rel=1e-3)
    assert folds(system, state.q) == []


def test_a_folded_equilibrium_is_refused_by_name():
    """From the straight start (``initial=``, the old default), Newton's first load step
    converges to a state folded in the middle elements: refused, naming the cable, the
    element and what (without relaxation or bisection it is the error's reason); with
    them the continuation goes on to the hanging state.  Before: the folded state
    accepted, the wire passing through itself."""
    cable, system = hanging_wire()
    straight = sc.State(system, system.q0)
    with pytest.raises(sc.StaticConvergenceError,
                       match=r"cable 'wire' folds back in 2 element\(s\), first in element 7 "
                             r"\(s = 5.25 to 6 m\): its tangent points against"):
        sc.solve_static(system, initial=straight, relax=False, max_bisections=0)
    state = sc.solve_static(system, initial=straight)
    assert measured(cable, state) == pytest.approx((2.9275, 4.3520, 7.2459), abs=1e-3)


def test_hanging_start_leaves_cables_held_at_one_end():
    """A cable whose one end only is held (a pendulum pinned at a point off its end)
    keeps its start: ``hanging_start`` replaces a cable only when the constraints hold
    both of its ends closer than its length."""
    from skfem_cable.solvers.static_states import hanging_start

    cable = sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], 16, WIRE)
    system = sc.System([cable]).pin(cable.node(0), [1.0, 0, 0]).add_gravity([0, 0, -9.81])
    q = hanging_start(system, system.q0, 1e-9)
    np.testing.assert_array_equal(q, system.q0)
    cable, system = hanging_wire()
    q = hanging_start(system, system.q0, 1e-9)
    np.testing.assert_allclose(q, hanging_wire("between")[0].q0, atol=1e-12)


def looped(n_elements=32, radius=1.0):
    """The 12 m wire laid straight along x with a full circle of ``radius`` in the plane
    x-z in its middle (the circle spans several elements, none of which folds): its
    centre line crosses itself where the circle closes."""
    circle = 2 * np.pi * radius
    flat = (LENGTH - circle) / 2

    def curve(u):
        t = (u - flat) / radius
        on = (u > flat) & (u < flat + circle)
        x = np.where(u <= flat, u, np.where(on, flat + radius * np.sin(t), u - circle))
        z = np.where(on, radius * (1 - np.cos(t)), 0.0)
        return np.stack([x, 0 * u, z], axis=1)

    s = np.linspace(0.0, LENGTH, n_elements + 1)
    slopes = (curve(s + 1e-6) - curve(s - 1e-6)) / 2e-6
    mesh = sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], n_elements, WIRE).mesh
    return sc.Cable(mesh, WIRE, curve(s), slopes, name="looped")


def test_a_cable_through_itself_is_named():
    """A loop over several elements (none folds back): ``crossings`` names the cable and
    the two arc lengths that meet (the circle closes at s = 2.86 m and 9.14 m); the
    straight wire and the hanging one pass.  The folded state of the wire's first load
    step crosses itself too, and the refusal says so."""
    from skfem_cable.solvers.static_states import crossings, folds

    cable = looped()
    system = sc.System([cable])
    assert folds(system, system.q0) == []
    reason, = crossings(system, system.q0)
    assert reason.startswith("cable 'looped' passes through itself: its centre line at s = ")
    at = [float(v) for v in reason.split("s = ")[1:3] for v in [v.split(" m")[0]]]
    assert at == pytest.approx([LENGTH / 2 - np.pi, LENGTH / 2 + np.pi], abs=0.1)
    straight = sc.System([sc.Cable.straight([0, 0, 0], [LENGTH, 0, 0], 32, WIRE)])
    assert crossings(straight, straight.q0) == []
    cable, system = hanging_wire()
    with pytest.raises(sc.StaticConvergenceError,
                       match=r"cable 'wire' passes through itself: its centre line at s = 5"):
        sc.solve_static(system, initial=sc.State(system, system.q0), relax=False,
                        max_bisections=0)
    assert crossings(system, sc.solve_static(system).q) == []
