"""The test session's set-up: what the suite's processes share, and the order of its files.

``python3 tasks.py test`` runs the suite on every core (pytest-xdist, ``--dist loadfile``:
a file's tests on one worker).  Six things here keep that fast from a cold kernel cache:

* **One package for every process.**  Tests that start Python processes (the CLI under a
  signal, the dask workers of a sweep) import ``skfem_cable`` from this checkout: its
  folder leads ``PYTHONPATH``.  Otherwise a process started outside the checkout imports
  whatever ``skfem_cable`` the environment installed (another worktree's, in an editable
  install made elsewhere), tests that code instead of this one, and compiles its kernels
  again into a cache of their own (numba's cache is per source folder).
* **No fsync.**  The suite's faults are killed processes, never power cuts: its writes
  skip ``fsync`` (``SKFEM_CABLE_FSYNC=0``, ``util.atomic.durable``; ``tests/test_faults.py``
  alone made 11,067 calls, 6.0 s of system time).
* **One BLAS thread.**  A process's OpenBLAS (numpy's and scipy's) starts a thread per core
  at import, which spin while they wait for work: with two workers on two cores they
  only burn CPU (``OPENBLAS_NUM_THREADS=1`` unless set, as the benchmarks' timed processes
  run; eight files of 275 tests in one process: 31.3 -> 28.1 CPU s, a ``skfem-cable run``
  child 1.72 -> 1.60, the 12 x 5 sail's 804 eigenvalues (``esail.spinning_modes``) 0.27 s
  on one thread against 1.4-5.7 s on two on a loaded machine; minimum of repeats).  The
  package's own threads are one unless asked (``SKFEM_CABLE_THREADS``).
* **The longest files first.**  xdist hands out the files in the order of its collection
  (``--loadscope-reorder``, its default, would sort them by their number of tests, which
  sent the few long E-sail runs last, onto one worker while the other waited).
  ``LONGEST`` names the files that took longest on a cold cache; they start first, the
  rest follow in alphabetical order, so that the last files handed out are short and the
  two workers end together.
* **A collection without garbage collections.**  Every worker imports every test file:
  it does so with the cyclic garbage collector off, and freezes what it imported
  (``pytest_collection``), which the tests' collections then leave alone.
* **A quick exit.**  At its end a process freezes what the tests left (``gc.freeze`` in
  ``pytest_unconfigure``): the interpreter's exit then frees it without its garbage
  collections walking every object of the package, numba and sympy again (``skfem-cable``
  does the same).
"""

import gc
import os
from pathlib import Path

import pytest

#: ``SKFEM_CABLE_COMPILE_LOG=DIR``: what numba compiles, test by test (``compile_recorder``).
pytest_plugins = ["compile_recorder"]

ROOT = Path(__file__).resolve().parents[1]

#: The test files that took longest on a cold kernel cache, longest first (CPU seconds of
#: their worker, ``SKFEM_CABLE_COMPILE_LOG``'s records of a run from an empty cache, and
#: of the processes they start; the sweep's, whose work is in its dask workers, after
#: them); then those of 3.5 s or more on a cold or a warm cache that the first list
#: leaves out, longest first (warm, their run time is most of the suite's: one of them
#: handed out last kept a worker 11 s after the other).  ``python
#: benchmarks/compile_cost.py --suite DIR`` prints when each worker ended: they should
#: end together, warm and cold.
LONGEST = (
    "test_laws.py", "test_contact.py", "test_esail_orbit.py", "test_elements.py",
    "test_peer_suites.py", "test_benchmarks.py", "test_mission.py",
    "test_contact_woodbury.py", "test_esail_baseline.py", "test_faults_records.py",
    "test_demos.py", "test_extending.py", "test_faults_round_three_cli.py",
    "test_contact_lines.py", "test_ed_deorbit.py", "test_two_level_schur.py",
    "test_esail_floor.py", "test_faults_round_two.py", "test_bench_guard.py",
    "test_body_surfaces.py", "test_line_bodies.py", "test_rods_coupling.py",
    "test_esail_rig.py", "test_faults.py", "test_reel.py", "test_deploy.py",
    "test_esail_vectoring.py", "test_rod_scenes.py", "test_kernels.py",
    "test_line_bodies_space.py", "test_orbit_scenes.py", "test_esail_attitude.py",
    "test_spin_control.py", "test_oml_force.py", "test_bare_tether_deorbit.py",
    "test_rodchain.py", "test_tss_deployment.py", "test_sweep.py",
    "test_plot.py", "test_validation_statics.py", "test_locking.py",
    "test_cli.py", "test_rodchain_io.py", "test_faults_round_three_control.py",
    "test_dynamics_hard.py", "test_compile_time.py", "test_esail.py", "test_oml.py",
    "test_rodchain_store.py", "test_plasma_brake.py", "test_adaptive.py", "test_dynamics.py",
    "test_run_storage.py", "test_esail_tangle.py", "test_environment_runs.py",
    "test_esail_deployment.py",
)


def _lead_pythonpath(folder):
    """``PYTHONPATH`` with ``folder`` first (once)."""
    paths = [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    os.environ["PYTHONPATH"] = os.pathsep.join([str(folder)] + [p for p in paths
                                                                if p != str(folder)])


_lead_pythonpath(ROOT)
#: No ``fsync`` (module notes), in this process and those it starts.
os.environ["SKFEM_CABLE_FSYNC"] = "0"
#: One BLAS thread (module notes), in this process and those it starts, unless set: set
#: before any of them imports numpy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def pytest_configure(config):
    """Files in the collection's order (``pytest_collection_modifyitems``), not in
    xdist's order by number of tests."""
    if hasattr(config.option, "loadscopereorder"):
        config.option.loadscopereorder = False


def pytest_unconfigure(config):
    """Freeze the objects left, the session over (``gc.freeze``): a worker's exit took 5.2
    CPU s of a one-process run of six files (170 tests), measured."""
    gc.freeze()


@pytest.hookimpl(wrapper=True)
def pytest_collection(session):
    """Collect without the cyclic garbage collector and freeze what the collection left
    (``gc.freeze``): its seven full collections walked the 440,000 objects of the
    package, numba, sympy and the test modules, 0.75 of its 3.5 CPU s, and the tests'
    full collections walked them again (measured).  Its garbage, 28,000 objects in a
    process of 470 MB, is kept: collecting it took 0.35 s."""
    gc.disable()
    try:
        return (yield)
    finally:
        gc.freeze()
        gc.enable()


def pytest_collection_modifyitems(config, items):
    """The files of ``LONGEST`` first, in its order; the others after them as collected
    (the tests of a file keep their order)."""
    rank = {name: i for i, name in enumerate(LONGEST)}
    items.sort(key=lambda item: rank.get(item.path.name, len(LONGEST)))
