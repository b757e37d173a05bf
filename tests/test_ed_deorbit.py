"""A bare tether deorbiting through IGRF and IRI: the models made without an epoch take
the system's (``environment.bound_model`` in ``ElectrodynamicForce``'s bind), and the
models sampled at knots along the reference orbit (``ElectrodynamicForce(...,
sample_every=h)``, ``loads.knots``) against their evaluation at every step."""

from collections import Counter

import numpy as np
import pytest
from demo_modules import load_demo
from test_electrodynamic import librated
from test_oml_force import CALLS, SIGMA, TAPE, THICKNESS, WIDTH, Counting

import skfem_cable as sc
from skfem_cable.loads.knots import BLOCK, OrbitKnots, lagrange_weights

EPOCH = "2026-01-01T12:00:00"
ISS_LIKE = sc.Orbit(sc.MU_EARTH, sc.R_EARTH + 400e3, inclination=np.radians(51.6))


class CountingSeries(Counting):
    """``test_oml_force.Counting`` with the models' evaluations at several times."""

    def density_series(self, x, times):
        CALLS["density"] += 1
        return self.model.density_series(x, times)

    def field_series(self, x, times):
        CALLS["field"] += 1
        return self.model.field_series(x, times)


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
    (measured over a whole orbit: 2.6e-5 and 5.5e-3; at 30 s knots 2.9e-6 and 1.4e-3),
    far below the models' own accuracy (IGRF's main field leaves out crustal and
    external fields of tens of nT at 400 km, about 1e-3; IRI's topside density is good
    to some 20 %)."""
    epoch = sc.Epoch(EPOCH)
    igrf, iri = sc.environment.IGRF(epoch), sc.environment.IRI(epoch, f107=150.0)
    knots = OrbitKnots(60.0, 0.0, ISS_LIKE.position, igrf, iri)
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
          f"{knots.calls} knots")
    assert field < 1e-4 and density < 2e-2
    assert knots.calls == BLOCK                       # one call of each model


def test_a_run_with_knots_calls_the_models_once_per_block():
    """The 5 km tape in orbit for 10 steps of 28 s with knots every 60 s: the density and
    the field are called once (a block of knots ahead), not per step, and the current
    at the end is within 1e-2 of the run that evaluates them at every step (measured
    5e-5)."""
    epoch = sc.Epoch(EPOCH)
    runs = {}
    for every in (None, 60.0):
        counted = CountingSeries(sc.environment.IRI(epoch, f107=150.0))
        field = CountingSeries(sc.environment.IGRF(epoch))
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
    assert calls_knots["density"] == calls_knots["field"] == 1
    assert abs(knotted["current"] / per_step["current"] - 1) < 1e-2


def test_models_at_several_times_in_one_call():
    """``IGRF.field_series`` and ``IRI.density_series`` (the knots' blocks) against the
    models called at each time, across a UTC midnight: the field within 1e-6 (the
    coefficients at the middle time: measured 4e-8 over 15 min), the density within
    1e-12."""
    epoch = sc.Epoch("2026-01-01T23:58:00")
    igrf, iri = sc.environment.IGRF(epoch), sc.environment.IRI(epoch, f107=150.0)
    times = np.arange(4) * 60.0
    x = np.array([ISS_LIKE.position(t) + [[0.0, 0.0, 0.0], [2e3, 0.0, 0.0]]
                  for t in times])
    B, dB = igrf.field_series(x, times)
    n = iri.density_series(x, times)
    for k, t in enumerate(times):
        B_ref, dB_ref = igrf.field(x[k], t)
        assert np.abs(B[k] - B_ref).max() < 1e-6 * np.abs(B_ref).max()
        assert np.abs(dB[k] - dB_ref).max() < 1e-6 * np.abs(dB_ref).max()
        np.testing.assert_allclose(n[k], iri.density(x[k], t), rtol=1e-12)


def test_demo_follows_gauss_equation():
    """``demos/ed_tether_deorbit.py`` (OML in IGRF and IRI at 60 s knots) without drag for
    0.07 days: the altitude drop within 2 % of Gauss's equation integrated with the
    Lorentz force the run reports (measured 1.179 km against 1.178 km, 0.1 %); the
    current and the EMF positive (the tape brakes)."""
    out = load_demo("ed_tether_deorbit").main(days=0.07, drag=False)
    assert out["drop"] == pytest.approx(out["reference_drop"], rel=0.02)
    assert out["current"].min() > 0 and out["emf"].min() > 0


SCENE = """
[sections.tape]
E = 7e10
rho = 2700.0
A = 1e-6
I = 1e-12

[[cables]]
name = "tape"
section = "tape"
start = [-2500, 0, 0]
end = [2500, 0, 0]
elements = 4

[orbit]
central_body = "earth"
altitude = 400e3

[environment]
epoch = 2026-01-01T00:00:00Z
field = "igrf"
plasma = { model = "iri", f107 = 150.0 }

[[loads.electrodynamic]]
cable = "tape"
current = "oml"
cathode_drop = 10.0
load = 100.0
conductivity = 3.5e7
perimeter = 0.0401
sample_every = 60.0

[solver]
t_end = 60.0
dt = 30.0
"""


def test_scene_file_electrodynamic_load():
    """``[[loads.electrodynamic]]``: the OML current of a cable in the ``[environment]``'s
    IGRF and IRI at the file's epoch (the models' epoch the system's), its circuit as
    given; a load without ``[environment]`` plasma is refused naming it."""
    spec = sc.scene_file.loads_text(SCENE, "ed.toml")
    force = spec.system.loads[-1]
    assert force.oml.load == 100.0 and force.oml.sample_every == 60.0
    assert force.oml.cathode.voltage_drop == 10.0 and force.oml.perimeter == 0.0401
    out = force.evaluate(spec.system, spec.system.q0)
    assert out["emf"] != 0.0 and np.isfinite(out["current"])
    with pytest.raises(sc.scene_file.SceneFileError, match="needs \\[environment\\] plasma"):
        sc.scene_file.loads_text(SCENE.replace('plasma = { model = "iri", f107 = 150.0 }',
                                               ""), "ed.toml")


def test_catalog_scene_takes_the_epoch():
    """``skfem-cable run ed-deorbit --epoch ...``: the catalog's scene takes ``--epoch``
    and builds its system at it."""
    from skfem_cable.scenes.catalog import SCENES
    from skfem_cable.scenes.ed_deorbit import scene

    assert SCENES["ed-deorbit"].takes == ("epoch",)
    run = scene(epoch="2026-03-01", orbits=0.01)
    assert run.system.epoch == sc.Epoch("2026-03-01")
    assert run.settings["t_end"] == pytest.approx(0.01 * 5553.6, rel=1e-3)
