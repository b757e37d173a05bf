"""Attitude hold of the E-sail around the Sun (``scenes.esail_attitude``): a short piece
of the five-day study of ``demos/esail_attitude_hold.py``.  Without control the sailing
angle drifts with the orbit's turn (``Omega`` = 1.99e-7 rad/s, 0.30 deg in 0.3 days); the
phase-synchronous modulation holds it."""

import numpy as np
import pytest

from skfem_cable.scenes.esail_attitude import hold_sail_angle
from skfem_cable.space.constants import AU, MU_SUN

DAYS = 0.3
#: Steps of 10 s (the scene's default 1 s; the controller samples every 10 s, now at
#: every step), saved every 600 s as by default: the numbers checked move by at most a
#: seventh of their tolerances (in the docstring below, after those of 5 and 1 s steps).
DT, EVERY = 10.0, 60


def test_the_free_sail_drifts_with_the_orbit_and_the_controlled_one_holds():
    """The free sail over half of ``DAYS`` (its drift the orbit's turn to 1.7 % there; 1.6
    % at steps of 5 s, 1.1 % at 1 s); the controlled one over ``DAYS`` (its largest error
    0.139 of the turn, 0.142 at 5 s, 0.140 at 1 s; over half, 0.239 of the half turn at
    5 and 1 s: the hold's transient needs the whole span)."""
    rate = np.degrees(np.sqrt(MU_SUN / AU**3)) * 86400.0  # deg per day
    free = hold_sail_angle(30.0, DAYS / 2, controlled=False, dt=DT, every=EVERY)
    assert 30.0 - free["sail_angle"][-1] == pytest.approx(rate * DAYS / 2, rel=0.05)
    turn = rate * DAYS
    held = hold_sail_angle(30.0, DAYS, controlled=True, dt=DT, every=EVERY)
    assert held["result"].stats["path"] == "compiled"
    assert np.abs(held["sail_angle"] - 30.0).max() < 0.2 * turn
    voltages = held["result"].inputs["voltages"]
    assert voltages.min() > 0 and voltages.max() < 2 * 20e3  # the modulation stays in range
