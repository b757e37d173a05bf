"""Rods (``docs/rods.md``): two of PyElastica's example cases rebuilt here, and the cost of
the rod's compiled step against the cable's.

* **PyElastica's Timoshenko cantilever** (its ``examples/TimoshenkoBeamCase``, Gazzola et
  al., *R. Soc. open sci.* 5 (2018) 171628, Sect. 3.4.3): a rod of length 3 m, radius
  0.25 m, ``E = 1e6`` Pa, density 5000 kg/m^3, clamped at one end, a transverse dead load
  of 15 N at the other, in its shear-stiff variant (``G = E / 0.3``, the example's
  "unshearable" rod).  PyElastica (its Cosserat rod, 100 elements, ``PositionVerlet``,
  its ``AnalyticalLinearDamper`` of the example, the load ramped over half the run)
  relaxes to the static state in time; we solve the static state (``solve_static``) of a
  ``sc.Rod``.  Each tip deflection is compared with its model's closed form: ours with
  the inextensible elastica (Bisshopp & Drucker 1945, ``analysis.analytic``), PyElastica's
  with the linear Timoshenko beam its example plots (``F L^3 / 3 EI + F L / (4/3 G A)``).
  Our time is that of the coarsest mesh at least as accurate as PyElastica; both CPU
  times, minimum of repeats.  The example's step ``0.07 dl`` diverges for the shear-stiff
  rod in PyElastica 1.0 (its shear waves: ``sqrt(G / rho) dt / dl = 1.8``); the older
  example's ``0.01 dl`` is used.  PyElastica runs only when importable (``pip install
  pyelastica``, the ``peers`` extra).
* **PyElastica's axial stretching** (its ``examples/AxialStretchingCase``): a rod of 1 m,
  radius 0.025 m, ``E = 1e4`` Pa, density 1000 kg/m^3, 19 elements, clamped, pulled by 1
  N at its tip (a strain of 5 %), relaxed by PyElastica over its example's 200 s (``dt =
  0.1 dl``, ``AnalyticalLinearDamper`` 0.1).  Its closed form is the example's "improved"
  ``F L / (EA - F)``, the static answer of its axial law ``n = EA (1 - 1 / |r'|)``; the
  same law written as a ``cable_law`` (``W = EA (|r'| - 1 - ln |r'|) + EI kappa^2 / 2``,
  ``COSSERAT_AXIAL``) gives our rod's static state, beside our default Green-strain law
  (``lambda (lambda^2 - 1) / 2 = F / EA``).
* **The compiled step, rod against cable**: a 10 m aluminium tape (2 cm x 50 um) of 64
  elements pinned at one end, released horizontally under gravity, ``dt = 1 ms``, 500
  steps, as a ``sc.Rod`` and as a ``sc.Cable`` of the same section: CPU time of each run
  (minimum of 5 repeats), their ratio and the rod kernel's own cost per evaluation with
  and without its tangent.

Run ``python benchmarks/rods.py [--quick]`` (``--quick``: PyElastica relaxes over a tenth
of the examples' times, far from static; fewer repeats).  About two minutes of CPU, most
of it PyElastica's cantilever.
"""

import time

import numpy as np

import skfem_cable as sc
from skfem_cable.analysis.analytic import elastica_tip_load
from skfem_cable.cli.bench import arguments
from skfem_cable.kernels import rod as rod_kernel
from skfem_cable.laws.law import cable_law
from skfem_cable.laws.symbolic import kappa2, log, norm

#: PyElastica's Timoshenko cantilever: length, radius, E, density, tip load, G (shear-stiff).
LENGTH, RADIUS, E, DENSITY, LOAD = 3.0, 0.25, 1e6, 5000.0, 15.0
G = E / (1.0 - 0.7)
TAPE = sc.Section.tape(0.02, 50e-6, E=7e10, rho=2700.0)


def cpu_time(function, repeats):
    """The least CPU time (s) of ``repeats`` calls of ``function()`` and its last value."""
    best, value = np.inf, None
    for _ in range(repeats):
        start = time.process_time()
        value = function()
        best = min(best, time.process_time() - start)
    return best, value


# --- the Timoshenko cantilever ----------------------------------------------------------------
def cantilever_exact():
    """Tip deflection (m) of the inextensible elastica of the case."""
    EI = E * np.pi * RADIUS**4 / 4
    return LENGTH * elastica_tip_load(LOAD * LENGTH**2 / EI)[1]


def cantilever_ours(n_elements):
    """Tip deflection (m) of the static state of the case as a ``sc.Rod``."""
    rod = sc.Rod.straight([0, 0, 0], [0, 0, LENGTH], n_elements,
                          sc.Section.circular(RADIUS, E, DENSITY, G=G), normal=[0, 1, 0])
    system = sc.System([rod]).clamp(rod.node(0)).add_point_load(rod.node(-1),
                                                                [-LOAD, 0.0, 0.0])
    q = sc.solve_static(system).q[system.dofs(rod)]
    return -q[rod.n_centreline - 6]


def cantilever_elastica(ea, final_time, n_elements=100):
    """PyElastica's run of the case (module ``ea``): its tip deflection (m), the linear
    Timoshenko tip deflection of its rod, the shear part of it and the CPU time (s) of
    its time loop."""

    class Simulator(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping):
        pass

    simulator = Simulator()
    area = np.pi * RADIUS**2
    rod = ea.CosseratRod.straight_rod(n_elements, np.zeros(3), np.array([0.0, 0.0, 1.0]),
                                      np.array([0.0, 1.0, 0.0]), LENGTH, RADIUS, DENSITY,
                                      youngs_modulus=E, shear_modulus=G)
    simulator.append(rod)
    dt = 0.01 * LENGTH / n_elements
    simulator.dampen(rod).using(ea.AnalyticalLinearDamper,
                                damping_constant=0.1 / 7 / DENSITY / area, time_step=dt)
    simulator.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,),
                                   constrained_director_idx=(0,))
    force = np.array([-LOAD, 0.0, 0.0])
    simulator.add_forcing_to(rod).using(ea.EndpointForces, 0.0 * force, force,
                                        ramp_up_time=final_time / 2)
    simulator.finalize()
    stepper, t = ea.PositionVerlet(), 0.0
    start = time.process_time()
    for _ in range(int(final_time / dt)):
        t = stepper.step(simulator, t, dt)
    cpu = time.process_time() - start
    shear = LOAD * LENGTH / rod.shear_matrix[0, 0, 0]
    linear = LOAD * LENGTH**3 / (3 * rod.bend_matrix[0, 0, 0]) + shear
    return -rod.position_collection[0, -1], linear, shear, cpu


def cantilever_table(final_time, repeats):
    """Print ours per mesh and PyElastica's run; returns the rows and the time ratio."""
    exact = cantilever_exact()
    print(f"Timoshenko cantilever (PyElastica's case, G = E / 0.3): elastica tip "
          f"deflection {exact:.9f} m")
    print(f"{'code':>12s}{'elements':>10s}{'tip (m)':>14s}{'rel. error':>12s}{'CPU s':>10s}")
    rows = []
    for n in (1, 2, 4, 8, 16):
        cpu, tip = cpu_time(lambda n=n: cantilever_ours(n), repeats)
        rows.append({"code": "skfem_cable", "elements": n, "tip": tip,
                     "error": abs(tip / exact - 1), "cpu_s": cpu})
    try:
        import elastica
    except ImportError:
        elastica = None
        print("elastica not importable: skipped")
    ratio = None
    if elastica is not None:
        tip, linear, shear, cpu = cantilever_elastica(elastica, final_time)
        peer = {"code": "pyelastica", "elements": 100, "tip": tip, "shear": shear,
                "error": abs(tip / linear - 1), "cpu_s": cpu, "final_time": final_time}
        rows.append(peer)
        match = next((r for r in rows[:-1] if r["error"] <= peer["error"]), rows[-2])
        ratio = peer["cpu_s"] / match["cpu_s"]
    for r in rows:
        print(f"{r['code']:>12s}{r['elements']:10d}{r['tip']:14.9f}{r['error']:12.2e}"
              f"{r['cpu_s']:10.3f}")
    if ratio is not None:
        print(f"PyElastica's tip less its shear deflection {shear:.3g} m against ours "
              f"(16 elements): {(tip - shear) / rows[-2]['tip'] - 1:.2e}; its CPU time / "
              f"ours at equal accuracy ({match['elements']} elements): {ratio:.0f}x")
    return {"rows": rows, "time_ratio": ratio}


# --- the axial stretching --------------------------------------------------------------------
#: PyElastica's axial stretching: length, radius, E, density, tip load, elements.
BAR = {"L": 1.0, "r": 0.025, "E": 1e4, "rho": 1000.0, "F": 1.0, "n": 19}


@cable_law(name="cosserat-axial")
def COSSERAT_AXIAL(a, b, EA, EI):
    """PyElastica's axial law ``n = EA (1 - 1 / |a|)`` (static: ``F L / (EA - F)``) and
    the cable's bending, ``W = EA (|a| - 1 - ln |a|) + EI kappa^2 / 2``."""
    stretch = norm(a)
    return EA * (stretch - 1 - log(stretch)) + EI * kappa2(a, b) / 2


def stretching_ours(law):
    """Tip displacement (m) of the static state of the bar as a ``sc.Rod`` of ``law``."""
    section = sc.Section.circular(BAR["r"], BAR["E"], BAR["rho"], G=BAR["E"] / 1.5)
    rod = sc.Rod.straight([0, 0, 0], [BAR["L"], 0, 0], BAR["n"], section, normal=[0, 1, 0],
                          law=law)
    system = sc.System([rod]).clamp(rod.node(0)).add_point_load(rod.node(-1),
                                                                [BAR["F"], 0.0, 0.0])
    return sc.solve_static(system).q[system.dofs(rod)][rod.n_centreline - 6] - BAR["L"]


def stretching_elastica(ea, final_time):
    """PyElastica's run of the bar (module ``ea``): tip displacement (m), CPU time (s)."""

    class Simulator(ea.BaseSystemCollection, ea.Constraints, ea.Forcing, ea.Damping):
        pass

    simulator = Simulator()
    rod = ea.CosseratRod.straight_rod(BAR["n"], np.zeros(3), np.array([1.0, 0.0, 0.0]),
                                      np.array([0.0, 1.0, 0.0]), BAR["L"], BAR["r"],
                                      BAR["rho"], youngs_modulus=BAR["E"],
                                      shear_modulus=BAR["E"] / 1.5)
    simulator.append(rod)
    steps = int(final_time / (0.1 * BAR["L"] / BAR["n"]))
    dt = final_time / steps
    simulator.dampen(rod).using(ea.AnalyticalLinearDamper, damping_constant=0.1,
                                time_step=dt)
    simulator.constrain(rod).using(ea.OneEndFixedBC, constrained_position_idx=(0,),
                                   constrained_director_idx=(0,))
    force = np.array([BAR["F"], 0.0, 0.0])
    simulator.add_forcing_to(rod).using(ea.EndpointForces, 0.0 * force, force,
                                        ramp_up_time=1e-2)
    simulator.finalize()
    stepper, t = ea.PositionVerlet(), 0.0
    start = time.process_time()
    for _ in range(steps):
        t = stepper.step(simulator, t, dt)
    return rod.position_collection[0, -1] - BAR["L"], time.process_time() - start


def stretching_table(final_time, repeats):
    """Print each answer against its law's closed form; returns the rows."""
    EA = BAR["E"] * np.pi * BAR["r"] ** 2
    ratio = BAR["F"] / EA
    cosserat = BAR["F"] * BAR["L"] / (EA - BAR["F"])
    stretch = np.roots([1.0, 0.0, -1.0, -2 * ratio])
    green = BAR["L"] * (stretch[np.argmin(abs(stretch - 1))].real - 1)
    print(f"axial stretching (PyElastica's case, F / EA = {ratio:.4f}): F L / (EA - F) = "
          f"{cosserat:.9f} m, Green strain {green:.9f} m")
    print(f"{'code (law)':>24s}{'tip (m)':>14s}{'rel. error':>12s}{'CPU s':>10s}")
    rows = []
    for name, law, exact in (("skfem_cable (cosserat)", COSSERAT_AXIAL, cosserat),
                             ("skfem_cable (cable)", "cable", green)):
        stretching_ours(law)  # compile the law outside the timing
        cpu, tip = cpu_time(lambda law=law: stretching_ours(law), repeats)
        rows.append({"code": name, "tip": tip, "error": abs(tip / exact - 1), "cpu_s": cpu})
    try:
        import elastica
    except ImportError:
        elastica = None
        print("elastica not importable: skipped")
    if elastica is not None:
        tip, cpu = stretching_elastica(elastica, final_time)
        rows.append({"code": "pyelastica", "tip": tip, "error": abs(tip / cosserat - 1),
                     "cpu_s": cpu})
    for r in rows:
        print(f"{r['code']:>24s}{r['tip']:14.9f}{r['error']:12.2e}{r['cpu_s']:10.3f}")
    if elastica is not None:
        ratio = rows[-1]["cpu_s"] / rows[0]["cpu_s"]
        print(f"PyElastica's CPU time / ours (same law, more accurate): {ratio:.0f}x")
    return rows


# --- the compiled step, rod against cable --------------------------------------------------------
def pinned_tape(kind, n_elements=64):
    """The tape of the step comparison as a ``"rod"`` or a ``"cable"``, and its system."""
    ends = ([0, 0, 0], [10, 0, 0], n_elements, TAPE)
    body = sc.Rod.straight(*ends, normal=[0, 0, 1]) if kind == "rod" else sc.Cable.straight(*ends)
    return body, sc.System([body]).pin(body.node(0)).add_gravity([0, 0, -9.81])


def kernel_cost(rod, repeats, calls=200):
    """The rod kernel's least CPU time (us) per evaluation with and without its tangent,
    at a perturbed state of ``rod``."""
    edofs = np.concatenate([rod.element_dofs, rod.twist_element_dofs], axis=1)
    pack = rod.kernel_pack(edofs, *rod.initial_frames())
    q = rod.q0 + 1e-2 * np.random.default_rng(0).standard_normal(rod.n_dofs)
    ne = edofs.shape[0]
    index = np.arange(ne * 256).reshape(ne, 16, 16)
    costs = []
    for size in (ne * 256, 0):
        zeros = [np.zeros_like(q) for _ in range(4)]
        ev = (q, zeros[0], np.ones(3), *zeros[1:], np.zeros(size), np.zeros(3), np.zeros(3))
        rod_kernel.kernel(pack, index, ev)

        def evaluate(ev=ev):
            for _ in range(calls):
                rod_kernel.kernel(pack, index, ev)

        costs.append(1e6 * cpu_time(evaluate, repeats)[0] / calls)
    return costs


def step_table(steps, repeats):
    """Print the CPU time of the tape's run as a rod and as a cable and their ratio."""
    times = {}
    for kind in ("rod", "cable"):
        body, system = pinned_tape(kind)
        sc.simulate(system, t_end=0.01, dt=1e-3)  # compile outside the timing
        times[kind], result = cpu_time(
            lambda system=system: sc.simulate(system, t_end=steps * 1e-3, dt=1e-3), repeats)
        times[kind + "_newton"] = result.stats["newton"]
    tangent, residual = kernel_cost(pinned_tape("rod")[0], repeats)
    ratio = times["rod"] / times["cable"]
    print(f"tape 10 m x 2 cm x 50 um, 64 elements, pinned, {steps} steps of 1 ms, CPU s "
          f"(min of {repeats}): rod {times['rod']:.3f} ({times['rod_newton']} Newton), "
          f"cable {times['cable']:.3f} ({times['cable_newton']} Newton), ratio {ratio:.2f}")
    print(f"rod kernel per evaluation: {tangent:.0f} us with its tangent, {residual:.0f} us "
          "without")
    return {**times, "ratio": ratio, "kernel_tangent_us": tangent, "kernel_residual_us": residual}


def main(argv=None):
    """Parse the arguments (``--quick``), print both tables and return their figures."""
    args = arguments(__doc__, "PyElastica over a tenth of the time, 2 repeats", argv)
    repeats = 2 if args.quick else 5
    return {"step": step_table(500, repeats),
            "stretching": stretching_table(20.0 if args.quick else 200.0, repeats),
            "cantilever": cantilever_table(50.0 if args.quick else 500.0, repeats)}


if __name__ == "__main__":
    main()
