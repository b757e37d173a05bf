"""Line-to-surface contact, second step (issue 49; ``docs/contact.md``): a contact that
works where its damping is below critical says so (the Atwood machine with a stiff rope),
and the broad phase skips the elements far from the surface."""

import warnings

import numpy as np
import pytest
from atwood import assert_follows_the_closed_form, atwood

import skfem_cable as sc
from skfem_cable.loads.surface_broad_phase import ContactDampingWarning
from skfem_cable.scenes.capstan import ROPE, R, capstan


def stiff_atwood():
    """The Atwood machine of ``test_contact.py`` with a rope ten times stiffer (EA = 1e6
    N) and the default contact: ``(system, cable)``."""
    return atwood(E=1.27e10)


def test_a_stiff_rope_on_a_drum_says_it_is_under_damped():
    """The stiff rope works at ``p = 0.12 p_0``, where the normal damping is 0.66 of
    critical: at ``rho_inf = 0.8`` (dt = 5e-3 s) the run warns (``ContactDampingWarning``,
    after 50 steps that shallow) -- unwarned, its rope bounced off the drum from 0.55 s
    and m1 fell 15 % short at 1 s (``docs/contact.md``)."""
    system, _ = stiff_atwood()
    with pytest.warns(ContactDampingWarning, match="of the onset"):
        sc.simulate(system, t_end=0.3, dt=5e-3, every=10)


def test_atwood_machine_with_a_stiff_rope_at_rho_inf_zero():
    """The same at ``rho_inf = 0`` (what the warning asks): m1 falls as the closed form
    of ``test_contact.py`` says, within 1 % over 0.2 .. 1 s and in its speed at 1 s, the
    drum carries the rope throughout (37.3 N within 2 %), and no warning."""
    system, cable = stiff_atwood()
    with warnings.catch_warnings():
        warnings.simplefilter("error", ContactDampingWarning)
        result = sc.simulate(system, t_end=1.0, dt=5e-3, every=4, rho_inf=0.0)
    assert_follows_the_closed_form(system, cable, result)
    contact = system.loads[-1]
    carried = [contact.forces(result.state(i))["normal"].sum()
               for i in np.flatnonzero(result.t >= 0.1 - 1e-9)[::5]]
    assert np.array(carried) == pytest.approx(37.3, rel=2e-2)


def test_the_broad_phase_skips_what_is_far_and_changes_nothing():
    """The capstan (mu = 0.3) over 0.15 s with and without the broad phase: the same
    motion (to 1e-9 of the rope's length) and the same friction; the broad phase skips
    the elements of the legs far from the drum.  A drum 100 m away: every element is
    skipped at every step, and the run is that of the rope without contact."""
    runs = {}
    for broad in (False, True):
        system, cable, contact = capstan(0.3)
        system.loads[-1].broad_phase = broad
        runs[broad] = (sc.simulate(system, t_end=0.15, dt=1e-3, every=50), contact)
    (off, _), (on, contact) = runs[False], runs[True]
    assert np.abs(on.q - off.q).max() < 1e-9 * cable.length
    assert contact.broad.skipped > 0
    far = sc.Cylinder([0, 100, 0], [0, 0, 1], R)
    system, cable, _ = capstan(0.3)
    system.loads[-1].surface = far
    result = sc.simulate(system, t_end=0.05, dt=1e-3)
    broad = system.loads[-1].broad
    assert broad.skipped == cable.mesh.t.shape[1] * result.stats["steps"]


def test_a_damping_below_critical_is_reported():
    """A contact made with a damping below critical on its penalty (none, here) warns,
    naming the critical value; the default does not."""
    cable = sc.Cable.straight([0, 4e-3, 0], [1, 4e-3, 0], 2, ROPE)
    plane = sc.Plane([0, 0, 0], [0, 1, 0])
    with pytest.warns(ContactDampingWarning, match="below the critical"):
        sc.System([cable]).contact(cable, plane, damping=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error", ContactDampingWarning)
        sc.System([cable]).contact(cable, plane)
