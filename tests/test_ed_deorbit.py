"""A bare tether deorbiting through IGRF and IRI: the models made without an epoch take
the system's (``environment.bound_model`` in ``ElectrodynamicForce``'s bind), and the
models sampled at knots along the reference orbit (``ElectrodynamicForce(...,
sample_every=h)``, ``loads.knots``) against their evaluation at every step."""

from collections import Counter

import numpy as np
from test_electrodynamic import librated
from test_oml_force import CALLS, SIGMA, TAPE, THICKNESS, WIDTH, Counting

import skfem_cable as sc
from skfem_cable.loads.knots import OrbitKnots, lagrange_weights

EPOCH = "2026-01-01T12:00:00"
ISS_LIKE = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3, inclination=np.radians(51.6))


def tape_force(field, plasma, **options):
    return lambda c: sc.ElectrodynamicForce(
        c, "oml", field, plasma=plasma, cathode=sc.Cathode(10.0), load=100.0,
        conductivity=SIGMA, perimeter=2 * (WIDTH + THICKNESS), **options)


def in_orbit(load, epoch=EPOCH):
    """``test_oml_force.dumbbell``'s 5 km tape between two 500 kg masses, in the orbit
    ``ISS_LIKE`` at ``epoch``, carrying ``load(cable)``."""
    cable = sc.Cable.straight([-2500.0, 0, 0], [2500.0, 0, 0], 4, TAPE)
    system = (sc.System([cable]).add_point_mass(cable.node(0), 500.0)
              .add_point_mass(cable.node(-1), 500.0).add_orbit(ISS_LIKE, epoch=epoch))
    return cable, system.add_load(load(cable))


def test_models_without_an_epoch_take_the_systems():
    """``IGRF()`` and ``IRI()`` made without an epoch, in a system with one: the OML
    force (and a short-circuit current in the same field) equal those of the models
    made with the system's epoch; the user's models are left without one."""
    igrf, iri = sc.environment.IGRF(), sc.environment.IRI(f107=150.0)
    _, bare = in_orbit(tape_force(igrf, iri))
    _, dated = in_orbit(tape_force(sc.environment.IGRF(EPOCH),
                                   sc.environment.IRI(EPOCH, f107=150.0)))
    q = librated(bare, 0.1).q
    a, b = (s.loads[-1].evaluate(s, q, t=30.0) for s in (bare, dated))
    print(f"I(0) = {a['current']:.4f} A, EMF = {a['emf']:.1f} V")
    assert a["current"] > 0 and a["current"] == b["current"] and a["emf"] == b["emf"]
    assert igrf.epoch is None and iri.epoch is None
    emf = [sc.ElectrodynamicForce(system.bodies[0], "short-circuit", field,
                                  resistance=1e3).evaluate(system, q, t=30.0)["emf"]
           for field, system in ((igrf, bare), (sc.environment.IGRF(EPOCH), dated))]
    assert emf[0] == emf[1] and emf[0] > 0


def test_lagrange_weights_are_exact_for_cubics():
    u = 0.37
    knots = np.array([-1.0, 0.0, 1.0, 2.0])
    for p in (lambda x: 1 + 0 * x, lambda x: x, lambda x: x**3 - 2 * x**2):
        assert abs(lagrange_weights(u) @ p(knots) - p(u)) < 1e-14


def test_knots_against_the_models_at_every_time():
    """IGRF and IRI at knots every 60 s along a 400 km, 51.6 deg orbit, carried to a 5 km
    vertical tether's points by their gradients, against the models at the points, at 11
    times over 600 s: the field within 1e-4 and the density within 2e-2 relative
    (measured over a whole orbit: 2.6e-5 and 7.1e-3; at 30 s knots 2.9e-6 and 1.6e-3),
    far below the models' own accuracy (IGRF's main field leaves out crustal and
    external fields of tens of nT at 400 km, about 1e-3; IRI's topside density is good
    to some 20 %)."""
    epoch = sc.Epoch(EPOCH)
    igrf, iri = sc.environment.IGRF(epoch), sc.environment.IRI(epoch, f107=150.0)
    knots = OrbitKnots(60.0, 0.0, ISS_LIKE.position, igrf.field, iri)
    s = np.linspace(-2500.0, 2500.0, 10)
    errors = []
    for t in np.linspace(7.0, 607.0, 11):
        R = ISS_LIKE.position(t)
        X = R + s[:, None] * R / np.linalg.norm(R)
        B, _, n = knots.at(X, t)
        B_ref = igrf.field(X, t)[0]
        errors.append((np.max(np.linalg.norm(B - B_ref, axis=1)
                              / np.linalg.norm(B_ref, axis=1)),
                       np.max(np.abs(n / iri.density(X, t) - 1))))
    field, density = np.max(errors, axis=0)
    print(f"knots every 60 s: field {field:.2e}, density {density:.2e}, "
          f"{knots.calls} knots for 11 times")
    assert field < 1e-4 and density < 2e-2
    assert knots.calls == 14


def test_a_run_with_knots_calls_the_models_once_per_knot():
    """The 5 km tape in orbit for 10 steps of 28 s with knots every 60 s: the density and
    the field are called once per knot (7 points each), not per step, and the current
    at the end is within 1e-2 of the run that evaluates them at every step."""
    epoch = sc.Epoch(EPOCH)
    runs = {}
    for every in (None, 60.0):
        counted = Counting(sc.environment.IRI(epoch, f107=150.0))
        field = Counting(sc.environment.IGRF(epoch))
        _, system = in_orbit(tape_force(field, counted, sample_every=every))
        start = librated(system, 0.1)
        CALLS.clear()
        result = sc.simulate(system, t_end=280.0, dt=28.0, initial=start)
        runs[every] = (Counter(CALLS), system.loads[-1].outputs(result),
                       result.stats["steps"] + result.stats["rejected"])
    (calls_step, per_step, attempts), (calls_knots, knotted, _) = runs[None], runs[60.0]
    print(f"per step {dict(calls_step)}, knots {dict(calls_knots)}, "
          f"I(0) {per_step['current']:.4f} against {knotted['current']:.4f} A")
    assert calls_step["density"] >= attempts
    assert calls_knots["density"] == calls_knots["field"] <= 280.0 / 60.0 + 4
    assert abs(knotted["current"] / per_step["current"] - 1) < 1e-2
