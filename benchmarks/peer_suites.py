"""The cable cases of Exudyn's and MoorDyn's own test suites, side by side: the peer's
stored number, the peer run here (when it imports), ours with the peer's law and ours
with our law (``skfem_cable.scenes.peer_suites``, ``docs/peers.md``).

The peers' models are built here with their Python APIs from the parameters of their
test files (nothing of theirs is copied); ``tests/test_peer_suites.py`` holds the numbers
this prints for the peers and checks ours against them.

Cases
-----
cantilever
    Exudyn ``TestModels/MiniExamples/ObjectANCFCable2D.py``: static tip x-displacement.
free_beam
    Exudyn ``TestModels/computeODE2EigenvaluesTest.py``: ``omega_analytic - omega_1``.
tip_load
    Exudyn ``TestModels/ANCFCableBeamDampingTest.py``, its cable part: tip displacement
    at 0.1 s under the two loads (the file stores only the sum with its beam part).
softening
    Exudyn ``TestModels/ANCFcable2DuserFunction.py``: sum of the tip's coordinates at
    0.5 s (user functions: axial stiffness softening in time, saturating moment).
pendulum
    MoorDyn ``tests/pendulum.cpp`` with ``tests/Mooring/pendulum.txt``: the period, from
    the zero crossings of the mass's x on output every 5 ms (cubic Hermite).

Examples
--------
``python benchmarks/peer_suites.py`` (all cases, under a minute once compiled),
``python benchmarks/peer_suites.py pendulum``.
"""

import argparse
import os
import tempfile

import numpy as np
from peers import import_peer, quiet

from skfem_cable.results.timeseries import period
from skfem_cable.scenes import peer_suites as ps

CASES = ("cantilever", "free_beam", "tip_load", "softening", "pendulum")

#: Exudyn's stored results (``main/pythonDev/TestModels/runTestSuiteRefSol.py``).
STORED = {"cantilever": -0.5013058140308901, "free_beam": -2.749026293713541e-11 / 1e-6,
          "softening": 0.6015588367721232}


def row(case, quantity, stored, peer, theirs, ours):
    """Print one line of the table (None: not available)."""
    cells = [f"{v:.12g}" if v is not None else "-" for v in (stored, peer, theirs, ours)]
    print(f"{case:<11} {quantity:<20} " + " ".join(f"{c:>20}" for c in cells))


# --- Exudyn's side ------------------------------------------------------------------------
def exudyn_cable(exu, n_elements, length, rho_a, EA, EI, clamp, reduced=False,
                 gravity=None, **more):
    """A straight 2-D ANCF cable of Exudyn from the origin along x: ``(mbs, nodes)``."""
    from exudyn.beams import GenerateStraightLineANCFCable2D
    from exudyn.utilities import Cable2D

    mbs = exu.SystemContainer().AddSystem()
    template = Cable2D(physicsMassPerLength=rho_a, physicsAxialStiffness=EA,
                       physicsBendingStiffness=EI, useReducedOrderIntegration=int(reduced),
                       **more)
    nodes = GenerateStraightLineANCFCable2D(
        mbs, positionOfNode0=[0, 0, 0], positionOfNode1=[length, 0, 0],
        numberOfElements=n_elements, cableTemplate=template,
        massProportionalLoad=gravity or [0, 0, 0], fixedConstraintsNode0=clamp)[0]
    return mbs, nodes


def exudyn_settings(exu, t_end, dt, zero_start=False):
    """Exudyn's settings of its tests (modified Newton, default tolerances, rho = 0.9),
    writing no solution file."""
    s = exu.SimulationSettings()
    s.timeIntegration.numberOfSteps = int(round(t_end / dt))
    s.timeIntegration.endTime = t_end
    s.timeIntegration.newton.useModifiedNewton = True
    s.timeIntegration.generalizedAlpha.computeInitialAccelerations = not zero_start
    s.timeIntegration.verboseMode = 0
    s.solutionSettings.writeSolutionToFile = False
    return s


def exudyn_tip(exu, mbs, node):
    return mbs.GetNodeOutput(node, exu.OutputVariableType.Displacement)


def peer_cantilever(exu):
    mbs, nodes = exudyn_cable(exu, 32, 2.0, 78.0, 1e6, 833.3333333333333, [1, 1, 0, 1],
                              gravity=[0, -9.81, 0])
    mbs.Assemble()
    with quiet():
        mbs.SolveStatic(exudyn_settings(exu, 1.0, 1.0))
    return exudyn_tip(exu, mbs, nodes[-1])[0]


def peer_free_beam(exu):
    E, rho, side, L = 2.07e11, 7800.0, 0.01, 2.0
    A, I = side**2, side**4 / 12
    mbs, _ = exudyn_cable(exu, 32, L, rho * A, 0.1 * E * A, E * I, [0, 0, 0, 0],
                          reduced=True)
    mbs.Assemble()
    with quiet():
        values, _ = mbs.ComputeODE2Eigenvalues(exudyn_settings(exu, 1.0, 1.0),
                                               numberOfEigenvalues=6)
    omega = (ps.BETA_1 / L) ** 2 * np.sqrt(E * I / (rho * A))
    return omega - np.sqrt(values[3])


def peer_tip_load(exu, case):
    from exudyn.utilities import LoadForceVector, MarkerNodePosition

    radius = 0.01
    area = np.pi * radius**2
    force, step = (([0, -5, 0], 4e-3), ([-100, 0, 0], 0.5e-3))[case]
    mbs, nodes = exudyn_cable(exu, 4, 0.5, 2.0, 1e8 * area, 1e8 * np.pi * radius**4 / 4,
                              [1, 1, 1, 1])
    marker = mbs.AddMarker(MarkerNodePosition(nodeNumber=nodes[-1]))
    mbs.AddLoad(LoadForceVector(markerNumber=marker, loadVector=force))
    mbs.Assemble()
    with quiet():
        mbs.SolveDynamic(exudyn_settings(exu, 0.1, step, zero_start=True))
    return exudyn_tip(exu, mbs, nodes[-1])[:2]


def peer_softening(exu):
    def axial(mbs, t, item, x, strain, strain_t, strain_ref, EA, damping, *curvature):
        return ps.softening_stiffness(t, EA) * (strain - strain_ref) + damping * strain_t

    def bending(mbs, t, item, x, kappa, kappa_t, kappa_ref, EI, damping, *strain):
        return EI * np.arctan(10 * (kappa - kappa_ref)) / 10 + damping * kappa_t

    EA, EI = 1e5, 2000.0
    mbs, nodes = exudyn_cable(exu, 16, 2.0, 78.0, EA, EI, [1, 1, 0, 1],
                              gravity=[0, -9.81, 0], physicsAxialDamping=0.05 * EA,
                              physicsBendingDamping=0.1 * EI,
                              axialForceUserFunction=axial,
                              bendingMomentUserFunction=bending)
    mbs.Assemble()
    with quiet():
        mbs.SolveDynamic(exudyn_settings(exu, 0.5, 5e-3))
    return float(np.sum(mbs.GetNodeOutput(nodes[-1], exu.OutputVariableType.Position)))


def exudyn_cases(exu, wanted):
    """Rows of the ``wanted`` Exudyn cases: (case, quantity, stored, peer, theirs, ours)."""
    peer = (lambda fn, *a: fn(exu, *a)) if exu else (lambda fn, *a: None)
    if "cantilever" in wanted:
        yield ("cantilever", "tip u_x (m)", STORED["cantilever"], peer(peer_cantilever),
               ps.exudyn_cantilever(), ps.exudyn_cantilever(law="cable", quadrature=None))
    if "free_beam" in wanted:
        yield ("free_beam", "u (rad/s)", STORED["free_beam"], peer(peer_free_beam),
               ps.exudyn_free_beam()[0],
               ps.exudyn_free_beam(law="cable", quadrature=None)[0])
    for case in (0, 1) if "tip_load" in wanted else ():
        ours = ps.exudyn_tip_load(case, law="cable", quadrature=None)
        theirs = ps.exudyn_tip_load(case)
        live = peer(peer_tip_load, case)
        for k, axis in enumerate("xy"):
            yield (f"tip_load {case}", f"tip u_{axis} (m)", None,
                   None if live is None else live[k], theirs[k], ours[k])
    if "softening" in wanted:
        yield ("softening", "sum of tip (m)", STORED["softening"], peer(peer_softening),
               ps.exudyn_softening()[0], None)


# --- MoorDyn's side -----------------------------------------------------------------------
PENDULUM_INPUT = """MoorDyn input: the pendulum of MoorDyn's tests/pendulum.cpp
-------------------------- LINE TYPES ----------------------------------
TypeName Diam Mass/m EA BA/-zeta EI Cd Ca CdAx CaAx
(-) (m) (kg/m) (N) (N-s/-) (N-m^2) (-) (-) (-) (-)
main 0.1 7.85398 1.0E9 -0.01 0 0 0 0 0
------------------------ POINT PROPERTIES ------------------------------
ID Type X Y Z Mass Volume CdA Ca
(#) (-) (m) (m) (m) (kg) (m^3) (m^2) (-)
1 Fixed 0 0 0 0 0 0 0
2 Free 10 0 -100 1E5 0 0 0
----------------------------- LINES ------------------------------------
ID LineType AttachA AttachB UnstrLen NumSegs LineOutputs
(#) (name) (#) (#) (m) (-) (-)
1 main 1 2 100.5 20 -
----------------------------- OPTIONS ----------------------------------
0 writeLog
0.1 cfl
RK4 tScheme
1000.0 WtrDnsty
500 WtrDpth
1.0 dtIC
10000.0 TmaxIC
1e-4 threshIC
0 ICgenDynamic
1 disableOutTime
------------------------- need this line -------------------------------
"""


def peer_pendulum(md, t_end=106.6, dt=0.005):
    """MoorDyn's period of the pendulum (s), from output every ``dt``."""
    with tempfile.TemporaryDirectory() as tmp, quiet():
        path = os.path.join(tmp, "pendulum.txt")
        with open(path, "w") as f:
            f.write(PENDULUM_INPUT)
        system = md.Create(path)
        md.Init(system, [], [])
        point = md.GetPoint(system, 2)
        n = int(round(t_end / dt))
        t = np.arange(n + 1) * dt
        x, v = np.empty(n + 1), np.empty(n + 1)
        x[0], v[0] = md.GetPointPos(point)[0], md.GetPointVel(point)[0]
        for k in range(n):
            md.Step(system, [], [], t[k], dt)
            x[k + 1], v[k + 1] = md.GetPointPos(point)[0], md.GetPointVel(point)[0]
        md.Close(system)
    return period(t, x, v)


def moordyn_cases(md):
    yield ("pendulum", "period (s)", None, peer_pendulum(md) if md else None,
           ps.moordyn_pendulum(), ps.moordyn_pendulum(law="truss"))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("cases", nargs="*", metavar="case",
                        help=f"any of {', '.join(CASES)} (default: all)")
    parser.add_argument("--quick", action="store_true", help="the same (all are short)")
    args = parser.parse_args(argv)
    args.cases = args.cases or list(CASES)
    unknown = set(args.cases) - set(CASES)
    if unknown:
        parser.error(f"unknown case {sorted(unknown)[0]!r}: choose from {', '.join(CASES)}")
    print(f"{'case':<11} {'quantity':<20} {'stored':>20} {'peer here':>20} "
          f"{'ours, their law':>20} {'ours, our law':>20}")
    rows = []
    if set(args.cases) - {"pendulum"}:
        rows += list(exudyn_cases(import_peer("exudyn"), args.cases))
    if "pendulum" in args.cases:
        rows += list(moordyn_cases(import_peer("moordyn")))
    for r in rows:
        row(*r)


if __name__ == "__main__":
    main()
