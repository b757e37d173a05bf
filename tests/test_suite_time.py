"""What keeps the test command short (issue 47, item 5: ``python3 tasks.py test`` in five
minutes): ``import skfem_cable`` leaves the heavy modules it does not need to their first
use (every process the suite starts imports the package), and ``bench --against HEAD``
in a clean checkout times this checkout twice instead of compiling every kernel again in a
new worktree."""

import json
import subprocess
import sys
from pathlib import Path

import pytest
from test_bench_guard import load

ROOT = Path(__file__).parents[1]

#: Third-party modules ``import skfem_cable`` must not import (imported where used).
LAZY = ("scipy.signal", "scipy.integrate", "scipy.stats", "astropy", "dask", "distributed",
        "xarray", "zarr", "matplotlib", "pyvista", "pandas")

#: Run in a fresh process: import the package, name some public names, print the modules.
IMPORT = """
import json, sys
import skfem_cable as sc
sc.System, sc.Orbit, sc.esail, sc.SolarWind, sc.Cathode
print(json.dumps(sorted(sys.modules)))
"""


#: Run in a fresh process: the modules ``import skfem_cable`` imports, then those the
#: command line's help adds.
BARE = """
import json, sys
import skfem_cable
bare = sorted(sys.modules)
from skfem_cable.cli import command
command.build_parser().format_help()
print(json.dumps([bare, sorted(sys.modules)]))
"""

#: What the help does without: the laws and their algebra, the run store, the solvers and
#: the model, and the registries that the choices of ``run``'s options name (the
#: formulations, the element types and scikit-fem, the frames of the VTU files): asked
#: only when a value is checked or ``run --help`` is shown (``runner.options.Choices``).
UNNEEDED = ("sympy", "zarr", "skfem.", "skfem_cable.solvers", "skfem_cable.model",
            "skfem_cable.laws", "skfem_cable.bodies", "skfem_cable.elements", "skfem_cable.io",
            "skfem_cable.scenes.classics")


def test_the_package_alone_imports_numba_and_its_public_names_on_use():
    """``import skfem_cable`` imports numba and the kernels' cache (``kernels``), and no
    other module of the package: each public name is imported when first named
    (``util.lazy``); ``skfem-cable --help`` does without the model, the solvers and
    scikit-fem."""
    out = subprocess.run([sys.executable, "-c", BARE], cwd=ROOT, check=True,
                         capture_output=True, text=True)
    bare, helped = json.loads(out.stdout.strip().splitlines()[-1])
    assert "numba" in bare
    assert {m for m in bare if m.startswith("skfem_cable")} <= {
        "skfem_cable", "skfem_cable._moved", "skfem_cable.kernels", "skfem_cable.kernels.cache",
        "skfem_cable.kernels.compile_log", "skfem_cable.util", "skfem_cable.util.lazy"}
    assert [m for m in helped if m.startswith(UNNEEDED)] == []


@pytest.fixture(scope="module")
def compare():
    return load(ROOT / "benchmarks" / "commit_compare.py")


def test_the_package_imports_without_the_heavy_modules():
    """A fresh ``import skfem_cable`` (and its public names) imports none of ``LAZY`` and
    compiles (or loads) no Kepler ufunc."""
    out = subprocess.run([sys.executable, "-c", IMPORT], cwd=ROOT, check=True,
                         capture_output=True, text=True)
    loaded = json.loads(out.stdout.strip().splitlines()[-1])
    assert [m for m in loaded if m.startswith(LAZY)] == []
    assert "kepler" not in out.stderr


def test_the_lazy_imports_are_there_when_used():
    """The AR(1) series of the solar wind (``scipy.signal.lfilter``) and the Kepler ufunc
    (float64 arrays and scalars) after the package's import."""
    import numpy as np

    from skfem_cable.loads import solar_wind_series
    from skfem_cable.space.kepler import eccentric_anomaly, solve_kepler

    series = solar_wind_series._ar1(np.random.default_rng(0), 50, 600.0, 3600.0, 0.1)
    assert series.shape == (50,) and np.all(np.isfinite(series))
    m = np.linspace(-3.0, 3.0, 7)
    ecc = eccentric_anomaly(m, 0.3)
    assert ecc.dtype == np.float64
    assert np.array_equal(ecc, [solve_kepler(x, 0.3) for x in m])
    assert eccentric_anomaly(1.0, 0.5) == solve_kepler(1.0, 0.5)


def test_a_clean_checkout_is_its_own_head(compare):
    """``same_sources``: the checkout holds HEAD's sources exactly when git sees no change
    to a tracked file (``checkout`` then hands out the checkout itself); the reference
    commit's sources are not this checkout's."""
    clean = not compare.git("status", "--porcelain", "--untracked-files=no")
    assert compare.same_sources("HEAD") == clean
    assert not compare.same_sources(compare.REFERENCE)
    with compare.checkout("HEAD") as tree:
        assert (tree == compare.ROOT) == clean
        assert (tree / "benchmarks" / "commit_compare.py").is_file()


def test_a_worktree_is_made_and_removed(compare):
    """``worktree``: a detached checkout of the commit in a temporary folder, gone after."""
    with compare.worktree("HEAD") as tree:
        assert (tree / "benchmarks" / "commit_compare.py").is_file()
        head = compare.git("rev-parse", "HEAD", cwd=tree)
        assert head == compare.git("rev-parse", "HEAD")
    assert not tree.exists()
    listed = compare.git("worktree", "list", "--porcelain")
    assert str(tree) not in listed


def test_the_schedule_says_when_each_worker_ended(tmp_path, capsys):
    """``compile_cost.py --suite``'s schedule: each worker's end from the records' ``wall``
    (``tests/compile_recorder.py``), from the earliest, with its CPU and its children's."""
    cost = load(ROOT / "benchmarks" / "compile_cost.py")
    for worker, wall, cpu in (("gw0", 1000.0, 50.0), ("gw1", 1012.5, 40.0)):
        record = {"test": "t", "cpu": cpu, "children": 3.0, "wall": wall, "compiles": []}
        (tmp_path / f"compile-{worker}.jsonl").write_text(json.dumps(record) + "\n")
    cost.schedule(cost.read_suite(tmp_path))
    out = capsys.readouterr().out
    assert "| gw0 | 0.0 | 50.0 | 3.0 |" in out and "| gw1 | 12.5 | 40.0 | 3.0 |" in out
