"""Compilation is said and counted apart: the first run that compiles a kernel says so on
stderr (quiet once cached), numba's cache lies in the cache folder and not in the package,
and ``Result.stats`` and the run summary give the compile time apart from the
integration's."""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
from numba import njit

import skfem_cable as sc
from skfem_cable import runner
from skfem_cable.cli import command as cli
from skfem_cable.kernels import cache, lapack

ROOT = Path(__file__).resolve().parents[1]

#: A process that defines a small generated module and calls its kernel, and prints where
#: numba caches it and a kernel of the package.
PROBE = """
import skfem_cable
from skfem_cable.kernels import generated, lapack
module = generated.load("probe", "skfem_cable_probe_" + generated.digest("1"),
                        lambda: "from numba import njit\\n\\n\\n@njit(cache=True)\\n"
                                "def twice(x):\\n    return 2.0 * x\\n",
                        description="the probe")
assert module.twice(1.5) == 3.0
print(module.twice.stats.cache_path)
print(lapack.band_factor.stats.cache_path)
"""


def _probe(folder):
    env = dict(os.environ, SKFEM_CABLE_CACHE=str(folder))
    done = subprocess.run([sys.executable, "-c", PROBE], cwd=ROOT, env=env,
                          capture_output=True, text=True, check=True)
    return done.stdout.split(), done.stderr


def test_first_compilation_is_said_and_cached_in_the_cache_folder(tmp_path):
    """Before: numba compiled silently, and cached the package's kernels in its
    ``__pycache__``.  Now the first process says what it compiled and how long it took,
    the second (cached) is quiet, and both caches lie under ``SKFEM_CABLE_CACHE``."""
    paths, err = _probe(tmp_path)
    assert "skfem_cable: compiled the probe in" in err
    assert str(tmp_path) in err
    for path in paths:
        assert Path(path).is_relative_to(tmp_path / "numba")
    assert list((tmp_path / "numba").rglob("skfem_cable_probe_*.nbc"))
    again, err = _probe(tmp_path)
    assert again == paths
    assert "compiled" not in err


def test_package_kernels_are_not_cached_in_the_package():
    """Before: numba's ``cache=True`` wrote ``*.nbc`` next to the package's sources."""
    path = Path(lapack.band_factor.stats.cache_path).resolve()
    assert not path.is_relative_to(cache.PACKAGE)
    assert path.parent.name == "numba"


class _Compiles(sc.Observer):
    """Compiles a fresh function at the first saved step after the start."""

    def start(self, run):
        pass

    def saved(self, run, step):
        if step.index == 1:
            assert njit(lambda x: x + 1.0)(1.0) == 2.0

    def finish(self, run, error):
        pass


def test_stats_count_compile_time_apart():
    """Before: ``Result.stats`` had no compile time, and ``wall_time`` counted the
    compilation in the time loop as integration."""
    cable = sc.Cable.straight([0, 0, 0], [1.0, 0, 0], n_elements=2,
                              section=sc.Section.circular(radius=0.01, E=7e10, rho=7800.0))
    system = sc.System([cable]).pin(cable.node(0)).add_gravity([0, -9.81, 0])
    stats = sc.simulate(system, t_end=3e-3, dt=1e-3, observers=[_Compiles()]).stats
    in_loop = stats["wall_time"] - stats["integration_time"]
    assert in_loop > 0
    assert stats["compile_time"] >= in_loop
    assert np.isclose(stats["integration_time"] + in_loop, stats["wall_time"])


def test_summary_gives_compile_time_apart(tmp_path, capsys):
    """Before: the summary's ``N steps in T s`` counted the compilation as integration."""
    args = ["run", "pendulum", "--elements", "2", "--t-end", "0.01", "--no-plots", "--no-progress",
            "--out", str(tmp_path / "run")]
    assert cli.main(args) == 0
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["compile_time"] >= 0
    assert summary["integration_time"] <= summary["wall_time"]
    text = runner.format_summary(dict(summary, integration_time=1.25, compile_time=4.5))
    assert "steps in 1.25 s" in text
    assert "compiling the kernels (or loading them from the cache): 4.50 s" in text
